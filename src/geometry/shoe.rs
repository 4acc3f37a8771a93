//! Shoes: the working face of a guide bar or of a tensioner arm's shoe, a
//! straight or circular-arc piece with optional straight lead-in ramps at
//! its ends, and the signed distance of a point from it.
//!
//! A face is one-sided: its *working normal* points to the side the rollers
//! run on. A ramp continues the body's end tangent, turned away from the
//! working side by its angle, so a roller arriving along the body's line
//! meets the face gradually. Plain arithmetic on `[f64; 2]` points: no
//! forces, no pose (a carried shoe is queried in its own frame).

use std::f64::consts::PI;

use super::v2::{dot, norm_sqrt, sub};
/// One piece of a face: a segment or a circular arc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Piece {
    /// The segment from `a` to `b`.
    Segment {
        /// Start, m.
        a: [f64; 2],
        /// End, m.
        b: [f64; 2],
    },
    /// The arc of radius `radius_m` about `center_m`, from polar angle
    /// `start_rad` counter-clockwise over `sweep_rad` (> 0).
    Arc {
        /// Centre, m.
        center_m: [f64; 2],
        /// Radius, m (> 0).
        radius_m: f64,
        /// Polar angle of the arc's counter-clockwise-most start, rad.
        start_rad: f64,
        /// Angle swept counter-clockwise, rad, in (0, 2π).
        sweep_rad: f64,
    },
}

/// The closest point of a piece (or face) to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FacePoint {
    /// Signed distance from the face, m: positive on the working side,
    /// negative behind it.
    pub distance_m: f64,
    /// The closest point on the face, m.
    pub point_m: [f64; 2],
    /// Unit normal at the contact, pointing from the face to the working
    /// side (the direction a force pushes a roller out).
    pub normal: [f64; 2],
    /// Which piece: 0 the body, 1 the ramp at the start, 2 the ramp at the end.
    pub piece: usize,
}

impl FacePoint {
    /// The point `c` of the body piece with working normal `n`, as seen from
    /// `p`: the signed distance is the projection of `p − c` on `n`.
    fn at(p: [f64; 2], c: [f64; 2], n: [f64; 2]) -> Self {
        Self {
            distance_m: dot(sub(p, c), n),
            point_m: c,
            normal: n,
            piece: 0,
        }
    }
}

/// Why a face cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub(crate) enum ShoeError {
    /// The end points coincide (or are not finite).
    #[error("the end points coincide")]
    DegenerateEnds,
    /// An arc's radius is shorter than half the chord.
    #[error(
        "the radius {radius_m} m is shorter than half the distance between the end points, {half_chord_m} m"
    )]
    RadiusTooShort {
        /// The radius given, m.
        radius_m: f64,
        /// Half the chord, m.
        half_chord_m: f64,
    },
    /// A centre not equidistant from the end points.
    #[error("the centre is {from_start_m} m from the start and {from_end_m} m from the end")]
    CentreOff {
        /// Distance from the start, m.
        from_start_m: f64,
        /// Distance from the end, m.
        from_end_m: f64,
    },
}

/// Relative tolerance on a given centre's distances from the two ends.
pub(crate) const CENTRE_TOLERANCE: f64 = 1e-6;

/// The body of a shoe from its end points.
///
/// `radius_m`: `None` for a straight shoe; `Some(r)` an arc through both ends
/// of radius |r| (the shorter one), bending to the left of the direction
/// start → end for r > 0 (the centre on the left), to the right for r < 0.
pub(crate) fn body_from_radius(
    start_m: [f64; 2],
    end_m: [f64; 2],
    radius_m: Option<f64>,
) -> Result<Piece, ShoeError> {
    let chord = sub(end_m, start_m);
    let length = norm_sqrt(chord);
    if !(length > 0.0) || !length.is_finite() {
        return Err(ShoeError::DegenerateEnds);
    }
    let Some(r) = radius_m else {
        return Ok(Piece::Segment {
            a: start_m,
            b: end_m,
        });
    };
    let half = 0.5 * length;
    if !(r.abs() >= half) {
        return Err(ShoeError::RadiusTooShort {
            radius_m: r.abs(),
            half_chord_m: half,
        });
    }
    let mid = [0.5 * (start_m[0] + end_m[0]), 0.5 * (start_m[1] + end_m[1])];
    let left = [-chord[1] / length, chord[0] / length];
    let h = (r * r - half * half).max(0.0).sqrt() * r.signum();
    let centre = [mid[0] + h * left[0], mid[1] + h * left[1]];
    Ok(arc_between(centre, start_m, end_m, r.abs()))
}

