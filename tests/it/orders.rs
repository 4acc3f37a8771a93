//! Order analysis (`analysis::orders`) on synthetic signals whose orders,
//! amplitudes and phases are known, at a speed that varies within the window.

use std::f64::consts::TAU;

use chaindrive::analysis::orders::{AngleWindow, OrderError, OrderSet};

/// A driver turning at a mean 2 rev/s with a ±20 % speed swing at 0.7 Hz
/// (not locked to its rotation): θ(t) = 2π (2 t + 0.4/(2π·0.7) (1 − cos 2π·0.7 t)) + θ₀,
/// sampled at `rate_hz` over `duration_s`.
fn turning(rate_hz: f64, duration_s: f64, sense: f64) -> (Vec<f64>, Vec<f64>) {
    let n = (rate_hz * duration_s) as usize;
    let t: Vec<f64> = (0..=n).map(|i| i as f64 / rate_hz).collect();
    let theta = t
        .iter()
        .map(|&t| {
            let swing = 0.4 / (TAU * 0.7) * (1.0 - (TAU * 0.7 * t).cos());
            sense * (0.3 + TAU * (2.0 * t + swing))
        })
        .collect();
    (t, theta)
}

/// x(θ) = 3 + 2 cos(3θ + 0.4) + 0.5 cos(20θ − 1.0) + 0.1 cos(θ/2 + 2.0), θ
/// the rotation angle (the driver's angle, times −1 for a clockwise driver).
fn signal(theta: &[f64], sense: f64) -> Vec<f64> {
    theta
        .iter()
        .map(|&th| {
            let phi = sense * th;
            3.0 + 2.0 * (3.0 * phi + 0.4).cos()
                + 0.5 * (20.0 * phi - 1.0).cos()
                + 0.1 * (0.5 * phi + 2.0).cos()
        })
        .collect()
}

fn check_known_orders(sense: f64) {
    // 1 kHz over 4.3 s: about 8.6 revolutions, 8 analysed (a multiple of the
    // step's denominator 2). At the slowest (1.6 rev/s) order 20 has 31
    // samples per period: cubic interpolation error ≈ (2π/31)⁴/24 ≈ 7·10⁻⁵.
    // Tolerances: 10⁻³ relative on amplitudes, 2·10⁻³ rad on phases.
    let (t, theta) = turning(1000.0, 4.3, sense);
    let x = signal(&theta, sense);
    let orders = OrderSet::new(40.0, 0.5).expect("valid set");
    let window = AngleWindow::new(&t, &theta, orders).expect("enough revolutions");
    assert_eq!(window.revolutions(), 8);
    let spectrum = window.spectrum(&x).expect("spectrum");
    assert!((spectrum.mean - 3.0).abs() < 1e-3, "mean {}", spectrum.mean);
    for (order, amplitude, phase) in [(3.0, 2.0, 0.4), (20.0, 0.5, -1.0), (0.5, 0.1, 2.0)] {
        let c = spectrum.at(order).expect("order asked for");
        assert!(
            (c.amplitude - amplitude).abs() < 1e-3 * amplitude,
            "order {order}: amplitude {} against {amplitude}",
            c.amplitude
        );
        assert!(
            (c.phase_rad - phase).abs() < 2e-3,
            "order {order}: phase {} against {phase}",
            c.phase_rad
        );
        // Its frequency: the order times the revolutions per second over the window.
        assert!((c.frequency_hz - order * window.rev_per_s()).abs() < 1e-12);
    }
    // Every other order is empty (below 10⁻³ of the smallest component).
    for c in &spectrum.components {
        if ![3.0, 20.0, 0.5].contains(&c.order) {
            assert!(c.amplitude < 1e-4, "order {}: {}", c.order, c.amplitude);
        }
    }
}

#[test]
fn orders_amplitudes_and_phases_are_recovered_at_a_varying_speed() {
    check_known_orders(1.0);
}

