//! Fitting a drive to its chain: where one sprocket must sit, along a
//! direction, for the unstretched chain of N rollers to match the path
//! through the seated rollers exactly (docs/model.md, “A drive that fits”).
//!
//! The path's need of chain, in pitches, is the layout's own count with every
//! strand link one pitch long ([`crate::geometry::needed_pitches`]); moving a
//! sprocket by s along a unit direction u makes it a function f(s) whose
//! root f(s) = N is found by bracketing and bisection (a 1-D root find; the
//! tolerance is [`FIT_TOLERANCE_M`] of chain length). The bracket grows from
//! the sprocket's position in the direction that brings f towards N and stops
//! where the drive changes shape: a wrap that vanishes or jumps (the chain
//! would leave a sprocket or cross itself), a strand that cannot be laid or
//! that would run through a sprocket it does not wrap, or two sprockets that
//! would overlap. There the fit is refused with the
//! length still missing.
//!
//! The tensioner rule starts from this fit: its sprocket first moves along
//! its `adjust_direction` until the chain fits, then on until the pretension
//! is reached (`settle_tensioner`). Nothing here relaxes the chain.

use crate::geometry::{PathCircle, ToothProfile, chain_path, needed_pitches};
use crate::scene::Scene;

/// Tolerance of the fit on the chain's length: at the fitted position the
/// path through the seated rollers needs the chain's N pitches within this
/// length, m.
pub const FIT_TOLERANCE_M: f64 = 1e-9;

/// A sprocket's position at which the chain fits.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// The moved sprocket, 0-based.
    pub sprocket: usize,
    /// Unit direction of the move.
    pub direction: [f64; 2],
    /// Distance moved along `direction`, m (negative: against it).
    pub offset_m: f64,
    /// The sprocket's fitted centre, m.
    pub center_m: [f64; 2],
    /// Pitches the path needed before the move.
    pub needed_before: f64,
    /// Pitches the path needs at the fitted position.
    pub needed_pitches: f64,
    /// |needed − N| · P at the fitted position, m.
    pub misfit_m: f64,
    /// d(needed)/d(offset) at the start, pitches per metre: positive when
    /// moving along `direction` lengthens the path (tightens the chain).
    pub slope_per_m: f64,
    /// Layouts evaluated.
    pub evaluations: usize,
}

/// Why no position fits.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The direction is zero or not finite.
    #[error("the direction [{0}, {1}] is not a finite, non-zero vector")]
    Direction(f64, f64),
    /// The sprocket index is out of range.
    #[error("there is no sprocket {0}")]
    NoSprocket(usize),
    /// The drive as it stands has no chain path.
    #[error("the drive as written has no chain path: {0}")]
    NoPath(String),
    /// Moving along the direction does not change the path's length.
    #[error(
        "moving sprocket \"{sprocket}\" along [{dx:.4}, {dy:.4}] does not change the path's length (the direction is across it): choose another direction"
    )]
    Flat {
        /// The moved sprocket's name.
        sprocket: String,
        /// Direction, x.
        dx: f64,
        /// Direction, y.
        dy: f64,
    },
    /// The drive changes shape before the chain fits.
    #[error(
        "sprocket \"{sprocket}\" cannot move far enough along [{dx:.4}, {dy:.4}]: {reason} {offset_m:+.4} m from where it stands; there the path needs {reached:.3} pitches, and the chain's {rollers} are {:.3} pitches ({:.4} m) too {}",
        gap_pitches.abs(),
        gap_m.abs(),
        if *gap_pitches > 0.0 { "many" } else { "few" }
    )]
    Unreachable {
        /// The moved sprocket's name.
        sprocket: String,
        /// Direction, x.
        dx: f64,
        /// Direction, y.
        dy: f64,
        /// What stops the move.
        reason: String,
        /// How far it can move, m (signed along the direction).
        offset_m: f64,
        /// Pitches the path needs there.
        reached: f64,
        /// Pitches still missing (positive) or in excess (negative).
        gap_pitches: f64,
        /// The same as a length, m.
        gap_m: f64,
        /// The chain's roller count.
        rollers: usize,
    },
    /// The path's need of chain jumps across N (a roller changes from a wrap
    /// to a strand there): no position fits exactly.
    #[error(
        "the path's need of chain jumps from {below:.4} to {above:.4} pitches at {offset_m:.6} m along the direction, across the chain's {rollers}: no position of sprocket \"{sprocket}\" fits exactly"
    )]
    Jump {
        /// The moved sprocket's name.
        sprocket: String,
        /// Where, m.
        offset_m: f64,
        /// Need on one side.
        below: f64,
        /// Need on the other.
        above: f64,
        /// The chain's roller count.
        rollers: usize,
    },
}

