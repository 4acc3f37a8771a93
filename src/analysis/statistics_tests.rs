//! Statistics that say how sure they are: the summary's standard errors,
//! RMS and stationarity on runs and synthetic signals, `run --window`, and
//! `bench convergence` end to end.

use crate::analysis::{RunSummary, SampleRow, Signals, SummaryInputs};
use crate::model::DriveModel;
use crate::scene::Scene;

const MOTORCYCLE: &str = include_str!("../../tests/data/motorcycle_520.toml");

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
    let s = crate::test_support::run_summary(1.2, 1000.0);
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
