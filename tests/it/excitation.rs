//! Excitation: the driver's speed harmonics against the closed-form angle
//! and speed, load torques in a sprocket's angle, the example scene.

use std::f64::consts::{PI, TAU};
use std::path::Path;

use chaindrive::scene::{Integrator, Overrides, Scene};
use chaindrive::sim::Simulation;

/// The scene at `tests/data/<name>`, read with its own directory.
fn data_scene(name: &str, overrides: &Overrides) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    Scene::from_path_with(&path, overrides)
        .expect("readable")
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The harmonic driver's law, from `tests/data/harmonic_driver_20_40.toml`:
/// ω(θ) = ω̄ (1 + a sin(k θ + φ)), 300 rpm, k = 2, a = 0.05, φ = 30°.
const MEAN_RAD_S: f64 = 300.0 * TAU / 60.0;
const ORDER: f64 = 2.0;
const AMPLITUDE: f64 = 0.05;
const PHASE_RAD: f64 = 30.0 * PI / 180.0;

/// The time the driver takes to turn from 0 to θ at constant ω̄ (no ramp):
/// t(θ) = ∫₀^θ dθ' / (ω̄ (1 + a sin(k θ' + φ))) = (F(kθ + φ) − F(φ)) / (k ω̄)
/// with the antiderivative of 1 / (1 + a sin u), |a| < 1, s = √(1 − a²):
/// F(u) = (2/s) [atan((tan(u/2) + a)/s) + π ⌊(u/2 + π/2)/π⌋]
/// (the floor term adds π at each pole of tan(u/2), making F continuous).
fn exact_time_s(theta_rad: f64) -> f64 {
    let s = (1.0 - AMPLITUDE * AMPLITUDE).sqrt();
    let f = |u: f64| {
        let v = 0.5 * u;
        2.0 / s * (((v.tan() + AMPLITUDE) / s).atan() + PI * ((v + 0.5 * PI) / PI).floor())
    };
    (f(ORDER * theta_rad + PHASE_RAD) - f(PHASE_RAD)) / (ORDER * MEAN_RAD_S)
}

/// The law's speed at the angle θ from the angle origin.
fn exact_speed(theta_rad: f64) -> f64 {
    MEAN_RAD_S * (1.0 + AMPLITUDE * (ORDER * theta_rad + PHASE_RAD).sin())
}

/// Runs the harmonic driver's scene with `scheme` for `duration_s`; returns
/// the driver's (t, θ − θ₀, ω) after every step.
fn driver_track(scheme: Integrator, duration_s: f64) -> Vec<(f64, f64, f64)> {
    let scene = data_scene(
        "harmonic_driver_20_40.toml",
        &Overrides {
            integrator: Some(scheme),
            dt_auto: true,
            ..Overrides::default()
        },
    );
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let driver = scene.driver();
    let origin = sim.state.theta[driver];
    let dt = scene.solver().dt_s;
    let steps = (duration_s / dt).round() as usize;
    let mut track = Vec::with_capacity(steps);
    for _ in 0..steps {
        sim.step(dt).expect("step");
        let s = &sim.state;
        track.push((s.t_s, s.theta[driver] - origin, s.omega[driver]));
    }
    track
}

#[test]
fn the_driver_angle_follows_the_closed_form_with_every_integrator() {
    // The angle integrates dθ/dt = ω(θ): the time at which the recorded angle
    // is reached must be t(θ) of the closed form. The explicit midpoint rule
    // (symplectic Euler, velocity Verlet, implicit damping) errs by
    // O(dt²) ≈ (ω̄ dt)² a k² / 6 per unit time, far below 1 µs over the run;
    // the Runge–Kutta schemes by less. Tolerance: 1e-8 s, a 1e-6 fraction of
    // the step.
    for scheme in [
        Integrator::SymplecticEuler,
        Integrator::VelocityVerlet,
        Integrator::ImplicitDamping,
        Integrator::Rk4,
        Integrator::DormandPrince45,
    ] {
        let track = driver_track(scheme, 0.25);
        let worst = track
            .iter()
            .map(|&(t, theta, _)| (exact_time_s(theta) - t).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-8,
            "{}: |t(θ) − t| up to {worst:e} s",
            scheme.name()
        );
        // More than a revolution was turned, so every phase of the harmonic
        // was met.
        let turned = track.last().map_or(0.0, |r| r.1);
        assert!(turned > TAU, "{}: turned {turned} rad", scheme.name());
    }
}

#[test]
fn the_driver_speed_is_the_law_at_its_angle() {
    // ω = ω̄ (1 + a sin(kθ + φ)) at the recorded angle. Symplectic Euler keeps
    // the step's midpoint speed: off by ≈ (dt/2) dω/dt = (dt/2) ω̄² a k,
    // 3e-5 of ω̄ at dt = 10 µs; tolerance 1e-4 of ω̄.
    for scheme in [Integrator::SymplecticEuler, Integrator::Rk4] {
        let track = driver_track(scheme, 0.1);
        let worst = track
            .iter()
            .map(|&(_, theta, omega)| (omega - exact_speed(theta)).abs() / MEAN_RAD_S)
            .fold(0.0, f64::max);
        assert!(worst < 1e-4, "{}: relative error {worst:e}", scheme.name());
    }
}

#[test]
fn the_driver_speed_has_the_stated_order_amplitude() {
    // Over whole revolutions of the driver, the speed's order-k Fourier
    // coefficient in its angle is a_k ω̄ (the law is a sine in θ); the
    // angle-mean speed is ω̄. Trapezoids over the steps' angles; within 1 %.
    let track = driver_track(Integrator::SymplecticEuler, 0.45);
    let revolutions = (track.last().map_or(0.0, |r| r.1) / TAU).floor();
    assert!(revolutions >= 2.0, "{revolutions} revolutions");
    let end = revolutions * TAU;
    let (mut mean, mut re, mut im) = (0.0, 0.0, 0.0);
    for w in track.windows(2) {
        let ((_, a0, w0), (_, a1, w1)) = (w[0], w[1]);
        if a1 > end {
            break;
        }
        let d = a1 - a0;
        mean += 0.5 * d * (w0 + w1);
        re += 0.5 * d * (w0 * (ORDER * a0).cos() + w1 * (ORDER * a1).cos());
        im += 0.5 * d * (w0 * (ORDER * a0).sin() + w1 * (ORDER * a1).sin());
    }
    let mean = mean / end;
    let amplitude = 2.0 * re.hypot(im) / end / mean;
    approx::assert_relative_eq!(mean, MEAN_RAD_S, max_relative = 1e-3);
    approx::assert_relative_eq!(amplitude, AMPLITUDE, max_relative = 0.01);
}
