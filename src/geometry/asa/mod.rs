//! ASA B29.1 (Type II) / ANSI roller-chain sprocket tooth form: dimensions, outline and
//! roller contact.
//!
//! This module builds the "real tooth profile" of Pedersen (Arch. Appl. Mech. 74 (2005),
//! §2.4) exactly as written out in docs/tooth-profile.md: the standard's constants
//! (“Constants”), the seven contact areas of one tooth gap in the gap-local frame
//! (“Construction”), and the contact rules (“Contact with a roller”).
//!
//! # What it does
//! - [`AsaDimensions`]: every standard dimension of one sprocket (A, B, C, α, Rs, Rt, ΔR,
//!   M, T, RE, W, V, RF, H, S, xy, yz, root and tip radius), with the corrected constants
//!   B = 18° − 56°/N, ab = 1.4 Dr and topping centres b = (±W, −V).
//! - [`GapPoints`]: the construction points x, y, z, f, the centres b, c and the area angles
//!   of one gap in its local frame.
//! - [`AsaProfile::signed_distance`]: signed distance from a point to the whole sprocket
//!   outline (positive in free space), closest point, area and gap.
//! - [`AsaProfile::contacts`]: the contact patches of a roller (at most two), O(1) and
//!   without allocation.
//! - [`AsaProfile::outline`]: the sampled outline of the whole sprocket (for drawing, CSV
//!   output and tests).
//!
//! # What it does not do
//! - No forces, no contact law, no contact memory: it only supplies depth, normal, point and
//!   a stable patch identity. The caller applies its law (e.g. Lankarani–Nikravesh).
//! - No sprocket pose: everything is in the SPROCKET frame (centre at the origin, angle 0).
//!   The caller transforms a roller centre into that frame and the results back.
//! - The tooth tip is the pointed tooth of the paper; the optional truncation to
//!   OD = P(0.6 + cot φ) is not applied.
//!
//! # Conventions
//! - SI units inside (metres, radians). The standard's additive constants 0.003 in and
//!   0.0015 in are used as 7.62e-5 m and 3.81e-5 m; all multipliers are unitless.
//! - φ = π/N is half the pitch angle; the pitch angle is Φ = 2π/N.
//! - Sprocket frame: gap j's seating centre O_j is at polar angle ψ_j = jΦ on the pitch
//!   circle (radius Rs); gap 0 is at (Rs, 0); gaps are numbered counter-clockwise and taken
//!   modulo N into 0..N. Tooth k is the tooth between gap k and gap k+1 (its centreline is
//!   at polar angle (k + ½)Φ).
//! - Gap-local frame (ξ, η), the paper's eq. (24): origin O_j, η = e_r (radially outward),
//!   ξ = (sin ψ, −cos ψ) (clockwise tangential). A point (ξ, η) is at
//!   (Rs + η) e_r + ξ ξ̂ in the sprocket frame.
//! - Areas 1..=7 as in docs/tooth-profile.md, “Construction”: 7 topping (convex,
//!   clockwise side, ξ > 0), 6 straight, 5 working (concave), 4 seating (concave),
//!   3 working, 2 straight, 1 topping (counter-clockwise side, ξ < 0). A counter-clockwise
//!   walk meets them in the order 7, 6, 5, 4, 3, 2, 1; the material is on the left of
//!   that walk.
//! - Signed distance: positive in free space, negative inside the material.
//! - Contact: depth = r − sd (contact when depth > 0); the normal is the unit free-side
//!   normal at the closest point, i.e. the unit vector from the closest outline point towards
//!   the roller centre whenever that centre is in free space. It is the direction of the
//!   force on the roller.
//!
//! # Patches and patch identity
//! The whole outline is tangent-continuous except at the tooth tips f, which are convex
//! corners; the nearest-point rule is continuous across both. A *patch* is a set of pieces
//! on which a roller has at most one nearest point; a roller can touch two separate places
//! only when the distance to the outline has two separate local minima within its radius.
//! Patch ids (N = number of teeth):
//! - `2·g` — the concave part (areas 2–6) of gap g.
//! - `2·k + 1` — tooth k: area 1 of gap k, the tip, and area 7 of gap k+1.
//! - `2·N + g` — only when ONE roller touches BOTH flanks of gap g at once (possible only for
//!   a roller that does not fit the seat, radius ≳ Rt): then the clockwise-side (ξ > 0)
//!   contact keeps `2·g` and the counter-clockwise-side one gets `2·N + g`.
//!
//! A roller sliding across the joint z (straight ↔ topping, tangent) changes from patch `2g`
//! to the tooth patch. That is a change of *place* for this id scheme but not of the force,
//! which is continuous; [`AsaProfile::patches_are_neighbours`] tells the caller when two ids
//! meet at such a joint, so it can carry its contact memory across.
//!
//! A patch is reported only where its nearest point is a genuine local minimum of the
//! distance: if a patch's nearest point is the end it shares with a neighbouring patch (z, z*
//! or the seat bottom between the two flank halves), the point belongs to the neighbour. The
//! ownership at each shared end is decided by ONE half-plane test (the normal line at the
//! joint), evaluated identically for both sides, so a point is never claimed twice and never
//! dropped by rounding (proof: docs/tooth-profile.md, section “Patch ownership at shared joints”).

