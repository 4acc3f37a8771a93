//! Tensioner arms in the layout: how much chain their shoes take up, and
//! the layout of a chain whose excess they take up.
//!
//! An arm turns about a fixed pivot and carries a circular shoe whose
//! outside the rollers ride on; its tensioner pushes one of its points
//! along a fixed line, and the travel along that line is bounded by the
//! tensioner's stops. A shoe pressed into a strand lengthens the chain's
//! path: the rollers' centres run from the last roller on one sprocket
//! along the tangent to the circle of radius R_shoe + R_roller about the
//! shoe's centre, round it, and along the tangent to the next sprocket. So
//! the shoe is a circle of the path, wrapped the other way round from the
//! sprockets the strand joins where it bends the strand inwards, and a
//! smooth one: its rollers lie a link apart, in no gap ([`super::walk`]).
//!
//! Take-up T: the pitches of chain the path through the seated rollers
//! needs with the shoes where the arms put them, less what it needs with
//! straight strands, times the pitch (the layout's own count both times,
//! so T is what `needed_pitches` misses). T ≥ 0: a shoe only lengthens.
//! A shoe clear of its strand adds nothing; one that would carry the chain
//! beyond either end of its arc is out of its range (the chain would run
//! over the shoe's end, which this layout does not model).
//!
//! Two equal sprockets of seat radius r, centres (±a, 0), the upper strand
//! at y = r, and a shoe circle of radius ρ centred at (x_c, y_c) above it
//! that bends it down: each side s (right: a_s = a − x_c, left: a + x_c)
//! runs along the crossed tangent from its sprocket to the shoe, of length
//! t_s = √(D_s² − (r + ρ)²), D_s = √(a_s² + y_c²), inclined by
//! α_s = asin((r + ρ)/D_s) − atan2(y_c, a_s) below the horizontal; the
//! sprocket wraps α_s more and the shoe α_R + α_L. So
//! T = t_R + t_L + (ρ + r)(α_R + α_L) − 2a while both α_s > 0, and 0 once
//! the shoe clears the strand; for a small push d = r + ρ − y_c at the
//! middle of a long strand, T → 2 d²/(2a) · (1 + O(ρ d / a²)). The module's
//! tests check the layout's count against it (a tenth of a millimetre:
//! the count is of links, not of the smooth curve).
//!
//! The arms move together, by a common fraction f of their travel: f = 1
//! every arm at its `max_travel_m`, f = −1 at its `min_travel_m`, f = 0 the
//! scene's pose. [`layout_with_arms`] finds the f at which the path needs
//! the chain's N pitches (bisection), and lays the chain there with links
//! of one pitch. It does not know forces: where the tensioners balance the
//! chain is the static equilibrium's question.

use std::f64::consts::TAU;

use super::laid::{ArmPose, ArmReach, Layout, LayoutError, TakeUpBound, length_error};
use super::path::{ChainPath, PathCircle, chain_path};
use super::v2::segment_distance;
use super::walk::Walker;

/// A tensioner arm as the layout sees it, at the scene's pose.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmShoe {
    /// The fixed pivot, m.
    pub pivot_m: [f64; 2],
    /// Centre of the shoe's arc, m.
    pub center_m: [f64; 2],
    /// Radius of the circle the roller centres follow on the shoe: the
    /// shoe's radius plus the roller's, m.
    pub radius_m: f64,
    /// Where the arc starts (counter-clockwise), rad.
    pub start_rad: f64,
    /// The arc's extent, rad.
    pub span_rad: f64,
    /// The point the tensioner pushes, m.
    pub point_m: [f64; 2],
    /// Unit direction of the push.
    pub direction: [f64; 2],
    /// The tensioner's travel at its lower stop (≤ 0), m.
    pub min_travel_m: f64,
    /// Its travel at its upper stop (≥ 0), m.
    pub max_travel_m: f64,
}

