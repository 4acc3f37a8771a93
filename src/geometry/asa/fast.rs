//! The trig-free form of the pieces used by the hot path of the contact query.

use super::TIE_M;
use super::pieces::{Joint, Piece, Shape};
#[cfg(doc)]
use super::{AsaProfile, pieces::nearest_hit};
use crate::geometry::v2::{V2, add, dot, neg, norm, polar, scale, sub, unit_or};

/// Trig-free form of one [`Piece`] for the hot path of [`AsaProfile::contacts`]: the same
/// closest-point rule as [`Piece::closest`], with the angular window tested by dot and cross
/// products against the precomputed bisector, and the end normals precomputed. It also
/// carries a cheap, conservative "farther than the radius" test used to skip the piece.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FastPiece {
    /// True for an arc, false for a segment.
    pub(super) is_arc: bool,
    /// True for a convex arc (sweep > 0).
    pub(super) convex: bool,
    /// Arc centre (arcs) or start point (segments).
    pub(super) centre: V2,
    /// Arc radius (0 for segments).
    pub(super) radius_m: f64,
    /// Unit bisector of the arc's angular window, `polar(start + sweep/2)`.
    pub(super) mid_dir: V2,
    /// tan of the half-sweep (< π/2).
    pub(super) tan_half: f64,
    /// Start point (walk order).
    pub(super) start: V2,
    /// End point (walk order).
    pub(super) end: V2,
    /// Segment vector end − start.
    pub(super) e: V2,
    /// |e|².
    pub(super) l2: f64,
    /// Free normals at the start and the end.
    pub(super) n_free: [V2; 2],
    /// Directions that decide the sign at the start and the end point.
    pub(super) n_sign: [V2; 2],
    /// Shared joint at the start (owns side ≥ 0).
    pub(super) start_joint: Option<Joint>,
    /// Shared joint at the end (owns side < 0).
    pub(super) end_joint: Option<Joint>,
    /// Area 1..=7.
    pub(super) area: u8,
    /// Gap of this piece relative to the evaluating gap.
    pub(super) gap_offset: i64,
}

/// Closest-point result of a [`FastPiece`] without the point and normal, which are only
/// computed ([`FastPiece::geometry`]) for the patches reported.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Near {
    /// Unsigned distance.
    pub(super) dist_m: f64,
    /// Signed distance, positive on the free side.
    pub(super) sd_m: f64,
    /// False when the point lies beyond a joint shared with another patch.
    pub(super) owned: bool,
    /// Index of the piece in [`AsaProfile::fast`].
    pub(super) piece: u8,
    /// Which rule gave the closest point: [`FOOT`], [`AT_START`] or [`AT_END`].
    pub(super) mode: u8,
}

/// One patch in gap-local form, before it is written in the sprocket frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Found {
    /// Penetration depth r − sd, > 0.
    pub(super) depth_m: f64,
    /// Unit free-side normal, gap-local.
    pub(super) normal: V2,
    /// Closest outline point, gap-local.
    pub(super) point: V2,
    /// Area 1..=7.
    pub(super) area: u8,
    /// Gap of the piece relative to the evaluating gap (−1, 0, +1).
    pub(super) gap_offset: i64,
    /// Patch id (see the module docs).
    pub(super) patch_id: u32,
}

/// An unused [`Found`] slot.
pub(super) const NONE: Found = Found {
    depth_m: 0.0,
    normal: [0.0; 2],
    point: [0.0; 2],
    area: 0,
    gap_offset: 0,
    patch_id: 0,
};

/// The closest point is the foot of the perpendicular.
pub(super) const FOOT: u8 = 0;
/// The closest point is the start point.
pub(super) const AT_START: u8 = 1;
/// The closest point is the end point.
pub(super) const AT_END: u8 = 2;

/// A result that is never the nearest and never in contact (a skipped, provably far piece).
pub(super) const FAR: Near = Near {
    dist_m: f64::INFINITY,
    sd_m: f64::INFINITY,
    owned: false,
    piece: 0,
    mode: FOOT,
};

