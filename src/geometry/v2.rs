//! The crate's 2-D arithmetic on `[f64; 2]` points and vectors, in one
//! place: the tooth form, the shoes, the arms and the scene's checks use
//! these. rapier's `Vector` is the type at the co-simulation's boundary;
//! inside, the model keeps plain arrays (and structure-of-arrays state).

use std::f64::consts::PI;

/// A 2-D vector or point, metres (or unitless for directions).
pub(crate) type V2 = [f64; 2];

/// a + b.
pub(crate) fn add(a: V2, b: V2) -> V2 {
    [a[0] + b[0], a[1] + b[1]]
}
/// a − b.
pub(crate) fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}
/// a·s.
pub(crate) fn scale(a: V2, s: f64) -> V2 {
    [a[0] * s, a[1] * s]
}
/// Dot product.
pub(crate) fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
/// Euclidean length.
pub(crate) fn norm(a: V2) -> f64 {
    a[0].hypot(a[1])
}
/// Euclidean length by a plain square root: `hypot`'s guard against
/// overflow is not needed at a drive's lengths and costs a library call in
/// a hot loop.
pub(crate) fn norm_sqrt(a: V2) -> f64 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}
/// Distance from `p` to the segment `a`–`b`, and where along it the
/// nearest point lies (0 at `a`, 1 at `b`; 0 for a segment of no length).
pub(crate) fn segment_distance(p: V2, a: V2, b: V2) -> (f64, f64) {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p[0] - a[0] - t * ab[0]).hypot(p[1] - a[1] - t * ab[1]), t)
}
/// −a.
pub(crate) fn neg(a: V2) -> V2 {
    [-a[0], -a[1]]
}
/// `a / |a|`, or `fallback` when `a` has no usable length.
pub(crate) fn unit_or(a: V2, fallback: V2) -> V2 {
    let n = norm(a);
    if n > 0.0 && n.is_finite() {
        [a[0] / n, a[1] / n]
    } else {
        fallback
    }
}
/// Right-hand normal of a direction (the free side of the counter-clockwise walk).
pub(crate) fn right_normal(t: V2) -> V2 {
    [t[1], -t[0]]
}
/// Unit vector at `angle_rad` from +x (+ξ).
pub(crate) fn polar(angle_rad: f64) -> V2 {
    [angle_rad.cos(), angle_rad.sin()]
}
/// Mirror about the gap centreline: ξ → −ξ.
pub(crate) fn mirror(a: V2) -> V2 {
    [-a[0], a[1]]
}
/// Polar angle of (x, y) to about 1e-5 rad (Abramowitz & Stegun 4.4.49); only a first guess
/// of the gap, which is then checked exactly.
#[inline]
pub(crate) fn atan2_approx(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if den.is_nan() || den <= 0.0 {
        return 0.0;
    }
    let t = num / den;
    let s = t * t;
    let mut a = t
        * (0.999_866_0
            + s * (-0.330_299_5 + s * (0.180_141_0 + s * (-0.085_133_0 + s * 0.020_835_1))));
    if ay > ax {
        a = 0.5 * PI - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 { -a } else { a }
}

/// Wrap an angle into (−π, π].
pub(crate) fn wrap_pi(a: f64) -> f64 {
    let r = a.rem_euclid(2.0 * PI);
    if r > PI { r - 2.0 * PI } else { r }
}
