//! The exact pieces of the outline (arcs and segments of one gap), their closest-point
//! rule and the ownership joints between patches.

use std::f64::consts::PI;

use super::dimensions::{AsaDimensions, GapPoints};
use crate::geometry::v2::{
    V2, add, dot, mirror, neg, norm, polar, right_normal, scale, sub, unit_or, wrap_pi,
};

/// Ownership test at a joint shared by two patches: the piece *before* the joint (in walk
/// order) owns the points with (p − point)·tangent < 0, the piece after it the others.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Joint {
    /// The joint point.
    pub(super) point: V2,
    /// Unit walk direction at the joint.
    pub(super) tangent: V2,
}

impl Joint {
    /// Signed distance of `p` along the tangent, measured from the joint.
    pub(super) fn side(&self, p: V2) -> f64 {
        dot(sub(p, self.point), self.tangent)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
/// Geometry of one piece.
pub(super) enum Shape {
    /// Circular arc walked from `start_rad` through `sweep_rad` (> 0: counter-clockwise about
    /// the centre = convex; < 0: clockwise = concave).
    Arc {
        /// Centre of the circle.
        centre: V2,
        /// Radius of the circle.
        radius_m: f64,
        /// Polar angle of the start point about the centre.
        start_rad: f64,
        /// Signed sweep from the start point to the end point.
        sweep_rad: f64,
    },
    /// Straight segment from `start` to `end`.
    Segment,
}

/// One piece of the outline in some gap-local frame, with its walk-order end points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Piece {
    /// Arc or segment.
    pub(super) shape: Shape,
    /// Start point (walk order).
    pub(super) start: V2,
    /// End point (walk order).
    pub(super) end: V2,
    /// Area 1..=7.
    pub(super) area: u8,
    /// Gap of this piece relative to the frame it is expressed in (−1, 0, +1).
    pub(super) gap_offset: i64,
    /// Shared joint at the start: the piece owns points with side ≥ 0.
    pub(super) start_joint: Option<Joint>,
    /// Shared joint at the end: the piece owns points with side < 0.
    pub(super) end_joint: Option<Joint>,
    /// At a convex corner (the tooth tip), the direction that decides the sign of the
    /// distance to that end point (the tooth centreline, outward), per end.
    pub(super) corner_normal: [Option<V2>; 2],
}

/// Result of the closest-point query on one piece (piece-local frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Hit {
    /// Unsigned distance.
    pub(super) dist_m: f64,
    /// Signed distance, positive on the free side.
    pub(super) sd_m: f64,
    /// Closest point.
    pub(super) point: V2,
    /// Unit free-side normal (towards `p` when `p` is in free space).
    pub(super) normal: V2,
    /// Area of the piece.
    pub(super) area: u8,
    /// Gap of the piece relative to the evaluating gap.
    pub(super) gap_offset: i64,
    /// False when the point lies beyond a joint shared with another patch.
    pub(super) owned: bool,
}

impl Piece {
    /// An arc piece; end points from the arc formula (overwritten by shared joints later).
    pub(super) fn arc(
        centre: V2,
        radius_m: f64,
        start_rad: f64,
        sweep_rad: f64,
        area: u8,
    ) -> Piece {
        Piece {
            shape: Shape::Arc {
                centre,
                radius_m,
                start_rad,
                sweep_rad,
            },
            start: add(centre, scale(polar(start_rad), radius_m)),
            end: add(centre, scale(polar(start_rad + sweep_rad), radius_m)),
            area,
            gap_offset: 0,
            start_joint: None,
            end_joint: None,
            corner_normal: [None, None],
        }
    }

    /// A straight piece from `start` to `end`.
    pub(super) fn segment(start: V2, end: V2, area: u8) -> Piece {
        Piece {
            shape: Shape::Segment,
            start,
            end,
            area,
            gap_offset: 0,
            start_joint: None,
            end_joint: None,
            corner_normal: [None, None],
        }
    }

    /// Unit tangent in walk direction at the start (`at_end == false`) or the end.
    pub(super) fn tangent(&self, at_end: bool) -> V2 {
        match self.shape {
            Shape::Arc {
                start_rad,
                sweep_rad,
                ..
            } => {
                let a = if at_end {
                    start_rad + sweep_rad
                } else {
                    start_rad
                };
                let t = [-a.sin(), a.cos()];
                if sweep_rad > 0.0 { t } else { neg(t) }
            }
            Shape::Segment => unit_or(sub(self.end, self.start), [1.0, 0.0]),
        }
    }

    /// Unit free-side normal at the start or the end.
    pub(super) fn free_normal(&self, at_end: bool) -> V2 {
        right_normal(self.tangent(at_end))
    }