impl FastPiece {
    /// The trig-free form of `piece`.
    pub(super) fn new(piece: &Piece) -> FastPiece {
        let n_free = [piece.free_normal(false), piece.free_normal(true)];
        let n_sign = [
            piece.corner_normal[0].unwrap_or(n_free[0]),
            piece.corner_normal[1].unwrap_or(n_free[1]),
        ];
        let e = sub(piece.end, piece.start);
        let (is_arc, convex, centre, radius_m, mid_dir, tan_half) = match piece.shape {
            Shape::Arc {
                centre,
                radius_m,
                start_rad,
                sweep_rad,
            } => (
                true,
                sweep_rad > 0.0,
                centre,
                radius_m,
                polar(start_rad + 0.5 * sweep_rad),
                (0.5 * sweep_rad.abs()).tan(),
            ),
            Shape::Segment => (false, false, piece.start, 0.0, [1.0, 0.0], 0.0),
        };
        FastPiece {
            is_arc,
            convex,
            centre,
            radius_m,
            mid_dir,
            tan_half,
            start: piece.start,
            end: piece.end,
            e,
            l2: dot(e, e),
            n_free,
            n_sign,
            start_joint: piece.start_joint,
            end_joint: piece.end_joint,
            area: piece.area,
            gap_offset: piece.gap_offset,
        }
    }

    /// True when `p` is provably farther than `reach` from the piece: farther than `reach`
    /// from its whole circle (arcs) or line (segments).
    #[inline(always)]
    pub(super) fn is_far(&self, p: V2, reach: f64) -> bool {
        if self.is_arc {
            let d = sub(p, self.centre);
            let r2 = dot(d, d);
            let outer = self.radius_m + reach;
            let inner = self.radius_m - reach;
            r2 > outer * outer || (inner > 0.0 && r2 < inner * inner)
        } else {
            dot(sub(p, self.start), self.n_free[0]).abs() > reach
        }
    }

    /// [`FastPiece::near`], or [`FAR`] when the piece is farther than `reach`.
    #[inline(always)]
    pub(super) fn eval(&self, p: V2, reach: f64, piece: u8) -> Near {
        if self.is_far(p, reach) {
            FAR
        } else {
            self.near(p, piece)
        }
    }

    /// False when `p` lies beyond a shared joint at either end.
    #[inline(always)]
    pub(super) fn owns(&self, p: V2) -> bool {
        let after_start = self.start_joint.is_none_or(|j| j.side(p) >= 0.0);
        let before_end = self.end_joint.is_none_or(|j| j.side(p) < 0.0);
        after_start && before_end
    }

    /// Distance part of [`Piece::closest`] (same rule, to rounding): the foot of the
    /// perpendicular when it falls on the span, otherwise the nearer end point.
    #[inline(always)]
    pub(super) fn near(&self, p: V2, piece: u8) -> Near {
        let owned = self.owns(p);
        if self.is_arc {
            let d = sub(p, self.centre);
            let r = dot(d, d).sqrt();
            let in_window = if r > 0.0 && r.is_finite() {
                let along = dot(d, self.mid_dir);
                let across = d[0] * self.mid_dir[1] - d[1] * self.mid_dir[0];
                along >= 0.0 && across.abs() <= self.tan_half * along
            } else {
                true
            };
            if in_window {
                let sd_m = if self.convex {
                    r - self.radius_m
                } else {
                    self.radius_m - r
                };
                return Near {
                    dist_m: sd_m.abs(),
                    sd_m,
                    owned,
                    piece,
                    mode: FOOT,
                };
            }
        } else {
            let v = sub(p, self.start);
            let t = self.segment_t(v);
            if (0.0..=1.0).contains(&t) {
                let sd_m = dot(v, self.n_free[0]);
                return Near {
                    dist_m: sd_m.abs(),
                    sd_m,
                    owned,
                    piece,
                    mode: FOOT,
                };
            }
        }
        // Nearer end point; the sign from the end's free normal (or the tip centreline).
        let vs = sub(p, self.start);
        let ve = sub(p, self.end);
        let (ds2, de2) = (dot(vs, vs), dot(ve, ve));
        let at_end = de2 < ds2;
        let (v, d2) = if at_end { (ve, de2) } else { (vs, ds2) };
        let d = d2.sqrt();
        let sd_m = if dot(v, self.n_sign[usize::from(at_end)]) >= 0.0 {
            d
        } else {
            -d
        };
        Near {
            dist_m: d,
            sd_m,
            owned,
            piece,
            mode: if at_end { AT_END } else { AT_START },
        }
    }

