//! Fitting a drive to its chain: where one sprocket must sit, along a
//! direction, for the unstretched chain of N rollers to match the path
//! through the seated rollers exactly (docs/model.md, “A drive that fits”).
//!
//! The path's need of chain, in pitches, is the layout's own count with every
//! strand link one pitch long ([`crate::geometry::needed_pitches`]); moving a
//! sprocket by s along a unit direction u makes it a function f(s) whose
//! roots f(s) = N are sought on a scan of the line on both sides of the
//! sprocket, nearest first ([`SCAN_STEPS`] samples a side, out to twice the
//! missing length plus the drive's size): two neighbouring samples whose
//! misfits f − N differ in sign bracket a root, which regula falsi kept
//! inside the bracket's middle half solves to [`FIT_TOLERANCE_M`] of chain
//! length. A bracket may span a change of the wrap's shape (a wrap that
//! grows or vanishes); where the need jumps across N there instead, no
//! position fits and the scan goes on to the next bracket. A position is
//! valid only where the drive can be built: no two sprockets overlap, no
//! strand runs through a sprocket it does not wrap, and no two strands
//! cross — strands that meet at a sprocket included, so a chain pulled
//! through the strand across the drive, or looped round a sprocket over its
//! own strand, is refused. A scan that finds no root says how near the
//! chain's length it came, where, and what bounds the move.
//!
//! The tensioner rule starts from this fit: its sprocket first moves along
//! its `adjust_direction` until the chain fits, then on until the pretension
//! is reached (`settle_tensioner`). Nothing here relaxes the chain.

use crate::geometry::v2::segment_distance;
use crate::geometry::{
    ArmTakeUp, PathCircle, ToothProfile, arm_take_up, chain_path, needed_pitches,
};
use crate::scene::Scene;

use super::error::FitError;

/// Samples of the scan on each side of the sprocket's position.
const SCAN_STEPS: usize = 200;

/// Tolerance of the fit on the chain's length: at the fitted position the
/// path through the seated rollers needs the chain's N pitches within this
/// length, m.
pub(crate) const FIT_TOLERANCE_M: f64 = 1e-9;