/// The body of an arc shoe from its end points and centre: the shorter arc
/// between them (a half circle goes counter-clockwise from start to end).
pub(crate) fn body_from_centre(
    start_m: [f64; 2],
    end_m: [f64; 2],
    centre_m: [f64; 2],
) -> Result<Piece, ShoeError> {
    let length = norm_sqrt(sub(end_m, start_m));
    if !(length > 0.0) || !length.is_finite() {
        return Err(ShoeError::DegenerateEnds);
    }
    let (r0, r1) = (
        norm_sqrt(sub(start_m, centre_m)),
        norm_sqrt(sub(end_m, centre_m)),
    );
    if !((r0 - r1).abs() <= CENTRE_TOLERANCE * r0.max(r1)) || !(r0 > 0.0) {
        return Err(ShoeError::CentreOff {
            from_start_m: r0,
            from_end_m: r1,
        });
    }
    Ok(arc_between(centre_m, start_m, end_m, 0.5 * (r0 + r1)))
}

/// The shorter arc about `centre` from `start` to `end`.
fn arc_between(centre: [f64; 2], start: [f64; 2], end: [f64; 2], radius: f64) -> Piece {
    let a0 = (start[1] - centre[1]).atan2(start[0] - centre[0]);
    let a1 = (end[1] - centre[1]).atan2(end[0] - centre[0]);
    let ccw = (a1 - a0).rem_euclid(2.0 * PI);
    let (start_rad, sweep_rad) = if ccw <= PI {
        (a0, ccw)
    } else {
        (a1, 2.0 * PI - ccw)
    };
    Piece::Arc {
        center_m: centre,
        radius_m: radius,
        start_rad,
        sweep_rad,
    }
}

impl Piece {
    /// Its two ends in the order the face runs (an arc given by its
    /// counter-clockwise start first).
    pub(crate) fn ends(&self) -> ([f64; 2], [f64; 2]) {
        match *self {
            Self::Segment { a, b } => (a, b),
            Self::Arc {
                center_m,
                radius_m,
                start_rad,
                sweep_rad,
            } => {
                let at = |phi: f64| {
                    [
                        center_m[0] + radius_m * phi.cos(),
                        center_m[1] + radius_m * phi.sin(),
                    ]
                };
                (at(start_rad), at(start_rad + sweep_rad))
            }
        }
    }

    /// Length, m.
    #[cfg(test)]
    pub(crate) fn length_m(&self) -> f64 {
        match *self {
            Self::Segment { a, b } => norm_sqrt(sub(b, a)),
            Self::Arc {
                radius_m,
                sweep_rad,
                ..
            } => radius_m * sweep_rad,
        }
    }

