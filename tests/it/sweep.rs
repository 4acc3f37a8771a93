//! The speed sweep (`studies::sweep`, `chaindrive sweep`): bad settings are
//! clear errors, a swept span's transverse response peaks where the
//! meshing order crosses its first transverse frequency (closed form), and
//! the speeds whose runs warned are flagged in every table and the report.

use chaindrive::analysis::orders::OrderSet;
use chaindrive::scene::Scene;
use chaindrive::studies::sweep::{
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

fn done_windows(cases: &[CaseOutcome]) -> Vec<&chaindrive::studies::sweep::CaseResult> {
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

/// `chaindrive sweep` end to end: the speeds whose runs warned are flagged
/// in `cases.csv` (status, warnings), in `sweep.csv` (`warned` = 1,
/// `warning_count`) and in `report.md` (a table of the runs to doubt, and
/// the worst-case speeds' `run` column); the summary's window is the
/// `--window` asked for, after the ramp and the settling time.
#[cfg(feature = "cli")]
#[test]
fn a_sweep_flags_the_speeds_whose_runs_warned() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/resonance_20_40.toml"
    );
    let out = crate::common::chaindrive(&[
        "sweep",
        scene,
        "--rpm",
        "300:310:10",
        "--settle",
        "0.1",
        "--window",
        "0.25",
        "--set",
        "contact.stiffness=1e7",
        "--jobs",
        "2",
        "--quiet",
        "--out",
        dir.path().to_str().expect("a UTF-8 path"),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", crate::common::stderr(&out));
    assert!(
        stdout.contains("2 warned (see report.md, cases.csv)"),
        "{stdout}"
    );
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).expect(name);
    // sweep.csv: rpm,statistic,value.
    let sweep = read("sweep.csv");
    let value = |rpm: &str, statistic: &str| -> f64 {
        sweep
            .lines()
            .find_map(|l| l.strip_prefix(&format!("{rpm},{statistic},")))
            .unwrap_or_else(|| panic!("{rpm} {statistic}"))
            .parse()
            .expect("a number")
    };
    for rpm in ["300", "310"] {
        // The criterion: deeper than 10 % of the roller radius, 3.96 mm.
        assert!(value(rpm, "max_penetration_m") > 0.1 * 0.00396, "{rpm}");
        assert_eq!(value(rpm, "warned"), 1.0, "{rpm}");
        assert!(value(rpm, "warning_count") >= 1.0, "{rpm}");
        // Ramp 0.2 s + settle 0.1 s, then the 0.25 s window, ending at the
        // last sample (the rate is at least 1 kHz).
        let (start, end) = (value(rpm, "window_s[0]"), value(rpm, "window_s[1]"));
        assert!((end - start - 0.25).abs() < 1e-9, "{rpm}: {start} … {end}");
        assert!(end <= 0.55 + 1e-9 && end > 0.55 - 1e-3, "{rpm}: {end}");
    }
    // cases.csv: one row per speed.
    let cases = read("cases.csv");
    let mut lines = cases.lines();
    assert_eq!(
        lines.next(),
        Some("rpm,status,stationary,warning_count,warnings,error")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 2, "{cases}");
    for row in &rows {
        assert!(row.contains(",warned,"), "{row}");
        assert!(row.contains("penetration: a roller sank"), "{row}");
    }
    // report.md: the runs to doubt, and the worst cases' runs.
    let report = read("report.md");
    let doubt = report
        .split("## Runs to doubt")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .unwrap_or_else(|| panic!("{report}"));
    assert!(doubt.contains("2 of 2 speeds"), "{doubt}");
    for rpm in ["| 300 |", "| 310 |"] {
        let line = doubt
            .lines()
            .find(|l| l.starts_with(rpm))
            .unwrap_or_else(|| panic!("{rpm}: {doubt}"));
        assert!(line.contains("penetration"), "{line}");
    }
    assert!(
        report.contains("| largest penetration | ") && report.contains(" | warned |"),
        "{report}"
    );
}

/// `chaindrive sweep` of a drive with a designation judges every speed by
/// its design checks (`verdict.csv`, the report's "Will it last?"): the
/// motorcycle's ISO 606 10B-1 chain on a 15-tooth engine sprocket, its
/// 44-tooth wheel braked by 560 N·m, at 2000 and 4000 rpm. By hand:
/// - rating: above about 1100 rpm the roller–bushing limit governs,
///   H₂ = 1000 · 17 · 15^1.5 · 0.625^0.8 / n^1.5 hp (n in rpm), and the
///   load takes 560 N·m · (2π n / 60) · 15/44; the run's transmitted power
///   is the driver's mean power, the load's plus what the chain's damping
///   and the impacts dissipate (a few per cent), so the margin is within
///   5 % of H₂ over the load's power;
/// - static safety factor: the tight strand carries at least the load's
///   torque over the wheel's pitch radius, 560 / (0.015875 / (2 sin(π/44)))
///   = 5.03 kN, so the factor is at most 22.2 kN / 5.03 kN = 4.41;
/// - the margin falls as n^−2.5 and the links pass the tight strand twice
///   as often at 4000 rpm under no smaller forces (the centrifugal tension
///   grows), so 4000 rpm is the weakest speed by margin and by damage.
#[cfg(feature = "cli")]
#[test]
fn a_sweep_tables_each_speeds_safety_factor_rating_margin_and_fatigue_damage() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/moto_10b_15_44_560nm.toml"
    );
    let out = crate::common::chaindrive(&[
        "sweep",
        scene,
        "--rpm",
        "2000:4000:2000",
        "--settle",
        "0.05",
        "--window",
        "0.15",
        "--jobs",
        "2",
        "--quiet",
        "--out",
        dir.path().to_str().expect("a UTF-8 path"),
    ]);
    assert!(out.status.success(), "{}", crate::common::stderr(&out));
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).expect(name);
    let verdict = read("verdict.csv");
    let mut lines = verdict.lines();
    assert_eq!(
        lines.next(),
        Some(
            "rpm,static_safety_factor,mean_static_safety_factor,rating_margin,design_power_w,transmitted_power_w,damage_per_hour,fatigue_life_h,fatigue_safety_factor"
        )
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|c| c.parse().unwrap_or_else(|_| panic!("{c:?} in {l}")))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), 2, "{verdict}");
    let wheel_radius_m = 0.015875 / (2.0 * (std::f64::consts::PI / 44.0).sin());
    let tight_n = 560.0 / wheel_radius_m;
    for row in &rows {
        let (rpm, factor, margin, damage, life) = (row[0], row[1], row[3], row[6], row[7]);
        let h2_w = 745.7 * 1000.0 * 17.0 * 15f64.powf(1.5) * 0.625f64.powf(0.8) / rpm.powf(1.5);
        let load_w = 560.0 * rpm * std::f64::consts::TAU / 60.0 * 15.0 / 44.0;
        approx::assert_relative_eq!(row[4], h2_w, max_relative = 1e-3);
        approx::assert_relative_eq!(margin, h2_w / load_w, max_relative = 0.05);
        assert!(
            factor > 0.0 && factor <= 22_200.0 / tight_n,
            "{rpm}: {factor}"
        );
        assert!(damage > 0.0, "{rpm}");
        approx::assert_relative_eq!(life * damage, 1.0, max_relative = 1e-12);
    }
    assert!(
        rows[1][3] < rows[0][3] && rows[1][6] > rows[0][6],
        "{verdict}"
    );
    let report = read("report.md");
    assert!(report.contains("## Will it last?"), "{report}");
    assert!(
        report.contains("- smallest rating margin: ")
            && report.contains("- largest fatigue damage per hour: "),
        "{report}"
    );
    for line in report.lines().filter(|l| {
        l.starts_with("- smallest rating margin") || l.starts_with("- largest fatigue damage")
    }) {
        assert!(line.ends_with("at 4000 rpm"), "{line}");
    }
}
