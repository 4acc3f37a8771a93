//! ASA B29.1 (Type II) / ANSI roller-chain sprocket tooth form: dimensions, outline and
//! roller contact.
//!
//! This module builds the "real tooth profile" of Pedersen (Arch. Appl. Mech. 74 (2005),
//! §2.4) exactly as written out in `tooth-profile.md` (the checked specification): the
//! standard's constants (§1), the seven contact areas of one tooth gap in the gap-local
//! frame (§2), and the contact rules (§2 "Contact").
//!
//! # What it does
//! - [`AsaDimensions`]: every standard dimension of one sprocket (A, B, C, α, Rs, Rt, ΔR,
//!   M, T, RE, W, V, RF, H, S, xy, yz, root and tip radius), with the corrected constants
//!   B = 18° − 56°/N, ab = 1.4 Dr and topping centres b = (±W, −V).
//! - [`GapPoints`]: the construction points x, y, z, f, the centres b, c and the area angles
//!   of one gap in its local frame.
//! - [`AsaProfile::signed_distance`]: signed distance from a point to the whole sprocket
//!   outline (positive in free space), closest point, area and gap.
//! - [`AsaProfile::contacts`]: the contact patches of a roller (at most two), O(1) and
//!   without allocation.
//! - [`AsaProfile::outline`]: the sampled outline of the whole sprocket (for drawing, CSV
//!   output and tests).
//!
//! # What it does not do
//! - No forces, no contact law, no contact memory: it only supplies depth, normal, point and
//!   a stable patch identity. The caller applies its law (e.g. Lankarani–Nikravesh).
//! - No sprocket pose: everything is in the SPROCKET frame (centre at the origin, angle 0).
//!   The caller transforms a roller centre into that frame and the results back.
//! - The tooth tip is the pointed tooth of the paper; the optional truncation to
//!   OD = P(0.6 + cot φ) is not applied.
//!
//! # Conventions
//! - SI units inside (metres, radians). The standard's additive constants 0.003 in and
//!   0.0015 in are used as 7.62e-5 m and 3.81e-5 m; all multipliers are unitless.
//! - φ = π/N is half the pitch angle; the pitch angle is Φ = 2π/N.
//! - Sprocket frame: gap j's seating centre O_j is at polar angle ψ_j = jΦ on the pitch
//!   circle (radius Rs); gap 0 is at (Rs, 0); gaps are numbered counter-clockwise and taken
//!   modulo N into 0..N. Tooth k is the tooth between gap k and gap k+1 (its centreline is
//!   at polar angle (k + ½)Φ).
//! - Gap-local frame (ξ, η), the paper's eq. (24): origin O_j, η = e_r (radially outward),
//!   ξ = (sin ψ, −cos ψ) (clockwise tangential). A point (ξ, η) is at
//!   (Rs + η) e_r + ξ ξ̂ in the sprocket frame.
//! - Areas 1..=7 as in the spec: 7 topping (convex, clockwise side, ξ > 0), 6 straight,
//!   5 working (concave), 4 seating (concave), 3 working, 2 straight, 1 topping
//!   (counter-clockwise side, ξ < 0). A counter-clockwise walk meets them in the order
//!   7, 6, 5, 4, 3, 2, 1; the material is on the left of that walk.
//! - Signed distance: positive in free space, negative inside the material.
//! - Contact: depth = r − sd (contact when depth > 0); the normal is the unit free-side
//!   normal at the closest point, i.e. the unit vector from the closest outline point towards
//!   the roller centre whenever that centre is in free space. It is the direction of the
//!   force on the roller.
//!
//! # Patches and patch identity
//! The whole outline is tangent-continuous except at the tooth tips f, which are convex
//! corners; the nearest-point rule is continuous across both. A *patch* is a set of pieces
//! on which a roller has at most one nearest point; a roller can touch two separate places
//! only when the distance to the outline has two separate local minima within its radius.
//! Patch ids (N = number of teeth):
//! - `2·g` — the concave part (areas 2–6) of gap g.
//! - `2·k + 1` — tooth k: area 1 of gap k, the tip, and area 7 of gap k+1.
//! - `2·N + g` — only when ONE roller touches BOTH flanks of gap g at once (possible only for
//!   a roller that does not fit the seat, radius ≳ Rt): then the clockwise-side (ξ > 0)
//!   contact keeps `2·g` and the counter-clockwise-side one gets `2·N + g`.
//!
//! A roller sliding across the joint z (straight ↔ topping, tangent) changes from patch `2g`
//! to the tooth patch. That is a change of *place* for this id scheme but not of the force,
//! which is continuous; [`AsaProfile::patches_are_neighbours`] tells the caller when two ids
//! meet at such a joint, so it can carry its contact memory across.
//!
//! A patch is reported only where its nearest point is a genuine local minimum of the
//! distance: if a patch's nearest point is the end it shares with a neighbouring patch (z, z*
//! or the seat bottom between the two flank halves), the point belongs to the neighbour. The
//! ownership at each shared end is decided by ONE half-plane test (the normal line at the
//! joint), evaluated identically for both sides, so a point is never claimed twice and never
//! dropped by rounding.

use std::f64::consts::PI;
use std::fmt;

/// 0.003 in expressed in metres (additive constant of Dt and xy).
pub const IN_0_003_M: f64 = 7.62e-5;
/// 0.0015 in expressed in metres (additive constant of Rt, RE and RF).
pub const IN_0_0015_M: f64 = 3.81e-5;
/// Smallest tooth count accepted before the geometric checks (B, C > 0 needs N ≥ 4).
pub const MIN_TEETH: u32 = 4;
/// Largest tooth count accepted (keeps patch ids well inside `u32`).
pub const MAX_TEETH: u32 = 100_000;
/// Smallest arc step used by [`AsaProfile::outline`] (bounds the allocation).
pub const MIN_OUTLINE_STEP_RAD: f64 = 1e-4;
/// Rounding allowance when comparing a patch with the nearest outline point.
const CONSISTENCY_TOL_M: f64 = 1e-9;
/// Distances closer than this are a tie (the earlier piece is kept: own before neighbour).
const TIE_M: f64 = 1e-15;

/// Standard dimensions of one sprocket (all SI: metres, radians).
///
/// Symbols and formulas are those of `tooth-profile.md` §1; points and angles of the
/// construction are in [`GapPoints`].
#[derive(Clone, Debug, PartialEq)]
pub struct AsaDimensions {
    /// Number of teeth N.
    pub teeth: u32,
    /// Chain pitch P.
    pub pitch_m: f64,
    /// Roller diameter Dr.
    pub roller_diameter_m: f64,
    /// A = 35° + 60°/N.
    pub a_rad: f64,
    /// B = 18° − 56°/N (sweep of the working curve).
    pub b_rad: f64,
    /// C = 17° − 64°/N (= A − B − φ).
    pub c_rad: f64,
    /// Pressure angle α = 35° − 120°/N = A − φ, eq. (48).
    pub pressure_angle_rad: f64,
    /// Pitch radius Rs = P / (2 sin φ).
    pub pitch_radius_m: f64,
    /// Seating-curve radius Rt = Dt/2 = 0.5025 Dr + 0.0015 in.
    pub seating_radius_m: f64,
    /// Clearance ΔR = Rt − Rr.
    pub clearance_m: f64,
    /// M = 0.8 Dr cos A.
    pub m_m: f64,
    /// T = 0.8 Dr sin A.
    pub t_m: f64,
    /// Working-curve radius RE = 1.3025 Dr + 0.0015 in.
    pub working_radius_m: f64,
    /// W = 1.4 Dr cos φ.
    pub w_m: f64,
    /// V = 1.4 Dr sin φ.
    pub v_m: f64,
    /// Topping-curve radius RF = Dr (0.8 cos B + 1.4 cos C − 1.3025) − 0.0015 in.
    pub topping_radius_m: f64,
    /// H = sqrt(RF² − (1.4 Dr − P/2)²), tip height above the chord midpoint.
    pub h_m: f64,
    /// S = P/2 cos φ + H sin φ, tangential distance of the tip from the gap centreline.
    pub s_m: f64,
    /// Chord of the working curve xy = (2.605 Dr + 0.003 in) sin(9° − 28°/N).
    pub working_chord_m: f64,
    /// Length of the straight portion yz = Dr (1.4 sin C − 0.8 sin B).
    pub straight_length_m: f64,
    /// Tip radius Rs cos φ + H (pointed tooth).
    pub tip_radius_m: f64,
    /// Root radius Rs − Rt.
    pub root_radius_m: f64,
}

/// Construction points and area angles of one gap, in the gap-local frame (ξ, η).
///
/// Unstarred points are on the clockwise side (ξ > 0); the starred ones are their mirror
/// images ξ → −ξ (angles θ → π − θ). Angles are polar angles about the named centre,
/// measured from +ξ counter-clockwise, in the ranges printed in the spec.
#[derive(Clone, Debug, PartialEq)]
pub struct GapPoints {
    /// x: seating ↔ working joint, Rt (cos A, −sin A).
    pub x_m: [f64; 2],
    /// y = d: working ↔ straight joint.
    pub y_m: [f64; 2],
    /// z = e: straight ↔ topping joint.
    pub z_m: [f64; 2],
    /// f: tooth tip on the tooth centreline.
    pub f_m: [f64; 2],
    /// b: centre of the topping curve of area 7, (W, −V).
    pub b_m: [f64; 2],
    /// c: centre of the working curve of area 5, (−M, T).
    pub c_m: [f64; 2],
    /// θ1a = π + A (seating arc, at x*).
    pub theta_1a_rad: f64,
    /// θ2a = 2π − A (seating arc, at x).
    pub theta_2a_rad: f64,
    /// θ1c = 2π − A (area 5 at x).
    pub theta_1c_rad: f64,
    /// θ2c = 2π − A + B (area 5 at y).
    pub theta_2c_rad: f64,
    /// θ1c* = π + A − B (area 3 at y*).
    pub theta_1c_star_rad: f64,
    /// θ2c* = π + A (area 3 at x*).
    pub theta_2c_star_rad: f64,
    /// θ1b = π − θ2b* (area 7 at f).
    pub theta_1b_rad: f64,
    /// θ2b = π − A + B (area 7 at z).
    pub theta_2b_rad: f64,
    /// θ1b* = A − B (area 1 at z*).
    pub theta_1b_star_rad: f64,
    /// θ2b* = atan2(f* − b*) (area 1 at f*).
    pub theta_2b_star_rad: f64,
    /// Sweep of each topping curve, θ2b* − θ1b*.
    pub topping_sweep_rad: f64,
}

/// Why a profile cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub enum AsaError {
    /// Fewer than [`MIN_TEETH`] teeth.
    TooFewTeeth {
        /// The requested tooth count.
        teeth: u32,
    },
    /// More than [`MAX_TEETH`] teeth.
    TooManyTeeth {
        /// The requested tooth count.
        teeth: u32,
    },
    /// An input that must be finite and positive is not.
    NonPositive {
        /// Which input.
        what: &'static str,
    },
    /// The seating curves of neighbouring gaps would meet (Dt ≥ P).
    RollerTooBig {
        /// Seating diameter Dt in metres.
        seating_diameter_m: f64,
        /// Pitch P in metres.
        pitch_m: f64,
    },
    /// The standard's construction does not give a valid profile for these inputs.
    DegenerateProfile {
        /// What failed.
        reason: &'static str,
    },
}

impl fmt::Display for AsaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AsaError::TooFewTeeth { teeth } => {
                write!(
                    f,
                    "ASA sprocket needs at least {MIN_TEETH} teeth, got {teeth}"
                )
            }
            AsaError::TooManyTeeth { teeth } => {
                write!(
                    f,
                    "ASA sprocket supports at most {MAX_TEETH} teeth, got {teeth}"
                )
            }
            AsaError::NonPositive { what } => write!(f, "{what} must be finite and positive"),
            AsaError::RollerTooBig {
                seating_diameter_m,
                pitch_m,
            } => write!(
                f,
                "seating diameter {seating_diameter_m} m is not smaller than the pitch {pitch_m} m"
            ),
            AsaError::DegenerateProfile { reason } => {
                write!(f, "degenerate ASA tooth profile: {reason}")
            }
        }
    }
}

impl std::error::Error for AsaError {}

/// One contact patch between a roller and the profile, in the SPROCKET frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patch {
    /// Penetration depth r − sd in metres, > 0.
    pub depth_m: f64,
    /// Unit free-side normal at the closest point: from the closest surface point towards
    /// the roller centre (when the centre is in free space). Direction of the force on the
    /// roller.
    pub normal: [f64; 2],
    /// Closest surface point, metres.
    pub point: [f64; 2],
    /// Area 1..=7 of the piece that holds the closest point.
    pub area: u8,
    /// Gap (0..N) whose piece holds the closest point.
    pub gap: i64,
    /// Stable identity of the place touched (see the module docs).
    pub patch_id: u32,
}

/// One sample of the sprocket outline, in the sprocket frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlinePoint {
    /// x in metres.
    pub x_m: f64,
    /// y in metres.
    pub y_m: f64,
    /// Gap (0..N) the sampled piece belongs to.
    pub gap: i64,
    /// Area 1..=7 of the sampled piece.
    pub area: u8,
}

// ---------------------------------------------------------------------------------------
// Small 2-D helpers.

/// A 2-D vector or point, metres (or unitless for directions).
type V2 = [f64; 2];

/// a + b.
fn add(a: V2, b: V2) -> V2 {
    [a[0] + b[0], a[1] + b[1]]
}
/// a − b.
fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}
/// a·s.
fn scale(a: V2, s: f64) -> V2 {
    [a[0] * s, a[1] * s]
}
/// Dot product.
fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
/// Euclidean length.
fn norm(a: V2) -> f64 {
    a[0].hypot(a[1])
}
/// −a.
fn neg(a: V2) -> V2 {
    [-a[0], -a[1]]
}
/// `a / |a|`, or `fallback` when `a` has no usable length.
fn unit_or(a: V2, fallback: V2) -> V2 {
    let n = norm(a);
    if n > 0.0 && n.is_finite() {
        [a[0] / n, a[1] / n]
    } else {
        fallback
    }
}
/// Right-hand normal of a direction (the free side of the counter-clockwise walk).
fn right_normal(t: V2) -> V2 {
    [t[1], -t[0]]
}
/// Unit vector at `angle_rad` from +x (+ξ).
fn polar(angle_rad: f64) -> V2 {
    [angle_rad.cos(), angle_rad.sin()]
}
/// Mirror about the gap centreline: ξ → −ξ.
fn mirror(a: V2) -> V2 {
    [-a[0], a[1]]
}
/// Polar angle of (x, y) to about 1e-5 rad (Abramowitz & Stegun 4.4.49); only a first guess
/// of the gap, which is then checked exactly.
#[inline]
fn atan2_approx(y: f64, x: f64) -> f64 {
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
fn wrap_pi(a: f64) -> f64 {
    let r = a.rem_euclid(2.0 * PI);
    if r > PI { r - 2.0 * PI } else { r }
}

// ---------------------------------------------------------------------------------------
// Pieces of the outline.

/// Ownership test at a joint shared by two patches: the piece *before* the joint (in walk
/// order) owns the points with (p − point)·tangent < 0, the piece after it the others.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Joint {
    /// The joint point.
    point: V2,
    /// Unit walk direction at the joint.
    tangent: V2,
}

