//! The speed sweep (`studies::sweep`, `chaindrive sweep`): bad settings are
//! clear errors, and a swept span's transverse response peaks where the
//! meshing order crosses its first transverse frequency (closed form).

use chaindrive::analysis::orders::OrderSet;
use chaindrive::scene::Scene;
use chaindrive::studies::sweep::{
    CaseOutcome, SpanMode, SweepError, SweepSettings, parse_rpm_range, parse_run_up, run_sweep,
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
    let e = run_sweep(
        &resonance_scene(),
        &settings(vec![30.0, 300.0], 1.0),
        None,
        &|_| {},
    )
    .expect_err("too short");
    assert!(
        matches!(
            e,
            SweepError::BadTime {
                what: "--window",
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("0.50 revolutions"), "{e}");
}

#[test]
fn a_negative_window_is_an_error() {
    let e = run_sweep(
        &resonance_scene(),
        &settings(vec![300.0], -1.0),
        None,
        &|_| {},
    )
    .expect_err("negative");
    assert!(e.to_string().starts_with("--window -1"), "{e}");
}

/// The first transverse frequency of a free strand meets the meshing order
/// (z₁ teeth per driver revolution) at, in closed form:
///
/// f_mesh = z₁ n = v / P (v = z₁ P n the chain speed, n rev/s),
/// f₁ = (1 / 2L) c (1 − v²/c²), c² = T/μ, with the running tension
/// T = T₀ + μ v² (the moving string's centrifugal term), so c² = c₀² + v²
/// (c₀² = T₀/μ) and f₁ = c₀² / (2 L √(c₀² + v²)). Setting them equal:
/// v² (c₀² + v²) = (P c₀² / 2L)², i.e. v² = (c₀²/2) (√(1 + (P/L)²) − 1),
/// and rpm = 60 v / (z₁ P).
///
/// L is the straight strand between the two pitch circles,
/// √(d² − (R₂ − R₁)²), R = P / (2 sin(π/z)). The assumptions: a strand
/// held at its tangent points, small amplitudes (linear string), the mean
/// tension at its static value (no load, T₀ the pretension).
fn predicted_crossing_rpm(scene: &Scene) -> f64 {
    let chain = scene.chain();
    let p = chain.pitch_m;
    let mu = chain.roller_mass_kg / p;
    let s = scene.sprockets();
    let radius = |z: u32| p / (2.0 * (std::f64::consts::PI / f64::from(z)).sin());
    let (r1, r2) = (radius(s[0].teeth), radius(s[1].teeth));
    let d = (s[0].center_m[0] - s[1].center_m[0]).hypot(s[0].center_m[1] - s[1].center_m[1]);
    let l = (d * d - (r2 - r1) * (r2 - r1)).sqrt();
    let c0_sq = chain.pretension_n / mu;
    let v = (0.5 * c0_sq * ((1.0 + (p / l) * (p / l)).sqrt() - 1.0)).sqrt();
    60.0 * v / (f64::from(s[0].teeth) * p)
}

#[test]
fn the_span_response_peaks_where_the_meshing_order_crosses_its_first_transverse_frequency() {
    let scene = resonance_scene();
    let predicted = predicted_crossing_rpm(&scene);
    // 20 teeth, P = 12.7 mm, L = 194.56 mm, T₀ = 1 kN, μ = 0.610 kg/m: 312.1 rpm.
    assert!((predicted - 312.1).abs() < 0.5, "{predicted}");
    // A coarse sweep, ±8 % around it in 10 rpm steps (the full range:
    // `chaindrive sweep tests/data/resonance_20_40.toml --rpm 200:450:5`).
    let rpm = vec![290.0, 300.0, 310.0, 320.0, 330.0, 340.0];
    let mut s = settings(rpm, 1.0);
    s.settle_s = 0.5;
    let cases = run_sweep(&scene, &s, None, &|_| {}).expect("sweep");
    let done: Vec<_> = cases
        .iter()
        .map(|c| match c {
            CaseOutcome::Done(r) => r.as_ref(),
            CaseOutcome::Failed { rpm, message } => panic!("{rpm} rpm failed: {message}"),
        })
        .collect();
    for span in ["seg1_transverse_m", "seg2_transverse_m"] {
        let response: Vec<(f64, f64)> = done
            .iter()
            .map(|c| {
                let a = c.signal(span).and_then(|o| o.at(20.0)).expect("order 20");
                (c.rpm, a.amplitude)
            })
            .collect();
        let (peak_rpm, peak) = response
            .iter()
            .copied()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("cases");
        assert!(
            (peak_rpm - predicted).abs() < 0.05 * predicted,
            "{span}: peak at {peak_rpm} rpm against {predicted:.1} rpm predicted; {response:?}"
        );
        // A peak, not an edge of the range: at least twice either end.
        assert!(
            peak > 2.0 * response[0].1 && peak > 2.0 * response[response.len() - 1].1,
            "{span}: {response:?}"
        );
    }
    // The report's crossing finder sees it too: the meshing order meets span
    // 1's first transverse frequency (from the runs' own tension), and the
    // response peaks there.
    let crossings = chaindrive::studies::sweep::resonance_crossings(&cases, &[20.0]);
    let c = crossings
        .iter()
        .find(|c| c.segment == 1 && c.mode == SpanMode::Transverse(1))
        .expect("a crossing of span 1's first transverse mode");
    assert!(c.response_peaks, "{c:?}");
    assert!((c.rpm - predicted).abs() < 0.05 * predicted, "{c:?}");
}
