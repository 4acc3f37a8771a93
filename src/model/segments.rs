//! Which links belong to which free strand ("segment"), and the strands'
//! transverse displacement — the definitions every output shares:
//!
//! - a link is in segment k's free strand when neither of its rollers touches
//!   a sprocket and its midpoint projects onto strand k's nominal line between
//!   the tangent points (the nearest such strand, within 0.25 m of its line);
//! - segment k's transverse displacement is the signed perpendicular distance,
//!   from the nominal line, of the roller nearest the line's middle; positive
//!   to the left of the direction from `from` to `to` (docs/model.md, “Segment
//!   link force and transverse displacement”).

use crate::geometry::ChainPath;

/// The nominal strand lines, prepared for classification.
#[derive(Clone, Debug)]
pub struct Segments {
    lines: Vec<Line>,
}

#[derive(Clone, Copy, Debug)]
struct Line {
    start: [f64; 2],
    dir: [f64; 2],
    length: f64,
    mid: [f64; 2],
}

/// Largest perpendicular distance of a free link's midpoint from its strand line, m.
/// Free strands vibrate by millimetres to centimetres; a link is given to the
/// nearest strand line within this distance.
const MAX_OFFSET_M: f64 = 0.25;

impl Segments {
    /// From the nominal path.
    pub fn new(path: &ChainPath) -> Self {
        Self {
            lines: path
                .strands
                .iter()
                .map(|s| {
                    let dir = s.direction();
                    Line {
                        start: s.start_m,
                        dir,
                        length: s.length_m,
                        mid: [
                            0.5 * (s.start_m[0] + s.end_m[0]),
                            0.5 * (s.start_m[1] + s.end_m[1]),
                        ],
                    }
                })
                .collect(),
        }
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// The segment whose free strand holds the link from `a` to `b`, if any
    /// (the caller checks that neither roller touches a sprocket).
    pub fn segment_of(&self, a: [f64; 2], b: [f64; 2]) -> Option<usize> {
        let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        // The nearest strand line whose span the midpoint projects onto (strands
        // of a small drive can lie closer together than MAX_OFFSET_M).
        let mut best: Option<(usize, f64)> = None;
        for (k, l) in self.lines.iter().enumerate() {
            let d = [m[0] - l.start[0], m[1] - l.start[1]];
            let along = d[0] * l.dir[0] + d[1] * l.dir[1];
            let across = (-d[0] * l.dir[1] + d[1] * l.dir[0]).abs();
            if (0.0..=l.length).contains(&along)
                && across < MAX_OFFSET_M
                && best.is_none_or(|(_, a)| across < a)
            {
                best = Some((k, across));
            }
        }
        best.map(|(k, _)| k)
    }

    /// Mean link force of each segment's free strand; NaN-free: a segment with
    /// no free link gets `None`.
    pub fn mean_forces(
        &self,
        x: &[f64],
        y: &[f64],
        link_force: &[f64],
        touching: &[bool],
        out: &mut [Option<f64>],
    ) {
        let n = x.len();
        let mut sum = [0.0f64; 32];
        let mut count = [0usize; 32];
        let k_max = self.lines.len().min(32);
        for i in 0..n {
            let j = if i + 1 == n { 0 } else { i + 1 };
            if touching[i] || touching[j] {
                continue;
            }
            if let Some(k) = self.segment_of([x[i], y[i]], [x[j], y[j]])
                && k < k_max
            {
                sum[k] += link_force[i];
                count[k] += 1;
            }
        }
        for (k, o) in out.iter_mut().enumerate().take(k_max) {
            *o = (count[k] > 0).then(|| sum[k] / count[k] as f64);
        }
    }

    /// Signed transverse displacement of segment `k`: the roller nearest the
    /// middle of the nominal line, its distance from the line (left positive).
    pub fn transverse(&self, k: usize, x: &[f64], y: &[f64]) -> f64 {
        let l = &self.lines[k];
        let mut best = (f64::INFINITY, 0.0);
        for (xi, yi) in x.iter().zip(y) {
            let d = [xi - l.mid[0], yi - l.mid[1]];
            let dist_sq = d[0] * d[0] + d[1] * d[1];
            if dist_sq < best.0 {
                best = (dist_sq, -d[0] * l.dir[1] + d[1] * l.dir[0]);
            }
        }
        best.1
    }
}
