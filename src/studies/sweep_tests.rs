//! The speed sweep (`studies::sweep`, `chaindrive sweep`): bad settings are
//! clear errors, a swept span's transverse response peaks where the
//! meshing order crosses its first transverse frequency (closed form), and
//! the speeds whose runs warned are flagged in every table and the report.

use crate::analysis::orders::OrderSet;
use crate::scene::Scene;
use crate::studies::sweep::{
    CaseFlags, CaseOutcome, DEFAULT_WINDOW_SPEED_CHANGE, PeakVerdict, RunUpSettings, SpanMode,
    SweepError, SweepSettings, judge_peak, resonance_crossings, run_sweep, run_up,
};

fn resonance_scene() -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/resonance_20_40.toml"
    ))
    .expect("scene file");
    Scene::from_toml(&text).expect("valid scene")
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

/// At 100 rpm a 0.6 s window turns the driver through exactly one
/// revolution, short of the one and 2 % the analysis asks: the refusal says
/// what it asks for, not a count its own rounding meets.
#[test]
fn a_window_of_just_one_revolution_is_refused_with_the_margin_named() {
    let s = settings(vec![100.0], 0.6);
    let e = run_sweep(&resonance_scene(), &s, None, &|_| {}).expect_err("too short");
    let text = e.to_string();
    assert!(text.contains("1.00 revolutions"), "{text}");
    assert!(text.contains("1.02 revolutions"), "{text}");
    assert!(!text.contains("needs at least 1 whole ones"), "{text}");
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
    let crossings = resonance_crossings(&cases, &[20.0]);
    let c = crossings
        .iter()
        .find(|c| c.segment == 1 && c.mode == SpanMode::Transverse(1))
        .expect("a crossing of span 1's first transverse mode");
    assert!(c.response_peaks, "{c:?}");
    assert!((c.rpm - predicted).abs() < 0.05 * predicted, "{c:?}");
}

fn scene_file(name: &str) -> Scene {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("scene file");
    Scene::from_toml(&text).expect("valid scene")
}

fn done_windows(cases: &[CaseOutcome]) -> Vec<&crate::studies::sweep::CaseResult> {
    cases
        .iter()
        .map(|c| match c {
            CaseOutcome::Done(r) => r.as_ref(),
            CaseOutcome::Failed { rpm, message } => panic!("{rpm} rpm failed: {message}"),
        })
        .collect()
}

/// ω(θ) = ω̄(t) (1 + a sin(2θ + φ)), a = 1 % (`harmonic_order2_1pct.toml`),
/// with ω̄ rising linearly from 300 to 420 rpm over 2 s: within each
/// window the order-2 amplitude of the driver's speed is a × its mean speed
/// (the harmonic rides on the slowly rising mean; the trend itself is taken
/// out of the spectrum). Tolerance: 2 % of a, over every window.
#[test]
fn a_run_up_recovers_an_order_2_speed_harmonic_across_the_ramp() {
    let scene = scene_file("harmonic_order2_1pct.toml");
    let settings = RunUpSettings {
        from_rpm: 300.0,
        to_rpm: 420.0,
        settle_s: 0.3,
        duration_s: 2.0,
        orders: OrderSet::new(40.0, 1.0).expect("valid"),
        max_speed_change: DEFAULT_WINDOW_SPEED_CHANGE,
    };
    let cases = run_up(&scene, &settings, None, &|_| {}).expect("run-up");
    let windows = done_windows(&cases);
    // 2 s at a mean 6 rev/s: about 12 revolutions, one per window at first.
    assert!(windows.len() >= 8, "{} windows", windows.len());
    let mut last_rpm = 0.0;
    for w in &windows {
        assert!(w.rpm > last_rpm, "windows in speed order");
        last_rpm = w.rpm;
        assert!(w.summary.is_none());
        let s = w.signal("omega_1_rad_s").expect("driver speed");
        let c = s.at(2.0).expect("order 2");
        let relative = c.amplitude / s.mean;
        assert!(
            (relative - 0.01).abs() < 0.02 * 0.01,
            "at {:.1} rpm: order 2 is {relative:.6} of the mean speed",
            w.rpm
        );
        // The window's mean speed is its target's (a rise of 60 rpm/s).
        assert!((s.mean * 60.0 / std::f64::consts::TAU - w.rpm).abs() < 0.01 * w.rpm);
        assert!(
            w.speed_change > 0.0 && w.speed_change < 0.05,
            "{}",
            w.speed_change
        );
    }
    assert!(windows[0].rpm < 320.0 && last_rpm > 400.0, "{last_rpm}");
}