impl ArmShoe {
    /// The tensioner's travel with the arm turned by `angle_rad` from the
    /// scene's pose: x = (R(q) r₀ − r₀)·ê = A (cos q − 1) + B sin q, with
    /// r₀ = point − pivot, A = r₀·ê and B = r₀ × ê (the lever at the pose).
    pub fn travel_m(&self, angle_rad: f64) -> f64 {
        let (a, b) = self.lever_terms();
        let (s, c) = angle_rad.sin_cos();
        a * (c - 1.0) + b * s
    }

    /// The arm's angle at which the travel is `travel_m`, on the branch
    /// through the scene's pose: with M = √(A² + B²) and ψ = atan2(B, A),
    /// x = M cos(q − ψ) − A, so q = ψ ∓ acos((x + A)/M) (the sign that
    /// gives q = 0 at x = 0); a travel beyond the arm's reach gives the
    /// angle of its furthest.
    pub fn angle_for_travel(&self, travel_m: f64) -> f64 {
        let (a, b) = self.lever_terms();
        let m = a.hypot(b);
        if !(m > 0.0) {
            return 0.0;
        }
        let psi = b.atan2(a);
        let turn = ((travel_m + a) / m).clamp(-1.0, 1.0).acos();
        if psi >= 0.0 { psi - turn } else { psi + turn }
    }

    /// (A, B) = (r₀·ê, r₀ × ê).
    fn lever_terms(&self) -> (f64, f64) {
        let r0 = [
            self.point_m[0] - self.pivot_m[0],
            self.point_m[1] - self.pivot_m[1],
        ];
        let e = self.direction;
        (r0[0] * e[0] + r0[1] * e[1], r0[0] * e[1] - r0[1] * e[0])
    }

    /// The shoe's centre and arc start with the arm turned by `angle_rad`.
    fn shoe_at(&self, angle_rad: f64) -> ([f64; 2], f64) {
        let (s, c) = angle_rad.sin_cos();
        let r = [
            self.center_m[0] - self.pivot_m[0],
            self.center_m[1] - self.pivot_m[1],
        ];
        (
            [
                self.pivot_m[0] + c * r[0] - s * r[1],
                self.pivot_m[1] + s * r[0] + c * r[1],
            ],
            self.start_rad + angle_rad,
        )
    }

    /// The arm's angle at fraction `f` of its travel (module docs).
    fn angle_at_fraction(&self, f: f64) -> f64 {
        let travel = if f >= 0.0 {
            f * self.max_travel_m
        } else {
            -f * self.min_travel_m
        };
        self.angle_for_travel(travel)
    }
}

/// The chain the arms' shoes take up over their travel (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmTakeUp {
    /// Take-up with the arms as far back as they go, m.
    pub min_m: f64,
    /// At the scene's pose, m.
    pub pose_m: f64,
    /// With the arms as far in as they go, m.
    pub max_m: f64,
    /// What stops the arms going further in.
    pub bound: TakeUpBound,
}

/// The path with the shoes that bend their strands inserted as circles.
struct Extended {
    circles: Vec<PathCircle>,
    teeth: Vec<u32>,
    path: ChainPath,
    /// For each circle: `Ok(sprocket)` or `Err(arm)`.
    owner: Vec<Result<usize, usize>>,
}

/// Why the arms cannot stand at some angles.
#[derive(Debug)]
enum Stand {
    /// The chain would run over the end of this arm's shoe.
    OffShoe(usize),
    /// No path passes the shoes.
    NoPath,
    /// No layout.
    Layout(LayoutError),
}

impl Stand {
    fn bound(&self) -> TakeUpBound {
        match self {
            Self::OffShoe(j) => TakeUpBound::ShoeEnd(*j),
            Self::NoPath | Self::Layout(_) => TakeUpBound::Path,
        }
    }
}

impl From<LayoutError> for Stand {
    fn from(e: LayoutError) -> Self {
        Self::Layout(e)
    }
}

