//! A chain that rests behind a fixed guide's entry: a roller just beyond
//! one of the guide's free ends (a ramp's tip, or the body's end where
//! there is no ramp) whose centre lies so far behind the line of that end
//! that, carried onto the guide, it would meet the face at once deeper than
//! the blow-up limit. The strand there sags below the guide (a worn chain
//! on fixed centres gains slack), and the first such roller to reach the
//! end stops the run with a penetration blow-up; the check says so before
//! the run.
//!
//! A tensioner arm's shoe is looked at the same way, as it stands at rest
//! ([`shoe_face`]): a chain longer than the arm's shoe takes up (a worn
//! chain, the arm turned in until the strand runs over the shoe's end) rests
//! with a roller behind the shoe's end.
//!
//! What this does not do: follow the strand as it moves (the rest state is
//! taken as the running one), nor the arms as they move in a run.

use crate::geometry::shoe::{Face, Piece};
use crate::scene::Tensioner;

/// How far beyond a free end, in pitches, a roller is taken as the next to
/// reach it.
const BEYOND_PITCHES: f64 = 1.0;

/// A roller at rest behind a guide's entry.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BehindEntry {
    /// The guide's index in the scene, 0-based.
    pub guide: usize,
    /// "start" or "end": the end of the guide (`start_m` or `end_m`).
    pub end: &'static str,
    /// Whether that end has a ramp.
    pub ramp: bool,
    /// The roller, 0-based.
    pub roller: usize,
    /// The depth at which it would meet the face: the roller radius less
    /// its centre's signed distance from the end's line, m.
    pub depth_m: f64,
}

/// A face's free end: the point, its outward unit direction and the unit
/// normal towards the working side, and whether a ramp ends there.
type FreeEnd = ([f64; 2], [f64; 2], [f64; 2], bool);

/// A face's two free ends, its start's first.
fn free_ends(face: &Face) -> [FreeEnd; 2] {
    let unit = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let n = dx.hypot(dy).max(f64::MIN_POSITIVE);
        [dx / n, dy / n]
    };
    let (p0, p1) = face.body.ends();
    // Two points along the body near each end give its end directions.
    let near0 = face.body.point_at(1e-6);
    let near1 = face.body.point_at(1.0 - 1e-6);
    let start = match face.start_ramp {
        Some(Piece::Segment { a, b }) => (a, unit(b, a), true),
        _ => (p0, unit(near0, p0), false),
    };
    let end = match face.end_ramp {
        Some(Piece::Segment { a, b }) => (b, unit(a, b), true),
        _ => (p1, unit(near1, p1), false),
    };
    // The face runs start → end; its working side is `side` times its
    // left normal: for the start the running direction is −outward.
    let left = |d: [f64; 2]| [-d[1], d[0]];
    let s = face.side;
    let n0 = left([-start.1[0], -start.1[1]]);
    let n1 = left(end.1);
    [
        (start.0, start.1, [s * n0[0], s * n0[1]], start.2),
        (end.0, end.1, [s * n1[0], s * n1[1]], end.2),
    ]
}

/// The shoe of the tensioner arm `arm` turned by `angle_rad` from the
/// scene's pose (counter-clockwise about its pivot), as the arm's force
/// element carries it: its arc, the rollers riding on its outside.
pub(crate) fn shoe_face(arm: &Tensioner, angle_rad: f64) -> Face {
    let (s, c) = angle_rad.sin_cos();
    let [px, py] = arm.pivot_m;
    let r = [arm.shoe_center_m[0] - px, arm.shoe_center_m[1] - py];
    Face::new(
        Piece::Arc {
            center_m: [px + c * r[0] - s * r[1], py + s * r[0] + c * r[1]],
            radius_m: arm.shoe_radius_m,
            start_rad: arm.shoe_start_rad + angle_rad,
            sweep_rad: arm.shoe_span_rad,
        },
        -1.0,
        None,
        None,
    )
}

