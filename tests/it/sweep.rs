//! The speed sweep (`studies::sweep`, `chaindrive sweep`): bad settings are
//! clear errors, and a swept span's transverse response peaks where the
//! meshing order crosses its first transverse frequency (closed form).

use chaindrive::analysis::orders::OrderSet;
use chaindrive::scene::Scene;
use chaindrive::studies::sweep::{
    CaseOutcome, SweepError, SweepSettings, parse_rpm_range, parse_run_up, run_sweep,
};

fn resonance_scene() -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/resonance_20_40.toml"
    ))
    .expect("scene file");
    Scene::from_toml(&text).expect("valid scene")
}

#[test]
fn a_speed_range_includes_both_ends() {
    let rpm = parse_rpm_range("--rpm", "300:3000:100").expect("valid");
    assert_eq!(rpm.len(), 28);
    assert_eq!(rpm[0], 300.0);
    assert_eq!(rpm[27], 3000.0);
    assert_eq!(parse_rpm_range("--rpm", "100:100:5").expect("one").len(), 1);
}

#[test]
fn bad_speed_ranges_are_errors_naming_the_option() {
    for (text, why) in [
        ("300:3000", "three numbers"),
        ("0:3000:100", "FROM must be > 0"),
        ("3000:300:100", "TO must not be below FROM"),
        ("300:3000:0", "STEP must be > 0"),
        ("300:3000:-5", "STEP must be > 0"),
        ("a:3000:100", "not a number"),
        ("1:1e9:1e-3", "more than"),
    ] {
        let e = parse_rpm_range("--rpm", text).expect_err(text);
        let msg = e.to_string();
        assert!(msg.starts_with("--rpm"), "{msg}");
        assert!(msg.contains(why), "{text}: {msg}");
    }
    let e = parse_run_up("3000:300").expect_err("descending");
    assert!(e.to_string().contains("--run-up"), "{e}");
}

fn settings(rpm: Vec<f64>, window_s: f64) -> SweepSettings {
    SweepSettings {
        rpm,
        settle_s: 0.2,
        window_s,
        jobs: 2,
        orders: OrderSet::new(80.0, 1.0).expect("valid"),
    }
}

#[test]
fn a_window_too_short_for_a_revolution_is_an_error_before_anything_runs() {
    // At 30 rpm a 1 s window turns the driver half a revolution.
    let e = run_sweep(&resonance_scene(), &settings(vec![30.0, 300.0], 1.0), None, &|_| {})
        .expect_err("too short");
    assert!(matches!(e, SweepError::BadTime { what: "--window", .. }), "{e}");
    assert!(e.to_string().contains("0.50 revolutions"), "{e}");
}

#[test]
fn a_negative_window_is_an_error() {
    let e = run_sweep(&resonance_scene(), &settings(vec![300.0], -1.0), None, &|_| {})
        .expect_err("negative");
    assert!(e.to_string().starts_with("--window -1"), "{e}");
}