mod dimensions;
mod fast;
mod pieces;
mod query;
#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;

use std::f64::consts::PI;

use super::v2::{V2, atan2_approx, dot};
use fast::{FastPiece, Found, farthest_from};
#[cfg(test)]
use pieces::{Hit, nearest_hit};
use pieces::{Piece, gap_pieces, neighbour_map};
use query::{Reach, Shortcuts, SideGraph};

pub use dimensions::{AsaDimensions, GapPoints};

use super::{MAX_PATCHES, OutlinePoint, Patch};

/// 0.003 in expressed in metres (additive constant of Dt and xy).
pub(crate) const IN_0_003_M: f64 = 7.62e-5;
/// 0.0015 in expressed in metres (additive constant of Rt, RE and RF).
pub(crate) const IN_0_0015_M: f64 = 3.81e-5;
/// Smallest tooth count accepted before the geometric checks (B, C > 0 needs N ≥ 4).
pub(crate) const MIN_TEETH: u32 = 4;
/// Largest tooth count accepted (keeps patch ids well inside `u32`).
pub(crate) const MAX_TEETH: u32 = 100_000;
/// Smallest arc step used by [`AsaProfile::outline`] (bounds the allocation).
pub(crate) const MIN_OUTLINE_STEP_RAD: f64 = 1e-4;
/// Rounding allowance when comparing a patch with the nearest outline point.
const CONSISTENCY_TOL_M: f64 = 1e-9;
/// Distances closer than this are a tie (the earlier piece is kept: own before neighbour).
const TIE_M: f64 = 1e-15;

/// Why a profile cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AsaError {
    /// Fewer than `MIN_TEETH` teeth.
    #[error("ASA sprocket needs at least {} teeth, got {teeth}", MIN_TEETH)]
    TooFewTeeth {
        /// The requested tooth count.
        teeth: u32,
    },
    /// More than `MAX_TEETH` teeth.
    #[error("ASA sprocket supports at most {} teeth, got {teeth}", MAX_TEETH)]
    TooManyTeeth {
        /// The requested tooth count.
        teeth: u32,
    },
    /// An input that must be finite and positive is not.
    #[error("{what} must be finite and positive")]
    NonPositive {
        /// Which input.
        what: &'static str,
    },
    /// The seating curves of neighbouring gaps would meet (Dt ≥ P).
    #[error("seating diameter {seating_diameter_m} m is not smaller than the pitch {pitch_m} m")]
    RollerTooBig {
        /// Seating diameter Dt in metres.
        seating_diameter_m: f64,
        /// Pitch P in metres.
        pitch_m: f64,
    },
    /// The standard's construction does not give a valid profile for these inputs.
    #[error("degenerate ASA tooth profile: {reason}")]
    DegenerateProfile {
        /// What failed.
        reason: &'static str,
    },
}

/// A contact patch of [`AsaProfile::contacts`] with the place it touches: the closest
/// outline point, in the sprocket frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg(any(test, feature = "bench-kernels"))]
pub struct LocatedPatch {
    /// Depth, normal, area, gap and identity of the patch.
    pub patch: Patch,
    /// Closest outline point, metres.
    pub point: [f64; 2],
}