/// The seated-roller circles of a scene, their positions free.
pub(crate) struct Fitter<'a> {
    scene: &'a Scene,
    seat_radii_m: Vec<f64>,
    teeth: Vec<u32>,
}

/// One evaluation of the path's need.
#[derive(Clone, Debug)]
struct Probe {
    needed: f64,
    wraps_rad: Vec<f64>,
}

impl<'a> Fitter<'a> {
    /// Builds the seat circles' radii from the scene's profiles.
    pub(crate) fn new(scene: &'a Scene) -> Result<Self, FitError> {
        let chain = &scene.chain;
        let seat_radii_m = scene
            .sprockets
            .iter()
            .map(|s| {
                ToothProfile::new(s.profile, s.teeth, chain.pitch_m, chain.roller_radius_m)
                    .map(|p| p.seated_radius_m())
                    .map_err(|e| FitError::NoPath(e.to_string()))
            })
            .collect::<Result<_, _>>()?;
        Ok(Self {
            scene,
            seat_radii_m,
            teeth: scene.sprockets.iter().map(|s| s.teeth).collect(),
        })
    }

    /// The path's need of chain with sprocket `k` moved by `offset` along `u`.
    fn probe(&self, k: usize, u: [f64; 2], offset: f64) -> Result<Probe, String> {
        let sp = &self.scene.sprockets;
        let mut circles: Vec<PathCircle> = sp
            .iter()
            .zip(&self.seat_radii_m)
            .map(|(s, &r)| PathCircle {
                center_m: s.center_m,
                radius_m: r,
                sense: s.wrap.sign(),
            })
            .collect();
        circles[k].center_m[0] += offset * u[0];
        circles[k].center_m[1] += offset * u[1];
        // Two sprockets whose tip circles meet cannot both turn (the scene's rule).
        let roller = self.scene.chain.roller_radius_m;
        for (j, other) in sp.iter().enumerate().filter(|&(j, _)| j != k) {
            let [ax, ay] = circles[k].center_m;
            let [bx, by] = circles[j].center_m;
            let reach = sp[k].pitch_radius_m + other.pitch_radius_m + 2.0 * roller;
            if (ax - bx).hypot(ay - by) < reach {
                return Err(format!("it would overlap sprocket \"{}\"", other.name));
            }
        }
        let path = chain_path(&circles).map_err(|e| e.to_string())?;
        // Two strands that cross: the chain would run through itself.
        let strands = &path.strands;
        for (a, sa) in strands.iter().enumerate() {
            for sb in &strands[a + 1..] {
                let shared = [sa.from, sa.to]
                    .iter()
                    .any(|j| *j == sb.from || *j == sb.to);
                if !shared && segments_cross(sa.start_m, sa.end_m, sb.start_m, sb.end_m) {
                    return Err(format!(
                        "the strand from \"{}\" to \"{}\" would cross the one from \"{}\" to \"{}\"",
                        sp[sa.from].name, sp[sa.to].name, sp[sb.from].name, sp[sb.to].name
                    ));
                }
            }
        }
        // A strand that runs through a sprocket it does not wrap: the chain
        // would cross that sprocket (or itself).
        for s in &path.strands {
            for (j, c) in circles.iter().enumerate() {
                if j == s.from || j == s.to {
                    continue;
                }
                if segment_distance(c.center_m, s.start_m, s.end_m) < c.radius_m + roller {
                    return Err(format!(
                        "the strand from \"{}\" to \"{}\" would run through sprocket \"{}\"",
                        sp[s.from].name, sp[s.to].name, sp[j].name
                    ));
                }
            }
        }
        let needed = needed_pitches(&path, &circles, &self.teeth, self.scene.chain.pitch_m)
            .map_err(|e| e.to_string())?;
        if !needed.is_finite() {
            return Err("the layout found no length".to_owned());
        }
        Ok(Probe {
            needed,
            wraps_rad: path.wraps.iter().map(|w| w.wrap_rad).collect(),
        })
    }