    /// The point at fraction `s` ∈ [0, 1] of its length from its first end.
    pub(crate) fn point_at(&self, s: f64) -> [f64; 2] {
        match *self {
            Self::Segment { a, b } => [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])],
            Self::Arc {
                center_m,
                radius_m,
                start_rad,
                sweep_rad,
            } => {
                let phi = start_rad + s * sweep_rad;
                [
                    center_m[0] + radius_m * phi.cos(),
                    center_m[1] + radius_m * phi.sin(),
                ]
            }
        }
    }

    /// The closest point of the piece to `p`, whether `p` projects inside
    /// the piece (not onto an end), and the normal there on the `left` side
    /// of the direction first end → second end (`side` = +1) or on the right
    /// (`side` = −1).
    fn closest(&self, p: [f64; 2], side: f64) -> (FacePoint, bool) {
        match *self {
            Self::Segment { a, b } => {
                let ab = sub(b, a);
                let len2 = dot(ab, ab);
                let t = dot(sub(p, a), ab) / len2;
                let inside = (0.0..=1.0).contains(&t);
                let t = t.clamp(0.0, 1.0);
                let c = [a[0] + t * ab[0], a[1] + t * ab[1]];
                let len = len2.sqrt();
                let n = [-side * ab[1] / len, side * ab[0] / len];
                (FacePoint::at(p, c, n), inside)
            }
            Self::Arc {
                center_m,
                radius_m,
                start_rad,
                sweep_rad,
            } => {
                let d = sub(p, center_m);
                let phi = d[1].atan2(d[0]);
                let rel = (phi - start_rad).rem_euclid(2.0 * PI);
                let inside = rel <= sweep_rad;
                let at = if inside {
                    phi
                } else if rel - sweep_rad < 2.0 * PI - rel {
                    start_rad + sweep_rad
                } else {
                    start_rad
                };
                let radial = [at.cos(), at.sin()];
                let c = [
                    center_m[0] + radius_m * radial[0],
                    center_m[1] + radius_m * radial[1],
                ];
                // Going counter-clockwise the left is towards the centre.
                let n = [-side * radial[0], -side * radial[1]];
                (FacePoint::at(p, c, n), inside)
            }
        }
    }

    /// Unit tangent at fraction `s`, in the direction first → second end.
    fn tangent_at(&self, s: f64) -> [f64; 2] {
        match *self {
            Self::Segment { a, b } => {
                let ab = sub(b, a);
                let l = norm_sqrt(ab);
                [ab[0] / l, ab[1] / l]
            }
            Self::Arc {
                start_rad,
                sweep_rad,
                ..
            } => {
                let phi = start_rad + s * sweep_rad;
                [-phi.sin(), phi.cos()]
            }
        }
    }
}

/// A lead-in ramp: a straight piece continuing the body's end tangent,
/// turned away from the working side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ramp {
    /// Length, m (> 0).
    pub length_m: f64,
    /// Angle away from the body's tangent, rad, in (0, π/2).
    pub angle_rad: f64,
}

/// A working face: a body with optional ramps, its working side fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Face {
    /// The body (the shoe proper).
    pub body: Piece,
    /// +1: the working side is on the left of the body's first → second end;
    /// −1: on its right.
    pub side: f64,
    /// The ramp at the body's first end, as a segment from the ramp's free
    /// end to the body's end.
    pub start_ramp: Option<Piece>,
    /// The ramp at the body's second end, from the body's end to its free end.
    pub end_ramp: Option<Piece>,
    /// Axis-aligned bounds of every piece, [min x, min y, max x, max y], m.
    pub bounds_m: [f64; 4],
}

impl Face {
    /// The face of `body` working on `side` (+1 left, −1 right of the body's
    /// direction), with ramps at its first and second ends.
    pub(crate) fn new(body: Piece, side: f64, start: Option<Ramp>, end: Option<Ramp>) -> Self {
        let (p0, p1) = body.ends();
        // Away from the working side: rotate the outward tangent towards the
        // back (−side normal).
        let ramp = |at: [f64; 2], outward: [f64; 2], r: Ramp, turn: f64| {
            let (s, c) = (turn * r.angle_rad).sin_cos();
            let dir = [
                c * outward[0] - s * outward[1],
                s * outward[0] + c * outward[1],
            ];
            [at[0] + r.length_m * dir[0], at[1] + r.length_m * dir[1]]
        };
        let t0 = body.tangent_at(0.0);
        let t1 = body.tangent_at(1.0);
        // With n the body's left normal, the back is −side·n. A turn by +α
        // moves a direction towards its own left normal: −n for the start's
        // outward −t0 (so a turn of +side·α), +n for the end's t1 (−side·α).
        let start_ramp = start.map(|r| Piece::Segment {
            a: ramp(p0, [-t0[0], -t0[1]], r, side),
            b: p0,
        });
        let end_ramp = end.map(|r| Piece::Segment {
            a: p1,
            b: ramp(p1, t1, r, -side),
        });
        let mut bounds = [f64::INFINITY, f64::INFINITY, -f64::INFINITY, -f64::INFINITY];
        let mut grow = |p: [f64; 2]| {
            bounds[0] = bounds[0].min(p[0]);
            bounds[1] = bounds[1].min(p[1]);
            bounds[2] = bounds[2].max(p[0]);
            bounds[3] = bounds[3].max(p[1]);
        };
        for piece in [Some(body), start_ramp, end_ramp].into_iter().flatten() {
            const SAMPLES: usize = 32;
            for k in 0..=SAMPLES {
                grow(piece.point_at(k as f64 / SAMPLES as f64));
            }
        }
        // An arc bulges between samples by at most r (1 − cos(sweep / 64)).
        if let Piece::Arc {
            radius_m,
            sweep_rad,
            ..
        } = body
        {
            let bulge = radius_m * (1.0 - (sweep_rad / 64.0).cos());
            bounds = [
                bounds[0] - bulge,
                bounds[1] - bulge,
                bounds[2] + bulge,
                bounds[3] + bulge,
            ];
        }
        Self {
            body,
            side,
            start_ramp,
            end_ramp,
            bounds_m: bounds,
        }
    }