impl Joint {
    /// Signed distance of `p` along the tangent, measured from the joint.
    fn side(&self, p: V2) -> f64 {
        dot(sub(p, self.point), self.tangent)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
/// Geometry of one piece.
enum Shape {
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
struct Piece {
    /// Arc or segment.
    shape: Shape,
    /// Start point (walk order).
    start: V2,
    /// End point (walk order).
    end: V2,
    /// Area 1..=7.
    area: u8,
    /// Gap of this piece relative to the frame it is expressed in (−1, 0, +1).
    gap_offset: i64,
    /// Shared joint at the start: the piece owns points with side ≥ 0.
    start_joint: Option<Joint>,
    /// Shared joint at the end: the piece owns points with side < 0.
    end_joint: Option<Joint>,
    /// At a convex corner (the tooth tip), the direction that decides the sign of the
    /// distance to that end point (the tooth centreline, outward), per end.
    corner_normal: [Option<V2>; 2],
}

/// Result of the closest-point query on one piece (piece-local frame).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Hit {
    /// Unsigned distance.
    dist_m: f64,
    /// Signed distance, positive on the free side.
    sd_m: f64,
    /// Closest point.
    point: V2,
    /// Unit free-side normal (towards `p` when `p` is in free space).
    normal: V2,
    /// Area of the piece.
    area: u8,
    /// Gap of the piece relative to the evaluating gap.
    gap_offset: i64,
    /// False when the point lies beyond a joint shared with another patch.
    owned: bool,
}

impl Piece {
    /// An arc piece; end points from the arc formula (overwritten by shared joints later).
    fn arc(centre: V2, radius_m: f64, start_rad: f64, sweep_rad: f64, area: u8) -> Piece {
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
    fn segment(start: V2, end: V2, area: u8) -> Piece {
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
    fn tangent(&self, at_end: bool) -> V2 {
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
    fn free_normal(&self, at_end: bool) -> V2 {
        right_normal(self.tangent(at_end))
    }

    /// False when `p` lies beyond a shared joint at either end.
    fn owns(&self, p: V2) -> bool {
        let after_start = self.start_joint.is_none_or(|j| j.side(p) >= 0.0);
        let before_end = self.end_joint.is_none_or(|j| j.side(p) < 0.0);
        after_start && before_end
    }

    /// A hit of this piece.
    fn hit(&self, sd_m: f64, point: V2, normal: V2, owned: bool) -> Hit {
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
    fn closest(&self, p: V2) -> Hit {
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
    fn end_point_hit(&self, p: V2, owned: bool) -> Hit {
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
    fn mapped(&self, map: impl Fn(V2) -> V2, rotate_rad: f64, gap_offset: i64) -> Piece {
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
    fn sample(&self, max_step_rad: f64, straight_step_m: f64, out: &mut Vec<V2>) {
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

/// Trig-free form of one [`Piece`] for the hot path of [`AsaProfile::contacts`]: the same
/// closest-point rule as [`Piece::closest`], with the angular window tested by dot and cross
/// products against the precomputed bisector, and the end normals precomputed. It also
/// carries a cheap, conservative "farther than the radius" test used to skip the piece.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FastPiece {
    /// True for an arc, false for a segment.
    is_arc: bool,
    /// True for a convex arc (sweep > 0).
    convex: bool,
    /// Arc centre (arcs) or start point (segments).
    centre: V2,
    /// Arc radius (0 for segments).
    radius_m: f64,
    /// Unit bisector of the arc's angular window, `polar(start + sweep/2)`.
    mid_dir: V2,
    /// tan of the half-sweep (< π/2).
    tan_half: f64,
    /// Start point (walk order).
    start: V2,
    /// End point (walk order).
    end: V2,
    /// Segment vector end − start.
    e: V2,
    /// |e|².
    l2: f64,
    /// Free normals at the start and the end.
    n_free: [V2; 2],
    /// Directions that decide the sign at the start and the end point.
    n_sign: [V2; 2],
    /// Shared joint at the start (owns side ≥ 0).
    start_joint: Option<Joint>,
    /// Shared joint at the end (owns side < 0).
    end_joint: Option<Joint>,
    /// Area 1..=7.
    area: u8,
    /// Gap of this piece relative to the evaluating gap.
    gap_offset: i64,
}

/// Closest-point result of a [`FastPiece`] without the point and normal, which are only
/// computed ([`FastPiece::geometry`]) for the patches reported.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Near {
    /// Unsigned distance.
    dist_m: f64,
    /// Signed distance, positive on the free side.
    sd_m: f64,
    /// False when the point lies beyond a joint shared with another patch.
    owned: bool,
    /// Index of the piece in [`AsaProfile::fast`].
    piece: u8,
    /// Which rule gave the closest point: [`FOOT`], [`AT_START`] or [`AT_END`].
    mode: u8,
}

/// One patch in gap-local form, before it is written in the sprocket frame.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Found {
    /// Penetration depth r − sd, > 0.
    depth_m: f64,
    /// Unit free-side normal, gap-local.
    normal: V2,
    /// Closest outline point, gap-local.
    point: V2,
    /// Area 1..=7.
    area: u8,
    /// Gap of the piece relative to the evaluating gap (−1, 0, +1).
    gap_offset: i64,
    /// Patch id (see the module docs).
    patch_id: u32,
}

/// An unused [`Found`] slot.
const NONE: Found = Found {
    depth_m: 0.0,
    normal: [0.0; 2],
    point: [0.0; 2],
    area: 0,
    gap_offset: 0,
    patch_id: 0,
};

/// The closest point is the foot of the perpendicular.
const FOOT: u8 = 0;
/// The closest point is the start point.
const AT_START: u8 = 1;
/// The closest point is the end point.
const AT_END: u8 = 2;

/// A result that is never the nearest and never in contact (a skipped, provably far piece).
const FAR: Near = Near {
    dist_m: f64::INFINITY,
    sd_m: f64::INFINITY,
    owned: false,
    piece: 0,
    mode: FOOT,
};

impl FastPiece {
    /// The trig-free form of `piece`.
    fn new(piece: &Piece) -> FastPiece {
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
    fn is_far(&self, p: V2, reach: f64) -> bool {
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
    fn eval(&self, p: V2, reach: f64, piece: u8) -> Near {
        if self.is_far(p, reach) {
            FAR
        } else {
            self.near(p, piece)
        }
    }

    /// False when `p` lies beyond a shared joint at either end.
    #[inline(always)]
    fn owns(&self, p: V2) -> bool {
        let after_start = self.start_joint.is_none_or(|j| j.side(p) >= 0.0);
        let before_end = self.end_joint.is_none_or(|j| j.side(p) < 0.0);
        after_start && before_end
    }

    /// Distance part of [`Piece::closest`] (same rule, to rounding): the foot of the
    /// perpendicular when it falls on the span, otherwise the nearer end point.
    #[inline(always)]
    fn near(&self, p: V2, piece: u8) -> Near {
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
    fn segment_t(&self, v: V2) -> f64 {
        if self.l2 > 0.0 {
            dot(v, self.e) / self.l2
        } else {
            -1.0
        }
    }

    /// Closest point and unit free-side normal for the rule `mode` found by
    /// [`FastPiece::near`] (the point and normal of [`Piece::closest`], to rounding).
    fn geometry(&self, p: V2, mode: u8) -> (V2, V2) {
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

/// [`patch_hit`] for [`Near`] results.
#[inline(always)]
fn patch_near(hits: &[Near]) -> Option<Near> {
    let mut best: Option<Near> = None;
    for &h in hits {
        match best {
            Some(b) if b.dist_m <= h.dist_m + TIE_M => {}
            _ => best = Some(h),
        }
    }
    best.filter(|h| h.owned)
}

/// [`nearest_hit`] for [`Near`] results.
#[inline(always)]
fn nearest_near(hits: &[Near; 8]) -> Near {
    let mut best = hits[0];
    for &h in &hits[1..] {
        if h.dist_m < best.dist_m {
            best = h;
        }
    }
    best
}

/// [`insert_deepest`] for [`Near`] results.
#[inline(always)]
fn insert_deepest_near(best: &mut [Option<(Near, u32)>; 2], c: (Near, u32)) {
    let deeper = |a: &(Near, u32), b: &Option<(Near, u32)>| b.is_none_or(|b| a.0.sd_m < b.0.sd_m);
    if deeper(&c, &best[0]) {
        best[1] = best[0];
        best[0] = Some(c);
    } else if deeper(&c, &best[1]) {
        best[1] = Some(c);
    }
}

/// Number of sub-steps for a ratio span/step (at least 1, bounded).
fn steps(ratio: f64) -> usize {
    if ratio.is_finite() && ratio > 1.0 {
        ratio.ceil().min(1e7) as usize
    } else {
        1
    }
}

/// Closest owned point of a patch, from the hits of its pieces: `None` when the nearest
/// point of the run lies beyond one of its shared joints (it then belongs to the
/// neighbouring patch). On a tie (within [`TIE_M`], e.g. both toppings at the tip) the
/// earlier piece wins.
#[cfg(test)]
fn patch_hit(hits: &[Hit]) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for &h in hits {
        match best {
            Some(b) if b.dist_m <= h.dist_m + TIE_M => {}
            _ => best = Some(h),
        }
    }
    best.filter(|h| h.owned)
}

/// The hit with the smallest distance (the first on a tie).
fn nearest_hit(hits: &[Hit; 8]) -> Hit {
    let mut best = hits[0];
    for &h in &hits[1..] {
        if h.dist_m < best.dist_m {
            best = h;
        }
    }
    best
}

// ---------------------------------------------------------------------------------------
// Dimensions and construction.

/// Range checks of the raw inputs.
fn check_inputs(teeth: u32, pitch_m: f64, roller_diameter_m: f64) -> Result<(), AsaError> {
    if teeth < MIN_TEETH {
        return Err(AsaError::TooFewTeeth { teeth });
    }
    if teeth > MAX_TEETH {
        return Err(AsaError::TooManyTeeth { teeth });
    }
    if !(pitch_m.is_finite() && pitch_m > 0.0) {
        return Err(AsaError::NonPositive { what: "pitch" });
    }
    if !(roller_diameter_m.is_finite() && roller_diameter_m > 0.0) {
        return Err(AsaError::NonPositive {
            what: "roller diameter",
        });
    }
    let seating_diameter_m = 1.005 * roller_diameter_m + IN_0_003_M;
    if seating_diameter_m >= pitch_m {
        return Err(AsaError::RollerTooBig {
            seating_diameter_m,
            pitch_m,
        });
    }
    Ok(())
}

/// The standard dimensions (§1), with the checks that the construction closes.
fn dimensions(teeth: u32, pitch_m: f64, dr: f64) -> Result<AsaDimensions, AsaError> {
    check_inputs(teeth, pitch_m, dr)?;
    let n = f64::from(teeth);
    let deg = PI / 180.0;
    let phi = PI / n;
    let a = (35.0 + 60.0 / n) * deg;
    let b = (18.0 - 56.0 / n) * deg;
    let c = (17.0 - 64.0 / n) * deg;
    let rt = 0.5025 * dr + IN_0_0015_M;
    let rf = dr * (0.8 * b.cos() + 1.4 * c.cos() - 1.3025) - IN_0_0015_M;
    let chord_offset = 1.4 * dr - 0.5 * pitch_m;
    let h2 = rf * rf - chord_offset * chord_offset;
    let yz = dr * (1.4 * c.sin() - 0.8 * b.sin());
    if b <= 0.0 || c <= 0.0 {
        return Err(AsaError::DegenerateProfile {
            reason: "B or C is not positive",
        });
    }
    if yz <= 0.0 {
        return Err(AsaError::DegenerateProfile {
            reason: "straight portion yz is not positive",
        });
    }
    if rf <= 0.0 || h2 <= 0.0 {
        return Err(AsaError::DegenerateProfile {
            reason: "topping curve does not reach the tooth centreline",
        });
    }
    let h = h2.sqrt();
    let rs = pitch_m / (2.0 * phi.sin());
    Ok(AsaDimensions {
        teeth,
        pitch_m,
        roller_diameter_m: dr,
        a_rad: a,
        b_rad: b,
        c_rad: c,
        pressure_angle_rad: (35.0 - 120.0 / n) * deg,
        pitch_radius_m: rs,
        seating_radius_m: rt,
        clearance_m: rt - 0.5 * dr,
        m_m: 0.8 * dr * a.cos(),
        t_m: 0.8 * dr * a.sin(),
        working_radius_m: 1.3025 * dr + IN_0_0015_M,
        w_m: 1.4 * dr * phi.cos(),
        v_m: 1.4 * dr * phi.sin(),
        topping_radius_m: rf,
        h_m: h,
        s_m: 0.5 * pitch_m * phi.cos() + h * phi.sin(),
        working_chord_m: (2.605 * dr + IN_0_003_M) * (9.0 - 28.0 / n).to_radians().sin(),
        straight_length_m: yz,
        tip_radius_m: rs * phi.cos() + h,
        root_radius_m: rs - rt,
    })
}

/// Construction points and angles (§2) of one gap.
fn gap_points(d: &AsaDimensions) -> Result<GapPoints, AsaError> {
    let phi = PI / f64::from(d.teeth);
    let (a, b) = (d.a_rad, d.b_rad);
    let c_m = [-d.m_m, d.t_m];
    let b_m = [d.w_m, -d.v_m];
    let x_m = scale([a.cos(), -a.sin()], d.seating_radius_m);
    let y_m = add(c_m, scale(polar(b - a), d.working_radius_m));
    let theta_2b = PI - a + b;
    let z_m = add(b_m, scale(polar(theta_2b), d.topping_radius_m));
    let f_m = [d.s_m, -0.5 * d.pitch_m * phi.sin() + d.h_m * phi.cos()];
    let fb = sub(mirror(f_m), mirror(b_m));
    let theta_2b_star = fb[1].atan2(fb[0]);
    let theta_1b_star = a - b;
    let sweep = theta_2b_star - theta_1b_star;
    if !(sweep > 0.0 && sweep < PI) {
        return Err(AsaError::DegenerateProfile {
            reason: "topping curve sweep is not in (0, π)",
        });
    }
    Ok(GapPoints {
        x_m,
        y_m,
        z_m,
        f_m,
        b_m,
        c_m,
        theta_1a_rad: PI + a,
        theta_2a_rad: 2.0 * PI - a,
        theta_1c_rad: 2.0 * PI - a,
        theta_2c_rad: 2.0 * PI - a + b,
        theta_1c_star_rad: PI + a - b,
        theta_2c_star_rad: PI + a,
        theta_1b_rad: PI - theta_2b_star,
        theta_2b_rad: theta_2b,
        theta_1b_star_rad: theta_1b_star,
        theta_2b_star_rad: theta_2b_star,
        topping_sweep_rad: sweep,
    })
}

/// The eight pieces of one gap in walk order 7, 6, 5, 4 (ξ ≥ 0 half), 4 (ξ ≤ 0 half), 3,
/// 2, 1, with the ownership joints z (7|6), seat bottom (4|4) and z* (2|1).
fn gap_pieces(d: &AsaDimensions, g: &GapPoints) -> [Piece; 8] {
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
fn neighbour_map(rs: f64, pitch_angle_rad: f64, k: i64) -> impl Fn(V2) -> V2 {
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

/// Precomputed geometry of one ASA sprocket: the pieces of one gap in its local frame, the
/// neighbouring toppings, and the gap rotations.
#[derive(Clone, Debug, PartialEq)]
pub struct AsaProfile {
    /// Standard dimensions.
    dims: AsaDimensions,
    /// Construction points and angles.
    points: GapPoints,
    /// Gap pieces, walk order 7, 6, 5, 4, 4, 3, 2, 1 (seat split at its bottom).
    own: [Piece; 8],
    /// Area 7 of gap +1, in gap 0's frame (the far side of tooth 0).
    next_area7: Piece,
    /// Area 1 of gap −1, in gap 0's frame (the far side of tooth −1).
    prev_area1: Piece,
    /// (cos ψ_j, sin ψ_j) for every gap.
    gap_trig: Vec<V2>,
    /// Pitch angle Φ = 2π/N.
    pitch_angle_rad: f64,
    /// Trig-free forms of `own` (0..8), `prev_area1` (8) and `next_area7` (9), for the hot
    /// path of [`AsaProfile::contacts`].
    fast: [FastPiece; 10],
    /// Smallest distance from the seating centre O to any own piece (≈ Rt), less a rounding
    /// allowance: no roller centred within `seat_clear_m − r` of O can touch.
    seat_clear_m: f64,
    /// Largest distance of the outline from the sprocket centre, plus a rounding allowance.
    reach_radius_m: f64,
    /// tan(Φ/2) shrunk by a relative 1e-9: a point strictly inside this cone about a gap
    /// direction is in that gap's sector whatever the rounding of `atan2`.
    tan_half_pitch_inner: f64,
    /// 1/Φ.
    inv_pitch_angle: f64,
    /// The outline as a graph, to tell free space from material far from the outline.
    graph: Option<SideGraph>,
    /// The direct rules of [`AsaProfile::contacts_hinted`] (see [`Shortcuts`]).
    cuts: Shortcuts,
    /// The radius-dependent constants for the profile's own roller, Dr/2.
    nominal: Reach,
}

/// Smallest distance |s| of `q` from the line c–O–x (or its mirror c*–O–x*) for which the
/// bottom-of-gap rules of [`Shortcuts`] decide between the seat and a working curve, as a
/// fraction of Rt. The losing piece is then farther by at least s²/(2(|c| + R_L)) ≈ 3·10⁻¹²
/// m for the paper's rollers (≫ [`TIE_M`] and the rounding); closer to the line the general
/// path decides.
const JOINT_LINE_MARGIN: f64 = 2e-5;

/// Margin by which a working curve's foot must be nearer than the seat bottom before the
/// bottom-of-gap rule reports it (≫ [`TIE_M`] and the rounding).
const BOTTOM_MARGIN_M: f64 = 1e-12;

/// The two direct rules of [`AsaProfile::contacts_hinted`], for the places where almost
/// every query of a running drive falls: the bottom of the gap (seated rollers, and rollers
/// rocked onto a working curve just past the joint x or x*), and the free space of the gap
/// above it. Radius-independent part; [`Reach`] holds the rest.
///
/// **Bottom of the gap**: `q` (gap-local) with `min_r ≤ |q| < R_L`, R_L = min(far − reach,
/// Rt(1 − 10⁻³)). Let s = cos A·η + sin A·|ξ|, the signed distance of `q` from the line
/// through c, O and x (from its mirror through c*, O, x* when ξ ≤ 0), positive on the
/// working curve's side. The owning half is the one with ξ > 0 (pieces 2, 3) or ξ ≤ 0
/// (pieces 5, 4), as the seat-bottom joint decides. Then:
/// - s ≤ −s_min: the seat foot, depth r − (Rt − |q|), area 4, id 2g;
/// - s ≥ s_min and the seat bottom farther than min(d_w + margin, reach): the working curve's
///   foot, depth r − d_w with d_w = RE − |q − c|, area 5 (3), id 2g;
/// - otherwise the general path.
///
/// Why this is the general answer:
/// - Pieces 0, 1, 6, 7 and both neighbouring toppings are at least `far` from O (checked
///   at construction), so farther than `reach` from `q`: never in contact (a negative
///   signed distance below −reach fails the consistency test, the nearest own piece having
///   a positive distance: `q` is deep in the free space of the gap, R_L < Rt), and never
///   preferred in a patch to a piece in contact (dist ≤ r < reach).
/// - The line c–O–x is the common normal of the seat and working circles at their tangent
///   point x. On its seat side, `q` is in the owning seat half's window (its wedge is
///   bounded by that line and by ξ = 0) and outside the working curve's window, whose
///   nearest point is then x: |q − x|² − (Rt − |q|)² = 2|q|Rt(1 − cos σ) with |q| sin σ = |s|,
///   so x is farther than the seat foot by at least s²/(2|q|). On the working side, `q` is
///   outside the seat's window (which lies on the other side of the line) and inside the
///   working curve's window (O is on its x edge, and the line c–y is farther than R_L from
///   O: checked); |q − x|² − (RE − |q − c|)² = 2|q − c|RE(1 − cos σ) gives the margin
///   s²/(2|q − c|) over x, and the bottom point, the seat half's other end, is checked at
///   run time. So the owning side's patch (pieces 1–3, resp. 4–6) is the stated foot.
/// - The other side's patch is empty. Its seat half is not owned (the bottom joint gives
///   ξ > 0 to piece 3 only) and its nearest point is an end (`q` is outside its wedge). Its
///   working curve reaches `q` either at the shared joint x*, where the seat half comes
///   first and wins the tie, or at its foot: `q` is then on that curve's side of its line,
///   so the angle between q and c* − O is at most π/2 − A, q·(c* − O) ≥ |q||c*| sin A and
///   |q − c*|² < |c*|² as |q| < 2|c*| sin A (checked): the foot is farther than Rt > reach.
/// - The teeth patches are far pieces (first point).
///
/// **Free space of the gap** (the roller is lifted out of the gap or coming in): `q`
/// outside the seat's wedge (s > 0 for ξ or for −ξ) and, on both sides (the left side by the
/// mirror image of `q` against the right side's pieces):
/// - on the free side of the straight portion's line by more than the reach,
/// - outside the topping circle by more than the reach,
/// - inside the working circle by more than the reach, unless `q` is beyond the working
///   curve's y end (then y, on the straight line, is its nearest point).
///
/// Each is a lower bound of the distance to its piece (the seat's nearest point is then x or
/// x*, on the working circles), so no own piece is within `reach`. And `q` is in free space:
/// below the outline, within the gap's sector, a point is inside the seat's wedge, or
/// outside a working circle, or beyond a straight line, or inside a topping circle (checked
/// over the graph of the outline, see [`SideGraph`]). The nearest outline point then has a
/// signed distance above the reach, so no candidate is both in contact and consistent with
/// it, the neighbouring toppings included: the answer is no contact.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Shortcuts {
    /// (cos A, sin A): s = cos A·η + sin A·|ξ|.
    cos_sin_a: V2,
    /// s_min, m.
    s_min_m: f64,
    /// Smallest |q|², (Rt·10⁻⁶)².
    min_r2: f64,
    /// Lower bound of the distance from O to pieces 0, 1, 6, 7, 8, 9 (0 disables the
    /// bottom-of-gap rules).
    far_m: f64,
    /// Upper bound of R_L: Rt(1 − 10⁻³) (q well inside the seat circle, where the foot on
    /// the seat is well conditioned: at the seat bottom, where the owning half's window ends,
    /// foot and end point then give the same normal to ~10⁻¹³), the distance from O to the
    /// line c–y, and 2|c| sin A.
    free_m: f64,
    /// The seat bottom (0, −Rt).
    bottom: V2,
    /// Unit direction from c to y: the working curve's y edge.
    c_to_y: V2,
    /// Whether the free-space rule holds for this construction (checked at construction).
    free_rule: bool,
}

impl Shortcuts {
    /// The rules of a gap, each disabled when its preconditions do not hold.
    fn new(
        d: &AsaDimensions,
        g: &GapPoints,
        fast: &[FastPiece; 10],
        graph: Option<&SideGraph>,
    ) -> Shortcuts {
        let rt = d.seating_radius_m;
        let (sin_a, cos_a) = d.a_rad.sin_cos();
        let c_to_y = unit_or(sub(g.y_m, g.c_m), [1.0, 0.0]);
        let far = [0, 1, 6, 7, 8, 9]
            .iter()
            .filter_map(|&k| fast.get(k))
            .map(|f| f.near([0.0, 0.0], 0).dist_m)
            .fold(f64::INFINITY, f64::min)
            * (1.0 - 1e-12);
        // R_L must stay clear of the working curve's y edge (the line c–y), and below
        // 2|c| sin A (the other side's working foot is then farther than Rt).
        let c_len = norm(g.c_m);
        let o_from_c = neg(g.c_m);
        let y_edge_m = (c_to_y[0] * o_from_c[1] - c_to_y[1] * o_from_c[0]).abs();
        let x_on_line = {
            // c, O and x are collinear (x on the ray from c through O).
            let u = unit_or(g.x_m, [1.0, 0.0]);
            (u[0] * o_from_c[1] - u[1] * o_from_c[0]).abs() < 1e-12 * c_len
                && dot(u, o_from_c) > 0.0
        };
        let ok = far.is_finite()
            && g.x_m[0] > 0.0
            && g.x_m[1] < 0.0
            && cos_a > 0.0
            && sin_a > 0.0
            && x_on_line;
        Shortcuts {
            cos_sin_a: [cos_a, sin_a],
            s_min_m: JOINT_LINE_MARGIN * rt,
            min_r2: (1e-6 * rt) * (1e-6 * rt),
            far_m: if ok { far } else { 0.0 },
            free_m: (rt * (1.0 - 1e-3))
                .min(y_edge_m * (1.0 - 1e-9))
                .min(2.0 * c_len * sin_a * (1.0 - 1e-9)),
            bottom: [0.0, -rt],
            c_to_y,
            // The graph shape, a rising straight portion (so that it passes above the topping
            // circle's lower branch beyond z) and the topping circle reaching left of z.
            free_rule: graph.is_some()
                && g.z_m[1] > g.y_m[1]
                && g.b_m[0] - d.topping_radius_m < g.z_m[0],
        }
    }
}

/// The radius-dependent constants of the fast paths (see [`Shortcuts`]), computed once for
/// the profile's own roller and on the fly for any other radius.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Reach {
    /// Roller radius r.
    r: f64,
    /// r + [`SKIP_MARGIN_M`].
    reach: f64,
    /// (tip reach + reach)²: beyond it nothing is within reach.
    outer2: f64,
    /// (seat clearance − reach)², negative when the roller does not fit the seat.
    clear2: f64,
    /// R_L², 0 when the bottom-of-gap rules are off.
    low2: f64,
    /// (RE − reach)², negative when the free-space rule is off.
    re_in2: f64,
    /// (RF + reach)².
    rf_out2: f64,
}

impl Reach {
    /// The constants for a roller of radius `r` (finite, ≥ 0).
    #[inline]
    fn new(pr: &AsaProfile, r: f64) -> Reach {
        let reach = r + SKIP_MARGIN_M;
        let outer = pr.reach_radius_m + reach;
        let clear = pr.seat_clear_m - reach;
        let cut = &pr.cuts;
        let low = (cut.far_m - reach).min(cut.free_m);
        let rt = pr.dims.seating_radius_m;
        let re_in = pr.dims.working_radius_m - reach;
        let rf_out = pr.dims.topping_radius_m + reach;
        Reach {
            r,
            reach,
            outer2: outer * outer,
            clear2: if clear > 0.0 { clear * clear } else { -1.0 },
            low2: if low > 0.0 && reach < rt {
                low * low
            } else {
                0.0
            },
            re_in2: if cut.free_rule && re_in > 0.0 {
                re_in * re_in
            } else {
                -1.0
            },
            rf_out2: rf_out * rf_out,
        }
    }
}

/// The half outline of one gap (ξ ≥ 0: seat half, working curve, straight, topping) as a
/// graph η = h(ξ) over 0 ≤ ξ ≤ ξ_f, mirrored for ξ < 0. Within the gap's sector a vertical
/// line meets the outline once, so a point is in the material exactly when it lies below
/// the graph (points with |ξ| > ξ_f in the sector are above the tip, in free space).
#[derive(Clone, Copy, Debug, PartialEq)]
struct SideGraph {
    /// ξ of x, y, z and f.
    xi: [f64; 4],
    /// Rt².
    rt2: f64,
    /// Working-curve centre c (lower branch).
    c: V2,
    /// RE².
    re2: f64,
    /// y (start of the straight portion).
    y: V2,
    /// dη/dξ of the straight portion.
    slope: f64,
    /// Topping centre b (upper branch).
    b: V2,
    /// RF².
    rf2: f64,
}

/// Vertical distance from the graph below which [`SideGraph::is_free`] does not decide.
const GRAPH_TOL_M: f64 = 1e-9;

impl SideGraph {
    /// The graph of a gap, when the construction has the graph shape (checked, not
    /// assumed): ξ increasing through 0 < x < y < z < f, the seat and working arcs below
    /// their centres, the topping arc above its centre.
    fn new(d: &AsaDimensions, g: &GapPoints) -> Option<SideGraph> {
        let xi = [g.x_m[0], g.y_m[0], g.z_m[0], g.f_m[0]];
        let ordered = 0.0 < xi[0] && xi[0] < xi[1] && xi[1] < xi[2] && xi[2] < xi[3];
        let arcs_on_branch = g.x_m[1] < 0.0
            && g.x_m[1] < g.c_m[1]
            && g.y_m[1] < g.c_m[1]
            && g.z_m[1] > g.b_m[1]
            && g.f_m[1] > g.b_m[1];
        (ordered && arcs_on_branch).then(|| SideGraph {
            xi,
            rt2: d.seating_radius_m * d.seating_radius_m,
            c: g.c_m,
            re2: d.working_radius_m * d.working_radius_m,
            y: g.y_m,
            slope: (g.z_m[1] - g.y_m[1]) / (g.z_m[0] - g.y_m[0]),
            b: g.b_m,
            rf2: d.topping_radius_m * d.topping_radius_m,
        })
    }

    /// Some(true) in free space, Some(false) in the material, None within
    /// [`GRAPH_TOL_M`] of the outline. `q` is gap-local and in the gap's sector.
    #[inline]
    fn is_free(&self, q: V2) -> Option<bool> {
        let a = q[0].abs();
        if a > self.xi[3] {
            return Some(true);
        }
        let h = if a <= self.xi[0] {
            -(self.rt2 - a * a).max(0.0).sqrt()
        } else if a <= self.xi[1] {
            let u = a - self.c[0];
            self.c[1] - (self.re2 - u * u).max(0.0).sqrt()
        } else if a <= self.xi[2] {
            self.y[1] + (a - self.y[0]) * self.slope
        } else {
            let u = a - self.b[0];
            self.b[1] + (self.rf2 - u * u).max(0.0).sqrt()
        };
        if q[1] > h + GRAPH_TOL_M {
            Some(true)
        } else if q[1] < h - GRAPH_TOL_M {
            Some(false)
        } else {
            None
        }
    }
}

/// Margin added to the roller radius when a piece is skipped as far away. Much larger than
/// every rounding error and than [`CONSISTENCY_TOL_M`], so skipping never changes a result.
const SKIP_MARGIN_M: f64 = 1e-7;

/// Largest distance from `s` to the piece `f` (an arc's farthest point from `s` is on the ray
/// from `s` through the centre when that ray's direction lies in the window, else an end).
fn farthest_from(f: &FastPiece, s: V2) -> f64 {
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

impl AsaProfile {
    /// Builds the profile of a sprocket with `teeth` teeth for a chain of pitch `pitch_m`
    /// and roller diameter `roller_diameter_m` (metres).
    ///
    /// # Errors
    /// [`AsaError`] when the inputs are out of range or the standard construction
    /// degenerates (e.g. too few teeth for a positive straight portion).
    pub fn new(teeth: u32, pitch_m: f64, roller_diameter_m: f64) -> Result<Self, AsaError> {
        let dims = dimensions(teeth, pitch_m, roller_diameter_m)?;
        let points = gap_points(&dims)?;
        let own = gap_pieces(&dims, &points);
        let pitch_angle_rad = 2.0 * PI / f64::from(teeth);
        let rs = dims.pitch_radius_m;
        let next_area7 = own[0].mapped(neighbour_map(rs, pitch_angle_rad, 1), pitch_angle_rad, 1);
        let prev_area1 =
            own[7].mapped(neighbour_map(rs, pitch_angle_rad, -1), -pitch_angle_rad, -1);
        let gap_trig = (0..teeth)
            .map(|j| {
                let (s, c) = (pitch_angle_rad * f64::from(j)).sin_cos();
                [c, s]
            })
            .collect();
        let fast = [
            FastPiece::new(&own[0]),
            FastPiece::new(&own[1]),
            FastPiece::new(&own[2]),
            FastPiece::new(&own[3]),
            FastPiece::new(&own[4]),
            FastPiece::new(&own[5]),
            FastPiece::new(&own[6]),
            FastPiece::new(&own[7]),
            FastPiece::new(&prev_area1),
            FastPiece::new(&next_area7),
        ];
        let seat_clear_m = own
            .iter()
            .map(|piece| piece.closest([0.0, 0.0]).dist_m)
            .fold(f64::INFINITY, f64::min)
            * (1.0 - 1e-12);
        let sprocket_centre = [0.0, -rs];
        let reach_radius_m = fast[..8]
            .iter()
            .map(|f| farthest_from(f, sprocket_centre))
            .fold(0.0, f64::max)
            * (1.0 + 1e-12)
            + 1e-12;
        let graph = SideGraph::new(&dims, &points);
        let cuts = Shortcuts::new(&dims, &points, &fast, graph.as_ref());
        let mut profile = AsaProfile {
            dims,
            points,
            own,
            next_area7,
            prev_area1,
            gap_trig,
            pitch_angle_rad,
            fast,
            seat_clear_m,
            reach_radius_m,
            tan_half_pitch_inner: (0.5 * pitch_angle_rad).tan() * (1.0 - 1e-9),
            inv_pitch_angle: 1.0 / pitch_angle_rad,
            graph,
            cuts,
            nominal: Reach {
                r: 0.0,
                reach: 0.0,
                outer2: 0.0,
                clear2: -1.0,
                low2: 0.0,
                re_in2: -1.0,
                rf_out2: 0.0,
            },
        };
        profile.nominal = Reach::new(&profile, 0.5 * roller_diameter_m);
        Ok(profile)
    }

    /// The standard dimensions of this sprocket.
    #[must_use]
    pub fn dimensions(&self) -> &AsaDimensions {
        &self.dims
    }

    /// The construction points and angles of one gap (gap-local frame).
    #[must_use]
    pub fn gap_points(&self) -> &GapPoints {
        &self.points
    }

    /// Number of teeth N.
    #[must_use]
    pub fn teeth(&self) -> u32 {
        self.dims.teeth
    }

    /// Pitch angle Φ = 2π/N.
    #[must_use]
    pub fn pitch_angle_rad(&self) -> f64 {
        self.pitch_angle_rad
    }

    /// True when patches `a` and `b` meet at a tangent joint (z or z*: a gap's concave
    /// patch and one of its two teeth), or are the two flank patches of one gap, so a
    /// contact sliding from one to the other is the same contact continuing; the caller
    /// may carry its contact memory over.
    #[must_use]
    pub fn patches_are_neighbours(&self, a: u32, b: u32) -> bool {
        let n = u64::from(self.dims.teeth);
        let (a, b) = (u64::from(a), u64::from(b));
        let gap_of_concave = |id: u64| -> Option<u64> {
            if id < 2 * n && id % 2 == 0 {
                Some(id / 2)
            } else if (2 * n..3 * n).contains(&id) {
                Some(id - 2 * n)
            } else {
                None
            }
        };
        let tooth_of = |id: u64| (id < 2 * n && id % 2 == 1).then_some(id / 2);
        let touches = |gap: u64, tooth: u64| tooth == gap || (tooth + 1) % n == gap;
        match (
            gap_of_concave(a),
            gap_of_concave(b),
            tooth_of(a),
            tooth_of(b),
        ) {
            (Some(ga), Some(gb), _, _) => ga == gb && a != b,
            (Some(g), _, _, Some(t)) | (_, Some(g), Some(t), _) => touches(g, t),
            _ => false,
        }
    }

    /// Gap nearest to `p` in polar angle, 0..N.
    fn gap_index(&self, p: V2) -> usize {
        let n = i64::from(self.dims.teeth);
        let k = (p[1].atan2(p[0]) / self.pitch_angle_rad).round() as i64;
        k.rem_euclid(n) as usize
    }

    /// Gap whose sector holds `p`: the same as [`AsaProfile::gap_index`] (which is used
    /// whenever `p` is within a relative 1e-9 of a sector boundary), found without `atan2`
    /// by testing the cone of `hint` (or of an approximate polar angle) and its neighbours.
    #[inline(always)]
    fn gap_near(&self, p: V2, hint: u32) -> usize {
        // The roller is almost always still in its hinted gap: one cone test, inline.
        if let Some(&u) = self.gap_trig.get(hint as usize) {
            let along = dot(u, p);
            let across = u[0] * p[1] - u[1] * p[0];
            if along > 0.0 && across.abs() < self.tan_half_pitch_inner * along {
                return hint as usize;
            }
        }
        self.gap_search(p, hint)
    }

    /// [`AsaProfile::gap_near`] when `p` has left the hinted gap's cone.
    #[inline(never)]
    fn gap_search(&self, p: V2, hint: u32) -> usize {
        let n = self.gap_trig.len();
        let mut j = if (hint as usize) < n {
            hint as usize
        } else {
            // θ/Φ + N + ½ > 0, so the truncation is a floor: the nearest gap, modulo N.
            let k = (atan2_approx(p[1], p[0]) * self.inv_pitch_angle + (n as f64 + 0.5)) as usize;
            if k >= n { k - n } else { k }
        };
        for _ in 0..3 {
            let Some(&u) = self.gap_trig.get(j) else {
                break;
            };
            let along = dot(u, p);
            let across = u[0] * p[1] - u[1] * p[0];
            if along > 0.0 && across.abs() < self.tan_half_pitch_inner * along {
                return j;
            }
            if along.is_nan() || along <= 0.0 {
                break;
            }
            j = if across > 0.0 {
                if j + 1 == n { 0 } else { j + 1 }
            } else if j == 0 {
                n - 1
            } else {
                j - 1
            };
        }
        self.gap_index(p)
    }

    /// (cos ψ, sin ψ) of a gap.
    fn trig(&self, gap: usize) -> V2 {
        self.gap_trig.get(gap).copied().unwrap_or([1.0, 0.0])
    }

    /// Sprocket frame → gap-local frame (point).
    fn to_local(&self, gap: usize, p: V2) -> V2 {
        let [c, s] = self.trig(gap);
        [
            p[0] * s - p[1] * c,
            p[0] * c + p[1] * s - self.dims.pitch_radius_m,
        ]
    }

    /// Gap-local frame → sprocket frame (point).
    fn to_global_point(&self, gap: usize, q: V2) -> V2 {
        let [c, s] = self.trig(gap);
        let r = self.dims.pitch_radius_m + q[1];
        [r * c + q[0] * s, r * s - q[0] * c]
    }

    /// Gap-local frame → sprocket frame (direction).
    fn to_global_vec(&self, gap: usize, v: V2) -> V2 {
        let [c, s] = self.trig(gap);
        [v[1] * c + v[0] * s, v[1] * s - v[0] * c]
    }

    /// `gap + offset` modulo N, for |offset| ≤ 1.
    fn wrap_gap(&self, gap: usize, offset: i64) -> i64 {
        let n = i64::from(self.dims.teeth);
        let g = gap as i64 + offset;
        if g < 0 {
            g + n
        } else if g >= n {
            g - n
        } else {
            g
        }
    }

    /// All contact patches of a roller of radius `roller_radius_m` centred at `p` (sprocket
    /// frame, gap 0's seating centre at (Rs, 0), gaps numbered counter-clockwise). Writes at
    /// most 2 patches into `out` (deepest first) and returns how many.
    ///
    /// O(1): the gap comes from the polar angle of `p`; only that gap's pieces and the two
    /// neighbouring teeth (both toppings and the tip) are examined. No allocation, no
    /// trigonometry. Non-finite input, or a negative radius, gives 0 patches.
    /// [`AsaProfile::contacts_hinted`] is the same with a gap hint.
    ///
    /// Algorithm: the closest point of each of the four candidate patches (clockwise flank
    /// half, counter-clockwise flank half, tooth g, tooth g−1) is computed piece by piece
    /// (foot of the perpendicular when it falls on the span, else the nearer end). A patch
    /// whose closest point lies beyond a shared joint is dropped (the neighbour owns it). A
    /// patch is kept if depth > 0 and it is consistent with the nearest outline point of
    /// the whole sprocket (same side of the surface, not nearer), which removes the parts
    /// of the neighbouring topping circles that reach into this gap. The deepest patch is
    /// always the nearest outline point, so `depth = r − signed_distance(p)`.
    ///
    /// Speed: a roller outside the tip circle, or in the seat with clearance, is rejected
    /// after one or two products. At the bottom of the gap (seated, or rocked onto a working
    /// curve past x or x*) and in the free space of the gap, direct rules answer with at most
    /// one square root (`Shortcuts` in the source). Otherwise every piece that is provably farther than the
    /// radius (by its whole circle or line) is skipped. Once the nearest outline point is
    /// known to be in free space (from the nearest evaluated piece, or, when all pieces are
    /// far, from the outline seen as a graph over ξ), a skipped piece can change no result.
    /// A centre inside the material falls back to examining every piece.
    ///
    /// Not examined: the concave parts of the neighbouring gaps. A roller in free space
    /// could only reach them across a whole tooth, i.e. with a radius of the order of the
    /// tooth width.
    pub fn contacts(&self, p: [f64; 2], roller_radius_m: f64, out: &mut [Patch; 2]) -> usize {
        let mut hint = u32::MAX;
        self.contacts_hinted(p, roller_radius_m, &mut hint, out)
    }

    /// Exactly [`AsaProfile::contacts`], but the gap search starts at `hint` (a gap the
    /// roller was recently in; any value works, e.g. `u32::MAX` for none) and `hint` is
    /// updated to the gap of `p` whenever that gap is looked up (it is left unchanged when
    /// `p` is rejected before, e.g. beyond the tips or non-finite).
    pub fn contacts_hinted(
        &self,
        p: [f64; 2],
        roller_radius_m: f64,
        hint: &mut u32,
        out: &mut [Patch; 2],
    ) -> usize {
        if !(roller_radius_m.is_finite() && roller_radius_m >= 0.0) {
            return 0;
        }
        let mut emit = |slot: usize, gap: usize, f: Found| {
            if let Some(slot) = out.get_mut(slot) {
                *slot = Patch {
                    depth_m: f.depth_m,
                    normal: self.to_global_vec(gap, f.normal),
                    point: self.to_global_point(gap, f.point),
                    area: f.area,
                    gap: self.wrap_gap(gap, f.gap_offset),
                    patch_id: f.patch_id,
                };
            }
        };
        if roller_radius_m == self.nominal.r {
            self.query(p, &self.nominal, hint, &mut emit)
        } else {
            self.query(p, &Reach::new(self, roller_radius_m), hint, &mut emit)
        }
    }

    /// [`AsaProfile::contacts_hinted`] for the profile's own roller (radius Dr/2), written
    /// as the contact generator's [`super::Patch`] (no contact point): the same patches.
    #[inline]
    pub fn contacts_nominal(
        &self,
        p: [f64; 2],
        hint: &mut u32,
        out: &mut [super::Patch; super::MAX_PATCHES],
    ) -> usize {
        self.query(p, &self.nominal, hint, &mut |slot, gap, f: Found| {
            if let Some(slot) = out.get_mut(slot) {
                *slot = super::Patch {
                    depth_m: f.depth_m,
                    normal: self.to_global_vec(gap, f.normal),
                    area: f.area,
                    gap: self.wrap_gap(gap, f.gap_offset) as u32,
                    patch_id: f.patch_id,
                };
            }
        })
    }

    /// The patches of a roller centred at `p` (sprocket frame) in gap-local form, and the
    /// gap. The commonest cases first: beyond the tips, seated with clearance, the bottom of
    /// the gap, the free space of the gap ([`Shortcuts`]); then the general path.
    #[inline(always)]
    fn query(
        &self,
        p: V2,
        k: &Reach,
        hint: &mut u32,
        emit: &mut impl FnMut(usize, usize, Found),
    ) -> usize {
        // Beyond every tip by more than the radius: free space, nothing within reach. This
        // also rejects a non-finite `p` (the comparison is false for NaN).
        if !(dot(p, p) <= k.outer2) {
            return 0;
        }
        let gap = self.gap_near(p, *hint);
        *hint = gap as u32;
        let q = self.to_local(gap, p);
        // Seated with clearance: every piece is at least seat_clear_m − |q| away, and the
        // disc about O is free space.
        let r2 = dot(q, q);
        if r2 < k.clear2 {
            return 0;
        }
        let cut = &self.cuts;
        let s = cut.cos_sin_a[0] * q[1] + cut.cos_sin_a[1] * q[0].abs();
        if r2 < k.low2 && r2 >= cut.min_r2 {
            if let Some(hit) = self.bottom_of_gap(q, r2, s, k, 2 * gap as u32) {
                return match hit {
                    Some(f) => {
                        emit(0, gap, f);
                        1
                    }
                    None => 0,
                };
            }
        } else if k.re_in2 > 0.0 && self.in_free_gap(q, s, k) {
            return 0;
        }
        let mut found = [NONE; 2];
        let count = self.contacts_general(gap, q, k.r, &mut found);
        for (slot, f) in found[..count.min(2)].iter().enumerate() {
            emit(slot, gap, *f);
        }
        count
    }

    /// The bottom-of-gap rule of [`Shortcuts`]: `Some(patch)` when it decides (`Some(None)`:
    /// no contact).
    #[inline(always)]
    fn bottom_of_gap(
        &self,
        q: V2,
        r2: f64,
        s: f64,
        k: &Reach,
        patch_id: u32,
    ) -> Option<Option<Found>> {
        let cut = &self.cuts;
        // The seat-bottom joint gives ξ > 0 to pieces 2, 3, the rest to pieces 5, 4.
        let right = q[0] > 0.0;
        if s <= -cut.s_min_m {
            let seat = self.fast.get(if right { 3 } else { 4 })?;
            let len = r2.sqrt();
            let depth_m = k.r - (seat.radius_m - len);
            if !(depth_m > 0.0) {
                return Some(None);
            }
            let dir = [q[0] / len, q[1] / len];
            return Some(Some(Found {
                depth_m,
                normal: neg(dir),
                point: scale(dir, seat.radius_m),
                area: seat.area,
                gap_offset: 0,
                patch_id,
            }));
        }
        if s < cut.s_min_m {
            return None;
        }
        let arc = self.fast.get(if right { 2 } else { 5 })?;
        let d = sub(q, arc.centre);
        let len = dot(d, d).sqrt();
        let dist_m = arc.radius_m - len;
        // The seat bottom, the seat half's other end, must lose to the working foot (or be
        // out of reach when the foot is).
        let to_bottom = sub(q, cut.bottom);
        let lim = (dist_m + BOTTOM_MARGIN_M).min(k.reach);
        if !(dot(to_bottom, to_bottom) > lim * lim) {
            return None;
        }
        let depth_m = k.r - dist_m;
        if !(depth_m > 0.0) {
            return Some(None);
        }
        let dir = [d[0] / len, d[1] / len];
        Some(Some(Found {
            depth_m,
            normal: neg(dir),
            point: add(arc.centre, scale(dir, arc.radius_m)),
            area: arc.area,
            gap_offset: 0,
            patch_id,
        }))
    }

    /// The free-space rule of [`Shortcuts`]: true when no piece is within reach of `q`.
    #[inline(always)]
    fn in_free_gap(&self, q: V2, s: f64, k: &Reach) -> bool {
        // Outside the seat's wedge: s > 0 on one side at least, and s (taken with |ξ|) is
        // the larger of the two sides' values.
        s > 0.0 && self.clear_of_side(q, k) && self.clear_of_side(mirror(q), k)
    }

    /// The lower bounds of the free-space rule against the right side's straight portion,
    /// topping and working curve (the left side is its mirror image).
    #[inline(always)]
    fn clear_of_side(&self, q: V2, k: &Reach) -> bool {
        let [topping, straight, working] = [&self.fast[0], &self.fast[1], &self.fast[2]];
        if !(dot(sub(q, straight.start), straight.n_free[0]) > k.reach) {
            return false;
        }
        let b = sub(q, topping.centre);
        if !(dot(b, b) > k.rf_out2) {
            return false;
        }
        let c = sub(q, working.centre);
        let y = self.cuts.c_to_y;
        let beyond_y = dot(c, working.mid_dir) > 0.0 && y[0] * c[1] - y[1] * c[0] > 0.0;
        beyond_y || dot(c, c) < k.re_in2
    }

    /// The contacts of a roller centred at the gap-local point `q` of `gap`'s sector, with
    /// the pieces farther than the radius skipped (see [`AsaProfile::contacts`]).
    #[inline(never)]
    fn contacts_general(
        &self,
        gap: usize,
        q: V2,
        roller_radius_m: f64,
        out: &mut [Found; 2],
    ) -> usize {
        let reach = roller_radius_m + SKIP_MARGIN_M;
        let f = &self.fast;
        let own = [
            f[0].eval(q, reach, 0),
            f[1].eval(q, reach, 1),
            f[2].eval(q, reach, 2),
            f[3].eval(q, reach, 3),
            f[4].eval(q, reach, 4),
            f[5].eval(q, reach, 5),
            f[6].eval(q, reach, 6),
            f[7].eval(q, reach, 7),
        ];
        let nearest = nearest_near(&own);
        // A skipped piece is farther than `reach`, so the nearest evaluated piece is the
        // nearest of all when it is within `reach`.
        if nearest.dist_m.is_nan() || nearest.dist_m > reach {
            // Every piece is farther than `reach`: no contact in free space.
            return match self.graph.and_then(|g| g.is_free(q)) {
                Some(true) => 0,
                _ => self.contacts_all(gap, q, roller_radius_m, out),
            };
        }
        // Inside the material a skipped piece could hide a deeper one: examine all.
        if nearest.sd_m < 0.0 {
            return self.contacts_all(gap, q, roller_radius_m, out);
        }
        // In free space a skipped piece is never a patch, and every run whose nearest piece
        // is skipped has no patch either (its nearest piece is farther than the radius).
        let prev_area1 = f[8].eval(q, reach, 8);
        let next_area7 = f[9].eval(q, reach, 9);
        self.finish(
            gap,
            q,
            &own,
            [prev_area1, next_area7],
            nearest.sd_m,
            roller_radius_m,
            out,
        )
    }

    /// The contacts with every piece examined (centre inside the material, or undecided).
    #[cold]
    #[inline(never)]
    fn contacts_all(&self, gap: usize, q: V2, roller_radius_m: f64, out: &mut [Found; 2]) -> usize {
        let mut all = [FAR; 10];
        for (k, (slot, f)) in all.iter_mut().zip(&self.fast).enumerate() {
            *slot = f.near(q, k as u8);
        }
        let own = [
            all[0], all[1], all[2], all[3], all[4], all[5], all[6], all[7],
        ];
        let nearest = nearest_near(&own).sd_m;
        self.finish(
            gap,
            q,
            &own,
            [all[8], all[9]],
            nearest,
            roller_radius_m,
            out,
        )
    }

    /// Patch selection from the results of the own pieces and of the neighbouring
    /// toppings `[prev_area1, next_area7]`, the signed distance `nearest` of the nearest own
    /// piece, and the radius; writes the patches (gap-local).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn finish(
        &self,
        gap: usize,
        q: V2,
        own: &[Near; 8],
        neighbours: [Near; 2],
        nearest: f64,
        roller_radius_m: f64,
        out: &mut [Found; 2],
    ) -> usize {
        let n = self.dims.teeth;
        let g = gap as u32;
        let prev_tooth = if g == 0 { n - 1 } else { g - 1 };
        // Own piece first, so a roller over a tip is labelled with the area on its side.
        let cw_tooth = [own[0], neighbours[0]];
        let ccw_tooth = [own[7], neighbours[1]];
        // The nearest point of the whole outline lies in p's sector (own pieces). No genuine
        // local minimum can be nearer, or on the other side of the surface; this rejects the
        // insides of the neighbouring topping circles, which reach into this gap.
        let consistent = |sd: f64| {
            if nearest >= 0.0 {
                sd >= nearest - CONSISTENCY_TOL_M
            } else {
                sd <= nearest + CONSISTENCY_TOL_M
            }
        };
        let in_contact = |h: Option<Near>| {
            h.filter(|h| h.sd_m.is_finite() && roller_radius_m - h.sd_m > 0.0 && consistent(h.sd_m))
        };
        let right = in_contact(patch_near(&own[1..4]));
        let left = in_contact(patch_near(&own[4..7]));
        let left_id = if right.is_some() { 2 * n + g } else { 2 * g };
        let candidates = [
            (right, 2 * g),
            (left, left_id),
            (in_contact(patch_near(&ccw_tooth)), 2 * g + 1),
            (in_contact(patch_near(&cw_tooth)), 2 * prev_tooth + 1),
        ];
        let mut best: [Option<(Near, u32)>; 2] = [None, None];
        for (hit, id) in candidates {
            let Some(h) = hit else { continue };
            insert_deepest_near(&mut best, (h, id));
        }
        let mut written = 0;
        for (h, id) in best.into_iter().flatten() {
            let Some(piece) = self.fast.get(usize::from(h.piece)) else {
                continue;
            };
            let (point, normal) = piece.geometry(q, h.mode);
            if let Some(slot) = out.get_mut(written) {
                *slot = Found {
                    depth_m: roller_radius_m - h.sd_m,
                    normal,
                    point,
                    area: piece.area,
                    gap_offset: piece.gap_offset,
                    patch_id: id,
                };
                written += 1;
            }
        }
        written
    }

    /// The previous implementation of [`AsaProfile::contacts`] (one `atan2` for the gap and
    /// one per arc piece, no skipping), kept as the oracle of the fast one.
    #[cfg(test)]
    fn contacts_reference(&self, p: [f64; 2], roller_radius_m: f64, out: &mut [Patch; 2]) -> usize {
        if !(p[0].is_finite() && p[1].is_finite() && roller_radius_m.is_finite())
            || roller_radius_m < 0.0
        {
            return 0;
        }
        let gap = self.gap_index(p);
        let q = self.to_local(gap, p);
        let n = self.dims.teeth;
        let g = gap as u32;
        let prev_tooth = (g + n - 1) % n;
        let own = self.own.map(|piece| piece.closest(q));
        // Own piece first, so a roller over a tip is labelled with the area on its side.
        let cw_tooth = [own[0], self.prev_area1.closest(q)];
        let ccw_tooth = [own[7], self.next_area7.closest(q)];
        // The nearest point of the whole outline lies in p's sector (own pieces). No genuine
        // local minimum can be nearer, or on the other side of the surface; this rejects the
        // insides of the neighbouring topping circles, which reach into this gap.
        let nearest = nearest_hit(&own).sd_m;
        let consistent = |sd: f64| {
            if nearest >= 0.0 {
                sd >= nearest - CONSISTENCY_TOL_M
            } else {
                sd <= nearest + CONSISTENCY_TOL_M
            }
        };
        let in_contact = |h: Option<Hit>| {
            h.filter(|h| h.sd_m.is_finite() && roller_radius_m - h.sd_m > 0.0 && consistent(h.sd_m))
        };
        let right = in_contact(patch_hit(&own[1..4]));
        let left = in_contact(patch_hit(&own[4..7]));
        let left_id = if right.is_some() { 2 * n + g } else { 2 * g };
        let candidates = [
            (right, 2 * g),
            (left, left_id),
            (in_contact(patch_hit(&ccw_tooth)), 2 * g + 1),
            (in_contact(patch_hit(&cw_tooth)), 2 * prev_tooth + 1),
        ];
        let mut best: [Option<(Hit, u32)>; 2] = [None, None];
        for (hit, id) in candidates {
            let Some(h) = hit else { continue };
            insert_deepest(&mut best, (h, id));
        }
        let mut written = 0;
        for (h, id) in best.into_iter().flatten() {
            if let Some(slot) = out.get_mut(written) {
                *slot = Patch {
                    depth_m: roller_radius_m - h.sd_m,
                    normal: self.to_global_vec(gap, h.normal),
                    point: self.to_global_point(gap, h.point),
                    area: h.area,
                    gap: self.wrap_gap(gap, h.gap_offset),
                    patch_id: id,
                };
                written += 1;
            }
        }
        written
    }

    /// Which step of [`AsaProfile::query`] decides `p`: 0 an early exit (beyond the tips,
    /// seated with clearance), 1 the bottom-of-gap rule, 2 the free-space rule, 3 the
    /// general path.
    #[cfg(test)]
    fn rule_of(&self, p: [f64; 2], roller_radius_m: f64) -> usize {
        let k = Reach::new(self, roller_radius_m);
        if !(dot(p, p) <= k.outer2) {
            return 0;
        }
        let gap = self.gap_index(p);
        let q = self.to_local(gap, p);
        let r2 = dot(q, q);
        if r2 < k.clear2 {
            return 0;
        }
        let cut = &self.cuts;
        let s = cut.cos_sin_a[0] * q[1] + cut.cos_sin_a[1] * q[0].abs();
        if r2 < k.low2 && r2 >= cut.min_r2 {
            if self.bottom_of_gap(q, r2, s, &k, 0).is_some() {
                return 1;
            }
        } else if k.re_in2 > 0.0 && self.in_free_gap(q, s, &k) {
            return 2;
        }
        3
    }

    /// Signed distance from `p` (sprocket frame) to the outline: positive in free space,
    /// negative inside the material. Returns (distance, closest point, area, gap).
    /// Non-finite input returns (NaN, [NaN, NaN], 0, 0).
    #[must_use]
    pub fn signed_distance(&self, p: [f64; 2]) -> (f64, [f64; 2], u8, i64) {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return (f64::NAN, [f64::NAN; 2], 0, 0);
        }
        let gap = self.gap_index(p);
        let best = self.nearest_own(self.to_local(gap, p));
        (
            best.sd_m,
            self.to_global_point(gap, best.point),
            best.area,
            gap as i64,
        )
    }

    /// Nearest point of the whole outline to the gap-local point `q`, `q` in this gap's
    /// sector. The sector is a union of two mirror half-sectors of the dihedral symmetry,
    /// so the nearest outline point lies on this gap's own pieces.
    fn nearest_own(&self, q: V2) -> Hit {
        nearest_hit(&self.own.map(|piece| piece.closest(q)))
    }

    /// The whole sprocket outline in the sprocket frame, counter-clockwise, starting at the
    /// tip f of gap 0. Every piece is sampled: arcs at angular steps ≤ `max_step_rad`,
    /// straight portions at length steps ≤ `max_step_rad`·RE. The outline is closed: the
    /// last point connects back to the first (not repeated). `max_step_rad` is clamped to
    /// [[`MIN_OUTLINE_STEP_RAD`], π/8]; a non-finite or non-positive step uses 1°.
    #[must_use]
    pub fn outline(&self, max_step_rad: f64) -> Vec<OutlinePoint> {
        let step = if max_step_rad.is_finite() && max_step_rad > 0.0 {
            max_step_rad.clamp(MIN_OUTLINE_STEP_RAD, PI / 8.0)
        } else {
            PI / 180.0
        };
        let straight_step_m = step * self.dims.working_radius_m;
        let mut local = Vec::new();
        let mut out = Vec::new();
        for gap in 0..self.gap_trig.len() {
            for piece in &self.own {
                local.clear();
                piece.sample(step, straight_step_m, &mut local);
                out.extend(local.iter().map(|&q| {
                    let [x_m, y_m] = self.to_global_point(gap, q);
                    OutlinePoint {
                        x_m,
                        y_m,
                        gap: gap as i64,
                        area: piece.area,
                    }
                }));
            }
        }
        out
    }
}

/// Keeps the two deepest (largest r − sd, i.e. smallest sd) candidates, deepest first.
#[cfg(test)]
fn insert_deepest(best: &mut [Option<(Hit, u32)>; 2], c: (Hit, u32)) {
    let deeper = |a: &(Hit, u32), b: &Option<(Hit, u32)>| b.is_none_or(|b| a.0.sd_m < b.0.sd_m);
    if deeper(&c, &best[0]) {
        best[1] = best[0];
        best[0] = Some(c);
    } else if deeper(&c, &best[1]) {
        best[1] = Some(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: f64 = 0.0889;
    const DR: f64 = 0.054;
    const RR: f64 = 0.027;
    /// Half a unit in the 4th printed decimal (plus rounding slack).
    const HALF_E4: f64 = 0.5e-4 + 1e-9;

    fn profile(n: u32) -> AsaProfile {
        match AsaProfile::new(n, P, DR) {
            Ok(p) => p,
            Err(e) => panic!("profile N={n}: {e}"),
        }
    }

    fn check(what: &str, got: f64, want: f64, tol: f64) {
        assert!(
            (got - want).abs() <= tol,
            "{what}: got {got}, want {want} (tol {tol}, diff {})",
            got - want
        );
    }
    fn mm(what: &str, got_m: f64, want_mm: f64) {
        check(what, got_m * 1e3, want_mm, HALF_E4);
    }
    fn mm2(what: &str, got_m: V2, want_mm: [f64; 2]) {
        mm(&format!("{what}.ξ"), got_m[0], want_mm[0]);
        mm(&format!("{what}.η"), got_m[1], want_mm[1]);
    }
    fn deg(what: &str, got_rad: f64, want_deg: f64) {
        check(what, got_rad.to_degrees(), want_deg, HALF_E4);
    }

    /// One column of the §4 table (lengths mm, angles deg).
    struct Column {
        n: u32,
        abc: [f64; 3],
        alpha: f64,
        rs: f64,
        rt: f64,
        dr_clear: f64,
        mt: [f64; 2],
        re: f64,
        wv: [f64; 2],
        rf: f64,
        hs: [f64; 2],
        xy_yz: [f64; 2],
        x: [f64; 2],
        y: [f64; 2],
        z: [f64; 2],
        f: [f64; 2],
        th_a: [f64; 2],
        th_c: [f64; 2],
        th_c_star: [f64; 2],
        th_b: [f64; 2],
        th_b_star: [f64; 2],
        sweep: f64,
        root: f64,
        tip: f64,
    }

    fn table() -> [Column; 3] {
        [
            Column {
                n: 60,
                abc: [36.0, 17.0667, 15.9333],
                alpha: 33.0,
                rs: 849.3205,
                rt: 27.1731,
                dr_clear: 0.1731,
                mt: [34.9495, 25.3923],
                re: 70.3731,
                wv: [75.4964, 3.9566],
                rf: 43.6201,
                hs: [30.5351, 45.9872],
                xy_yz: [20.8846, 8.0751],
                x: [21.9835, -15.9719],
                y: [31.6162, 2.5585],
                z: [34.2363, 10.1967],
                f: [45.9872, 28.1669],
                th_a: [216.0, 324.0],
                th_c: [324.0, 341.0667],
                th_c_star: [198.9333, 216.0],
                th_b: [132.5711, 161.0667],
                th_b_star: [18.9333, 47.4289],
                sweep: 28.4955,
                root: 822.1474,
                tip: 878.6916,
            },
            Column {
                n: 30,
                abc: [37.0, 16.1333, 14.8667],
                alpha: 31.0,
                rs: 425.2430,
                rt: 27.1731,
                dr_clear: 0.1731,
                mt: [34.5011, 25.9984],
                re: 70.3731,
                wv: [75.1859, 7.9024],
                rf: 44.1949,
                hs: [31.3507, 47.4835],
                xy_yz: [19.7502, 7.3926],
                x: [21.7014, -16.3532],
                y: [31.2564, 0.9319],
                z: [33.8896, 7.8396],
                f: [47.4835, 26.5327],
                th_a: [217.0, 323.0],
                th_c: [323.0, 339.1333],
                th_c_star: [200.8667, 217.0],
                th_b: [128.8160, 159.1333],
                th_b_star: [20.8667, 51.1840],
                sweep: 30.3173,
                root: 398.0699,
                tip: 454.2642,
            },
            Column {
                n: 28,
                abc: [37.1429, 16.0, 14.7143],
                alpha: 30.7143,
                rs: 397.0009,
                rt: 27.1731,
                dr_clear: 0.1731,
                mt: [34.4361, 26.0844],
                re: 70.3731,
                wv: [75.1246, 8.4645],
                rf: 44.2741,
                hs: [31.4622, 47.6932],
                xy_yz: [19.5881, 7.2948],
                x: [21.6606, -16.4072],
                y: [31.1997, 0.7012],
                z: [33.8309, 7.5049],
                f: [47.6932, 26.2876],
                th_a: [217.1429, 322.8571],
                th_c: [322.8571, 338.8571],
                th_c_star: [201.1429, 217.1429],
                th_b: [128.2857, 158.8571],
                th_b_star: [21.1429, 51.7143],
                sweep: 30.5714,
                root: 369.8278,
                tip: 425.9669,
            },
        ]
    }

    #[test]
    fn dimension_tables_of_section_4() {
        for col in table() {
            let pr = profile(col.n);
            let d = pr.dimensions();
            let g = pr.gap_points();
            let tag = |s: &str| format!("N={} {s}", col.n);
            assert_eq!(d.teeth, col.n);
            deg(&tag("A"), d.a_rad, col.abc[0]);
            deg(&tag("B"), d.b_rad, col.abc[1]);
            deg(&tag("C"), d.c_rad, col.abc[2]);
            deg(&tag("alpha"), d.pressure_angle_rad, col.alpha);
            mm(&tag("Rs"), d.pitch_radius_m, col.rs);
            mm(&tag("Rt"), d.seating_radius_m, col.rt);
            mm(&tag("dR"), d.clearance_m, col.dr_clear);
            mm(&tag("M"), d.m_m, col.mt[0]);
            mm(&tag("T"), d.t_m, col.mt[1]);
            mm(&tag("RE"), d.working_radius_m, col.re);
            mm(&tag("W"), d.w_m, col.wv[0]);
            mm(&tag("V"), d.v_m, col.wv[1]);
            mm(&tag("RF"), d.topping_radius_m, col.rf);
            mm(&tag("H"), d.h_m, col.hs[0]);
            mm(&tag("S"), d.s_m, col.hs[1]);
            mm(&tag("xy"), d.working_chord_m, col.xy_yz[0]);
            mm(&tag("yz"), d.straight_length_m, col.xy_yz[1]);
            mm2(&tag("x"), g.x_m, col.x);
            mm2(&tag("y"), g.y_m, col.y);
            mm2(&tag("z"), g.z_m, col.z);
            mm2(&tag("f"), g.f_m, col.f);
            deg(&tag("th1a"), g.theta_1a_rad, col.th_a[0]);
            deg(&tag("th2a"), g.theta_2a_rad, col.th_a[1]);
            deg(&tag("th1c"), g.theta_1c_rad, col.th_c[0]);
            deg(&tag("th2c"), g.theta_2c_rad, col.th_c[1]);
            deg(&tag("th1c*"), g.theta_1c_star_rad, col.th_c_star[0]);
            deg(&tag("th2c*"), g.theta_2c_star_rad, col.th_c_star[1]);
            deg(&tag("th1b"), g.theta_1b_rad, col.th_b[0]);
            deg(&tag("th2b"), g.theta_2b_rad, col.th_b[1]);
            deg(&tag("th1b*"), g.theta_1b_star_rad, col.th_b_star[0]);
            deg(&tag("th2b*"), g.theta_2b_star_rad, col.th_b_star[1]);
            deg(&tag("sweep"), g.topping_sweep_rad, col.sweep);
            mm(&tag("root"), d.root_radius_m, col.root);
            mm(&tag("tip"), d.tip_radius_m, col.tip);
            // Derived identities of §1.
            let phi = PI / f64::from(col.n);
            check(&tag("C=A-B-phi"), d.c_rad, d.a_rad - d.b_rad - phi, 1e-15);
            check(
                &tag("alpha=A-phi"),
                d.pressure_angle_rad,
                d.a_rad - phi,
                1e-15,
            );
            check(
                &tag("RE=0.8Dr+Rt"),
                d.working_radius_m,
                0.8 * DR + d.seating_radius_m,
                1e-15,
            );
            check(
                &tag("|x-y|=xy"),
                norm(sub(g.x_m, g.y_m)),
                d.working_chord_m,
                1e-14,
            );
            check(
                &tag("|y-z|=yz"),
                norm(sub(g.y_m, g.z_m)),
                d.straight_length_m,
                1e-14,
            );
            check(
                &tag("|f-b|=RF"),
                norm(sub(g.f_m, g.b_m)),
                d.topping_radius_m,
                1e-14,
            );
            // Truncated OD/2 of the table's last row is not used, but check the formula.
            let od2 = P * (0.6 + 1.0 / phi.tan()) / 2.0;
            let want = match col.n {
                60 => 874.8265,
                30 => 449.5835,
                _ => 421.1747,
            };
            mm(&tag("OD/2"), od2, want);
        }
    }

    #[test]
    fn aca_gears_ids_number_80_n28_in_inches() {
        let inch = 0.0254;
        let pr = match AsaProfile::new(28, inch, 0.625 * inch) {
            Ok(p) => p,
            Err(e) => panic!("#80: {e}"),
        };
        let d = pr.dimensions();
        let tol = HALF_E4;
        let i = |x: f64| x / inch;
        check("B deg", d.b_rad.to_degrees(), 16.0, tol);
        check("ab", 1.4 * i(d.roller_diameter_m), 0.8750, tol);
        check("W", i(d.w_m), 0.8695, tol);
        check("V", i(d.v_m), 0.0980, tol);
        check("F", i(d.topping_radius_m), 0.5114, tol);
        check("H", i(d.h_m), 0.3477, tol);
        check("S", i(d.s_m), 0.5358, tol);
        check("yz", i(d.straight_length_m), 0.0844, tol);
        check("xy", i(d.working_chord_m), 0.2270, tol);
        check("M", i(d.m_m), 0.3986, tol);
        check("T", i(d.t_m), 0.3019, tol);
        check("E", i(d.working_radius_m), 0.8156, tol);
        check("Ds", 2.0 * i(d.seating_radius_m), 0.6311, tol);
        check("PD", 2.0 * i(d.pitch_radius_m), 8.9314, tol);
    }

    fn arc_point(piece: &Piece, at_end: bool) -> V2 {
        match piece.shape {
            Shape::Arc {
                centre,
                radius_m,
                start_rad,
                sweep_rad,
            } => {
                let a = if at_end {
                    start_rad + sweep_rad
                } else {
                    start_rad
                };
                add(centre, scale(polar(a), radius_m))
            }
            Shape::Segment => {
                if at_end {
                    piece.end
                } else {
                    piece.start
                }
            }
        }
    }

    #[test]
    fn joints_continuous_and_tangent() {
        for n in [60, 30, 28, 17, 10] {
            let pr = profile(n);
            let own = &pr.own;
            for piece in own.iter().chain([&pr.next_area7, &pr.prev_area1]) {
                // Stored end points agree with the arc formula.
                check(
                    "start",
                    norm(sub(arc_point(piece, false), piece.start)),
                    0.0,
                    1e-14,
                );
                check(
                    "end",
                    norm(sub(arc_point(piece, true), piece.end)),
                    0.0,
                    1e-14,
                );
            }
            for w in own.windows(2) {
                let (a, b) = (&w[0], &w[1]);
                let tag = format!("N={n} areas {}->{}", a.area, b.area);
                check(&tag, norm(sub(a.end, b.start)), 0.0, 1e-14);
                let ta = a.tangent(true);
                let tb = b.tangent(false);
                check(
                    &format!("{tag} tangent"),
                    ta[0] * tb[1] - ta[1] * tb[0],
                    0.0,
                    1e-12,
                );
                assert!(dot(ta, tb) > 0.999_999, "{tag}: tangent reversed");
            }
            // Tip: area 1 of this gap ends where area 7 of the next gap starts.
            check(
                "tip",
                norm(sub(own[7].end, pr.next_area7.start)),
                0.0,
                1e-12,
            );
            check(
                "tip'",
                norm(sub(pr.prev_area1.end, own[0].start)),
                0.0,
                1e-12,
            );
            // The tip is a convex corner: the walk turns left there.
            let t1 = own[7].tangent(true);
            let t7 = pr.next_area7.tangent(false);
            assert!(t1[0] * t7[1] - t1[1] * t7[0] > 0.0, "N={n}: tip not convex");
            // The tip lies on the tooth centreline at the tip radius.
            let f_global = pr.to_global_point(0, own[0].start);
            let d = pr.dimensions();
            check("tip radius", norm(f_global), d.tip_radius_m, 1e-12);
            let want_angle = -PI / f64::from(n);
            check(
                "tip angle",
                f_global[1].atan2(f_global[0]),
                want_angle,
                1e-14,
            );
        }
    }

    #[test]
    fn outline_is_closed_and_ordered() {
        let pr = profile(28);
        let step = 0.01;
        let pts = pr.outline(step);
        let max_gap = step * pr.dimensions().working_radius_m * 1.0001;
        let n = pts.len();
        let mut turning = 0.0;
        for k in 0..n {
            let a = pts[k];
            let b = pts[(k + 1) % n];
            let c = pts[(k + 2) % n];
            let ab = [b.x_m - a.x_m, b.y_m - a.y_m];
            let bc = [c.x_m - b.x_m, c.y_m - b.y_m];
            assert!(norm(ab) <= max_gap, "step {k} too long: {}", norm(ab));
            assert!(norm(ab) > 0.0, "repeated point at {k}");
            turning += (ab[0] * bc[1] - ab[1] * bc[0]).atan2(dot(ab, bc));
            assert!((1..=7).contains(&a.area) && (0..28).contains(&a.gap));
        }
        // One counter-clockwise turn.
        check("total turning", turning, 2.0 * PI, 1e-9);
        // Area order within each gap: 7, 6, 5, 4, 3, 2, 1.
        let mut last = (0_i64, 8_u8);
        for pt in &pts {
            if pt.gap == last.0 {
                assert!(pt.area <= last.1, "area order broken at gap {}", pt.gap);
            } else {
                assert_eq!(pt.gap, last.0 + 1);
                assert_eq!(pt.area, 7);
            }
            last = (pt.gap, pt.area);
        }
        // Non-finite and tiny steps are guarded.
        assert!(!pr.outline(f64::NAN).is_empty());
        assert!(!pr.outline(-1.0).is_empty());
    }

    /// Simple LCG in [0, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
    }

    fn seg_dist(p: V2, a: V2, b: V2) -> f64 {
        let e = sub(b, a);
        let l2 = dot(e, e);
        let t = if l2 > 0.0 {
            (dot(sub(p, a), e) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        norm(sub(p, add(a, scale(e, t))))
    }

    /// Even-odd test against the polygon.
    fn inside(p: V2, poly: &[V2]) -> bool {
        let mut c = false;
        let n = poly.len();
        for k in 0..n {
            let a = poly[k];
            let b = poly[(k + 1) % n];
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    c = !c;
                }
            }
        }
        c
    }

    #[test]
    fn signed_distance_matches_brute_force_oracle() {
        let pr = profile(28);
        let step = 2e-4;
        let poly: Vec<V2> = pr.outline(step).iter().map(|q| [q.x_m, q.y_m]).collect();
        // Chord sag of the coarsest arc (RE) bounds the polyline error.
        let tol = pr.dimensions().working_radius_m * step * step / 8.0 * 1.5 + 1e-12;
        let d = pr.dimensions();
        let mut rng = Lcg(12345);
        for _ in 0..300 {
            let r = rng.range(d.root_radius_m - 0.03, d.tip_radius_m + 0.03);
            let a = rng.range(-PI, PI);
            let p = [r * a.cos(), r * a.sin()];
            let (sd, q, area, gap) = pr.signed_distance(p);
            let brute = poly
                .iter()
                .zip(poly.iter().cycle().skip(1))
                .map(|(&a, &b)| seg_dist(p, a, b))
                .fold(f64::INFINITY, f64::min);
            check("|sd| vs brute", sd.abs(), brute, tol);
            check("|p-q| = |sd|", norm(sub(p, q)), sd.abs(), 1e-12);
            if sd.abs() > 10.0 * tol {
                let material = inside(p, &poly);
                assert_eq!(sd < 0.0, material, "sign at {p:?}: sd {sd}");
            }
            assert!((1..=7).contains(&area) && (0..28).contains(&gap));
            // The contact with a zero-radius probe is consistent with the distance.
            let mut out = [empty_patch(); 2];
            let k = pr.contacts(p, 0.0, &mut out);
            assert_eq!(k > 0, sd < 0.0, "probe at {p:?}");
            if k > 0 {
                check("probe depth", out[0].depth_m, -sd, 1e-12);
            }
            // A roller of random size: the deepest patch is the nearest outline point, and
            // every patch is a local minimum of the distance to the (sampled) outline.
            let r = rng.range(0.0, 0.045);
            let k = pr.contacts(p, r, &mut out);
            assert_eq!(k > 0, sd < r, "roller at {p:?} r {r}");
            if k > 0 {
                check("deepest = nearest", out[0].depth_m, r - sd, 1e-12);
            }
            for x in &out[..k] {
                let (sq, _, _, _) = pr.signed_distance(x.point);
                check("patch point on outline", sq, 0.0, 1e-12);
                let dq = norm(sub(p, x.point));
                if sd > 0.0 {
                    check("depth = r - |p-q|", x.depth_m, r - dq, 1e-12);
                }
                let near_closer = poly
                    .iter()
                    .zip(poly.iter().cycle().skip(1))
                    .filter(|(a, _)| norm(sub(**a, x.point)) < 2e-3)
                    .any(|(&a, &b)| seg_dist(p, a, b) < dq - tol);
                assert!(!near_closer, "patch {x:?} of {p:?} is no local minimum");
            }
        }
    }

    fn empty_patch() -> Patch {
        Patch {
            depth_m: 0.0,
            normal: [0.0; 2],
            point: [0.0; 2],
            area: 0,
            gap: 0,
            patch_id: 0,
        }
    }

    fn contacts(pr: &AsaProfile, p: V2, r: f64) -> Vec<Patch> {
        let mut out = [empty_patch(); 2];
        let k = pr.contacts(p, r, &mut out);
        out[..k].to_vec()
    }

    #[test]
    fn seated_roller() {
        for n in [60, 30, 28] {
            let pr = profile(n);
            let d = pr.dimensions();
            let rs = d.pitch_radius_m;
            // Centred on the seating centre: clearance all round, no contact.
            assert!(contacts(&pr, [rs, 0.0], RR).is_empty());
            let (sd, _, area, gap) = pr.signed_distance([rs, 0.0]);
            check("sd at O", sd, d.seating_radius_m, 1e-15);
            // O is equidistant from the whole seat and from x, x* on the working curves.
            assert!((3..=5).contains(&area) && gap == 0);
            // Just touching after moving by ΔR, depth d after ΔR + d.
            for depth in [1e-6, 1e-4, 1e-3] {
                let c = contacts(&pr, [rs - d.clearance_m - depth, 0.0], RR);
                assert_eq!(c.len(), 1);
                check("depth", c[0].depth_m, depth, 1e-14);
                check("nx", c[0].normal[0], 1.0, 1e-15);
                check("ny", c[0].normal[1], 0.0, 1e-15);
                check("px", c[0].point[0], d.root_radius_m, 1e-14);
                check("py", c[0].point[1], 0.0, 1e-15);
                assert_eq!((c[0].area, c[0].gap, c[0].patch_id), (4, 0, 0));
            }
            // Same in gap 5, rotated.
            let psi = 5.0 * pr.pitch_angle_rad();
            let r = rs - d.clearance_m - 1e-4;
            let c = contacts(&pr, [r * psi.cos(), r * psi.sin()], RR);
            assert_eq!(c.len(), 1);
            check("depth gap 5", c[0].depth_m, 1e-4, 1e-13);
            check(
                "n gap 5",
                dot(c[0].normal, [psi.cos(), psi.sin()]),
                1.0,
                1e-14,
            );
            assert_eq!((c[0].gap, c[0].patch_id), (5, 10));
        }
    }

    fn rotate(v: V2, a: f64) -> V2 {
        let (s, c) = a.sin_cos();
        [c * v[0] - s * v[1], s * v[0] + c * v[1]]
    }

    fn random_point(rng: &mut Lcg, d: &AsaDimensions) -> V2 {
        let r = rng.range(d.root_radius_m - 0.01, d.tip_radius_m + 0.03);
        let a = rng.range(-PI, PI);
        [r * a.cos(), r * a.sin()]
    }

    #[test]
    fn rotational_symmetry() {
        let pr = profile(30);
        let n = 30_i64;
        let phi_p = pr.pitch_angle_rad();
        let d = pr.dimensions().clone();
        let mut rng = Lcg(7);
        let mut seen = 0;
        for _ in 0..4000 {
            let p = random_point(&mut rng, &d);
            let a = contacts(&pr, p, RR);
            let b = contacts(&pr, rotate(p, phi_p), RR);
            assert_eq!(a.len(), b.len(), "at {p:?}");
            seen += a.len();
            for (x, y) in a.iter().zip(&b) {
                check("depth", y.depth_m, x.depth_m, 1e-12);
                check(
                    "n",
                    norm(sub(y.normal, rotate(x.normal, phi_p))),
                    0.0,
                    1e-12,
                );
                check("q", norm(sub(y.point, rotate(x.point, phi_p))), 0.0, 1e-12);
                assert_eq!(y.area, x.area);
                assert_eq!(y.gap, (x.gap + 1).rem_euclid(n));
                assert_eq!(y.patch_id, (x.patch_id + 2) % (2 * n as u32));
            }
            let (sa, qa, aa, ga) = pr.signed_distance(p);
            let (sb, qb, ab, gb) = pr.signed_distance(rotate(p, phi_p));
            check("sd", sb, sa, 1e-12);
            check("sd q", norm(sub(qb, rotate(qa, phi_p))), 0.0, 1e-12);
            assert_eq!((ab, gb), (aa, (ga + 1).rem_euclid(n)));
        }
        assert!(seen > 100, "too few contacts sampled: {seen}");
    }

    #[test]
    fn mirror_symmetry() {
        let pr = profile(28);
        let n = 28_i64;
        let d = pr.dimensions().clone();
        let flip = |v: V2| [v[0], -v[1]];
        let mut rng = Lcg(99);
        for _ in 0..4000 {
            let p = random_point(&mut rng, &d);
            let (sa, qa, aa, ga) = pr.signed_distance(p);
            let (sb, qb, ab, gb) = pr.signed_distance(flip(p));
            check("sd", sb, sa, 1e-12);
            check("q", norm(sub(qb, flip(qa))), 0.0, 1e-12);
            // Ties at the sector boundary may pick the mirror piece of the other gap.
            if (qa[1].atan2(qa[0]) / pr.pitch_angle_rad()).fract().abs() > 1e-9 {
                assert_eq!((ab, gb), (8 - aa, (-ga).rem_euclid(n)), "at {p:?}");
            }
            let a = contacts(&pr, p, RR);
            let b = contacts(&pr, flip(p), RR);
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(&b) {
                check("depth", y.depth_m, x.depth_m, 1e-12);
                check("n", norm(sub(y.normal, flip(x.normal))), 0.0, 1e-12);
            }
        }
        // Within a gap's local frame: pieces mirror onto pieces.
        for k in 0..8 {
            let a = &pr.own[k];
            let b = &pr.own[7 - k];
            assert_eq!(a.area, 8 - b.area);
            check(
                "mirror start",
                norm(sub(a.start, mirror(b.end))),
                0.0,
                1e-15,
            );
        }
    }

    /// Roller centre on the curve where sd = Rr − depth, at polar angle `a` (bisection
    /// along the ray).
    fn pressed_centre(pr: &AsaProfile, a: f64, depth: f64) -> V2 {
        let d = pr.dimensions();
        let (mut lo, mut hi) = (d.root_radius_m - 0.01, d.tip_radius_m + 0.05);
        let at = |r: f64| [r * a.cos(), r * a.sin()];
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if pr.signed_distance(at(mid)).0 < RR - depth {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        at(0.5 * (lo + hi))
    }

    #[test]
    fn force_is_continuous_from_seat_over_tip_into_next_gap() {
        for n in [60, 28] {
            let pr = profile(n);
            let depth = 2e-4;
            let steps = 20_000;
            let phi_p = pr.pitch_angle_rad();
            let mut prev: Option<(V2, V2)> = None;
            let mut areas: Vec<u8> = Vec::new();
            let mut ids: Vec<u32> = Vec::new();
            let mut max_jump: f64 = 0.0;
            for k in 0..=steps {
                let a = phi_p * k as f64 / steps as f64;
                let c = pressed_centre(&pr, a, depth);
                let patches = contacts(&pr, c, RR);
                assert_eq!(patches.len(), 1, "N={n} step {k}: {patches:?}");
                let p = patches[0];
                check("depth", p.depth_m, depth, 1e-9);
                check("|n|", norm(p.normal), 1.0, 1e-12);
                // The normal points from the surface point to the centre.
                let to_c = sub(c, p.point);
                check(
                    "n || q->c",
                    norm(sub(scale(p.normal, norm(to_c)), to_c)),
                    0.0,
                    1e-9,
                );
                let force = scale(p.normal, p.depth_m);
                if let Some((f0, c0)) = prev {
                    assert!(
                        norm(sub(c, c0)) < 1e-4,
                        "path step too long at {k}: {} {c:?}",
                        norm(sub(c, c0))
                    );
                    max_jump = max_jump.max(norm(sub(force, f0)));
                }
                prev = Some((force, c));
                if areas.last() != Some(&p.area) {
                    areas.push(p.area);
                }
                if ids.last() != Some(&p.patch_id) {
                    assert!(
                        ids.last()
                            .is_none_or(|&last| pr.patches_are_neighbours(last, p.patch_id)),
                        "patch {p:?} after {ids:?}"
                    );
                    ids.push(p.patch_id);
                }
            }
            // The path steps are < 100 µm (mostly ≈ 5 µm); the tightest turn of the normal is in the seat
            // (offset radius ΔR + depth ≈ 0.37 mm), ≈ 0.03 rad per step. A jump would be
            // of the order of the depth itself.
            assert!(
                max_jump < 0.05 * depth,
                "N={n}: largest force-proxy step {max_jump}"
            );
            assert_eq!(areas, vec![4, 3, 2, 1, 7, 6, 5, 4], "N={n}");
            assert_eq!(ids, vec![0, 1, 2], "N={n}");
        }
    }

    #[test]
    fn depth_is_continuous_across_every_joint() {
        let pr = profile(30);
        let mut rng = Lcg(3);
        // Straight lines through each joint, slightly on the free side.
        let own = pr.own;
        for (k, piece) in own.iter().enumerate() {
            let j = piece.start;
            let n_free = piece.free_normal(false);
            let base = pr.to_global_point(0, add(j, scale(n_free, RR - 1e-4)));
            for _ in 0..20 {
                let dir = polar(rng.range(0.0, 2.0 * PI));
                let mut last: Option<V2> = None;
                for s in -100..=100 {
                    let p = add(base, scale(dir, 1e-7 * f64::from(s)));
                    let c = contacts(&pr, p, RR);
                    let f = c
                        .iter()
                        .fold([0.0, 0.0], |acc, x| add(acc, scale(x.normal, x.depth_m)));
                    if let Some(l) = last {
                        assert!(norm(sub(f, l)) < 1e-6, "jump at joint {k}: {c:?}");
                    }
                    last = Some(f);
                }
            }
        }
    }

    #[test]
    fn two_separate_places_give_two_patches() {
        let pr = profile(28);
        let d = pr.dimensions().clone();
        // An oversized roller (radius 40 mm) on the gap axis touches both flanks.
        let r = 0.040;
        let p = [d.pitch_radius_m + 0.010, 0.0];
        let c = contacts(&pr, p, r);
        assert_eq!(c.len(), 2, "{c:?}");
        check("equal depths", c[0].depth_m, c[1].depth_m, 1e-12);
        let mut ids = [c[0].patch_id, c[1].patch_id];
        ids.sort_unstable();
        assert_eq!(ids, [0, 56]);
        assert!(pr.patches_are_neighbours(0, 56));
        // Slightly off-axis: the clockwise side keeps id 0 in both orders of depth.
        for dy in [-1e-4, 1e-4] {
            let c = contacts(&pr, [p[0], dy], r);
            assert_eq!(c.len(), 2);
            for x in &c {
                let id = if x.area >= 5 { 0 } else { 56 };
                assert_eq!(x.patch_id, id, "{x:?}");
            }
        }
        // A 40 mm roller wedged between the topping of tooth 0 (area 1) and the opposite
        // straight flank (area 6): one tooth patch and the gap's concave patch.
        let p = pr.to_global_point(0, [-0.002, 0.020]);
        let c = contacts(&pr, p, r);
        assert_eq!(c.len(), 2, "{c:?}");
        let mut got: Vec<(u8, u32)> = c.iter().map(|x| (x.area, x.patch_id)).collect();
        got.sort_unstable();
        assert_eq!(got, vec![(1, 1), (6, 0)]);
        assert!(
            norm(sub(c[0].point, c[1].point)) > 0.05,
            "two separate places"
        );
        for x in &c {
            let v = sub(p, x.point);
            check("depth = r - |p-q|", x.depth_m, r - norm(v), 1e-12);
            check(
                "normal",
                norm(sub(x.normal, scale(v, 1.0 / norm(v)))),
                0.0,
                1e-12,
            );
        }
    }

    #[test]
    fn neighbour_relation_of_patch_ids() {
        let pr = profile(10);
        assert!(pr.patches_are_neighbours(0, 1));
        assert!(pr.patches_are_neighbours(0, 19));
        assert!(pr.patches_are_neighbours(2, 1));
        assert!(pr.patches_are_neighbours(19, 18));
        assert!(!pr.patches_are_neighbours(0, 3));
        assert!(!pr.patches_are_neighbours(1, 3));
        assert!(!pr.patches_are_neighbours(0, 2));
        assert!(pr.patches_are_neighbours(4, 22));
        assert!(!pr.patches_are_neighbours(4, 4));
        assert!(!pr.patches_are_neighbours(0, 1000));
    }

    #[test]
    fn no_panics_and_non_finite_input() {
        let pr = profile(17);
        let mut out = [empty_patch(); 2];
        for p in [
            [f64::NAN, 0.0],
            [0.0, f64::INFINITY],
            [f64::NEG_INFINITY, f64::NAN],
        ] {
            assert_eq!(pr.contacts(p, RR, &mut out), 0);
            assert!(pr.signed_distance(p).0.is_nan());
        }
        assert_eq!(pr.contacts([0.4, 0.0], f64::NAN, &mut out), 0);
        assert_eq!(pr.contacts([0.4, 0.0], -1.0, &mut out), 0);
        let mut rng = Lcg(1);
        for k in 0..20_000 {
            let mag = 10f64.powf(rng.range(-310.0, 300.0));
            let p = [mag * rng.range(-1.0, 1.0), mag * rng.range(-1.0, 1.0)];
            let p = if k % 7 == 0 { [0.0, 0.0] } else { p };
            let n = pr.contacts(p, RR, &mut out);
            for x in &out[..n] {
                assert!(x.depth_m > 0.0 && x.depth_m.is_finite());
                assert!((norm(x.normal) - 1.0).abs() < 1e-9, "{x:?} at {p:?}");
                assert!((0..17).contains(&x.gap) && (1..=7).contains(&x.area));
            }
            let _ = pr.signed_distance(p);
        }
    }

    /// Compares the fast `contacts` (and `contacts_hinted`) with the previous implementation.
    fn assert_same_as_reference(pr: &AsaProfile, p: V2, r: f64, hint: &mut u32) {
        let mut want = [empty_patch(); 2];
        let mut got = [empty_patch(); 2];
        let mut got_h = [empty_patch(); 2];
        let kw = pr.contacts_reference(p, r, &mut want);
        let kg = pr.contacts(p, r, &mut got);
        let kh = pr.contacts_hinted(p, r, hint, &mut got_h);
        assert_eq!(
            kg,
            kw,
            "count at {p:?} r {r}: {:?} vs {:?}",
            &got[..kg],
            &want[..kw]
        );
        assert_eq!(kh, kg, "hinted count at {p:?} r {r}");
        assert_eq!(got_h[..kh], got[..kg], "hinted at {p:?} r {r}");
        if r == 0.5 * pr.dimensions().roller_diameter_m {
            let mut nominal = [crate::geometry::Patch::default(); 2];
            let kn = pr.contacts_nominal(p, &mut 0, &mut nominal);
            assert_eq!(kn, kg, "nominal count at {p:?}");
            for (a, b) in nominal[..kn].iter().zip(&got[..kg]) {
                assert_eq!(
                    (a.depth_m, a.normal, a.area, i64::from(a.gap), a.patch_id),
                    (b.depth_m, b.normal, b.area, b.gap, b.patch_id),
                    "nominal at {p:?}"
                );
            }
        }
        for (g, w) in got[..kg].iter().zip(&want[..kw]) {
            assert_eq!(
                (g.area, g.gap, g.patch_id),
                (w.area, w.gap, w.patch_id),
                "labels at {p:?} r {r}: {g:?} vs {w:?}"
            );
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-12;
            assert!(
                close(g.depth_m, w.depth_m)
                    && close(g.normal[0], w.normal[0])
                    && close(g.normal[1], w.normal[1])
                    && close(g.point[0], w.point[0])
                    && close(g.point[1], w.point[1]),
                "values at {p:?} r {r}: {g:?} vs {w:?}"
            );
        }
    }

    #[test]
    fn fast_contacts_match_the_reference_implementation() {
        let mut rng = Lcg(4242);
        let mut touching = 0;
        let mut total = 0;
        for n in [60, 30, 28, 17, 9] {
            let pr = profile(n);
            let d = pr.dimensions().clone();
            let phi_p = pr.pitch_angle_rad();
            let mut hint = 0;
            // Random points near the outline, random radii (mostly the roller's).
            for k in 0..20_000 {
                let rad = rng.range(d.root_radius_m - 0.03, d.tip_radius_m + 0.03);
                let a = rng.range(-PI, PI);
                let p = [rad * a.cos(), rad * a.sin()];
                let r = match k % 4 {
                    0 => rng.range(0.0, 0.045),
                    1 => 0.0,
                    _ => RR,
                };
                assert_same_as_reference(&pr, p, r, &mut hint);
                let mut out = [empty_patch(); 2];
                touching += usize::from(pr.contacts(p, r, &mut out) > 0);
                total += 1;
            }
            // Realistic rollers: pressed against the profile by −2..+1 mm, in the seat with
            // and without clearance, and hints that are right, neighbouring or stale.
            for k in 0..1_000 {
                let a = phi_p * (rng.range(-0.5, 0.5) + f64::from(k % n));
                let c = pressed_centre(&pr, a, rng.range(-2e-3, 1e-3));
                let mut h = [k % n, (k + 1) % n, 7 * k, u32::MAX][(k % 4) as usize];
                assert_same_as_reference(&pr, c, RR, &mut h);
                let b = rng.range(-1.2, 1.2);
                let s = rng.range(0.0, d.clearance_m + 1e-3);
                let seat = pr.to_global_point((k % n) as usize, [s * b.sin(), -s * b.cos()]);
                assert_same_as_reference(&pr, seat, RR, &mut h);
                touching += 1;
                total += 2;
            }
        }
        assert!(
            total >= 100_000 && touching > 30_000,
            "{touching} of {total}"
        );
    }

    /// The direct rules of [`Shortcuts`] against the reference: dense points in the bottom
    /// of the gap (across the joint lines c–O–x and c*–O–x*, ξ = 0, the inner and outer
    /// radius), rollers rocked onto a working curve just past x or x*, and the free space of
    /// the gap, for several sprockets and roller radii; every rule must be exercised.
    #[test]
    fn direct_rules_match_the_reference_implementation() {
        let mut rng = Lcg(2718);
        let sprockets = [
            (60, P, DR),
            (30, P, DR),
            (28, P, DR),
            (17, P, DR),
            (9, P, DR),
            (10, 0.0127, 0.00792),
            (17, 0.0127, 0.00792),
            (30, 0.0127, 0.00792),
        ];
        let mut by_rule = [0_usize; 4];
        let mut contacts_by_rule = [0_usize; 4];
        let mut total = 0;
        for (n, pitch, dr) in sprockets {
            let pr = match AsaProfile::new(n, pitch, dr) {
                Ok(p) => p,
                Err(e) => panic!("N={n}: {e}"),
            };
            let cut = pr.cuts;
            assert!(
                cut.far_m > 0.0 && cut.free_rule,
                "N={n} P={pitch}: rules enabled"
            );
            let d = pr.dimensions().clone();
            let g = pr.gap_points().clone();
            let rr = 0.5 * dr;
            let (rt, re) = (d.seating_radius_m, d.working_radius_m);
            // Unit directions of the joint line c–O–x and of its mirror.
            let ux = unit_or(g.x_m, [1.0, 0.0]);
            let ux_star = mirror(ux);
            let normal_of = |u: V2| [-u[1], u[0]];
            let mut hint = 0;
            for k in 0..30_000_u32 {
                let gap = (k % n) as usize;
                let r = match k % 8 {
                    0 => rng.range(0.0, 1.2 * rt),
                    1 => rr * rng.range(0.9, 1.1),
                    2 => 0.0,
                    _ => rr,
                };
                let reach = r + SKIP_MARGIN_M;
                let r_l = (cut.far_m - reach).min(cut.free_m).max(0.0);
                let q = match k % 6 {
                    // Bottom of the gap: anywhere, and on and next to its radii.
                    0 => {
                        let a = rng.range(-PI, PI);
                        let s = match k / 6 % 4 {
                            0 => r_l * (1.0 + rng.range(-1e-9, 1e-9)),
                            1 => cut.min_r2.sqrt() * (1.0 + rng.range(-1e-6, 1e-6)),
                            _ => rng.range(0.0, 1.3 * r_l),
                        };
                        [s * a.cos(), s * a.sin()]
                    }
                    // Across a joint line, at distances from 1e-12 m to 1 mm, and across ξ = 0.
                    1 | 2 => {
                        let u = if k % 2 == 0 { ux } else { ux_star };
                        let along = rng.range(-1.0, 1.0) * r_l;
                        let off =
                            10f64.powf(rng.range(-12.0, -3.0)) * [1.0, -1.0][(k / 6 % 2) as usize];
                        let off = match k / 12 % 5 {
                            0 => cut.s_min_m * (1.0 + rng.range(-1e-6, 1e-6)) * off.signum(),
                            _ => off,
                        };
                        let q = add(scale(u, along), scale(normal_of(u), off));
                        if k / 6 % 7 == 0 {
                            [1e-300 * off.signum(), q[1]]
                        } else {
                            q
                        }
                    }
                    // A roller pressed onto a working curve just past x (or x*), or just off it.
                    3 => {
                        let sigma =
                            10f64.powf(rng.range(-9.0, -1.0)) * [1.0, -1.0][(k / 6 % 2) as usize];
                        let depth = rng.range(-1e-3, 2e-3) * dr / DR;
                        let u = rotate(unit_or(sub(g.x_m, g.c_m), [1.0, 0.0]), sigma);
                        let q = add(g.c_m, scale(u, re - r + depth));
                        if k / 6 % 3 == 0 { mirror(q) } else { q }
                    }
                    // The free space of the gap and its surroundings.
                    _ => [
                        rng.range(-1.1, 1.1) * g.f_m[0],
                        rng.range(-rt, g.f_m[1] + 2.0 * r + 1e-3),
                    ],
                };
                let p = pr.to_global_point(gap, q);
                let rule = pr.rule_of(p, r);
                by_rule[rule] += 1;
                let mut h = [gap as u32, u32::MAX, hint][(k % 3) as usize];
                assert_same_as_reference(&pr, p, r, &mut h);
                hint = h;
                let mut out = [empty_patch(); 2];
                if pr.contacts(p, r, &mut out) > 0 {
                    contacts_by_rule[rule] += 1;
                }
                total += 1;
            }
        }
        assert!(total >= 200_000, "{total} points");
        // Every rule decides many points, with and without contact.
        assert!(
            by_rule[1] > 40_000 && by_rule[2] > 10_000 && by_rule[3] > 10_000,
            "points by rule {by_rule:?}"
        );
        assert!(
            contacts_by_rule[1] > 20_000,
            "contacts by rule {contacts_by_rule:?}"
        );
    }

    #[test]
    fn gap_search_matches_atan2() {
        let mut rng = Lcg(77);
        for n in [5, 9, 28, 30, 60, 1000, 100_000] {
            let pr = match AsaProfile::new(n, 0.0127 * f64::from(n.min(1000)) / 50.0, 0.002) {
                Ok(p) => p,
                Err(_) => profile(n.min(60)),
            };
            let nn = pr.teeth();
            for k in 0..20_000_u32 {
                let a = rng.range(-PI, PI);
                let r = 10f64.powf(rng.range(-3.0, 1.0));
                let p = if k % 10 == 0 {
                    // Exactly on or next to a sector boundary.
                    let b = pr.pitch_angle_rad() * (f64::from(k % nn) + 0.5);
                    let b = b + [0.0, 1e-13, -1e-13, 1e-7][(k / 10 % 4) as usize];
                    [r * b.cos(), r * b.sin()]
                } else {
                    [r * a.cos(), r * a.sin()]
                };
                let want = pr.gap_index(p);
                for hint in [u32::MAX, want as u32, (want as u32 + 1) % nn, k] {
                    assert_eq!(pr.gap_near(p, hint), want, "N={nn} p {p:?} hint {hint}");
                }
            }
        }
    }

    #[test]
    fn reach_and_seat_bounds_hold() {
        for n in [60, 30, 28, 9] {
            let pr = profile(n);
            let d = pr.dimensions();
            check("reach", pr.reach_radius_m, d.tip_radius_m, 1e-9);
            check("seat clearance", pr.seat_clear_m, d.seating_radius_m, 1e-9);
            let max_r = pr
                .outline(1e-3)
                .iter()
                .map(|q| q.x_m.hypot(q.y_m))
                .fold(0.0, f64::max);
            assert!(max_r <= pr.reach_radius_m, "{max_r} {}", pr.reach_radius_m);
            assert!(pr.graph.is_some(), "N={n}: the outline is a graph");
            // The graph agrees with the sign of the signed distance.
            let mut rng = Lcg(5);
            for _ in 0..5_000 {
                let p = random_point(&mut rng, d);
                let gap = pr.gap_index(p);
                let q = pr.to_local(gap, p);
                let (sd, ..) = pr.signed_distance(p);
                if let Some(free) = pr.graph.and_then(|g| g.is_free(q)) {
                    assert_eq!(free, sd > 0.0, "N={n} at {q:?}: sd {sd}");
                }
            }
        }
    }

    #[test]
    fn invalid_inputs_are_errors() {
        assert_eq!(
            AsaProfile::new(3, P, DR).err(),
            Some(AsaError::TooFewTeeth { teeth: 3 })
        );
        assert!(matches!(
            AsaProfile::new(4, P, DR),
            Err(AsaError::DegenerateProfile { .. })
        ));
        assert!(matches!(
            AsaProfile::new(200_000, P, DR),
            Err(AsaError::TooManyTeeth { .. })
        ));
        for (p, dr) in [
            (0.0, DR),
            (-P, DR),
            (f64::NAN, DR),
            (P, 0.0),
            (P, f64::INFINITY),
        ] {
            assert!(matches!(
                AsaProfile::new(20, p, dr),
                Err(AsaError::NonPositive { .. })
            ));
        }
        assert!(matches!(
            AsaProfile::new(20, P, 0.09),
            Err(AsaError::RollerTooBig { .. })
        ));
        let e = AsaError::TooFewTeeth { teeth: 3 };
        assert!(e.to_string().contains('3'));
    }
}
