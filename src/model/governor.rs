//! A torque-driven driver's torque: the drive torque in its angle plus a PI
//! speed governor to the scene's speed law (docs/model.md, “A torque-driven
//! driver”),
//!
//! T = T_d(φ) + K_p (ω_ref(t) − ω) + K_i (Θ_ref(t) − φ),
//!
//! φ = θ − θ₀ the driver's angle from its origin, ω_ref the speed law (its
//! ramp included) and Θ_ref its integral from t = 0. The integral action
//! lives in the angle error: the governor has no state of its own, and its
//! torque depends on (t, θ, ω) only, so every integrator advances it as a
//! free sprocket's load.
//!
//! This module knows nothing of stepping.

use super::excitation::AngleLoad;
use crate::geometry::ChainPath;
use crate::scene::{DEFAULT_GOVERNOR_BANDWIDTH_HZ, GovernorGains, GovernorSpec, Scene, SpeedLaw};

/// The default bandwidth is the drive's lowest span frequency divided by
/// this: a decade below it.
pub(crate) const SPAN_FREQUENCY_DIVISOR: f64 = 10.0;

/// A driver's governor with its gains resolved.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Governor {
    /// The target speed law ω_ref(t).
    pub target: SpeedLaw,
    /// Proportional gain K_p, N·m per rad/s.
    pub kp_n_m_s_rad: f64,
    /// Integral gain K_i, N·m per rad.
    pub ki_n_m_rad: f64,
    /// Constant drive torque, N·m.
    pub drive_torque_n_m: f64,
    /// The drive torque's part in the angle φ; `None`: none.
    pub drive_angle: Option<AngleLoad>,
    /// Added to the target angle Θ_ref(t), rad: zero from the scene; a
    /// target changed mid-run keeps the target angle continuous with it.
    pub target_angle_offset_rad: f64,
}

impl Governor {
    /// The governor of `spec` on the driver `driver` of `scene`, its target
    /// `target`; gains from a bandwidth use the drive's inertia referred to
    /// the driver ([`referred_inertia_kg_m2`]), and the default bandwidth
    /// the free strands of `path` ([`default_bandwidth_hz`]).
    pub(crate) fn new(
        scene: &Scene,
        driver: usize,
        spec: &GovernorSpec,
        target: SpeedLaw,
        path: &ChainPath,
    ) -> Self {
        let (kp_n_m_s_rad, ki_n_m_rad) = match spec.gains {
            GovernorGains::Given {
                kp_n_m_s_rad,
                ki_n_m_rad,
            } => (kp_n_m_s_rad, ki_n_m_rad),
            GovernorGains::Bandwidth { hz } => {
                critical_gains(referred_inertia_kg_m2(scene, driver), hz)
            }
            GovernorGains::FromSpans => critical_gains(
                referred_inertia_kg_m2(scene, driver),
                default_bandwidth_hz(scene, path),
            ),
        };
        Self {
            target,
            kp_n_m_s_rad,
            ki_n_m_rad,
            drive_torque_n_m: spec.drive_torque_n_m,
            drive_angle: AngleLoad::new(&spec.drive_harmonics, spec.drive_table.as_ref()),
            target_angle_offset_rad: 0.0,
        }
    }

    /// The drive torque T_d(φ) at the angle `phi_rad` from the origin, N·m.
    #[inline]
    pub(crate) fn drive_torque_at(&self, phi_rad: f64) -> f64 {
        self.drive_torque_n_m + self.drive_angle.as_ref().map_or(0.0, |a| a.at(phi_rad))
    }

    /// The governor's part K_p (ω_ref − ω) + K_i (Θ_ref − φ) at time `t_s`,
    /// angle `phi_rad` from the origin and speed `omega_rad_s`, N·m.
    #[inline]
    pub(crate) fn control_torque_at(&self, t_s: f64, phi_rad: f64, omega_rad_s: f64) -> f64 {
        self.kp_n_m_s_rad * (self.target.speed_at(t_s) - omega_rad_s)
            + self.ki_n_m_rad
                * (target_angle_rad(&self.target, t_s) + self.target_angle_offset_rad - phi_rad)
    }

    /// The whole torque on the driver, N·m.
    #[inline]
    pub(crate) fn torque_at(&self, t_s: f64, phi_rad: f64, omega_rad_s: f64) -> f64 {
        self.drive_torque_at(phi_rad) + self.control_torque_at(t_s, phi_rad, omega_rad_s)
    }
}