/// Precomputed geometry of one ASA sprocket: the pieces of one gap in its local frame, the
/// neighbouring toppings, and the gap rotations.
#[derive(Clone, Debug, PartialEq)]
pub struct AsaProfile {
    /// Standard dimensions.
    dims: AsaDimensions,
    /// Construction points and angles.
    points: GapPoints,
    /// Gap pieces, walk order 7, 6, 5, 4, 4, 3, 2, 1 (seat split at its bottom).
    own: [Piece; 8],
    /// Area 7 of gap +1, in gap 0's frame (the far side of tooth 0).
    next_area7: Piece,
    /// Area 1 of gap −1, in gap 0's frame (the far side of tooth −1).
    prev_area1: Piece,
    /// (cos ψ_j, sin ψ_j) for every gap.
    gap_trig: Vec<V2>,
    /// Pitch angle Φ = 2π/N.
    pitch_angle_rad: f64,
    /// Trig-free forms of `own` (0..8), `prev_area1` (8) and `next_area7` (9), for the hot
    /// path of [`AsaProfile::contacts`].
    fast: [FastPiece; 10],
    /// Smallest distance from the seating centre O to any own piece (≈ Rt), less a rounding
    /// allowance: no roller centred within `seat_clear_m − r` of O can touch.
    seat_clear_m: f64,
    /// Largest distance of the outline from the sprocket centre, plus a rounding allowance.
    reach_radius_m: f64,
    /// tan(Φ/2) shrunk by a relative 1e-9: a point strictly inside this cone about a gap
    /// direction is in that gap's sector whatever the rounding of `atan2`.
    tan_half_pitch_inner: f64,
    /// 1/Φ.
    inv_pitch_angle: f64,
    /// The outline as a graph, to tell free space from material far from the outline.
    graph: Option<SideGraph>,
    /// The direct rules of [`AsaProfile::contacts_hinted`] (see [`Shortcuts`]).
    cuts: Shortcuts,
    /// The radius-dependent constants for the profile's own roller, Dr/2.
    nominal: Reach,
}

impl AsaProfile {
    /// Builds the profile of a sprocket with `teeth` teeth for a chain of pitch `pitch_m`
    /// and roller diameter `roller_diameter_m` (metres).
    ///
    /// # Errors
    /// [`AsaError`] when the inputs are out of range or the standard construction
    /// degenerates (e.g. too few teeth for a positive straight portion).
    pub fn new(teeth: u32, pitch_m: f64, roller_diameter_m: f64) -> Result<Self, AsaError> {
        let dims = dimensions::dimensions(teeth, pitch_m, roller_diameter_m)?;
        let points = dimensions::gap_points(&dims)?;
        let own = gap_pieces(&dims, &points);
        let pitch_angle_rad = 2.0 * PI / f64::from(teeth);
        let rs = dims.pitch_radius_m;
        let next_area7 = own[0].mapped(neighbour_map(rs, pitch_angle_rad, 1), pitch_angle_rad, 1);
        let prev_area1 =
            own[7].mapped(neighbour_map(rs, pitch_angle_rad, -1), -pitch_angle_rad, -1);
        let gap_trig = (0..teeth)
            .map(|j| {
                let (s, c) = (pitch_angle_rad * f64::from(j)).sin_cos();
                [c, s]
            })
            .collect();
        let fast = [
            FastPiece::new(&own[0]),
            FastPiece::new(&own[1]),
            FastPiece::new(&own[2]),
            FastPiece::new(&own[3]),
            FastPiece::new(&own[4]),
            FastPiece::new(&own[5]),
            FastPiece::new(&own[6]),
            FastPiece::new(&own[7]),
            FastPiece::new(&prev_area1),
            FastPiece::new(&next_area7),
        ];
        let seat_clear_m = own
            .iter()
            .map(|piece| piece.closest([0.0, 0.0]).dist_m)
            .fold(f64::INFINITY, f64::min)
            * (1.0 - 1e-12);
        let sprocket_centre = [0.0, -rs];
        let reach_radius_m = fast[..8]
            .iter()
            .map(|f| farthest_from(f, sprocket_centre))
            .fold(0.0, f64::max)
            * (1.0 + 1e-12)
            + 1e-12;
        let graph = SideGraph::new(&dims, &points);
        let cuts = Shortcuts::new(&dims, &points, &fast, graph.as_ref());
        let mut profile = AsaProfile {
            dims,
            points,
            own,
            next_area7,
            prev_area1,
            gap_trig,
            pitch_angle_rad,
            fast,
            seat_clear_m,
            reach_radius_m,
            tan_half_pitch_inner: (0.5 * pitch_angle_rad).tan() * (1.0 - 1e-9),
            inv_pitch_angle: 1.0 / pitch_angle_rad,
            graph,
            cuts,
            nominal: Reach {
                r: 0.0,
                reach: 0.0,
                outer2: 0.0,
                clear2: -1.0,
                low2: 0.0,
                re_in2: -1.0,
                rf_out2: 0.0,
            },
        };
        profile.nominal = Reach::new(&profile, 0.5 * roller_diameter_m);
        Ok(profile)
    }