    /// False when `p` lies beyond a shared joint at either end.
    pub(super) fn owns(&self, p: V2) -> bool {
        let after_start = self.start_joint.is_none_or(|j| j.side(p) >= 0.0);
        let before_end = self.end_joint.is_none_or(|j| j.side(p) < 0.0);
        after_start && before_end
    }

    /// A hit of this piece.
    pub(super) fn hit(&self, sd_m: f64, point: V2, normal: V2, owned: bool) -> Hit {
        Hit {
            dist_m: sd_m.abs(),
            sd_m,
            point,
            normal,
            area: self.area,
            gap_offset: self.gap_offset,
            owned,
        }
    }

    /// Closest point of this piece to `p`: the foot of the perpendicular when it falls on
    /// the span, otherwise the nearer end point.
    pub(super) fn closest(&self, p: V2) -> Hit {
        let owned = self.owns(p);
        match self.shape {
            Shape::Arc {
                centre,
                radius_m,
                start_rad,
                sweep_rad,
            } => {
                let mid = start_rad + 0.5 * sweep_rad;
                let d = sub(p, centre);
                let r = norm(d);
                let dir = unit_or(d, polar(mid));
                let angle = dir[1].atan2(dir[0]);
                if wrap_pi(angle - mid).abs() <= 0.5 * sweep_rad.abs() {
                    let point = add(centre, scale(dir, radius_m));
                    if sweep_rad > 0.0 {
                        self.hit(r - radius_m, point, dir, owned)
                    } else {
                        self.hit(radius_m - r, point, neg(dir), owned)
                    }
                } else {
                    self.end_point_hit(p, owned)
                }
            }
            Shape::Segment => {
                let e = sub(self.end, self.start);
                let l2 = dot(e, e);
                let t = if l2 > 0.0 {
                    dot(sub(p, self.start), e) / l2
                } else {
                    -1.0
                };
                if (0.0..=1.0).contains(&t) {
                    let n = self.free_normal(false);
                    let sd = dot(sub(p, self.start), n);
                    self.hit(sd, add(self.start, scale(e, t)), n, owned)
                } else {
                    self.end_point_hit(p, owned)
                }
            }
        }
    }

    /// Hit at the nearer end point; the sign is taken from the end's free normal (or the
    /// tip's centreline direction at a convex corner).
    pub(super) fn end_point_hit(&self, p: V2, owned: bool) -> Hit {
        let to_start = norm(sub(p, self.start));
        let to_end = norm(sub(p, self.end));
        let at_end = to_end < to_start;
        let q = if at_end { self.end } else { self.start };
        let n_free = self.free_normal(at_end);
        let n_sign = self.corner_normal[usize::from(at_end)].unwrap_or(n_free);
        let v = sub(p, q);
        let d = norm(v);
        let sign = if dot(v, n_sign) >= 0.0 { 1.0 } else { -1.0 };
        let normal = if d > 0.0 {
            [sign * v[0] / d, sign * v[1] / d]
        } else {
            n_free
        };
        self.hit(sign * d, q, normal, owned)
    }

    /// The same piece after a map of the gap-local frame that rotates directions by
    /// `rotate_rad` (points mapped with `map`).
    pub(super) fn mapped(&self, map: impl Fn(V2) -> V2, rotate_rad: f64, gap_offset: i64) -> Piece {
        let (s, c) = rotate_rad.sin_cos();
        let rot = |v: V2| [c * v[0] - s * v[1], s * v[0] + c * v[1]];
        let joint = |j: Joint| Joint {
            point: map(j.point),
            tangent: rot(j.tangent),
        };
        let shape = match self.shape {
            Shape::Arc {
                centre,
                radius_m,
                start_rad,
                sweep_rad,
            } => Shape::Arc {
                centre: map(centre),
                radius_m,
                start_rad: start_rad + rotate_rad,
                sweep_rad,
            },
            Shape::Segment => Shape::Segment,
        };
        Piece {
            shape,
            start: map(self.start),
            end: map(self.end),
            area: self.area,
            gap_offset,
            start_joint: self.start_joint.map(joint),
            end_joint: self.end_joint.map(joint),
            corner_normal: self.corner_normal.map(|n| n.map(rot)),
        }
    }

