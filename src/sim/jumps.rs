//! Tooth jumps: a roller that leaves its gap over a tooth tip and settles in
//! another gap of the same sprocket (docs/model.md, "Tooth jump").
//!
//! Each roller's gap on each sprocket is followed while the roller lies
//! *deep* in it: its centre within half the tooth's height above the pitch
//! circle (deeper than any roller passing over a tip can be). A roller deep
//! in gap j that is next deep in gap j′ ≠ j of the same sprocket, without
//! having left the sprocket's reach in between, has jumped j′ − j gaps. A
//! roller that leaves the reach (the end of a wrap) is forgotten, so a
//! roller entering the next wrap is a seating, not a jump. Gap j's centre is
//! at the sprocket's angle plus j 2π/z, as the profiles place them.
//!
//! On the real tooth form it also sees a roller *ride a tip*: touching the
//! sprocket with its centre at or beyond the radius where a roller resting
//! on a flank touches the tooth's tip corner
//! ([`AsaProfile::tip_ride_radius_m`](crate::geometry::asa::AsaProfile)):
//! every roller that touches the sprocket farther out rests on a tip. A ride
//! is counted once per roller until the roller lies deep in a gap again or
//! leaves the reach. The circular form has no tips: nothing rides them.
//!
//! It is looked at once per sample, not every step: a jump is a change of
//! state that lasts (a roller deep in another gap), which no sample misses;
//! its time is known to a sample period. A ride shorter than a sample period
//! can be missed. It reads the state only: no force changes, whether it
//! looks or not; the profile's contact query runs only for the few rollers
//! farther out than the tip-ride radius and within reach.

use serde::{Deserialize, Serialize};

use crate::geometry::{MAX_PATCHES, Patch, ToothProfile};
use crate::model::{DriveModel, DriveState};

/// Fraction of the tooth's height above the pitch circle within which a
/// roller's centre lies deep in its gap.
const DEEP_FRACTION: f64 = 0.5;

/// No gap: the roller is not deep in any gap of the sprocket since it last
/// came within reach.
const NO_GAP: i32 = i32::MIN;

/// One tooth jump.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToothJump {
    /// When it was seen (the sample after the roller settled), s.
    pub t_s: f64,
    /// The sprocket, 0-based.
    pub sprocket: usize,
    /// The roller, 0-based (the state's index).
    pub roller: usize,
    /// Gaps moved, counter-clockwise positive (±1 for one tooth).
    pub gaps: i32,
    /// Whether the roller moved ahead in the sprocket's sense of rotation
    /// at that time (the chain slipped forward on it), or behind.
    pub ahead: bool,
}

/// A roller that came to ride a tooth's tip (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct TipRide {
    /// When it was seen, s (to a sample period).
    pub t_s: f64,
    /// The sprocket, 0-based.
    pub sprocket: usize,
    /// The roller, 0-based (the state's index).
    pub roller: usize,
}

/// Follows every roller's gap on every sprocket (module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JumpWatch {
    /// Per sprocket: (deep radius², reach radius², teeth).
    limits: Vec<(f64, f64, u32)>,
    /// Gap of roller i on sprocket s at `i * sprockets + s`, or `NO_GAP`.
    gap: Vec<i32>,
    /// Every jump seen, in order.
    jumps: Vec<ToothJump>,
    /// Per sprocket: the tip-ride radius², m² (infinite on the circular
    /// form). Absent from checkpoints written before it: a resumed run then
    /// watches no tips.
    #[serde(default)]
    ride_sq_m2: Vec<f64>,
    /// Whether roller i rides a tip of sprocket s, at `i * sprockets + s`.
    #[serde(default)]
    riding: Vec<bool>,
    /// Every ride seen, in order.
    #[serde(default)]
    rides: Vec<TipRide>,
    /// Per sprocket, each gap's cone (derived from `limits`, not saved).
    #[serde(skip)]
    cones: Cones,
}

/// Fraction of half a gap's angle that a roller's direction may lie off
/// the gap's centre for [`Cones::holds`] to decide that it is still in the
/// gap: far more than the rounding of `atan2` and the sprocket's angle.
const CONE_FRACTION: f64 = 1.0 - 1e-6;

/// Largest sprocket angle, rad, at which [`Cones::holds`] decides (its
/// rounding grows with the angle).
const CONE_MAX_ANGLE_RAD: f64 = 1e6;

/// Each gap's centre direction in its sprocket's frame, (cos, sin) of
/// j 2π/z, and tan of [`CONE_FRACTION`] of half a gap's angle: whether a
/// roller deep in a gap is still in it, without `atan2`. Derived data,
/// equal whatever it holds.
#[derive(Clone, Debug, Default)]
struct Cones {
    /// Per sprocket: each gap's direction, then the cone's tan.
    sprockets: Vec<(Vec<[f64; 2]>, f64)>,
}