/// The straight path, its circles and the arms: what every evaluation needs.
struct Drive<'a> {
    path: &'a ChainPath,
    circles: &'a [PathCircle],
    teeth: &'a [u32],
    arms: &'a [ArmShoe],
    pitch_m: f64,
    /// The strand each arm's shoe sits nearest, and the shoe's place along it.
    strand_of: Vec<(usize, f64)>,
}

impl<'a> Drive<'a> {
    fn new(
        path: &'a ChainPath,
        circles: &'a [PathCircle],
        teeth: &'a [u32],
        arms: &'a [ArmShoe],
        pitch_m: f64,
    ) -> Self {
        let strand_of = arms
            .iter()
            .map(|arm| {
                let mid = arm.start_rad + 0.5 * arm.span_rad;
                let p = [
                    arm.center_m[0] + arm.radius_m * mid.cos(),
                    arm.center_m[1] + arm.radius_m * mid.sin(),
                ];
                path.strands
                    .iter()
                    .enumerate()
                    .map(|(k, s)| {
                        let (d, along) = segment_distance(p, s.start_m, s.end_m);
                        (d, k, along)
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map_or((0, 0.0), |(_, k, along)| (k, along))
            })
            .collect();
        Self {
            path,
            circles,
            teeth,
            arms,
            pitch_m,
            strand_of,
        }
    }

    fn angles(&self, f: f64) -> Vec<f64> {
        self.arms.iter().map(|a| a.angle_at_fraction(f)).collect()
    }

    /// The path with the shoes at `angles` inserted where they bend their
    /// strands (a shoe whose wrap would not lie in (0, π) is clear).
    fn extended(&self, angles: &[f64]) -> Result<Extended, Stand> {
        let mut used: Vec<bool> = vec![true; self.arms.len()];
        for _ in 0..=self.arms.len() {
            let ext = self.insert(angles, &used)?;
            let mut changed = false;
            for (c, owner) in ext.owner.iter().enumerate() {
                if let Err(j) = *owner {
                    let wrap = ext.path.wraps[c].wrap_rad;
                    if !(wrap > 1e-9 && wrap < std::f64::consts::PI) {
                        used[j] = false;
                        changed = true;
                    }
                }
            }
            if !changed {
                // The chain's contact must lie on each shoe's arc.
                for (c, owner) in ext.owner.iter().enumerate() {
                    if let Err(j) = *owner {
                        let (_, start) = self.arms[j].shoe_at(angles[j]);
                        let w = &ext.path.wraps[c];
                        let on = |a: f64| (a - start).rem_euclid(TAU) <= self.arms[j].span_rad;
                        if !(on(w.arrive_rad) && on(w.leave_rad)) {
                            return Err(Stand::OffShoe(j));
                        }
                    }
                }
                return Ok(ext);
            }
        }
        Err(Stand::NoPath)
    }

    /// The circles with the shoes of `used` arms at `angles` inserted in
    /// their strands, ordered along them.
    fn insert(&self, angles: &[f64], used: &[bool]) -> Result<Extended, Stand> {
        let n = self.circles.len();
        let mut circles = Vec::with_capacity(n + self.arms.len());
        let mut teeth = Vec::with_capacity(n + self.arms.len());
        let mut owner = Vec::with_capacity(n + self.arms.len());
        for k in 0..n {
            circles.push(self.circles[k]);
            teeth.push(self.teeth[k]);
            owner.push(Ok(k));
            let strand = &self.path.strands[k];
            let t = strand.direction();
            let mut on: Vec<(f64, usize)> = (0..self.arms.len())
                .filter(|&j| used[j] && self.strand_of[j].0 == k)
                .map(|j| (self.strand_of[j].1, j))
                .collect();
            on.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (_, j) in on {
                let (center_m, _) = self.arms[j].shoe_at(angles[j]);
                let rel = [
                    center_m[0] - strand.start_m[0],
                    center_m[1] - strand.start_m[1],
                ];
                // The chain keeps the shoe's centre on the side it lies on.
                let sense = if t[0] * rel[1] - t[1] * rel[0] >= 0.0 {
                    1.0
                } else {
                    -1.0
                };
                circles.push(PathCircle {
                    center_m,
                    radius_m: self.arms[j].radius_m,
                    sense,
                });
                teeth.push(0);
                owner.push(Err(j));
            }
        }
        let path = chain_path(&circles).map_err(|_| Stand::NoPath)?;
        Ok(Extended {
            circles,
            teeth,
            path,
            owner,
        })
    }

    /// Pitches of chain the path needs with the arms at fraction `f`.
    fn need_at(&self, f: f64) -> Result<f64, Stand> {
        let ext = self.extended(&self.angles(f))?;
        let walker = Walker::engaged(&ext.path, &ext.circles, &ext.teeth)?;
        Ok(walker.walk(self.pitch_m, None)?.needed_links(self.pitch_m))
    }

    /// The fraction nearest `to` on the way from `from` (valid) at which
    /// the arms still stand, by bisection, and what stops them short of
    /// `to` (their stops, when nothing does).
    fn reach(&self, from: f64, to: f64) -> (f64, TakeUpBound) {
        let Err(mut why) = self.need_at(to) else {
            return (to, TakeUpBound::Stops);
        };
        let (mut ok, mut bad) = (from, to);
        for _ in 0..50 {
            let mid = 0.5 * (ok + bad);
            match self.need_at(mid) {
                Ok(_) => ok = mid,
                Err(e) => (bad, why) = (mid, e),
            }
        }
        (ok, why.bound())
    }
}

/// The chain the shoes of `arms` take up over their travel on the straight
/// `path` round `circles` (seated-roller circles; module docs), or `None`
/// when the arms cannot stand at the scene's pose (a chain over a shoe's
/// end there) or the straight path does not lay out.
pub fn arm_take_up(
    path: &ChainPath,
    circles: &[PathCircle],
    teeth: &[u32],
    arms: &[ArmShoe],
    pitch_m: f64,
) -> Option<ArmTakeUp> {
    if arms.is_empty() {
        return None;
    }
    let straight = Walker::engaged(path, circles, teeth)
        .and_then(|w| w.walk(pitch_m, None))
        .ok()?
        .needed_links(pitch_m);
    let drive = Drive::new(path, circles, teeth, arms, pitch_m);
    let pose = drive.need_at(0.0).ok()?;
    let ((lo, _), (hi, bound)) = (drive.reach(0.0, -1.0), drive.reach(0.0, 1.0));
    let take_up = |f: f64| {
        drive
            .need_at(f)
            .map_or(pose - straight, |need| need - straight)
            .max(0.0)
            * pitch_m
    };
    Some(ArmTakeUp {
        min_m: take_up(lo),
        pose_m: ((pose - straight) * pitch_m).max(0.0),
        max_m: take_up(hi),
        bound,
    })
}

/// Lays `rollers` rollers of pitch `pitch_m` on `path` round `circles`
/// with the arms turned so that the path through the seated rollers and
/// the shoes needs the chain's length (module docs): every link one pitch
/// long (to the loop's closure), each arm's pose in [`Layout::arms`]. A
/// chain the arms cannot take up gets [`LayoutError::ChainLength`] with
/// their take-up.
pub fn layout_with_arms(
    path: &ChainPath,
    circles: &[PathCircle],
    teeth: &[u32],
    rollers: usize,
    pitch_m: f64,
    arms: &[ArmShoe],
) -> Result<Layout, LayoutError> {
    let straight = Walker::engaged(path, circles, teeth)?
        .walk(pitch_m, None)?
        .needed_links(pitch_m);
    let refused = |take_up: Option<ArmTakeUp>| {
        let mut e = length_error(straight, rollers);
        if let LayoutError::ChainLength { arms: a, .. } = &mut e {
            *a = take_up.map(|t| ArmReach {
                min_m: t.min_m,
                max_m: t.max_m,
                excess_m: (rollers as f64 - straight) * pitch_m,
                bound: t.bound,
            });
        }
        e
    };
    let drive = Drive::new(path, circles, teeth, arms, pitch_m);
    if drive.need_at(0.0).is_err() {
        return Err(refused(None));
    }
    let target = rollers as f64;
    let ((lo, _), (hi, _)) = (drive.reach(0.0, -1.0), drive.reach(0.0, 1.0));
    let gap = |f: f64| drive.need_at(f).map(|n| n - target);
    let (Ok(g_lo), Ok(g_hi)) = (gap(lo), gap(hi)) else {
        return Err(refused(arm_take_up(path, circles, teeth, arms, pitch_m)));
    };
    if g_lo.signum() == g_hi.signum() && g_lo != 0.0 && g_hi != 0.0 {
        return Err(refused(arm_take_up(path, circles, teeth, arms, pitch_m)));
    }
    // Bisection on the need's sign change: f where the path needs N pitches.
    let (mut a, mut b) = (lo, hi);
    let rising = g_hi > g_lo;
    for _ in 0..60 {
        let mid = 0.5 * (a + b);
        let g = match gap(mid) {
            Ok(g) => g,
            Err(_) => break,
        };
        if g.abs() < 1e-9 {
            (a, b) = (mid, mid);
            break;
        }
        if (g < 0.0) == rising {
            a = mid;
        } else {
            b = mid;
        }
    }
    let f = 0.5 * (a + b);
    let angles = drive.angles(f);
    let ext = drive.extended(&angles).map_err(|e| match e {
        Stand::Layout(e) => e,
        Stand::OffShoe(_) | Stand::NoPath => refused(None),
    })?;
    let (walk, needed) =
        Walker::engaged(&ext.path, &ext.circles, &ext.teeth)?.close(rollers, pitch_m)?;
    // Back to the sprockets: a strand's free links run from its sprocket's
    // last seated roller to the next sprocket's first, over any shoe.
    let mut strand_links = vec![0; circles.len()];
    let mut sprocket_angles_rad = Vec::with_capacity(circles.len());
    let mut current = 0;
    for (c, owner) in ext.owner.iter().enumerate() {
        match *owner {
            Ok(k) => {
                current = k;
                sprocket_angles_rad.push(walk.sprocket_angles_rad[c]);
            }
            Err(_) => strand_links[current] += walk.seated[c] - 1,
        }
        strand_links[current] += walk.strand_links[c];
    }
    let seats = walk
        .seats
        .iter()
        .map(|s| s.and_then(|(c, gap)| ext.owner[c].ok().map(|k| (k, gap))))
        .collect();
    // As the straight layout counts it: wrap links of a pitch on the
    // sprockets, links of λ elsewhere, and the closing strand's residual.
    let free_links: usize = strand_links.iter().sum();
    let wrap_links: usize = (0..ext.owner.len())
        .filter(|&c| ext.owner[c].is_ok())
        .map(|c| walk.seated[c] - 1)
        .sum();
    let polygon_length_m =
        wrap_links as f64 * pitch_m + free_links as f64 * walk.lambda_m + walk.residual_m;
    let poses = arms
        .iter()
        .enumerate()
        .map(|(j, arm)| ArmPose {
            angle_rad: angles[j],
            travel_m: arm.travel_m(angles[j]),
            strand: ext.owner.contains(&Err(j)).then_some(drive.strand_of[j].0),
        })
        .collect();
    Ok(Layout {
        rollers_m: walk.rollers_m,
        sprocket_angles_rad,
        seats,
        strand_links,
        strand_link_m: walk.lambda_m,
        polygon_length_m,
        misfit_pitches: needed - target,
        hanging: false,
        arms: poses,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const PITCH_M: f64 = 0.0127;
    const HALF_SPAN_M: f64 = 0.5;
    const SHOE_RHO_M: f64 = 0.304;

    /// Two sprockets of 60 teeth (P = 12.7 mm) at (±0.5, 0) m, both
    /// counter-clockwise: strand 0 below, strand 1 above at y = r, run
    /// right to left. An arm pivoted 0.6 m left of the middle, level with
    /// its shoe's centre, whose shoe circle (ρ = 0.304 m) clears the upper
    /// strand's roller centres by 1 mm at the pose; its tensioner pushes
    /// straight down 0.3 m from the pivot, so the arm turns clockwise as
    /// the travel grows.
    fn drive(max_travel_m: f64) -> (ChainPath, Vec<PathCircle>, Vec<u32>, ArmShoe) {
        let r = PITCH_M / (2.0 * (std::f64::consts::PI / 60.0).sin());
        let circle = |x: f64| PathCircle {
            center_m: [x, 0.0],
            radius_m: r,
            sense: 1.0,
        };
        let circles = vec![circle(-HALF_SPAN_M), circle(HALF_SPAN_M)];
        let path = chain_path(&circles).expect("a path");
        let y0 = r + SHOE_RHO_M + 0.001;
        let arm = ArmShoe {
            pivot_m: [-0.6, y0],
            center_m: [0.0, y0],
            radius_m: SHOE_RHO_M,
            start_rad: 200f64.to_radians(),
            span_rad: 140f64.to_radians(),
            point_m: [-0.3, y0],
            direction: [0.0, -1.0],
            min_travel_m: -0.004,
            max_travel_m,
        };
        (path, circles, vec![60, 60], arm)
    }

    /// The take-up of the module docs' closed form with the shoe's circle
    /// centred at `c` over sprockets of radius `r`.
    fn closed_form_m(r: f64, c: [f64; 2]) -> f64 {
        let (mut tangents, mut bends) = (0.0, 0.0);
        for a_s in [HALF_SPAN_M - c[0], HALF_SPAN_M + c[0]] {
            let d = a_s.hypot(c[1]);
            let alpha = ((r + SHOE_RHO_M) / d).asin() - c[1].atan2(a_s);
            if alpha <= 0.0 {
                return 0.0;
            }
            tangents += (d * d - (r + SHOE_RHO_M).powi(2)).sqrt();
            bends += alpha;
        }
        tangents + (SHOE_RHO_M + r) * bends - 2.0 * HALF_SPAN_M
    }

    #[test]
    fn the_arm_angle_for_a_travel_gives_that_travel_back() {
        let (_, _, _, arm) = drive(0.025);
        assert_eq!(arm.angle_for_travel(0.0), 0.0);
        for x in [-0.004, 0.001, 0.01, 0.025] {
            let q = arm.angle_for_travel(x);
            // The pushed point turned about the pivot, read along the push.
            let (s, c) = q.sin_cos();
            let r0 = [0.3, 0.0];
            let moved = [c * r0[0] - s * r0[1], s * r0[0] + c * r0[1]];
            let along = -(moved[1] - r0[1]);
            assert!((along - x).abs() < 1e-12, "travel {x}: {along}");
            assert!((arm.travel_m(q) - x).abs() < 1e-12);
            // Pushing down turns the arm clockwise.
            assert!(q * x <= 0.0, "travel {x}: angle {q}");
        }
    }

    #[test]
    fn a_shoe_takes_up_what_its_tangents_and_arcs_add_to_the_path() {
        for max_travel in [0.01, 0.025, 0.05] {
            let (path, circles, teeth, arm) = drive(max_travel);
            let t = arm_take_up(&path, &circles, &teeth, std::slice::from_ref(&arm), PITCH_M)
                .expect("the arm stands");
            // Clear of the strand at the pose and below it.
            assert_eq!((t.min_m, t.pose_m), (0.0, 0.0));
            assert_eq!(t.bound, TakeUpBound::Stops);
            let (c, _) = arm.shoe_at(arm.angle_for_travel(max_travel));
            let expected = closed_form_m(circles[0].radius_m, c);
            // Within 0.1 mm: the layout counts links, not the smooth curve
            // (chords on the shoe, the closing strand's landing).
            assert!(
                (t.max_m - expected).abs() < 1e-4,
                "max travel {max_travel} m: take-up {} mm, closed form {} mm",
                t.max_m * 1e3,
                expected * 1e3
            );
        }
        // 25 mm of travel turns the arm by −asin(0.025/0.3) = −0.0834 rad,
        // its shoe 50 mm down, and takes up 4.93 mm (the closed form by
        // hand: t_s = 0.4613, 0.4568 m, α_s = 0.1016, 0.1026 rad;
        // 0.9181 + (0.304 + 0.1213) · 0.2042 − 1 = 4.93e-3 m).
        let (path, circles, teeth, arm) = drive(0.025);
        let t = arm_take_up(&path, &circles, &teeth, &[arm], PITCH_M).expect("stands");
        assert!((t.max_m - 4.93e-3).abs() < 0.05e-3, "{} mm", t.max_m * 1e3);
    }

    #[test]
    fn a_chain_a_link_longer_is_laid_round_the_shoe_with_links_of_one_pitch() {
        let (path, circles, teeth, arm) = drive(0.06);
        let needed = super::super::needed_pitches(&path, &circles, &teeth, PITCH_M).expect("walks");
        let rollers = needed.round() as usize + 1;
        let layout = layout_with_arms(
            &path,
            &circles,
            &teeth,
            rollers,
            PITCH_M,
            std::slice::from_ref(&arm),
        )
        .expect("the arm takes a link up");
        assert_eq!(layout.rollers_m.len(), rollers);
        assert_eq!(layout.arms.len(), 1);
        let pose = layout.arms[0];
        assert_eq!(pose.strand, Some(1));
        assert!(pose.travel_m > 0.0 && pose.travel_m < 0.06);
        assert!((layout.strand_stretch(PITCH_M)).abs() < 1e-6);
        // Every link a pitch long (wrap chords of the pitch circle included).
        let n = rollers;
        for i in 0..n {
            let (a, b) = (layout.rollers_m[i], layout.rollers_m[(i + 1) % n]);
            let l = (b[0] - a[0]).hypot(b[1] - a[1]);
            assert!((l / PITCH_M - 1.0).abs() < 1e-6, "link {i}: {l} m");
        }
        // No roller inside the shoe's circle (deeper than the walk's
        // landing allows: a roller half a link past a tangent point lies
        // in by λ φ/2 − λ²/(2ρ), zero to first order).
        let (c, _) = arm.shoe_at(pose.angle_rad);
        let deepest = layout
            .rollers_m
            .iter()
            .map(|p| SHOE_RHO_M - (p[0] - c[0]).hypot(p[1] - c[1]))
            .fold(f64::NEG_INFINITY, f64::max);
        eprintln!("deepest {deepest:e}");
        assert!(deepest < 1e-6, "a roller {deepest} m inside the shoe");
        // The shoe takes up the chain's excess over the straight path.
        let excess_m = (rollers as f64 - needed) * PITCH_M;
        let expected = closed_form_m(circles[0].radius_m, c);
        assert!(
            (excess_m - expected).abs() < 1e-4,
            "excess {} mm, closed form at the arm's pose {} mm",
            excess_m * 1e3,
            expected * 1e3
        );
    }

    #[test]
    fn a_chain_longer_than_the_arms_take_up_is_refused_with_their_reach() {
        let (path, circles, teeth, arm) = drive(0.025);
        let needed = super::super::needed_pitches(&path, &circles, &teeth, PITCH_M).expect("walks");
        let rollers = needed.round() as usize + 1;
        let err = layout_with_arms(&path, &circles, &teeth, rollers, PITCH_M, &[arm])
            .expect_err("4.9 mm of take-up is less than the 6.6 mm of excess");
        let LayoutError::ChainLength {
            arms: Some(reach), ..
        } = &err
        else {
            panic!("{err}");
        };
        assert!((reach.max_m - 4.93e-3).abs() < 0.05e-3);
        assert!(err.to_string().contains("take up 0.00 to 4.9"), "{err}");
    }
}