/// The deepest roller at rest behind a guide's entry (module docs), if one
/// would meet the face deeper than `limit_m`.
pub(crate) fn behind_entry(
    faces: &[Face],
    x: &[f64],
    y: &[f64],
    pitch_m: f64,
    roller_radius_m: f64,
    limit_m: f64,
) -> Option<BehindEntry> {
    let mut worst: Option<BehindEntry> = None;
    for (g, face) in faces.iter().enumerate() {
        for (k, (at, out, normal, ramp)) in free_ends(face).into_iter().enumerate() {
            for (i, (&px, &py)) in x.iter().zip(y).enumerate() {
                let w = [px - at[0], py - at[1]];
                let along = w[0] * out[0] + w[1] * out[1];
                let across = w[0] * normal[0] + w[1] * normal[1];
                // Beyond the end by up to a pitch, and behind the line by
                // at most a pitch (a strand further off is another one).
                if !(along > 0.0 && along <= BEYOND_PITCHES * pitch_m && across > -pitch_m) {
                    continue;
                }
                let depth_m = roller_radius_m - across;
                if depth_m > limit_m && worst.as_ref().is_none_or(|w| depth_m > w.depth_m) {
                    worst = Some(BehindEntry {
                        guide: g,
                        end: if k == 0 { "start" } else { "end" },
                        ramp,
                        roller: i,
                        depth_m,
                    });
                }
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shoe::Ramp;

    /// An arm pivoted at the origin whose shoe (centre (0.1, 0), radius
    /// 0.05 m, from 90° over 90°: its ends at (0.1, 0.05) and (0.05, 0))
    /// is turned by 90° counter-clockwise: the shoe's centre goes to
    /// (0, 0.1) and its ends to (−0.05, 0.1) and (0, 0.05), the arc from
    /// 180° to 270° about the new centre, running +x at its end (the
    /// rollers ride outside it: below the end). A roller of r = 5 mm 10 mm
    /// beyond that end, 3 mm inside the arc's circle (y = 0.1 −
    /// √(0.047² − 0.01²) = 0.054076 m), lies 4.076 mm behind the end's
    /// tangent line y = 0.05: carried onto the shoe it would meet it
    /// r + 4.076 mm deep. At the scene's pose the shoe is far from it.
    #[test]
    fn a_roller_behind_the_end_of_a_turned_shoe_is_found_at_its_depth() {
        use crate::scene::{SpringTensioner, TensionerKind};
        let arm = Tensioner {
            name: "arm".into(),
            pivot_m: [0.0, 0.0],
            inertia_kg_m2: 1e-3,
            mass_kg: 0.0,
            center_of_mass_m: [0.0, 0.0],
            shoe_center_m: [0.1, 0.0],
            shoe_radius_m: 0.05,
            shoe_start_rad: std::f64::consts::FRAC_PI_2,
            shoe_span_rad: std::f64::consts::FRAC_PI_2,
            shoe_friction: 0.0,
            shoe_friction_speed_m_s: 0.01,
            point_m: [0.05, 0.0],
            direction: [0.0, 1.0],
            kind: TensionerKind::Spring(SpringTensioner {
                preload_n: 10.0,
                stiffness_n_m: 1e3,
                damping_n_s_m: 0.0,
                min_travel_m: -0.01,
                max_travel_m: 0.01,
                stop_stiffness_n_m: 1e6,
            }),
        };
        let face = shoe_face(&arm, std::f64::consts::FRAC_PI_2);
        let (a, b) = face.body.ends();
        for (got, want) in [(a, [-0.05, 0.1]), (b, [0.0, 0.05])] {
            approx::assert_abs_diff_eq!(got[0], want[0], epsilon = 1e-12);
            approx::assert_abs_diff_eq!(got[1], want[1], epsilon = 1e-12);
        }
        // 3 mm inside the circle of radius 0.05 about (0, 0.1), 10 mm along +x.
        let roller = [0.01, 0.1 - (0.047f64.powi(2) - 0.01f64.powi(2)).sqrt()];
        let found =
            behind_entry(&[face], &[roller[0]], &[roller[1]], 0.0159, 0.005, 0.005).expect("found");
        assert_eq!((found.end, found.ramp, found.roller), ("end", false, 0));
        // The depth is measured from the end's tangent line (y = 0.05),
        // which `free_ends` takes from a chord 10⁻⁶ of the arc long: its
        // direction is off by half that chord's angle (0.8 µrad), 8 nm
        // over the roller's 10 mm.
        approx::assert_relative_eq!(
            found.depth_m,
            0.005 + (roller[1] - 0.05),
            max_relative = 1e-5
        );
        approx::assert_abs_diff_eq!(found.depth_m, 0.009076, epsilon = 1e-6);
        let unturned = shoe_face(&arm, 0.0);
        assert_eq!(
            behind_entry(
                &[unturned],
                &[roller[0]],
                &[roller[1]],
                0.0159,
                0.005,
                0.005
            ),
            None
        );
    }

    #[test]
    fn a_roller_sagging_behind_a_ramps_tip_is_found_at_its_depth() {
        // A straight guide from (0, 0) to (1, 0) working upwards (+y: the
        // left of start → end, side +1), a ramp of 10 mm at 10° at its
        // start: the tip is at (−0.01 cos 10°, −0.01 sin 10°), its outward
        // direction (−cos 10°, −sin 10°), the working normal (−sin 10°,
        // cos 10°). A roller of r = 5 mm, 4 mm beyond the tip along it and
        // 3 mm behind its line would meet the face r + 3 mm = 8 mm deep.
        let face = Face::new(
            Piece::Segment {
                a: [0.0, 0.0],
                b: [1.0, 0.0],
            },
            1.0,
            Some(Ramp {
                length_m: 0.01,
                angle_rad: 10f64.to_radians(),
            }),
            None,
        );
        let (s, c) = 10f64.to_radians().sin_cos();
        let tip = [-0.01 * c, -0.01 * s];
        let (out, normal) = ([-c, -s], [-s, c]);
        let at = |along: f64, across: f64| {
            [
                tip[0] + along * out[0] + across * normal[0],
                tip[1] + along * out[1] + across * normal[1],
            ]
        };
        let sagging = at(0.004, -0.003);
        let riding = at(-0.004, 0.005);
        let x = [riding[0], sagging[0]];
        let y = [riding[1], sagging[1]];
        let found = behind_entry(&[face], &x, &y, 0.0159, 0.005, 0.005).expect("found");
        assert_eq!(
            (found.guide, found.end, found.ramp, found.roller),
            (0, "start", true, 1)
        );
        approx::assert_relative_eq!(found.depth_m, 0.008, max_relative = 1e-9);
        // A limit above that depth: nothing to report; a roller on the
        // working side of the line is never reported.
        assert_eq!(behind_entry(&[face], &x, &y, 0.0159, 0.005, 0.0081), None);
        let clear = at(0.004, 0.001);
        assert_eq!(
            behind_entry(&[face], &[clear[0]], &[clear[1]], 0.0159, 0.005, 0.005),
            None
        );
    }
}