/// Θ_ref(t) = ∫₀ᵗ ω_ref: ω̄ t² / (2 t_r) on the ramp, ω̄ (t − t_r / 2) after
/// it; 0 before t = 0. A run-up from t₁ over T to ω₁ adds
/// (ω₁ − ω̄) τ² / (2T) for τ = t − t₁ in [0, T] and (ω₁ − ω̄)(τ − T/2) after.
#[inline]
pub(crate) fn target_angle_rad(law: &SpeedLaw, t_s: f64) -> f64 {
    let base = if t_s <= 0.0 {
        0.0
    } else if t_s < law.ramp_s {
        0.5 * law.speed_rad_s * t_s * t_s / law.ramp_s
    } else {
        law.speed_rad_s * (t_s - 0.5 * law.ramp_s)
    };
    match law.run_up {
        Some(r) if t_s > r.start_s => {
            let (tau, rise) = (t_s - r.start_s, r.to_rad_s - law.speed_rad_s);
            if tau < r.duration_s {
                base + 0.5 * rise * tau * tau / r.duration_s
            } else {
                base + rise * (tau - 0.5 * r.duration_s)
            }
        }
        _ => base,
    }
}

/// The lowest first transverse frequency of the drive's free strands at
/// rest, Hz: c / (2L) with c = √(T₀/μ) from the pretension T₀ and μ = m_r/P,
/// L each strand's length between pitch circles. `None` without a strand of
/// positive length or a positive pretension.
pub(crate) fn lowest_span_frequency_hz(scene: &Scene, path: &ChainPath) -> Option<f64> {
    let chain = scene.chain();
    let mu = chain.roller_mass_kg / chain.pitch_m;
    let c = (chain.pretension_n / mu).sqrt();
    path.strands
        .iter()
        .filter(|s| s.length_m > 0.0)
        .map(|s| c / (2.0 * s.length_m))
        .filter(|f| f.is_finite() && *f > 0.0)
        .min_by(f64::total_cmp)
}

/// The bandwidth of a governor given neither gains nor `bandwidth_hz`, Hz:
/// a decade below the drive's lowest span frequency
/// ([`lowest_span_frequency_hz`] / [`SPAN_FREQUENCY_DIVISOR`]), so that the
/// governor holds the mean speed and leaves the spans' dynamics alone;
/// [`DEFAULT_GOVERNOR_BANDWIDTH_HZ`] when the drive has no such frequency.
pub(crate) fn default_bandwidth_hz(scene: &Scene, path: &ChainPath) -> f64 {
    lowest_span_frequency_hz(scene, path).map_or(DEFAULT_GOVERNOR_BANDWIDTH_HZ, |f| {
        f / SPAN_FREQUENCY_DIVISOR
    })
}

/// The gains that make J φ̈ + K_p φ̇ + K_i φ = 0 critically damped at the
/// natural frequency `bandwidth_hz`: (2 ω_n J, ω_n² J), ω_n = 2π f_n.
pub(crate) fn critical_gains(inertia_kg_m2: f64, bandwidth_hz: f64) -> (f64, f64) {
    let omega_n = std::f64::consts::TAU * bandwidth_hz;
    (
        2.0 * omega_n * inertia_kg_m2,
        omega_n * omega_n * inertia_kg_m2,
    )
}