    /// Pitches of chain the path needs with the sprockets where the scene has them.
    pub(crate) fn needed_here(&self) -> Result<f64, FitError> {
        self.probe(0, [1.0, 0.0], 0.0)
            .map(|p| p.needed)
            .map_err(FitError::NoPath)
    }

    /// Moves sprocket `k` along `direction` until a chain of `rollers`
    /// rollers fits (module docs).
    pub(crate) fn fit(
        &self,
        k: usize,
        direction: [f64; 2],
        rollers: usize,
    ) -> Result<Fit, FitError> {
        let sp = self.scene.sprockets.get(k).ok_or(FitError::NoSprocket(k))?;
        let norm = direction[0].hypot(direction[1]);
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(FitError::Direction(direction[0], direction[1]));
        }
        let u = [direction[0] / norm, direction[1] / norm];
        let pitch = self.scene.chain.pitch_m;
        let target = rollers as f64;
        let evaluations = std::cell::Cell::new(0usize);
        let eval = |s: f64| {
            evaluations.set(evaluations.get() + 1);
            self.probe(k, u, s)
        };
        let start = eval(0.0).map_err(FitError::NoPath)?;
        let tol = FIT_TOLERANCE_M / pitch;
        let fitted = |offset: f64, needed: f64, slope: f64, evaluations: usize| Fit {
            sprocket: k,
            direction: u,
            offset_m: offset,
            center_m: [
                sp.center_m[0] + offset * u[0],
                sp.center_m[1] + offset * u[1],
            ],
            needed_before: start.needed,
            needed_pitches: needed,
            misfit_m: (needed - target).abs() * pitch,
            slope_per_m: slope,
            evaluations,
        };
        // The slope of the need along u, from a small step either way.
        let h = 1e-3 * pitch;
        let slope = match (eval(h), eval(-h)) {
            (Ok(a), Ok(b)) => (a.needed - b.needed) / (2.0 * h),
            (Ok(a), Err(_)) => (a.needed - start.needed) / h,
            (Err(_), Ok(b)) => (start.needed - b.needed) / h,
            (Err(e), Err(_)) => return Err(FitError::NoPath(e)),
        };
        if (start.needed - target).abs() <= tol {
            return Ok(fitted(0.0, start.needed, slope, evaluations.get()));
        }
        // Moving by a pitch changes the need by less than a millionth of a pitch.
        if !(slope.abs() * pitch > 1e-6) {
            return Err(FitError::Flat {
                sprocket: sp.name.clone(),
                dx: u[0],
                dy: u[1],
            });
        }
        let sign = if (target - start.needed) / slope > 0.0 {
            1.0
        } else {
            -1.0
        };
        let want = |n: f64| sign * slope.signum() * (target - n);
        // Grow the bracket from 0 in steps of the linear estimate, doubling.
        let mut step = ((target - start.needed) / slope).abs().max(h);
        let (mut lo, mut lo_probe) = (0.0, start.clone());
        let hi = loop {
            let s = lo + sign * step;
            match eval(s) {
                Ok(p) if changed_shape(&lo_probe, &p) => {
                    let (at, reason) = self.edge(k, u, lo, s, &lo_probe, &evaluations);
                    // The need may have passed N before the shape changed.
                    match self.probe(k, u, at) {
                        Ok(q) if want(q.needed) <= 0.0 => break (at, q),
                        _ => return Err(self.unreachable(k, u, at, reason, rollers)),
                    }
                }
                Ok(p) if want(p.needed) <= 0.0 => break (s, p),
                Ok(p) => {
                    (lo, lo_probe) = (s, p);
                    step *= 2.0;
                    if !(lo.abs() < 1e6) {
                        return Err(self.unreachable(
                            k,
                            u,
                            lo,
                            "it would have to move more than 1000 km".to_owned(),
                            rollers,
                        ));
                    }
                }
                Err(reason) => {
                    let (at, reason) = self.edge_failing(k, u, lo, s, reason, &evaluations);
                    match self.probe(k, u, at) {
                        Ok(q) if want(q.needed) <= 0.0 => break (at, q),
                        _ => return Err(self.unreachable(k, u, at, reason, rollers)),
                    }
                }
            }
        };
        // Bisection on [lo, hi]: f(lo) short of N, f(hi) at or past it.
        let (mut a, mut b) = (lo, hi.0);
        let (mut fa, mut fb) = (lo_probe.needed, hi.1.needed);
        for _ in 0..200 {
            if (fb - target).abs() <= tol || (a - b).abs() <= 1e-15 * (1.0 + a.abs()) {
                break;
            }
            // Regula falsi point, kept inside the middle half (Illinois-free safeguard).
            let mut m = a + (target - fa) * (b - a) / (fb - fa);
            let (low, high) = (a.min(b), a.max(b));
            let quarter = 0.25 * (high - low);
            if !(m > low + quarter && m < high - quarter) {
                m = 0.5 * (a + b);
            }
            let p = eval(m).map_err(FitError::NoPath)?;
            if want(p.needed) > 0.0 {
                (a, fa) = (m, p.needed);
            } else {
                (b, fb) = (m, p.needed);
            }
        }
        if (fb - target).abs() <= tol {
            return Ok(fitted(b, fb, slope, evaluations.get()));
        }
        if (fa - target).abs() <= tol {
            return Ok(fitted(a, fa, slope, evaluations.get()));
        }
        Err(FitError::Jump {
            sprocket: sp.name.clone(),
            offset_m: 0.5 * (a + b),
            below: fa,
            above: fb,
            rollers,
        })
    }

    /// The last offset before the drive changes shape between `good` (at
    /// `a`) and `b`, by bisection to a micrometre, and what changes.
    fn edge(
        &self,
        k: usize,
        u: [f64; 2],
        mut a: f64,
        mut b: f64,
        good: &Probe,
        evaluations: &std::cell::Cell<usize>,
    ) -> (f64, String) {
        let mut good = good.clone();
        let mut bad_reason = String::new();
        while (b - a).abs() > 1e-6 {
            let m = 0.5 * (a + b);
            evaluations.set(evaluations.get() + 1);
            match self.probe(k, u, m) {
                Ok(p) if !changed_shape(&good, &p) => (a, good) = (m, p),
                Ok(p) => {
                    bad_reason = shape_change(&self.scene.sprockets, &good, &p);
                    b = m;
                }
                Err(e) => {
                    bad_reason = e;
                    b = m;
                }
            }
        }
        if bad_reason.is_empty() {
            bad_reason = "the wrap changes".to_owned();
        }
        (a, bad_reason)
    }

    /// [`Self::edge`] when the probe at `b` failed with `reason`.
    fn edge_failing(
        &self,
        k: usize,
        u: [f64; 2],
        a: f64,
        b: f64,
        reason: String,
        evaluations: &std::cell::Cell<usize>,
    ) -> (f64, String) {
        match self.probe(k, u, a) {
            Ok(good) => {
                let (at, r) = self.edge(k, u, a, b, &good, evaluations);
                (at, if r.is_empty() { reason } else { r })
            }
            Err(_) => (a, reason),
        }
    }

    fn unreachable(
        &self,
        k: usize,
        u: [f64; 2],
        offset: f64,
        reason: String,
        rollers: usize,
    ) -> FitError {
        let reached = self.probe(k, u, offset).map_or(f64::NAN, |p| p.needed);
        let gap = rollers as f64 - reached;
        FitError::Unreachable {
            sprocket: self.scene.sprockets[k].name.clone(),
            dx: u[0],
            dy: u[1],
            reason: format!("{reason} when it has moved"),
            offset_m: offset,
            reached,
            gap_pitches: gap,
            gap_m: gap * self.scene.chain.pitch_m,
            rollers,
        }
    }
}