    /// The standard dimensions of this sprocket.
    #[must_use]
    pub fn dimensions(&self) -> &AsaDimensions {
        &self.dims
    }

    /// The construction points and angles of one gap (gap-local frame).
    #[must_use]
    #[cfg(any(test, feature = "bench-kernels"))]
    pub fn gap_points(&self) -> &GapPoints {
        &self.points
    }

    /// Number of teeth N.
    #[must_use]
    #[cfg(test)]
    pub(crate) fn teeth(&self) -> u32 {
        self.dims.teeth
    }

    /// Pitch angle Φ = 2π/N.
    #[must_use]
    #[cfg(test)]
    pub(crate) fn pitch_angle_rad(&self) -> f64 {
        self.pitch_angle_rad
    }

    /// The radius (from the sprocket centre) of the profile's own roller's centre where it
    /// touches a tooth's tip f with its centre on the topping curve's normal at f:
    /// b + (R_F + R_r)(f − b)/R_F, gap-local. Along the flank the touching roller's
    /// centre rises monotonically up to here; a roller touching the sprocket farther out
    /// rests on the tip's corner itself (docs/model.md, "Riding a tip").
    #[must_use]
    pub(crate) fn tip_ride_radius_m(&self) -> f64 {
        let (b, f) = (self.points.b_m, self.points.f_m);
        let rf = self.dims.topping_radius_m;
        let q = super::v2::add(
            b,
            super::v2::scale(
                super::v2::sub(f, b),
                (rf + 0.5 * self.dims.roller_diameter_m) / rf,
            ),
        );
        (self.dims.pitch_radius_m + q[1]).hypot(q[0])
    }

    /// True when patches `a` and `b` meet at a tangent joint (z or z*: a gap's concave
    /// patch and one of its two teeth), or are the two flank patches of one gap, so a
    /// contact sliding from one to the other is the same contact continuing; the caller
    /// may carry its contact memory over.
    #[must_use]
    pub(crate) fn patches_are_neighbours(&self, a: u32, b: u32) -> bool {
        let n = u64::from(self.dims.teeth);
        let (a, b) = (u64::from(a), u64::from(b));
        let gap_of_concave = |id: u64| -> Option<u64> {
            if id < 2 * n && id % 2 == 0 {
                Some(id / 2)
            } else if (2 * n..3 * n).contains(&id) {
                Some(id - 2 * n)
            } else {
                None
            }
        };
        let tooth_of = |id: u64| (id < 2 * n && id % 2 == 1).then_some(id / 2);
        let touches = |gap: u64, tooth: u64| tooth == gap || (tooth + 1) % n == gap;
        match (
            gap_of_concave(a),
            gap_of_concave(b),
            tooth_of(a),
            tooth_of(b),
        ) {
            (Some(ga), Some(gb), _, _) => ga == gb && a != b,
            (Some(g), _, _, Some(t)) | (_, Some(g), Some(t), _) => touches(g, t),
            _ => false,
        }
    }

    /// Gap nearest to `p` in polar angle, 0..N.
    fn gap_index(&self, p: V2) -> usize {
        let n = i64::from(self.dims.teeth);
        let k = (p[1].atan2(p[0]) / self.pitch_angle_rad).round() as i64;
        k.rem_euclid(n) as usize
    }

    /// Gap whose sector holds `p`: the same as [`AsaProfile::gap_index`] (which is used
    /// whenever `p` is within a relative 1e-9 of a sector boundary), found without `atan2`
    /// by testing the cone of `hint` (or of an approximate polar angle) and its neighbours.
    #[inline(always)]
    fn gap_near(&self, p: V2, hint: u32) -> usize {
        // The roller is almost always still in its hinted gap: one cone test, inline.
        if let Some(&u) = self.gap_trig.get(hint as usize) {
            let along = dot(u, p);
            let across = u[0] * p[1] - u[1] * p[0];
            if along > 0.0 && across.abs() < self.tan_half_pitch_inner * along {
                return hint as usize;
            }
        }
        self.gap_search(p, hint)
    }

