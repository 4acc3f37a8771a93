//! A chain that rests behind a fixed guide's entry: a roller just beyond
//! one of the guide's free ends (a ramp's tip, or the body's end where
//! there is no ramp) whose centre lies so far behind the line of that end
//! that, carried onto the guide, it would meet the face at once deeper than
//! the blow-up limit. The strand there sags below the guide (a worn chain
//! on fixed centres gains slack), and the first such roller to reach the
//! end stops the run with a penetration blow-up; the check says so before
//! the run.
//!
//! What this does not do: follow the strand as it moves (the rest state is
//! taken as the running one), or look at the arms' shoes, which move.

use crate::geometry::shoe::{Face, Piece};

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