/// Whether the segments a–b and c–d cross (a proper intersection).
fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    let (d1, d2) = (orient(a, b, c), orient(a, b, d));
    let (d3, d4) = (orient(c, d, a), orient(c, d, b));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Distance from `p` to the segment from `a` to `b`.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * ab[0]).hypot(p[1] - a[1] - t * ab[1])
}

/// Whether the wraps changed shape between two probes: a wrap that jumps by
/// more than a quarter turn (the chain leaves a sprocket or crosses itself).
fn changed_shape(a: &Probe, b: &Probe) -> bool {
    a.wraps_rad
        .iter()
        .zip(&b.wraps_rad)
        .any(|(x, y)| (x - y).abs() > std::f64::consts::FRAC_PI_2)
}

/// Names the wrap that changed between two probes.
fn shape_change(sprockets: &[crate::scene::Sprocket], a: &Probe, b: &Probe) -> String {
    a.wraps_rad
        .iter()
        .zip(&b.wraps_rad)
        .enumerate()
        .find(|(_, (x, y))| (*x - *y).abs() > std::f64::consts::FRAC_PI_2)
        .map(|(k, (x, y))| {
            format!(
                "the chain's wrap on sprocket \"{}\" jumps from {:.1} to {:.1} degrees",
                sprockets[k].name,
                x.to_degrees(),
                y.to_degrees()
            )
        })
        .unwrap_or_default()
}

