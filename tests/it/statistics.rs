//! Statistics that say how sure they are: the summary's standard errors,
//! RMS and stationarity on runs and synthetic signals, `run --window`, and
//! `bench convergence` end to end.

use chaindrive::analysis::{RunSummary, SampleRow, Signals, SummaryInputs};
use chaindrive::model::DriveModel;
use chaindrive::scene::Scene;

const MOTORCYCLE: &str = include_str!("../data/motorcycle_520.toml");

/// The motorcycle drive without its load, at constant speed, judged on
/// synthetic samples at 1 kHz over 1.5 s, each strand's force from `force(t)`.
fn synthetic(force: impl Fn(f64) -> f64, window_s: f64) -> RunSummary {
    let toml = MOTORCYCLE
        .replace("load_torque_n_m = -220.0", "")
        .replace("ramp_s = 0.1", "ramp_s = 0.0");
    let scene = Scene::from_toml(&toml).expect("valid");
    let (model, _, _) = DriveModel::build(&scene).expect("lays out");
    let mut signals = Signals::new(&model, 1000.0, 0.0);
    let segments = model.segments.len();
    signals.rows = (0..=1500)
        .map(|k| {
            let t = k as f64 * 1e-3;
            // 600 rad/s: the 15T sprocket's tooth-passing frequency, 1432 Hz,
            // and its harmonics keep away from multiples of the 1 kHz samples.
            let omega = 600.0 + 3.0 * (std::f64::consts::TAU * 50.0 * t).sin();
            SampleRow {
                t_s: t,
                omega_rad_s: vec![omega, omega / 3.0],
                chain_torque_n_m: vec![-2.0, 0.0],
                bearing_max_n: vec![0.0; 2],
                segment_force_n: vec![Some(force(t)); segments],
                transverse_m: vec![0.0; segments],
                link_range_n: (100.0, 3000.0),
                tensioners: Vec::new(),
                shoes: Vec::new(),
                step_sums: Default::default(),
            }
        })
        .collect();
    RunSummary::compute_over(
        &SummaryInputs {
            scene: &scene,
            model: &model,
            static_tension_n: scene.chain().pretension_n,
            static_force_residual: None,
            static_unsettled_cause: None,
            steps: 1,
            wall_s: 0.0,
            setup_wall_s: 0.0,
            interrupted: false,
            max_penetration_m: 1e-4,
        },
        &signals,
        window_s,
    )
}