    /// [`AsaProfile::gap_near`] when `p` has left the hinted gap's cone.
    #[inline(never)]
    fn gap_search(&self, p: V2, hint: u32) -> usize {
        let n = self.gap_trig.len();
        let mut j = if (hint as usize) < n {
            hint as usize
        } else {
            // θ/Φ + N + ½ > 0, so the truncation is a floor: the nearest gap, modulo N.
            let k = (atan2_approx(p[1], p[0]) * self.inv_pitch_angle + (n as f64 + 0.5)) as usize;
            if k >= n { k - n } else { k }
        };
        for _ in 0..3 {
            let Some(&u) = self.gap_trig.get(j) else {
                break;
            };
            let along = dot(u, p);
            let across = u[0] * p[1] - u[1] * p[0];
            if along > 0.0 && across.abs() < self.tan_half_pitch_inner * along {
                return j;
            }
            if along.is_nan() || along <= 0.0 {
                break;
            }
            j = if across > 0.0 {
                if j + 1 == n { 0 } else { j + 1 }
            } else if j == 0 {
                n - 1
            } else {
                j - 1
            };
        }
        self.gap_index(p)
    }

    /// (cos ψ, sin ψ) of a gap.
    fn trig(&self, gap: usize) -> V2 {
        self.gap_trig.get(gap).copied().unwrap_or([1.0, 0.0])
    }

    /// Sprocket frame → gap-local frame (point).
    fn to_local(&self, gap: usize, p: V2) -> V2 {
        let [c, s] = self.trig(gap);
        [
            p[0] * s - p[1] * c,
            p[0] * c + p[1] * s - self.dims.pitch_radius_m,
        ]
    }

    /// Gap-local frame → sprocket frame (point).
    fn to_global_point(&self, gap: usize, q: V2) -> V2 {
        let [c, s] = self.trig(gap);
        let r = self.dims.pitch_radius_m + q[1];
        [r * c + q[0] * s, r * s - q[0] * c]
    }

    /// Gap-local frame → sprocket frame (direction).
    fn to_global_vec(&self, gap: usize, v: V2) -> V2 {
        let [c, s] = self.trig(gap);
        [v[1] * c + v[0] * s, v[1] * s - v[0] * c]
    }

    /// `gap + offset` modulo N, for |offset| ≤ 1.
    fn wrap_gap(&self, gap: usize, offset: i64) -> i64 {
        let n = i64::from(self.dims.teeth);
        let g = gap as i64 + offset;
        if g < 0 {
            g + n
        } else if g >= n {
            g - n
        } else {
            g
        }
    }

    /// All contact patches of a roller of radius `roller_radius_m` centred at `p` (sprocket
    /// frame, gap 0's seating centre at (Rs, 0), gaps numbered counter-clockwise). Writes at
    /// most 2 patches into `out` (deepest first) and returns how many.
    ///
    /// O(1): the gap comes from the polar angle of `p`; only that gap's pieces and the two
    /// neighbouring teeth (both toppings and the tip) are examined. No allocation, no
    /// trigonometry. Non-finite input, or a negative radius, gives 0 patches.
    /// [`AsaProfile::contacts_hinted`] is the same with a gap hint.
    ///
    /// Algorithm: the closest point of each of the four candidate patches (clockwise flank
    /// half, counter-clockwise flank half, tooth g, tooth g−1) is computed piece by piece
    /// (foot of the perpendicular when it falls on the span, else the nearer end). A patch
    /// whose closest point lies beyond a shared joint is dropped (the neighbour owns it). A
    /// patch is kept if depth > 0 and it is consistent with the nearest outline point of
    /// the whole sprocket (same side of the surface, not nearer), which removes the parts
    /// of the neighbouring topping circles that reach into this gap. The deepest patch is
    /// always the nearest outline point, so `depth = r − signed_distance(p)`.
    ///
    /// Speed: the commonest cases (beyond the tips, seated with clearance, the bottom and the
    /// free space of the gap) are decided by direct rules with at most one square root;
    /// otherwise the pieces provably farther than the radius are skipped, which changes no
    /// result (docs/tooth-profile.md, section “The general query”).
    ///
    /// Not examined: the concave parts of the neighbouring gaps. A roller in free space
    /// could only reach them across a whole tooth, i.e. with a radius of the order of the
    /// tooth width.
    #[cfg(test)]
    pub(crate) fn contacts(
        &self,
        p: [f64; 2],
        roller_radius_m: f64,
        out: &mut [LocatedPatch; 2],
    ) -> usize {
        let mut hint = u32::MAX;
        self.contacts_hinted(p, roller_radius_m, &mut hint, out)
    }