/// A sprocket's position at which the chain fits.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Fit {
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

    /// The seated-roller circles with the sprockets where the scene has them.
    fn circles(&self) -> Vec<PathCircle> {
        self.scene
            .sprockets
            .iter()
            .zip(&self.seat_radii_m)
            .map(|(s, &r)| PathCircle {
                center_m: s.center_m,
                radius_m: r,
                sense: s.wrap.sign(),
            })
            .collect()
    }

    /// The chain the scene's tensioner arms take up over their travel, as
    /// the sprockets stand ([`crate::geometry::arm_take_up`]).
    fn arm_take_up(&self) -> Option<ArmTakeUp> {
        let scene = self.scene;
        let arms: Vec<_> = scene
            .tensioners
            .iter()
            .map(|t| t.arm_shoe(scene.chain.roller_radius_m))
            .collect();
        let circles = self.circles();
        let path = chain_path(&circles).ok()?;
        arm_take_up(&path, &circles, &self.teeth, &arms, scene.chain.pitch_m)
    }

    /// The path's need of chain with sprocket `k` moved by `offset` along `u`.
    fn probe(&self, k: usize, u: [f64; 2], offset: f64) -> Result<Probe, String> {
        let sp = &self.scene.sprockets;
        let mut circles = self.circles();
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
        // Two strands that cross: the chain would run through itself. Strands
        // that meet at a sprocket are checked too: theirs are distinct
        // tangent points, so a crossing is a loop of the chain around that
        // sprocket (a wrap past the half turn that crosses its own strand),
        // or a strand pulled through the strand across the drive (in a
        // three-sprocket drive every pair of strands shares a sprocket).
        let strands = &path.strands;
        for (a, sa) in strands.iter().enumerate() {
            for sb in &strands[a + 1..] {
                if segments_cross(sa.start_m, sa.end_m, sb.start_m, sb.end_m) {
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
                if segment_distance(c.center_m, s.start_m, s.end_m).0 < c.radius_m + roller {
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
        Ok(Probe { needed })
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
        // Scan the need along the line, nearest offsets first, out to where
        // even a move that lengthened both strands at once could not close
        // the gap twice over, and at least the drive's size.
        let gap_m = (target - start.needed).abs() * pitch;
        let reach_m = (2.0 * gap_m + self.drive_size_m()).max(4.0 * pitch);
        let step_m = reach_m / SCAN_STEPS as f64;
        let mut best: Option<(f64, Probe)> = None;
        let mut jump: Option<FitError> = None;
        let mut stop: [Option<(f64, String)>; 2] = [None, None];
        let mut last: [(f64, Option<Probe>); 2] =
            [(0.0, Some(start.clone())), (0.0, Some(start.clone()))];
        for i in 1..=SCAN_STEPS {
            for (side, sign) in [(0, 1.0), (1, -1.0)] {
                let s = sign * step_m * i as f64;
                let probe = match eval(s) {
                    Ok(p) => Some(p),
                    Err(reason) => {
                        if stop[side].is_none() {
                            stop[side] = Some((s, reason));
                        }
                        None
                    }
                };
                let (prev_s, prev) = std::mem::replace(&mut last[side], (s, probe.clone()));
                if let (Some(p0), Some(p1)) = (prev, probe.as_ref())
                    && let Some(found) =
                        self.solve(k, target, tol, (prev_s, p0), (s, p1.clone()), &eval)
                {
                    match found {
                        Ok(root) => {
                            let local = self.local_slope(k, u, root.0, h).unwrap_or(slope);
                            return Ok(fitted(root.0, root.1.needed, local, evaluations.get()));
                        }
                        Err(e) => {
                            jump.get_or_insert(e);
                        }
                    }
                }
                if let Some(p) = probe {
                    let closer = best
                        .as_ref()
                        .is_none_or(|(_, b)| (p.needed - target).abs() < (b.needed - target).abs());
                    if closer {
                        best = Some((s, p));
                    }
                }
            }
        }
        if let Some(e) = jump {
            return Err(e);
        }
        // No position along the line fits: say how near it came and what
        // bounds the move on the side that comes nearest.
        let (at, reached) = best.map_or((0.0, f64::NAN), |(s, p)| (s, p.needed));
        let side = usize::from(at < 0.0);
        let reason = match &stop[side] {
            Some((s, why)) => {
                format!("{why} at {s:+.4} m, and nowhere closer to the chain's length")
            }
            None => format!(
                "the path's need stays short of the chain's length out to {:+.4} m",
                if side == 0 { reach_m } else { -reach_m }
            ),
        };
        let gap = rollers as f64 - reached;
        Err(FitError::Unreachable {
            sprocket: sp.name.clone(),
            dx: u[0],
            dy: u[1],
            reason,
            offset_m: at,
            reached,
            gap_pitches: gap,
            gap_m: gap * pitch,
            rollers,
        })
    }

    /// The largest distance between two sprockets' far edges, m: the scale
    /// of the scan.
    fn drive_size_m(&self) -> f64 {
        let sp = &self.scene.sprockets;
        let mut size: f64 = 0.0;
        for a in sp {
            for b in sp {
                let d = (a.center_m[0] - b.center_m[0]).hypot(a.center_m[1] - b.center_m[1]);
                size = size.max(d + a.pitch_radius_m + b.pitch_radius_m);
            }
        }
        size
    }

    /// d(needed)/d(offset) at `s`, by central differences.
    fn local_slope(&self, k: usize, u: [f64; 2], s: f64, h: f64) -> Option<f64> {
        let a = self.probe(k, u, s + h).ok()?;
        let b = self.probe(k, u, s - h).ok()?;
        let slope = (a.needed - b.needed) / (2.0 * h);
        (slope.abs() > 0.0).then_some(slope)
    }

    /// The root of need(s) = `target` between two valid probes, if their
    /// misfits differ in sign: regula falsi kept inside the middle half,
    /// through any change of the wrap's shape between them. A probe that
    /// fails inside narrows the bracket to the valid side that still
    /// changes sign. `None`: no sign change (or none left among valid
    /// positions); `Some(Err)`: the need jumps across the target there.
    fn solve(
        &self,
        k: usize,
        target: f64,
        tol: f64,
        lo: (f64, Probe),
        hi: (f64, Probe),
        eval: &impl Fn(f64) -> Result<Probe, String>,
    ) -> Option<Result<(f64, Probe), FitError>> {
        let (mut a, mut pa) = lo;
        let (mut b, mut pb) = hi;
        let (ga, gb) = (pa.needed - target, pb.needed - target);
        if ga.abs() <= tol {
            return Some(Ok((a, pa)));
        }
        if gb.abs() <= tol {
            return Some(Ok((b, pb)));
        }
        if ga.signum() == gb.signum() {
            return None;
        }
        for _ in 0..200 {
            let (fa, fb) = (pa.needed - target, pb.needed - target);
            if (a - b).abs() <= 1e-13 * (1.0 + a.abs()) {
                break;
            }
            let mut m = a - fa * (b - a) / (fb - fa);
            let (low, high) = (a.min(b), a.max(b));
            let quarter = 0.25 * (high - low);
            if !(m > low + quarter && m < high - quarter) {
                m = 0.5 * (a + b);
            }
            match eval(m) {
                Ok(p) => {
                    let g = p.needed - target;
                    if g.abs() <= tol {
                        return Some(Ok((m, p)));
                    }
                    if g.signum() == fa.signum() {
                        (a, pa) = (m, p);
                    } else {
                        (b, pb) = (m, p);
                    }
                }
                Err(_) => {
                    // An invalid stretch inside: keep the half whose valid
                    // end lies nearer a sign change, found by sampling.
                    let inner = (1..8)
                        .map(|j| a + (b - a) * j as f64 / 8.0)
                        .filter_map(|x| eval(x).ok().map(|p| (x, p)))
                        .collect::<Vec<_>>();
                    let mut chain = vec![(a, pa.clone())];
                    chain.extend(inner);
                    chain.push((b, pb.clone()));
                    let pair = chain.windows(2).find(|w| {
                        (w[0].1.needed - target).signum() != (w[1].1.needed - target).signum()
                    })?;
                    ((a, pa), (b, pb)) = (pair[0].clone(), pair[1].clone());
                }
            }
        }
        let (fa, fb) = (pa.needed - target, pb.needed - target);
        if fa.abs() <= tol {
            return Some(Ok((a, pa)));
        }
        if fb.abs() <= tol {
            return Some(Ok((b, pb)));
        }
        Some(Err(FitError::Jump {
            sprocket: self.scene.sprockets[k].name.clone(),
            offset_m: 0.5 * (a + b),
            below: pa.needed.min(pb.needed),
            above: pa.needed.max(pb.needed),
            rollers: target as usize,
        }))
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

/// Moves sprocket `k` of `scene` along `direction` until a chain of
/// `rollers` rollers fits the path through the seated rollers within
/// [`FIT_TOLERANCE_M`] (module docs).
pub(crate) fn fit_sprocket(
    scene: &Scene,
    k: usize,
    direction: [f64; 2],
    rollers: usize,
) -> Result<Fit, FitError> {
    Fitter::new(scene)?.fit(k, direction, rollers)
}

/// Pitches of chain the path through the seated rollers needs as the scene
/// stands (the layout's count at strand links of one pitch).
pub(crate) fn needed_pitches_of(scene: &Scene) -> Result<f64, FitError> {
    Fitter::new(scene)?.needed_here()
}

/// The direction `fit` moves sprocket `k` in by default: its adjustment
/// direction if it is a tensioner, else away from the other sprockets'
/// centroid (for two sprockets: along the centre line). `None` when the
/// sprocket sits on that centroid.
pub(crate) fn default_direction(scene: &Scene, k: usize) -> Option<[f64; 2]> {
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

/// The chain the scene's tensioner arms take up over their travel on the
/// path through the seated rollers as the sprockets stand (`None` without
/// arms, or where they cannot stand at the scene's pose): a chain longer
/// than that path by `min_m` to `max_m` is laid with the arms turned into
/// it (docs/model.md, “Tensioner arms”).
pub(crate) fn arm_take_up_of(scene: &Scene) -> Option<ArmTakeUp> {
    if scene.tensioners.is_empty() {
        return None;
    }
    Fitter::new(scene).ok()?.arm_take_up()
}