#[test]
fn a_steady_periodic_force_is_stationary_with_its_closed_form_rms() {
    // 1725 N plus 200 N at 120 Hz: RMS = 200/√2 = 141.42 N (the window holds
    // 120 whole periods: exact up to rounding); the sprocket's speed swings
    // 3 rad/s at 50 Hz: RMS 3/√2. The batch means of a sine over 50 ms
    // batches (6 periods each) agree to rounding: SE ≈ 0.
    let s = synthetic(
        |t| 1725.0 + 200.0 * (std::f64::consts::TAU * 120.0 * t).sin(),
        1.0,
    );
    assert_eq!(s.window_s, [0.5, 1.5]);
    for seg in &s.segments {
        approx::assert_relative_eq!(
            seg.link_force_rms_n,
            200.0 / 2f64.sqrt(),
            max_relative = 1e-6
        );
        assert!(
            seg.mean_link_force_se_n < 1e-6,
            "{}",
            seg.mean_link_force_se_n
        );
        assert!(seg.stationary);
    }
    approx::assert_relative_eq!(
        s.sprockets[0].speed_rms_rad_s,
        3.0 / 2f64.sqrt(),
        max_relative = 1e-6
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn a_drifting_force_is_not_stationary_and_warns() {
    // +100 N/s on 1725 N with the same oscillation: over a 1 s window the
    // thirds' means differ by 66.7 N; the batch-means SE of each third
    // (20 batches of 16–17 ms, not whole periods) is below 1 N.
    let s = synthetic(
        |t| 1725.0 + 100.0 * t + 200.0 * (std::f64::consts::TAU * 120.0 * t).sin(),
        1.0,
    );
    assert!(s.segments.iter().all(|seg| !seg.stationary));
    let warning = s
        .warnings
        .iter()
        .find(|w| w.starts_with("not stationary"))
        .unwrap_or_else(|| panic!("{:?}", s.warnings));
    assert!(warning.contains("segment 1"), "{warning}");
    assert!(warning.contains("0.50–1.50 s"), "{warning}");
}

#[test]
fn the_window_is_the_last_seconds_asked_for() {
    // A step of 100 N at t = 0.75 s: the last 0.5 s sees only the upper level
    // (stationary), the last 1.5 s both (not).
    let step = |t: f64| if t < 0.75 { 1725.0 } else { 1825.0 };
    let late = synthetic(step, 0.5);
    assert_eq!(late.window_s, [1.0, 1.5]);
    approx::assert_relative_eq!(late.segments[0].mean_link_force_n, 1825.0);
    assert!(late.segments[0].stationary);
    let whole = synthetic(step, 1.5);
    assert_eq!(whole.window_s, [0.0, 1.5]);
    assert!(!whole.segments[0].stationary);
}

#[test]
fn the_paper_drive_summary_bounds_its_fluctuation() {
    // Popoviciu: a variable confined to [lo, hi] has a standard deviation of
    // at most (hi − lo)/2, so RMS ≤ p2p / 2; the SE of the mean is positive
    // (the force fluctuates) and far below the RMS (1000 samples).
    let s = crate::common::run_summary(1.2, 1000.0);
    for seg in &s.segments {
        assert!(seg.link_force_rms_n > 0.0);
        assert!(
            seg.link_force_rms_n <= 0.5 * seg.link_force_p2p_n + 1e-9,
            "{seg:?}"
        );
        assert!(seg.mean_link_force_se_n > 0.0, "{seg:?}");
        assert!(seg.mean_link_force_se_n < seg.link_force_rms_n, "{seg:?}");
    }
    for sp in &s.sprockets {
        assert!(
            sp.speed_rms_rad_s <= 0.5 * sp.speed_p2p_rad_s + 1e-12,
            "{sp:?}"
        );
    }
}

#[cfg(feature = "cli")]
mod cli {
    use crate::common::{chaindrive, read_json, stderr};

    #[test]
    fn run_window_is_checked_and_used() {
        for (window, reason) in [("-1", "> 0"), ("0", "> 0"), ("3", "longer than the run")] {
            let out = chaindrive(&["run", "--duration", "0.5", "--window", window, "--quiet"]);
            assert!(!out.status.success());
            let err = stderr(&out);
            assert!(err.contains("--window") && err.contains(reason), "{err}");
            assert!(!err.contains("panicked"), "{err}");
        }
        let dir = tempfile::tempdir().expect("tmp");
        let summary = dir.path().join("s.json");
        let out = chaindrive(&[
            "run",
            "--duration",
            "0.6",
            "--window",
            "0.4",
            "--quiet",
            "--summary",
            summary.to_str().expect("utf8"),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let v = read_json(&summary);
        let w: Vec<f64> = v["window_s"]
            .as_array()
            .expect("window")
            .iter()
            .map(|x| x.as_f64().expect("number"))
            .collect();
        approx::assert_abs_diff_eq!(w[0], 0.2, epsilon = 1e-9);
        approx::assert_abs_diff_eq!(w[1], 0.6, epsilon = 1e-9);
        let table = String::from_utf8(out.stdout).expect("utf8");
        assert!(
            table.contains("±se_n") && table.contains("speed_rms_rad_s"),
            "{table}"
        );
    }

    #[test]
    fn bench_convergence_writes_its_csv_and_verdict() {
        let dir = tempfile::tempdir().expect("tmp");
        let out = chaindrive(&[
            "bench",
            "convergence",
            "--quick",
            "--duration",
            "0.1",
            "--warmup",
            "0.1",
            "--out",
            dir.path().to_str().expect("utf8"),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let stdout = String::from_utf8(out.stdout).expect("utf8");
        assert!(stdout.contains("verdict: "), "{stdout}");
        let text = std::fs::read_to_string(dir.path().join("convergence.csv")).expect("csv");
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let header: Vec<String> = reader
            .headers()
            .expect("header")
            .iter()
            .map(str::to_owned)
            .collect();
        assert_eq!(
            header.join(","),
            "integrator,setting,dt_s,wall_s,duration_s,statistic,value,reference,reference_se,rel_error"
        );
        let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.expect("row")).collect();
        // The paper's drive: 4 segments × 3 statistics, the 3 sprockets
        // besides the driver × 1, 3 for the run (penetration, driver and
        // friction power) = 18 per run; the reference and 2 settings.
        assert_eq!(rows.len(), 3 * 18, "{text}");
        assert!(
            !text.contains("sprocket1_"),
            "the driver's speed is prescribed"
        );
        let settings: std::collections::BTreeSet<&str> = rows.iter().map(|r| &r[1]).collect();
        assert_eq!(
            settings.into_iter().collect::<Vec<_>>(),
            ["dt=1e-5", "dt=2e-5", "dt=5e-6"]
        );
        for r in &rows {
            let value: f64 = r[6].parse().expect("a value");
            let reference: f64 = r[7].parse().expect("a reference");
            let rel: f64 = r[9].parse().expect("a relative error");
            assert!(value.is_finite() && reference.is_finite(), "{r:?}");
            approx::assert_abs_diff_eq!(
                r[4].parse::<f64>().expect("duration"),
                0.1,
                epsilon = 1e-9
            );
            // rel_error is what it says, from the row's own numbers.
            if reference != 0.0 {
                approx::assert_relative_eq!(
                    rel,
                    (value - reference) / reference.abs(),
                    max_relative = 1e-9,
                    epsilon = 1e-15
                );
            }
            if &r[1] == "dt=5e-6" {
                assert_eq!(rel, 0.0, "the reference against itself: {r:?}");
            }
        }
        assert!(dir.path().join("convergence.png").exists());
    }
}

/// `bench soak` runs a scene file: its two-sprocket drive has two segments,
/// and the report has one row per window and the verdict line.
#[cfg(feature = "cli")]
#[test]
fn soak_runs_a_scene_file() {
    let scene = format!(
        "{}/tests/data/flat_30_30_real.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let out = crate::common::chaindrive_stdout(&[
        "bench",
        "soak",
        &scene,
        "--duration",
        "0.4",
        "--window",
        "0.1",
    ]);
    assert!(out.contains("seg2_mean_n"), "{out}");
    assert!(!out.contains("seg3_mean_n"), "{out}");
    let rows = out.lines().filter(|l| l.contains('–')).count();
    assert_eq!(rows, 4, "{out}");
    assert!(
        out.contains("steady from") || out.contains("not steady"),
        "{out}"
    );
}