/// The drive's inertia referred to the driver, kg·m²: Σ J_i (z_d / z_i)²
/// over the sprockets (the driver's own with factor 1) plus the chain's mass
/// at the driver's pitch radius, m_chain r_d², the chain taken as rigid and
/// every sprocket as turning with it. Tensioner arms are left out.
pub(crate) fn referred_inertia_kg_m2(scene: &Scene, driver: usize) -> f64 {
    let sprockets = scene.sprockets();
    let z_d = f64::from(sprockets[driver].teeth);
    let r_d = sprockets[driver].pitch_radius_m;
    let chain = scene.chain();
    let wheels: f64 = sprockets
        .iter()
        .map(|s| {
            let ratio = z_d / f64::from(s.teeth);
            s.inertia_kg_m2 * ratio * ratio
        })
        .sum();
    wheels + chain.rollers as f64 * chain.roller_mass_kg * r_d * r_d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The governor alone on a rigid inertia J: J φ̈ = T(t, φ, φ̇) − M,
    /// advanced by classical RK4 at `dt_s` up to `t_end_s`; (t, φ, φ̇) after
    /// every step.
    fn rigid(g: &Governor, j: f64, load: f64, dt_s: f64, t_end_s: f64) -> Vec<(f64, f64, f64)> {
        let acc = |t: f64, p: f64, w: f64| (g.torque_at(t, p, w) - load) / j;
        let (mut t, mut p, mut w) = (0.0, 0.0, 0.0);
        let mut out = Vec::new();
        while t < t_end_s {
            let h = dt_s;
            let (k1p, k1w) = (w, acc(t, p, w));
            let (k2p, k2w) = (
                w + 0.5 * h * k1w,
                acc(t + 0.5 * h, p + 0.5 * h * k1p, w + 0.5 * h * k1w),
            );
            let (k3p, k3w) = (
                w + 0.5 * h * k2w,
                acc(t + 0.5 * h, p + 0.5 * h * k2p, w + 0.5 * h * k2w),
            );
            let (k4p, k4w) = (w + h * k3w, acc(t + h, p + h * k3p, w + h * k3w));
            p += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
            w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
            t += h;
            out.push((t, p, w));
        }
        out
    }

    fn governor(j: f64, hz: f64, speed: f64, drive: f64) -> Governor {
        let (kp, ki) = critical_gains(j, hz);
        Governor {
            target: SpeedLaw::ramped(speed, 0.0),
            kp_n_m_s_rad: kp,
            ki_n_m_rad: ki,
            drive_torque_n_m: drive,
            drive_angle: None,
            target_angle_offset_rad: 0.0,
        }
    }

    #[test]
    fn a_step_in_the_target_speed_follows_the_critically_damped_closed_form() {
        // From rest to ω̄ at t = 0: the angle error e = ω̄ t − φ obeys
        // J ë + K_p ė + K_i e = 0, e(0) = 0, ė(0) = ω̄; critically damped
        // (ζ = 1): e = ω̄ t exp(−ω_n t), so the speed is
        // φ̇ = ω̄ [1 − (1 − ω_n t) exp(−ω_n t)], which overshoots once, by
        // ω̄ e⁻² = 13.5 % at t = 2 / ω_n, and settles within 2 % after
        // t ≈ 5.8 / ω_n. RK4 at ω_n dt = 2.5e-3 errs by ~1e-11 ω̄.
        let (j, hz, speed) = (0.05, 2.0, 30.0);
        let wn = std::f64::consts::TAU * hz;
        let g = governor(j, hz, speed, 0.0);
        let track = rigid(&g, j, 0.0, 2e-4, 10.0 / wn);
        let mut peak = (0.0, 0.0);
        for &(t, p, w) in &track {
            let e = (-wn * t).exp();
            let exact_w = speed * (1.0 - (1.0 - wn * t) * e);
            let exact_p = speed * t - speed * t * e;
            approx::assert_abs_diff_eq!(w, exact_w, epsilon = 1e-8 * speed);
            approx::assert_abs_diff_eq!(p, exact_p, epsilon = 1e-8 * speed / wn);
            if w > peak.1 {
                peak = (t, w);
            }
        }
        let overshoot = peak.1 / speed - 1.0;
        approx::assert_abs_diff_eq!(overshoot, (-2.0f64).exp(), epsilon = 1e-6);
        approx::assert_abs_diff_eq!(peak.0, 2.0 / wn, epsilon = 2e-4);
    }

    #[test]
    fn a_constant_load_is_carried_without_a_lasting_speed_error() {
        // A load M against a drive torque T_d: the integral action supplies
        // M − T_d; at rest in the error, φ → Θ_ref − (M − T_d)/K_i and
        // φ̇ → ω̄ (a PI loop has no steady error under a constant load).
        let (j, hz, speed, load, drive) = (0.05, 2.0, 30.0, 40.0, 15.0);
        let wn = std::f64::consts::TAU * hz;
        let g = governor(j, hz, speed, drive);
        let track = rigid(&g, j, load, 2e-4, 20.0 / wn);
        let &(t, p, w) = track.last().expect("steps");
        approx::assert_abs_diff_eq!(w, speed, epsilon = 1e-4 * speed);
        let lag = (load - drive) / g.ki_n_m_rad;
        approx::assert_abs_diff_eq!(speed * t - p, lag, epsilon = 1e-3 * lag);
    }

    #[test]
    fn the_target_angle_integrates_the_ramp() {
        let law = SpeedLaw::ramped(10.0, 0.375);
        // Trapezoids on a piecewise-linear ω are exact at the knot.
        let n = 4096;
        let dt = 1.0 / f64::from(n);
        let mut theta = 0.0;
        for k in 0..n {
            let t = f64::from(k) * dt;
            theta += 0.5 * dt * (law.speed_at(t) + law.speed_at(t + dt));
            approx::assert_abs_diff_eq!(target_angle_rad(&law, t + dt), theta, epsilon = 1e-9);
        }
    }

    #[test]
    fn the_target_angle_integrates_a_run_up() {
        // A ramp to 10 rad/s over 0.25 s, then a run-up to 30 rad/s from
        // 0.5 s over 1.25 s: ω is piecewise linear with knots on the grid
        // (multiples of 1/4096 s), so trapezoids are exact.
        let law = SpeedLaw {
            run_up: Some(crate::scene::RunUp {
                start_s: 0.5,
                duration_s: 1.25,
                to_rad_s: 30.0,
            }),
            ..SpeedLaw::ramped(10.0, 0.25)
        };
        approx::assert_abs_diff_eq!(law.speed_at(1.125), 20.0, epsilon = 1e-12);
        approx::assert_abs_diff_eq!(law.speed_at(2.0), 30.0, epsilon = 1e-12);
        let n = 4096;
        let dt = 1.0 / f64::from(n);
        let mut theta = 0.0;
        for k in 0..2 * n {
            let t = f64::from(k) * dt;
            theta += 0.5 * dt * (law.speed_at(t) + law.speed_at(t + dt));
            approx::assert_abs_diff_eq!(target_angle_rad(&law, t + dt), theta, epsilon = 1e-9);
        }
    }
}
