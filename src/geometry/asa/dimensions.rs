//! The standard's dimensions of one sprocket and the construction points of one gap, with
//! the checks that the construction closes.

use std::f64::consts::PI;

use super::{AsaError, IN_0_003_M, IN_0_0015_M, MAX_TEETH, MIN_TEETH};
use crate::geometry::v2::{add, mirror, polar, scale, sub};

/// Standard dimensions of one sprocket (all SI: metres, radians).
///
/// Symbols and formulas are those of docs/tooth-profile.md, “Constants”; points and angles of the
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
/// measured from +ξ counter-clockwise, in the ranges of docs/tooth-profile.md,
/// “Construction” (e.g. θ2a = 2π − A).
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

/// Range checks of the raw inputs.
pub(super) fn check_inputs(
    teeth: u32,
    pitch_m: f64,
    roller_diameter_m: f64,
) -> Result<(), AsaError> {
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

/// The standard dimensions (docs/tooth-profile.md, “Constants”), with the checks that the
/// construction closes.
pub(super) fn dimensions(teeth: u32, pitch_m: f64, dr: f64) -> Result<AsaDimensions, AsaError> {
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

/// Construction points and angles of one gap (docs/tooth-profile.md, “Construction”).
pub(super) fn gap_points(d: &AsaDimensions) -> Result<GapPoints, AsaError> {
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