    /// The signed distance of `p` from the face and the closest point.
    ///
    /// Outside (on the working side of some piece): the distance to the
    /// nearest point of any piece, the normal from it to `p`. Behind every
    /// piece: the piece whose span `p` projects into with the smallest
    /// depth, its face normal (the ramps bend away from the working side, so
    /// the solid behind the face is locally the intersection of the pieces'
    /// back half-planes). `None` behind the face and beyond its ends.
    pub(crate) fn query(&self, p: [f64; 2]) -> Option<FacePoint> {
        let mut outside: Option<FacePoint> = None;
        let mut behind: Option<FacePoint> = None;
        let pieces = [Some(self.body), self.start_ramp, self.end_ramp];
        for (k, piece) in pieces.iter().enumerate() {
            let Some(piece) = piece else { continue };
            let (mut fp, inside) = piece.closest(p, self.side);
            fp.piece = k;
            if fp.distance_m >= 0.0 {
                let d = norm_sqrt(sub(p, fp.point_m));
                if outside.is_none_or(|o| d < o.distance_m) {
                    if d > 0.0 {
                        fp.normal = [(p[0] - fp.point_m[0]) / d, (p[1] - fp.point_m[1]) / d];
                    }
                    fp.distance_m = d;
                    outside = Some(fp);
                }
            } else if inside && behind.is_none_or(|b| fp.distance_m > b.distance_m) {
                behind = Some(fp);
            }
        }
        outside.or(behind)
    }

    /// The face as a [`Straight`] (a segment body without ramps), whose
    /// query answers as [`Self::query`] with the segment's constants
    /// computed once; `None` for any other face.
    pub fn straight(&self) -> Option<Straight> {
        let (Piece::Segment { a, b }, None, None) = (self.body, self.start_ramp, self.end_ramp)
        else {
            return None;
        };
        // The constants exactly as `Piece::closest` computes them.
        let ab = sub(b, a);
        let len2 = dot(ab, ab);
        let len = len2.sqrt();
        let side = self.side;
        Some(Straight {
            a,
            ab,
            len2,
            normal: [-side * ab[1] / len, side * ab[0] / len],
        })
    }

    /// The face's middle point (the body's), m.
    pub(crate) fn middle_m(&self) -> [f64; 2] {
        self.body.point_at(0.5)
    }
}

/// A straight face without ramps, its constants computed once
/// ([`Face::straight`]): the query of a guide bar, for every roller at every
/// evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Straight {
    a: [f64; 2],
    /// b − a.
    ab: [f64; 2],
    /// |b − a|².
    len2: f64,
    /// The working normal.
    normal: [f64; 2],
}

impl Straight {
    /// [`Face::query`] of the face it was made from: the same operations on
    /// the same numbers, so the same bits.
    #[inline]
    pub fn query(&self, p: [f64; 2]) -> Option<FacePoint> {
        let (some, hit) = self.query_parts(p);
        some.then_some(hit)
    }