/// The resonance drive run up slowly through its crossing (10 rpm/s, so a
/// 3-revolution window spans 2 % of speed): the meshing order's transverse
/// response peaks within 5 % of the closed-form crossing (see
/// `predicted_crossing_rpm`). A slow sweep lags the peak upward by about the
/// rate × the span's decay time; at 10 rpm/s that is well inside 5 %.
#[test]
fn a_slow_run_up_peaks_at_the_closed_form_crossing() {
    let scene = resonance_scene();
    let predicted = predicted_crossing_rpm(&scene);
    let settings = RunUpSettings {
        from_rpm: 280.0,
        to_rpm: 350.0,
        settle_s: 0.5,
        duration_s: 7.0,
        orders: OrderSet::new(40.0, 1.0).expect("valid"),
        max_speed_change: DEFAULT_WINDOW_SPEED_CHANGE,
    };
    let cases = run_up(&scene, &settings, None, &|_| {}).expect("run-up");
    let windows = done_windows(&cases);
    let response: Vec<(f64, f64)> = windows
        .iter()
        .map(|w| {
            let a = w
                .signal("seg1_transverse_m")
                .and_then(|o| o.at(20.0))
                .expect("order 20");
            (w.rpm, a.amplitude)
        })
        .collect();
    let (peak_rpm, peak) = response
        .iter()
        .copied()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("windows");
    assert!(
        (peak_rpm - predicted).abs() < 0.05 * predicted,
        "peak at {peak_rpm:.1} rpm against {predicted:.1} rpm predicted; {response:?}"
    );
    assert!(
        peak > 2.0 * response[0].1 && peak > 2.0 * response[response.len() - 1].1,
        "{response:?}"
    );
    let crossings = resonance_crossings(&cases, &[20.0]);
    let c = crossings
        .iter()
        .find(|c| c.segment == 1 && c.mode == SpanMode::Transverse(1))
        .expect("a crossing of span 1's first transverse mode");
    assert_eq!(c.verdict, PeakVerdict::Peaks, "{c:?}");
}

/// A synthetic response: a floor of 1 plus a resonance of height 20 and
/// half-width 2 % at 300 rpm, 1/(1 + ((rpm − 300)/6)²).
fn resonance(rpm: f64) -> f64 {
    1.0 + 20.0 / (1.0 + ((rpm - 300.0) / 6.0).powi(2))
}

#[test]
fn a_crossing_peaks_only_where_the_response_is_a_local_maximum_well_above_its_median() {
    // A 1 % grid from 200 to 400 rpm.
    let rpm: Vec<f64> = (0..=100).map(|i| 200.0 + 2.0 * f64::from(i)).collect();
    let response: Vec<f64> = rpm.iter().map(|&r| resonance(r)).collect();
    // At the resonance: a local maximum, 21 against a median near 1.
    let (v, j) = judge_peak(&rpm, &response, 299.3);
    assert_eq!(v, PeakVerdict::Peaks);
    assert_eq!(rpm[j], 300.0);
    // A crossing 10 % away: no peak there, though the sweep has one.
    assert_eq!(judge_peak(&rpm, &response, 330.5).0, PeakVerdict::NoPeak);
    // A flat response with a ripple: local maxima, but not 1.5 × the median.
    let ripple: Vec<f64> = rpm
        .iter()
        .enumerate()
        .map(|(i, _)| 1.0 + 0.3 * f64::from(u8::from(i % 2 == 0)))
        .collect();
    assert_eq!(judge_peak(&rpm, &ripple, 300.5).0, PeakVerdict::NoPeak);
    // A rising response peaks only at the sweep's edge: not resolved there.
    let rising: Vec<f64> = rpm.iter().map(|r| r * r).collect();
    assert_eq!(judge_peak(&rpm, &rising, 399.0).0, PeakVerdict::NotResolved);
    assert_eq!(judge_peak(&rpm, &rising, 300.5).0, PeakVerdict::NoPeak);
}

#[test]
fn a_coarse_grid_does_not_resolve_a_crossing() {
    // 10 % steps: 270, 300, 330 straddle the resonance, but 30 rpm apart is
    // more than 5 % of the crossing's rpm.
    let rpm = [240.0, 270.0, 300.0, 330.0, 360.0];
    let response: Vec<f64> = rpm.iter().map(|&r| resonance(r)).collect();
    assert_eq!(
        judge_peak(&rpm, &response, 295.0).0,
        PeakVerdict::NotResolved
    );
    // The same speeds every 4 % resolve it.
    let rpm: Vec<f64> = (0..9).map(|i| 252.0 + 12.0 * f64::from(i)).collect();
    let response: Vec<f64> = rpm.iter().map(|&r| resonance(r)).collect();
    assert_eq!(judge_peak(&rpm, &response, 298.0).0, PeakVerdict::Peaks);
}