impl PartialEq for Cones {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Cones {
    /// The cones of sprockets with `teeth[s]` teeth.
    fn new(teeth: impl Iterator<Item = u32>) -> Self {
        let sprockets = teeth
            .map(|z| {
                let per_gap = std::f64::consts::TAU / f64::from(z);
                let gaps = (0..z)
                    .map(|j| {
                        let (sin, cos) = (f64::from(j) * per_gap).sin_cos();
                        [cos, sin]
                    })
                    .collect();
                (gaps, (0.5 * per_gap * CONE_FRACTION).tan())
            })
            .collect();
        Self { sprockets }
    }

    /// Whether the roller `(dx, dy)` from sprocket `s`'s centre, the
    /// sprocket turned to (`sin θ`, `cos θ`), lies within gap `gap`'s cone:
    /// then [`gap_of`] gives `gap`. False where it cannot tell.
    fn holds(&self, s: usize, gap: i32, sin_cos: [f64; 2], dx: f64, dy: f64) -> bool {
        let Some((gaps, tan)) = self.sprockets.get(s) else {
            return false;
        };
        let Some(&[c, sn]) = usize::try_from(gap).ok().and_then(|j| gaps.get(j)) else {
            return false;
        };
        let [sin, cos] = sin_cos;
        // The gap's centre direction in the world: rotated by θ.
        let u = [cos * c - sin * sn, sin * c + cos * sn];
        let along = u[0] * dx + u[1] * dy;
        let across = u[0] * dy - u[1] * dx;
        along > 0.0 && across.abs() < tan * along
    }
}

/// The gap of a roller `(dx, dy)` from the centre of a sprocket of `teeth`
/// teeth turned to `theta`: gap j's centre is at θ + j 2π/z.
fn gap_of(dx: f64, dy: f64, theta: f64, teeth: u32) -> i32 {
    let per_gap = std::f64::consts::TAU / f64::from(teeth);
    let turns = (dy.atan2(dx) - theta) / per_gap;
    turns.round().rem_euclid(f64::from(teeth)) as i32
}

impl JumpWatch {
    /// A watch over `model`'s sprockets for `rollers` rollers.
    pub fn new(model: &DriveModel, rollers: usize) -> Self {
        let limits = model
            .sprockets
            .iter()
            .map(|sp| {
                let deep = sp.pitch_radius_m + DEEP_FRACTION * tooth_height_m(sp);
                (deep * deep, sp.reach_sq_m2, sp.teeth)
            })
            .collect::<Vec<_>>();
        let ride_sq_m2 = model
            .sprockets
            .iter()
            .map(|sp| match &sp.profile {
                ToothProfile::Real(r) => r.tip_ride_radius_m().powi(2),
                ToothProfile::Circular(_) => f64::INFINITY,
            })
            .collect();
        Self {
            gap: vec![NO_GAP; rollers * limits.len()],
            riding: vec![false; rollers * limits.len()],
            cones: Cones::new(limits.iter().map(|l| l.2)),
            limits,
            jumps: Vec::new(),
            ride_sq_m2,
            rides: Vec::new(),
        }
    }

    /// Every jump seen so far, in order.
    pub fn jumps(&self) -> &[ToothJump] {
        &self.jumps
    }

    /// Every tip ride seen so far, in order.
    pub(crate) fn rides(&self) -> &[TipRide] {
        &self.rides
    }