    /// [`Self::query`] without branches (for a loop the compiler
    /// vectorises): whether there is a point, and the point (meaningless
    /// where there is none).
    #[inline(always)]
    pub fn query_parts(&self, p: [f64; 2]) -> (bool, FacePoint) {
        let (a, ab) = (self.a, self.ab);
        let t = dot(sub(p, a), ab) / self.len2;
        // `&`, not `contains` (`&&`): no branch in the vectorised loop.
        #[allow(clippy::manual_range_contains)]
        let inside = (0.0 <= t) & (t <= 1.0);
        let t = t.clamp(0.0, 1.0);
        let c = [a[0] + t * ab[0], a[1] + t * ab[1]];
        let n = self.normal;
        let distance = dot(sub(p, c), n);
        // On the working side: the distance to the closest point, the
        // normal from it (the face normal where the point is on the face).
        let above = distance >= 0.0;
        let d = norm_sqrt(sub(p, c));
        let apart = d > 0.0;
        let from = [(p[0] - c[0]) / d, (p[1] - c[1]) / d];
        let normal = [
            if above & apart { from[0] } else { n[0] },
            if above & apart { from[1] } else { n[1] },
        ];
        let hit = FacePoint {
            distance_m: if above { d } else { distance },
            point_m: c,
            normal,
            piece: 0,
        };
        (above | inside, hit)
    }
}