#[test]
fn bad_run_ups_are_errors_naming_the_option_or_field() {
    let scene = resonance_scene();
    let base = RunUpSettings {
        from_rpm: 300.0,
        to_rpm: 400.0,
        settle_s: 0.1,
        duration_s: 2.0,
        orders: OrderSet::new(40.0, 1.0).expect("valid"),
        max_speed_change: DEFAULT_WINDOW_SPEED_CHANGE,
    };
    for (settings, start) in [
        (
            RunUpSettings {
                duration_s: -1.0,
                ..base.clone()
            },
            "--duration -1",
        ),
        (
            RunUpSettings {
                duration_s: 0.1,
                ..base.clone()
            },
            "--duration 0.1",
        ),
        (
            RunUpSettings {
                settle_s: f64::NAN,
                ..base.clone()
            },
            "--settle",
        ),
        (
            RunUpSettings {
                to_rpm: 200.0,
                ..base.clone()
            },
            "--run-up",
        ),
    ] {
        let e = run_up(&scene, &settings, None, &|_| {}).expect_err(start);
        assert!(e.to_string().starts_with(start), "{e}");
    }
    // In a scene file: the field's path and what is allowed.
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/resonance_20_40.toml"
    ))
    .expect("scene file");
    for (table, path, why) in [
        (
            "run_up = { to_rpm = 400.0, duration_s = 0.0 }",
            "sprockets[0].run_up.duration_s",
            "must be > 0",
        ),
        (
            "run_up = { to_rpm = -400.0, duration_s = 1.0 }",
            "sprockets[0].run_up.to_rpm",
            "sense",
        ),
        (
            "run_up = { to_rpm = 400.0, duration_s = 1.0, start_s = 0.1 }",
            "sprockets[0].run_up.start_s",
            "ramp",
        ),
    ] {
        let edited = text.replace("ramp_s = 0.2", &format!("ramp_s = 0.2\n{table}"));
        let e = Scene::from_toml(&edited).expect_err(table).to_string();
        assert!(e.contains(path) && e.contains(why), "{table}: {e}");
    }
    let edited = text.replace(
        "role = \"free\"",
        "role = \"free\"\nrun_up = { to_rpm = 400.0, duration_s = 1.0 }",
    );
    let e = Scene::from_toml(&edited).expect_err("free").to_string();
    assert!(e.contains("sprockets[1].run_up"), "{e}");
}

/// The resonance drive with a soft contact (K = 1e7 N/m^1.5 against its
/// 1e8): a seated roller carries about T·2π/z = 1000 · 2π/20 ≈ 314 N, so
/// Hertz's δ = (F/K)^(2/3) ≈ 1 mm, a quarter of the roller radius
/// (3.96 mm): the summary's penetration warning (above 10 %) fires at every
/// speed.
fn soft_contact_scene() -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/resonance_20_40.toml"
    ))
    .expect("scene file")
    .replace("stiffness = 1e8", "stiffness = 1e7");
    Scene::from_toml(&text).expect("valid scene")
}

/// A case is `warned` when its summary warns or a segment is not
/// stationary, `ok` when neither, `failed` when it did not finish.
#[test]
fn a_case_is_flagged_by_its_warnings_and_its_stationarity() {
    let cases = run_sweep(
        &soft_contact_scene(),
        &SweepSettings {
            settle_s: 0.1,
            ..settings(vec![300.0], 0.25)
        },
        None,
        &|_| {},
    )
    .expect("runs");
    let CaseOutcome::Done(done) = &cases[0] else {
        panic!("{:?}", cases[0])
    };
    let summary = done.summary.as_ref().expect("a stepped case has a summary");
    // The criterion, from the summary's own depth.
    assert!(summary.max_penetration_m > 0.1 * 0.00396, "{summary:?}");
    let flags = CaseFlags::of(&cases[0]);
    assert_eq!(flags.status, "warned");
    assert!(
        flags
            .warnings
            .as_ref()
            .is_some_and(|w| w.iter().any(|w| w.starts_with("penetration"))),
        "{flags:?}"
    );
    // The same case with its warnings gone and every segment stationary is
    // ok; one segment drifting makes it warned again.
    let mut clean = done.clone();
    let s = clean.summary.as_mut().expect("summary");
    s.warnings.clear();
    s.segments.iter_mut().for_each(|g| g.stationary = true);
    let ok = CaseFlags::of(&CaseOutcome::Done(clean.clone()));
    assert_eq!((ok.status, ok.stationary), ("ok", Some(true)));
    clean.summary.as_mut().expect("summary").segments[1].stationary = false;
    let drifting = CaseFlags::of(&CaseOutcome::Done(clean));
    assert_eq!(drifting.status, "warned");
    assert_eq!(drifting.stationary, Some(false));
    assert_eq!(drifting.not_stationary, [2]);
    let failed = CaseFlags::of(&CaseOutcome::Failed {
        rpm: 300.0,
        message: "blew up".to_owned(),
    });
    assert_eq!(failed.status, "failed");
    assert_eq!(failed.error.as_deref(), Some("blew up"));
}