    /// Looks at `state`; returns how many jumps it found.
    pub fn look(&mut self, model: &DriveModel, state: &DriveState) -> usize {
        let before = self.jumps.len();
        let count = self.limits.len();
        if self.cones.sprockets.len() != count {
            // A watch read from a checkpoint.
            self.cones = Cones::new(self.limits.iter().map(|l| l.2));
        }
        for (s, (sp, &(deep_sq, reach_sq, teeth))) in
            model.sprockets.iter().zip(&self.limits).enumerate()
        {
            let [cx, cy] = sp.center_m;
            let theta = state.theta[s];
            let (sin, cos) = theta.sin_cos();
            let cones = theta.abs() < CONE_MAX_ANGLE_RAD;
            for i in 0..state.rollers() {
                let (dx, dy) = (state.x[i] - cx, state.y[i] - cy);
                let r_sq = dx * dx + dy * dy;
                let slot = &mut self.gap[i * count + s];
                if r_sq > reach_sq {
                    *slot = NO_GAP;
                    if let Some(riding) = self.riding.get_mut(i * count + s) {
                        *riding = false;
                    }
                    continue;
                }
                if r_sq > deep_sq {
                    let ride_sq = self.ride_sq_m2.get(s).copied().unwrap_or(f64::INFINITY);
                    if r_sq >= ride_sq
                        && let Some(riding) = self.riding.get_mut(i * count + s)
                        && !*riding
                        && touches(sp, theta, dx, dy)
                    {
                        *riding = true;
                        self.rides.push(TipRide {
                            t_s: state.t_s,
                            sprocket: s,
                            roller: i,
                        });
                    }
                    continue;
                }
                if let Some(riding) = self.riding.get_mut(i * count + s) {
                    *riding = false;
                }
                let last = *slot;
                // Still in the gap it was deep in (the commonest case).
                if cones && self.cones.holds(s, last, [sin, cos], dx, dy) {
                    continue;
                }
                let gap = gap_of(dx, dy, theta, teeth);
                *slot = gap;
                if last == NO_GAP || last == gap {
                    continue;
                }
                let moved = wrapped(gap - last, teeth);
                let ahead = f64::from(moved) * state.omega[s] > 0.0;
                self.jumps.push(ToothJump {
                    t_s: state.t_s,
                    sprocket: s,
                    roller: i,
                    gaps: moved,
                    ahead,
                });
            }
        }
        self.jumps.len() - before
    }
}

/// Whether a roller centred `(dx, dy)` from the centre of `sp`, turned to
/// `theta`, touches it (the contact generator's query: a patch of positive
/// depth).
fn touches(sp: &crate::model::SprocketModel, theta: f64, dx: f64, dy: f64) -> bool {
    let (sin, cos) = theta.sin_cos();
    let local = [cos * dx + sin * dy, -sin * dx + cos * dy];
    let mut patches = [Patch::default(); MAX_PATCHES];
    let mut hint = u32::MAX;
    sp.profile.contacts(local, &mut hint, &mut patches) > 0
}

/// A difference of gap indices folded into (−z/2, z/2].
fn wrapped(d: i32, teeth: u32) -> i32 {
    let z = teeth as i32;
    let d = d.rem_euclid(z);
    if 2 * d > z { d - z } else { d }
}

/// Height of the teeth's tips above the pitch circle, m: the real profile's
/// tip radius less its pitch radius; for the circular profile, whose teeth
/// are no contact surface, the height the real profile of the same chain
/// would have (a third of the pitch where even that cannot be built).
fn tooth_height_m(sp: &crate::model::SprocketModel) -> f64 {
    use crate::geometry::{ToothProfile, asa::AsaProfile};
    match &sp.profile {
        ToothProfile::Real(r) => r.dimensions().tip_radius_m - r.dimensions().pitch_radius_m,
        ToothProfile::Circular(c) => {
            let half_angle = std::f64::consts::PI / f64::from(c.teeth);
            let pitch_m = 2.0 * c.pitch_radius_m * half_angle.sin();
            AsaProfile::new(c.teeth, pitch_m, 2.0 * c.roller_radius_m).map_or(pitch_m / 3.0, |p| {
                p.dimensions().tip_radius_m - p.dimensions().pitch_radius_m
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where a gap's cone holds a roller, `atan2` puts it in that gap:
    /// rollers at the edge between two gaps (10⁻¹⁶ to 10⁻⁸ rad off it) and
    /// anywhere, sprocket angles up to 10⁵ rad, each gap asked.
    #[test]
    fn a_gaps_cone_holds_only_rollers_in_that_gap() {
        let teeth = [11_u32, 30, 97];
        let cones = Cones::new(teeth.iter().copied());
        let mut rng = crate::rng::SeededRng::new(11);
        let (mut held, mut edges) = (0, 0);
        for k in 0..60_000 {
            let s = k % teeth.len();
            let z = teeth[s];
            let per_gap = std::f64::consts::TAU / f64::from(z);
            let theta = rng.range(-1.0, 1.0) * 10f64.powf(rng.range(-1.0, 5.0));
            let j = rng.below(z as usize) as f64;
            let off = if k % 2 == 0 {
                edges += 1;
                0.5 * per_gap + rng.range(-1.0, 1.0) * 10f64.powf(-rng.range(8.0, 16.0))
            } else {
                rng.range(-0.5, 0.5) * per_gap
            };
            let r = rng.range(0.01, 1.0);
            let (sin, cos) = (theta + j * per_gap + off).sin_cos();
            let (dx, dy) = (r * cos, r * sin);
            let gap = gap_of(dx, dy, theta, z);
            let (sin, cos) = theta.sin_cos();
            for last in [gap - 1, gap, gap + 1, (gap + 1).rem_euclid(z as i32)] {
                if cones.holds(s, last, [sin, cos], dx, dy) {
                    assert_eq!(last, gap, "teeth {z}, theta {theta}, at ({dx}, {dy})");
                    held += 1;
                }
            }
        }
        assert!(held > 25_000 && edges > 25_000, "{held} held");
    }

    #[test]
    fn gap_differences_fold_into_half_a_turn() {
        assert_eq!(wrapped(1, 30), 1);
        assert_eq!(wrapped(-1, 30), -1);
        assert_eq!(wrapped(29, 30), -1);
        assert_eq!(wrapped(-29, 30), 1);
        assert_eq!(wrapped(15, 30), 15);
        assert_eq!(wrapped(16, 30), -14);
    }
}