    /// Samples from the start (inclusive) to the end (exclusive).
    pub(super) fn sample(&self, max_step_rad: f64, straight_step_m: f64, out: &mut Vec<V2>) {
        match self.shape {
            Shape::Arc {
                centre,
                radius_m,
                start_rad,
                sweep_rad,
            } => {
                let n = steps(sweep_rad.abs() / max_step_rad);
                out.push(self.start);
                for k in 1..n {
                    let a = start_rad + sweep_rad * (k as f64 / n as f64);
                    out.push(add(centre, scale(polar(a), radius_m)));
                }
            }
            Shape::Segment => {
                let e = sub(self.end, self.start);
                let n = steps(norm(e) / straight_step_m);
                for k in 0..n {
                    out.push(add(self.start, scale(e, k as f64 / n as f64)));
                }
            }
        }
    }
}

/// Number of sub-steps for a ratio span/step (at least 1, bounded).
pub(super) fn steps(ratio: f64) -> usize {
    if ratio.is_finite() && ratio > 1.0 {
        ratio.ceil().min(1e7) as usize
    } else {
        1
    }
}

/// The hit with the smallest distance (the first on a tie).
#[cfg(any(test, doc))]
pub(super) fn nearest_hit(hits: &[Hit; 8]) -> Hit {
    let mut best = hits[0];
    for &h in &hits[1..] {
        if h.dist_m < best.dist_m {
            best = h;
        }
    }
    best
}

/// The eight pieces of one gap in walk order 7, 6, 5, 4 (ξ ≥ 0 half), 4 (ξ ≤ 0 half), 3,
/// 2, 1, with the ownership joints z (7|6), seat bottom (4|4) and z* (2|1).
pub(super) fn gap_pieces(d: &AsaDimensions, g: &GapPoints) -> [Piece; 8] {
    let (a, b) = (d.a_rad, d.b_rad);
    let half_seat = 0.5 * (PI - 2.0 * a);
    let mut p = [
        Piece::arc(
            g.b_m,
            d.topping_radius_m,
            g.theta_1b_rad,
            g.topping_sweep_rad,
            7,
        ),
        Piece::segment(g.z_m, g.y_m, 6),
        Piece::arc(g.c_m, d.working_radius_m, 2.0 * PI - a + b, -b, 5),
        Piece::arc([0.0, 0.0], d.seating_radius_m, -a, -half_seat, 4),
        Piece::arc([0.0, 0.0], d.seating_radius_m, -0.5 * PI, -half_seat, 4),
        Piece::arc(mirror(g.c_m), d.working_radius_m, PI + a, -b, 3),
        Piece::segment(mirror(g.y_m), mirror(g.z_m), 2),
        Piece::arc(
            mirror(g.b_m),
            d.topping_radius_m,
            g.theta_1b_star_rad,
            g.topping_sweep_rad,
            1,
        ),
    ];
    // Share the exact joint coordinates between neighbouring pieces.
    p[0].start = g.f_m;
    p[0].end = g.z_m;
    p[2].start = g.y_m;
    p[2].end = g.x_m;
    p[3].start = g.x_m;
    p[3].end = [0.0, -d.seating_radius_m];
    p[4].start = [0.0, -d.seating_radius_m];
    p[4].end = mirror(g.x_m);
    p[5].start = mirror(g.x_m);
    p[5].end = mirror(g.y_m);
    p[7].start = mirror(g.z_m);
    p[7].end = mirror(g.f_m);
    let joints = [
        (
            0,
            Joint {
                point: g.z_m,
                tangent: p[1].tangent(false),
            },
        ),
        (
            3,
            Joint {
                point: [0.0, -d.seating_radius_m],
                tangent: [-1.0, 0.0],
            },
        ),
        (
            6,
            Joint {
                point: mirror(g.z_m),
                tangent: p[6].tangent(true),
            },
        ),
    ];
    // The tips are convex corners on the tooth centrelines through the sprocket centre.
    let tip_normal = unit_or(sub(g.f_m, [0.0, -d.pitch_radius_m]), [0.0, 1.0]);
    p[0].corner_normal[0] = Some(tip_normal);
    p[7].corner_normal[1] = Some(mirror(tip_normal));
    for (i, j) in joints {
        p[i].end_joint = Some(j);
        p[i + 1].start_joint = Some(j);
    }
    p
}

/// Map of gap (offset k) local coordinates into gap 0's local coordinates.
pub(super) fn neighbour_map(rs: f64, pitch_angle_rad: f64, k: i64) -> impl Fn(V2) -> V2 {
    let (s, c) = (pitch_angle_rad * k as f64).sin_cos();
    move |q: V2| {
        // local k -> sprocket frame (gap k at polar angle kΦ)
        let r = rs + q[1];
        let x = r * c + q[0] * s;
        let y = r * s - q[0] * c;
        // sprocket frame -> local 0
        [-y, x - rs]
    }
}