    /// Exactly [`AsaProfile::contacts`], but the gap search starts at `hint` (a gap the
    /// roller was recently in; any value works, e.g. `u32::MAX` for none) and `hint` is
    /// updated to the gap of `p` whenever that gap is looked up (it is left unchanged when
    /// `p` is rejected before, e.g. beyond the tips or non-finite).
    #[cfg(any(test, feature = "bench-kernels"))]
    pub fn contacts_hinted(
        &self,
        p: [f64; 2],
        roller_radius_m: f64,
        hint: &mut u32,
        out: &mut [LocatedPatch; 2],
    ) -> usize {
        if !(roller_radius_m.is_finite() && roller_radius_m >= 0.0) {
            return 0;
        }
        let mut emit = |slot: usize, gap: usize, f: Found| {
            if let Some(slot) = out.get_mut(slot) {
                *slot = LocatedPatch {
                    patch: self.patch(gap, &f),
                    point: self.to_global_point(gap, f.point),
                };
            }
        };
        if roller_radius_m == self.nominal.r {
            self.query(p, &self.nominal, hint, &mut emit)
        } else {
            self.query(p, &Reach::new(self, roller_radius_m), hint, &mut emit)
        }
    }

    /// [`AsaProfile::contacts_hinted`] for the profile's own roller (radius Dr/2), without
    /// the contact point (the contact generator's call): the same patches.
    #[inline]
    pub fn contacts_nominal(
        &self,
        p: [f64; 2],
        hint: &mut u32,
        out: &mut [Patch; MAX_PATCHES],
    ) -> usize {
        self.query(p, &self.nominal, hint, &mut |slot, gap, f: Found| {
            if let Some(slot) = out.get_mut(slot) {
                *slot = self.patch(gap, &f);
            }
        })
    }

    /// A gap-local patch of `gap` written in the sprocket frame.
    #[inline(always)]
    fn patch(&self, gap: usize, f: &Found) -> Patch {
        Patch {
            depth_m: f.depth_m,
            normal: self.to_global_vec(gap, f.normal),
            area: f.area,
            gap: self.wrap_gap(gap, f.gap_offset) as u32,
            patch_id: f.patch_id,
        }
    }

    /// Signed distance from `p` (sprocket frame) to the outline: positive in free space,
    /// negative inside the material. Returns (distance, closest point, area, gap).
    /// Non-finite input returns (NaN, [NaN, NaN], 0, 0).
    #[must_use]
    #[cfg(test)]
    pub(crate) fn signed_distance(&self, p: [f64; 2]) -> (f64, [f64; 2], u8, i64) {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return (f64::NAN, [f64::NAN; 2], 0, 0);
        }
        let gap = self.gap_index(p);
        let best = self.nearest_own(self.to_local(gap, p));
        (
            best.sd_m,
            self.to_global_point(gap, best.point),
            best.area,
            gap as i64,
        )
    }

    /// Nearest point of the whole outline to the gap-local point `q`, `q` in this gap's
    /// sector. The sector is a union of two mirror half-sectors of the dihedral symmetry,
    /// so the nearest outline point lies on this gap's own pieces (docs/tooth-profile.md,
    /// section “The nearest point lies in the roller's own gap”).
    #[cfg(test)]
    fn nearest_own(&self, q: V2) -> Hit {
        nearest_hit(&self.own.map(|piece| piece.closest(q)))
    }

    /// The whole sprocket outline in the sprocket frame, counter-clockwise, starting at the
    /// tip f of gap 0. Every piece is sampled: arcs at angular steps ≤ `max_step_rad`,
    /// straight portions at length steps ≤ `max_step_rad`·RE. The outline is closed: the
    /// last point connects back to the first (not repeated). `max_step_rad` is clamped to
    /// [[`MIN_OUTLINE_STEP_RAD`], π/8]; a non-finite or non-positive step uses 1°.
    #[must_use]
    pub(crate) fn outline(&self, max_step_rad: f64) -> Vec<OutlinePoint> {
        let step = if max_step_rad.is_finite() && max_step_rad > 0.0 {
            max_step_rad.clamp(MIN_OUTLINE_STEP_RAD, PI / 8.0)
        } else {
            PI / 180.0
        };
        let straight_step_m = step * self.dims.working_radius_m;
        let mut local = Vec::new();
        let mut out = Vec::new();
        for gap in 0..self.gap_trig.len() {
            for piece in &self.own {
                local.clear();
                piece.sample(step, straight_step_m, &mut local);
                out.extend(local.iter().map(|&q| {
                    let [x_m, y_m] = self.to_global_point(gap, q);
                    OutlinePoint {
                        x_m,
                        y_m,
                        gap: gap as i64,
                        area: piece.area,
                    }
                }));
            }
        }
        out
    }
}