    /// Parameter of the foot of the perpendicular on a segment (−1 when degenerate).
    #[inline(always)]
    pub(super) fn segment_t(&self, v: V2) -> f64 {
        if self.l2 > 0.0 {
            dot(v, self.e) / self.l2
        } else {
            -1.0
        }
    }

    /// Closest point and unit free-side normal for the rule `mode` found by
    /// [`FastPiece::near`] (the point and normal of [`Piece::closest`], to rounding).
    pub(super) fn geometry(&self, p: V2, mode: u8) -> (V2, V2) {
        if mode == FOOT {
            if self.is_arc {
                let d = sub(p, self.centre);
                let r = dot(d, d).sqrt();
                let dir = if r > 0.0 && r.is_finite() {
                    [d[0] / r, d[1] / r]
                } else {
                    self.mid_dir
                };
                let point = add(self.centre, scale(dir, self.radius_m));
                (point, if self.convex { dir } else { neg(dir) })
            } else {
                let t = self.segment_t(sub(p, self.start));
                (add(self.start, scale(self.e, t)), self.n_free[0])
            }
        } else {
            let k = usize::from(mode == AT_END);
            let q = if mode == AT_END { self.end } else { self.start };
            let v = sub(p, q);
            let d = dot(v, v).sqrt();
            let sign = if dot(v, self.n_sign[k]) >= 0.0 {
                1.0
            } else {
                -1.0
            };
            let normal = if d > 0.0 {
                [sign * v[0] / d, sign * v[1] / d]
            } else {
                self.n_free[k]
            };
            (q, normal)
        }
    }
}

/// Closest owned point of a patch, from the results of its pieces: `None` when the nearest
/// point of the run lies beyond one of its shared joints (it then belongs to the
/// neighbouring patch). On a tie (within [`TIE_M`], e.g. both toppings at the tip) the
/// earlier piece wins. The reference implementation's `patch_hit` for [`Near`] results.
#[inline(always)]
pub(super) fn patch_near(hits: &[Near]) -> Option<Near> {
    let mut best: Option<Near> = None;
    for &h in hits {
        match best {
            Some(b) if b.dist_m <= h.dist_m + TIE_M => {}
            _ => best = Some(h),
        }
    }
    best.filter(|h| h.owned)
}

/// The result with the smallest distance (the first on a tie): [`nearest_hit`] for [`Near`]
/// results.
#[inline(always)]
pub(super) fn nearest_near(hits: &[Near; 8]) -> Near {
    let mut best = hits[0];
    for &h in &hits[1..] {
        if h.dist_m < best.dist_m {
            best = h;
        }
    }
    best
}

/// Keeps the two deepest (largest r − sd, i.e. smallest sd) candidates, deepest first: the
/// reference implementation's `insert_deepest` for [`Near`] results.
#[inline(always)]
pub(super) fn insert_deepest_near(best: &mut [Option<(Near, u32)>; 2], c: (Near, u32)) {
    let deeper = |a: &(Near, u32), b: &Option<(Near, u32)>| b.is_none_or(|b| a.0.sd_m < b.0.sd_m);
    if deeper(&c, &best[0]) {
        best[1] = best[0];
        best[0] = Some(c);
    } else if deeper(&c, &best[1]) {
        best[1] = Some(c);
    }
}

/// Largest distance from `s` to the piece `f` (an arc's farthest point from `s` is on the ray
/// from `s` through the centre when that ray's direction lies in the window, else an end).
pub(super) fn farthest_from(f: &FastPiece, s: V2) -> f64 {
    let ends = norm(sub(f.start, s)).max(norm(sub(f.end, s)));
    if !f.is_arc {
        return ends;
    }
    let w = unit_or(sub(f.centre, s), f.mid_dir);
    let along = dot(w, f.mid_dir);
    let across = w[0] * f.mid_dir[1] - w[1] * f.mid_dir[0];
    if along >= 0.0 && across.abs() <= f.tan_half * along {
        ends.max(norm(sub(f.centre, s)) + f.radius_m)
    } else {
        ends
    }
}