/// Moves sprocket `k` of `scene` along `direction` until a chain of
/// `rollers` rollers fits the path through the seated rollers within
/// [`FIT_TOLERANCE_M`] (module docs).
pub fn fit_sprocket(
    scene: &Scene,
    k: usize,
    direction: [f64; 2],
    rollers: usize,
) -> Result<Fit, FitError> {
    Fitter::new(scene)?.fit(k, direction, rollers)
}

/// Pitches of chain the path through the seated rollers needs as the scene
/// stands (the layout's count at strand links of one pitch).
pub fn needed_pitches_of(scene: &Scene) -> Result<f64, FitError> {
    Fitter::new(scene)?.needed_here()
}

/// The direction `fit` moves sprocket `k` in by default: its adjustment
/// direction if it is a tensioner, else away from the other sprockets'
/// centroid (for two sprockets: along the centre line). `None` when the
/// sprocket sits on that centroid.
pub fn default_direction(scene: &Scene, k: usize) -> Option<[f64; 2]> {
    let sp = scene.sprockets.get(k)?;
    if let crate::scene::Role::Tensioner { direction, .. } = sp.role {
        return Some(direction);
    }
    let others: Vec<[f64; 2]> = scene
        .sprockets
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != k)
        .map(|(_, s)| s.center_m)
        .collect();
    if others.is_empty() {
        return None;
    }
    let n = others.len() as f64;
    let cx = others.iter().map(|c| c[0]).sum::<f64>() / n;
    let cy = others.iter().map(|c| c[1]).sum::<f64>() / n;
    let d = [sp.center_m[0] - cx, sp.center_m[1] - cy];
    let norm = d[0].hypot(d[1]);
    (norm > 0.0).then(|| [d[0] / norm, d[1] / norm])
}

/// The roller counts the drive accepts as it stands, nearest the path's
/// need first: a count is accepted when the layout lays it out and, under
/// the rest-length rule, the pretension can take up its misfit
/// (`feasibility::check_chain_length`); under the tensioner rule, when the
/// tensioner's travel makes it fit. Tried: the two counts either side of
/// the need. Empty when neither is accepted (then only a move fits).
pub fn fitting_counts(scene: &Scene) -> Vec<usize> {
    let Ok(needed) = needed_pitches_of(scene) else {
        return Vec::new();
    };
    let mut candidates = vec![
        needed.floor().max(4.0) as usize,
        needed.ceil().max(4.0) as usize,
    ];
    candidates.dedup();
    candidates.sort_by(|a, b| {
        (*a as f64 - needed)
            .abs()
            .total_cmp(&(*b as f64 - needed).abs())
    });
    candidates
        .into_iter()
        .filter(|&n| {
            let mut s = scene.clone();
            s.chain.rollers = n;
            match s.chain.pretension_by {
                crate::scene::PretensionRule::Tensioner => s.tensioner().is_some_and(|t| {
                    default_direction(&s, t).is_some_and(|d| fit_sprocket(&s, t, d, n).is_ok())
                }),
                // The arms' preload: links at their rest length, as the rest-length rule lays them.
                crate::scene::PretensionRule::RestLength
                | crate::scene::PretensionRule::TensionerPreload => {
                    crate::model::DriveModel::build(&s).is_ok_and(|(model, _, layout)| {
                        super::feasibility::check_chain_length(&s, &layout, &model.path).is_ok()
                    })
                }
            }
        })
        .collect()
}