/// The side (+1 left, −1 right of the body's first → second end) on which
/// `p` lies as seen from the body's middle, or `None` if `p` is on the
/// body's tangent line there.
pub(crate) fn side_of(body: &Piece, p: [f64; 2]) -> Option<f64> {
    let m = body.point_at(0.5);
    let t = body.tangent_at(0.5);
    let cross = t[0] * (p[1] - m[1]) - t[1] * (p[0] - m[0]);
    (cross != 0.0 && cross.is_finite()).then(|| cross.signum())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn straight_query_matches_the_face_query_to_the_bit() {
        // The guide's fast query against the general one: points on both
        // sides, beyond both ends, on the face, at its ends and corners, for
        // faces in several directions and both working sides.
        let faces = [
            ([-0.6038, 0.041329], [-9.4038, 0.041329]),
            ([0.0, 0.0], [1.0, 0.0]),
            ([0.3, -0.2], [-0.1, 0.7]),
            ([1e-3, 2e-3], [1e-3, 5.0]),
        ];
        let mut checked = 0;
        for (start, end) in faces {
            let body = body_from_radius(start, end, None).unwrap();
            for side in [1.0, -1.0] {
                let face = Face::new(body, side, None, None);
                let fast = face.straight().expect("a straight face without ramps");
                let (ab, mid) = (
                    sub(end, start),
                    [0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1])],
                );
                for i in -40..=40 {
                    for j in -40..=40 {
                        // Along the face from before its start to after its end,
                        // across it within a few roller radii, and exact points.
                        let s = f64::from(i) / 30.0;
                        let off = f64::from(j) * 1e-3 * if j % 7 == 0 { 1e-6 } else { 1.0 };
                        let p = [
                            start[0] + s * ab[0] - off * ab[1],
                            start[1] + s * ab[1] + off * ab[0],
                        ];
                        for q in [p, start, end, mid] {
                            let (x, y) = (face.query(q), fast.query(q));
                            assert_eq!(x.is_some(), y.is_some(), "{q:?}");
                            if let (Some(x), Some(y)) = (x, y) {
                                assert_eq!(x.distance_m.to_bits(), y.distance_m.to_bits(), "{q:?}");
                                assert_eq!(
                                    x.point_m.map(f64::to_bits),
                                    y.point_m.map(f64::to_bits)
                                );
                                assert_eq!(x.normal.map(f64::to_bits), y.normal.map(f64::to_bits));
                                assert_eq!(x.piece, y.piece);
                                checked += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(checked > 100_000, "{checked}");
        // Faces with ramps or an arc have no fast query.
        let arc = body_from_radius([0.0, 0.0], [1.0, 0.0], Some(2.0)).unwrap();
        assert!(Face::new(arc, 1.0, None, None).straight().is_none());
        let bar = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
        let ramp = Ramp {
            length_m: 0.05,
            angle_rad: 0.1,
        };
        assert!(Face::new(bar, 1.0, Some(ramp), None).straight().is_none());
    }

    #[test]
    fn straight_face_distance_and_ends() {
        // Face y = 0 from x = 0 to 1, working side above (left of +x).
        let body = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
        let f = Face::new(body, 1.0, None, None);
        let q = f.query([0.3, 0.02]).unwrap();
        assert!(close(q.distance_m, 0.02) && close(q.normal[1], 1.0));
        let q = f.query([0.3, -0.01]).unwrap();
        assert!(close(q.distance_m, -0.01) && close(q.normal[1], 1.0));
        // Beyond the end, above: distance to the corner.
        let q = f.query([1.03, 0.04]).unwrap();
        assert!(close(q.distance_m, 0.05));
        assert!(close(q.normal[0], 0.6) && close(q.normal[1], 0.8));
        // Behind and beyond the end: no contact.
        assert!(f.query([1.1, -0.01]).is_none());
    }

    #[test]
    fn ramps_turn_away_from_the_working_side() {
        let body = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
        let r = Ramp {
            length_m: 0.1,
            angle_rad: 0.1,
        };
        for side in [1.0, -1.0] {
            let f = Face::new(body, side, Some(r), Some(r));
            let (a, _) = f.start_ramp.unwrap().ends();
            let (_, b) = f.end_ramp.unwrap().ends();
            // Both free ends behind the face (−side in y) by L sin α, and
            // beyond the body's ends by L cos α.
            let behind = -side * 0.1 * 0.1f64.sin();
            assert!(
                close(a[1], behind) && close(b[1], behind),
                "{side}: {a:?} {b:?}"
            );
            assert!(close(a[0], -0.1 * 0.1f64.cos()) && close(b[0], 1.0 + 0.1 * 0.1f64.cos()));
            // A point above the start ramp's middle is at distance along its normal.
            let m = f.start_ramp.unwrap().point_at(0.5);
            let q = f.query([m[0], m[1] + side * 0.01]).unwrap();
            assert_eq!(q.piece, 1);
            assert!((q.distance_m - 0.01 * 0.1f64.cos()).abs() < 1e-12);
        }
    }

    #[test]
    fn arc_from_radius_and_centre_agree() {
        // Quarter circle of radius 1 about the origin, from (1, 0) to (0, 1):
        // counter-clockwise, the centre on the left: r > 0.
        let a = body_from_radius([1.0, 0.0], [0.0, 1.0], Some(1.0)).unwrap();
        let b = body_from_centre([1.0, 0.0], [0.0, 1.0], [0.0, 0.0]).unwrap();
        let (Piece::Arc { center_m: c, .. }, Piece::Arc { center_m: d, .. }) = (a, b) else {
            panic!("arcs expected");
        };
        assert!(close(c[0], 0.0) && close(c[1], 0.0) && close(d[0], 0.0));
        assert!((a.length_m() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Working outside (right of the counter-clockwise direction).
        let f = Face::new(a, -1.0, None, None);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let q = f.query([1.2 * s, 1.2 * s]).unwrap();
        assert!((q.distance_m - 0.2).abs() < 1e-12);
        assert!((q.normal[0] - s).abs() < 1e-12);
        let q = f.query([0.9 * s, 0.9 * s]).unwrap();
        assert!((q.distance_m + 0.1).abs() < 1e-12);
        // Working inside.
        let f = Face::new(a, 1.0, None, None);
        let q = f.query([0.9 * s, 0.9 * s]).unwrap();
        assert!((q.distance_m - 0.1).abs() < 1e-12);
        assert!((q.normal[0] + s).abs() < 1e-12);
        // The arc's bounds hold the whole quarter circle.
        assert!(f.bounds_m[2] >= 1.0 - 1e-12 && f.bounds_m[3] >= 1.0 - 1e-12);
    }

    #[test]
    fn bad_shoes_are_refused() {
        assert_eq!(
            body_from_radius([0.0, 0.0], [0.0, 0.0], None),
            Err(ShoeError::DegenerateEnds)
        );
        assert!(matches!(
            body_from_radius([0.0, 0.0], [1.0, 0.0], Some(0.4)),
            Err(ShoeError::RadiusTooShort { .. })
        ));
        assert!(matches!(
            body_from_centre([0.0, 0.0], [1.0, 0.0], [0.0, 0.5]),
            Err(ShoeError::CentreOff { .. })
        ));
        assert_eq!(
            body_from_radius([f64::NAN, 0.0], [1.0, 0.0], None),
            Err(ShoeError::DegenerateEnds)
        );
    }

    #[test]
    fn side_follows_the_point() {
        let body = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
        assert_eq!(side_of(&body, [0.5, 0.3]), Some(1.0));
        assert_eq!(side_of(&body, [0.5, -0.3]), Some(-1.0));
        assert_eq!(side_of(&body, [2.0, 0.0]), None);
    }
}
