//! Excitation: the driver's speed harmonics against the closed-form angle
//! and speed, load torques in a sprocket's angle, the example scene.

use crate::scene::{Integrator, Overrides, Scene};
use crate::sim::Simulation;
use std::f64::consts::{PI, TAU};
use std::path::Path;

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
    // O(dt²) ≈ (ω̄ dt)² a k² / 6 per unit time (≈ 1e-11 s over the run at
    // dt ≈ 5 µs); the Runge–Kutta schemes by less. Tolerance: 1e-10 s. (A
    // first RK stage at the relaxed speed 0 instead of ω(0, θ₀) errs by 1e-6 s.)
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
        eprintln!("{}: |t(θ) − t| ≤ {worst:.2e} s", scheme.name());
        assert!(
            worst < 1e-10,
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
        eprintln!("{}: speed off the law by ≤ {worst:.2e} ω̄", scheme.name());
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
    eprintln!("angle-mean speed {mean} rad/s, order-2 amplitude {amplitude}");
    approx::assert_relative_eq!(mean, MEAN_RAD_S, max_relative = 1e-3);
    approx::assert_relative_eq!(amplitude, AMPLITUDE, max_relative = 0.01);
}

/// The example timing drive, `assets/timing-excited.toml`, read from its
/// directory (its cam table beside it), run for `duration_s`.
fn timing_excited(duration_s: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/timing-excited.toml");
    Scene::from_path_with(
        &path,
        &Overrides {
            duration_s: Some(duration_s),
            ..Overrides::default()
        },
    )
    .expect("readable")
    .unwrap_or_else(|e| panic!("timing-excited.toml: {e}"))
}

/// The rows of `assets/cam-torque.csv` (angle °, torque N·m), read here
/// independently of the crate's reader.
fn cam_table() -> Vec<(f64, f64)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cam-torque.csv");
    std::fs::read_to_string(path)
        .expect("cam table")
        .lines()
        .filter_map(|l| {
            let (a, t) = l.split_once(',')?;
            Some((a.parse().ok()?, t.parse().ok()?))
        })
        .collect()
}

#[test]
fn the_cam_table_load_is_exact_at_the_nodes() {
    // The load on a cam at angle θ₀ + α (α a tabled angle) is
    // −1.5 N·m + scale · T(α) with scale = −1 (the scene), exactly at every
    // node of the spline; halfway between nodes it stays within the
    // table's local spread.
    let scene = timing_excited(0.1);
    let (model, _, layout) = crate::model::DriveModel::build(&scene).expect("model");
    let rows = cam_table();
    assert_eq!(rows.len(), 181);
    for cam in [1, 2] {
        let sp = &model.sprockets[cam];
        let origin = layout.sprocket_angles_rad[cam];
        for &(deg, torque) in &rows {
            let got = sp.torque_at(1.0, origin + deg.to_radians(), 0.0);
            approx::assert_abs_diff_eq!(got, -1.5 - torque, epsilon = 1e-9);
        }
        for w in rows.windows(2) {
            let mid = 0.5 * (w[0].0 + w[1].0);
            let got = -1.5 - sp.torque_at(1.0, origin + mid.to_radians(), 0.0);
            let (lo, hi) = (w[0].1.min(w[1].1), w[0].1.max(w[1].1));
            let spread = 0.05 * (hi - lo) + 1e-3;
            assert!(
                got >= lo - spread && got <= hi + spread,
                "{mid}°: {got} outside [{lo}, {hi}]"
            );
        }
    }
}