#[test]
fn a_clockwise_driver_has_the_same_orders_in_its_own_sense() {
    check_known_orders(-1.0);
}

#[test]
fn a_window_of_less_than_a_revolution_is_an_error() {
    let (t, theta) = turning(1000.0, 0.3, 1.0);
    let orders = OrderSet::new(10.0, 1.0).expect("valid set");
    let e = AngleWindow::new(&t, &theta, orders).expect_err("too short");
    assert!(matches!(e, OrderError::TooFewRevolutions { .. }), "{e}");
    assert!(e.to_string().contains("revolutions"), "{e}");
}

#[test]
fn an_empty_order_set_is_an_error() {
    let e = OrderSet::new(0.0, 1.0).expect_err("empty");
    assert!(e.to_string().contains("order set is empty"), "{e}");
    let e = OrderSet::new(f64::NAN, 1.0).expect_err("empty");
    assert!(matches!(e, OrderError::EmptyOrderSet { .. }), "{e}");
}

#[test]
fn a_driver_standing_still_is_an_error() {
    let t: Vec<f64> = (0..100).map(|i| i as f64 * 1e-3).collect();
    let theta = vec![0.0; 100];
    let orders = OrderSet::new(10.0, 1.0).expect("valid set");
    let e = AngleWindow::new(&t, &theta, orders).expect_err("no turn");
    assert!(e.to_string().contains("advance"), "{e}");
}

/// The sweep's order analysis of a run whose driver follows
/// ω(θ) = ω̄ (1 + a sin(2θ + φ)), a = 1 %, φ = 30°
/// (`tests/data/harmonic_order2_1pct.toml`, 300 rpm, stiff and slow): the
/// driver's speed has order 2 of amplitude a ω̄ exactly, and phase φ − π/2 in
/// the cosine form (a sin u = a cos(u − π/2)); the driven sprocket follows
/// at the kinematic ratio z₁/z₂ = 20/40, so its order 2 is a ω̄ z₁/z₂.
/// Tolerances: 1 % on the driver's amplitude, 2 % on the driven one's.
#[cfg(feature = "lab")]
#[test]
fn an_order_2_speed_harmonic_is_recovered_at_the_driver_and_at_the_kinematic_ratio() {
    use chaindrive::scene::Scene;
    use chaindrive::studies::sweep::{CaseOutcome, SweepSettings, run_sweep};
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/harmonic_order2_1pct.toml"
    ))
    .expect("scene file");
    let scene = Scene::from_toml(&text).expect("valid scene");
    let settings = SweepSettings {
        rpm: vec![300.0],
        settle_s: 0.3,
        window_s: 1.0,
        jobs: 1,
        orders: OrderSet::new(40.0, 1.0).expect("valid set"),
    };
    let cases = run_sweep(&scene, &settings, None, &|_| {}).expect("sweep");
    let CaseOutcome::Done(case) = &cases[0] else {
        panic!("{:?}", cases[0]);
    };
    let mean = 300.0 * TAU / 60.0;
    let expected = 0.01 * mean;
    let driver = case
        .signal("omega_1_rad_s")
        .and_then(|s| s.at(2.0))
        .expect("order 2");
    assert!(
        (driver.amplitude - expected).abs() < 0.01 * expected,
        "driver: {} against {expected}",
        driver.amplitude
    );
    let phase = 30f64.to_radians() - 0.5 * std::f64::consts::PI;
    assert!(
        (driver.phase_rad - phase).abs() < 0.01,
        "driver phase {}",
        driver.phase_rad
    );
    let driven = case
        .signal("omega_2_rad_s")
        .and_then(|s| s.at(2.0))
        .expect("order 2");
    let ratio = 20.0 / 40.0;
    assert!(
        (driven.amplitude - ratio * expected).abs() < 0.02 * ratio * expected,
        "driven: {} against {}",
        driven.amplitude,
        ratio * expected
    );
}