#[test]
fn the_example_timing_drive_runs_with_its_excitation() {
    // A short run of the example: no blow-up, every value finite, and the
    // crankshaft's speed carries its order-2 harmonic of 1.5 % (within 2 %)
    // over the last whole revolution once the ramp is over (0.2 s).
    let scene = timing_excited(0.3);
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let dt = scene.solver().dt_s;
    let origin = sim.state.theta[0];
    let mut track = Vec::new();
    for _ in 0..(0.3 / dt).round() as usize {
        sim.step(dt).expect("step");
        let s = &sim.state;
        assert!(s.omega.iter().all(|w| w.is_finite()), "t = {}", s.t_s);
        if s.t_s > 0.2 {
            track.push((s.theta[0] - origin, s.omega[0]));
        }
    }
    let start = track[0].0;
    let end = start + TAU;
    assert!(
        track.last().map_or(0.0, |r| r.0) > end,
        "a whole revolution"
    );
    let (mut mean, mut re, mut im) = (0.0, 0.0, 0.0);
    for w in track.windows(2) {
        let ((a0, w0), (a1, w1)) = (w[0], w[1]);
        if a1 > end {
            break;
        }
        let d = a1 - a0;
        mean += 0.5 * d * (w0 + w1);
        re += 0.5 * d * (w0 * (2.0 * a0).cos() + w1 * (2.0 * a1).cos());
        im += 0.5 * d * (w0 * (2.0 * a0).sin() + w1 * (2.0 * a1).sin());
    }
    let mean = mean / TAU;
    eprintln!(
        "example: mean {mean} rad/s, order-2 amplitude {}",
        2.0 * re.hypot(im) / TAU / mean
    );
    approx::assert_relative_eq!(mean, 1500.0 * TAU / 60.0, max_relative = 1e-3);
    approx::assert_relative_eq!(2.0 * re.hypot(im) / TAU / mean, 0.015, max_relative = 0.02);
}

/// The errors of the harmonic driver's scene with `edit` applied to its text.
fn errors_of(edit: impl Fn(String) -> String) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let text = std::fs::read_to_string(path.join("harmonic_driver_20_40.toml")).expect("scene");
    Scene::from_toml_in(&edit(text), Some(&path), &Overrides::default())
        .expect_err("invalid")
        .to_string()
}

#[test]
fn speed_harmonics_on_a_free_sprocket_are_a_field_error() {
    let msg = errors_of(|t| {
        t.replace(
            "role = \"free\"",
            "role = \"free\"\nspeed_harmonics = [{ order = 2, amplitude = 0.1 }]",
        )
    });
    assert!(msg.contains("sprockets[1].speed_harmonics"), "{msg}");
}

#[test]
fn speed_harmonics_that_stop_the_driver_are_a_field_error() {
    let msg = errors_of(|t| t.replace("amplitude = 0.05", "amplitude = 1.2"));
    assert!(
        msg.contains("sprockets[0].speed_harmonics") && msg.contains("< 1"),
        "{msg}"
    );
    let msg = errors_of(|t| t.replace("order = 2", "order = 0"));
    assert!(
        msg.contains("sprockets[0].speed_harmonics[0].order"),
        "{msg}"
    );
}

#[test]
fn a_missing_load_table_is_a_field_error() {
    let msg = errors_of(|t| {
        t.replace(
            "role = \"free\"",
            "role = \"free\"\nload_table = { file = \"no-such-table.csv\" }",
        )
    });
    assert!(
        msg.contains("sprockets[1].load_table.file") && msg.contains("no-such-table.csv"),
        "{msg}"
    );
}

#[test]
fn a_bad_load_table_is_a_field_error_naming_its_line() {
    // A table whose angles span 350°, written beside a scene.
    let dir = std::env::temp_dir().join(format!("chaindrive-excitation-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(
        dir.join("short.csv"),
        "angle_deg,torque_n_m\n0,1\n120,2\n240,0\n350,1\n",
    )
    .expect("table");
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/harmonic_driver_20_40.toml"),
    )
    .expect("scene")
    .replace(
        "role = \"free\"",
        "role = \"free\"\nload_table = { file = \"short.csv\" }",
    );
    let msg = Scene::from_toml_in(&text, Some(&dir), &Overrides::default())
        .expect_err("invalid")
        .to_string();
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        msg.contains("sprockets[1].load_table.file") && msg.contains("360°"),
        "{msg}"
    );
}
