//! Design studies (`chaindrive study`): a plan's cases run in parallel,
//! resume, a failed case kept and retried only when asked, bad plans refused
//! before anything runs, and the collected table read back from Parquet.

use crate::scene::L60MC_TOML;
use crate::studies::study::{CaseOutcome, ColumnData, Study, StudyDir, Table};
use crate::test_support::read_json;

/// A case whose rollers sink 36 % of their radius into the teeth (a soft
/// contact, K = 5e6 N/m^1.5; the summary warns above 10 %) is `warned`,
/// with its warning in the table; the stiff case beside it is whatever its
/// own summary says. Found as: every finished case was "ok", warnings or not.
#[test]
fn a_case_with_a_warning_is_warned_in_the_table() {
    let plan = r#"
scene = "x"
responses = ["max_penetration_m"]
set = { "solver.duration_s" = 0.1 }
[[factors]]
path = "contact.stiffness"
[design]
kind = "explicit"
cases = [[1e9], [5e6]]
"#;
    let study = Study::from_texts(plan, L60MC_TOML).expect("valid plan");
    let dir = tempfile::tempdir().expect("temp dir");
    let sd = StudyDir::prepare(dir.path(), study).expect("prepared");
    sd.run_all(2, false, None, &|_| {}).expect("run");
    let soft = sd.status(1).expect("read").expect("finished");
    assert!(soft.ok, "{soft:?}");
    assert!(
        soft.warnings.iter().any(|w| w.starts_with("penetration")),
        "status.json keeps the warnings: {soft:?}"
    );
    let table = Table::collect(&sd).expect("table");
    let column = |name: &str| {
        &table
            .columns
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("no column {name}"))
            .data
    };
    // The criterion, from the table's own response: deeper than 10 % of
    // the paper's roller radius, 27 mm.
    let ColumnData::Float(depth) = column("max_penetration_m") else {
        panic!("max_penetration_m")
    };
    let depth = depth[1].expect("finished");
    assert!(depth > 0.1 * 0.027, "{depth} m");
    let ColumnData::Text(status) = column("status") else {
        panic!("status")
    };
    assert_eq!(status[1].as_deref(), Some("warned"));
    let ColumnData::Text(warnings) = column("warnings") else {
        panic!("warnings")
    };
    assert!(
        warnings[1]
            .as_deref()
            .is_some_and(|w| w.contains("penetration: a roller sank")),
        "{warnings:?}"
    );
    let ColumnData::Count(count) = column("warning_count") else {
        panic!("warning_count")
    };
    assert_eq!(count[1], Some(soft.warnings.len() as i64));
    // The CSV says the same.
    let csv = table.to_csv().expect("CSV in memory");
    let row = csv.lines().nth(2).expect("case 1");
    assert!(row.contains(",warned,"), "{row}");
}

/// A plan's `window_s` is each case's statistics window: the last 0.05 s
/// of a 0.2 s run, as the summary and the table report it.
#[test]
fn a_plans_window_is_each_cases_statistics_window() {
    let plan = r#"
scene = "x"
window_s = 0.05
responses = ["window_s.0", "window_s.1"]
set = { "solver.duration_s" = 0.2 }
[[factors]]
path = "chain.pretension_n"
[design]
kind = "explicit"
cases = [[21000]]
"#;
    let study = Study::from_texts(plan, L60MC_TOML).expect("valid plan");
    assert_eq!(study.window_s, Some(0.05));
    let dir = tempfile::tempdir().expect("temp dir");
    let sd = StudyDir::prepare(dir.path(), study).expect("prepared");
    sd.run_all(1, false, None, &|_| {}).expect("run");
    let summary = read_json(&sd.case_dir(0).join("summary.json"));
    let window = [
        summary["window_s"][0].as_f64().expect("start"),
        summary["window_s"][1].as_f64().expect("end"),
    ];
    assert!((window[1] - 0.2).abs() < 1e-9, "{window:?}");
    assert!((window[1] - window[0] - 0.05).abs() < 1e-9, "{window:?}");
    let table = Table::collect(&sd).expect("table");
    let start = table
        .columns
        .iter()
        .find(|c| c.name == "window_s.0")
        .expect("window_s.0");
    assert_eq!(start.data, ColumnData::Float(vec![Some(window[0])]));
}

/// With `responses = "all"`, the summary's own `wall_s` (the stepping's)
/// and the case's wall time are two columns with two names. Found as:
/// both were `wall_s`, and pyarrow refused to read the file ("Multiple
/// matches for FieldRef.Name(wall_s)").
#[test]
fn every_column_has_its_own_name_with_all_responses() {
    let plan = r#"
scene = "x"
responses = "all"
set = { "solver.duration_s" = 0.05 }
[[factors]]
path = "sprockets.0.speed_rpm"
[design]
kind = "explicit"
cases = [[60]]
"#;
    let study = Study::from_texts(plan, L60MC_TOML).expect("valid plan");
    let dir = tempfile::tempdir().expect("temp dir");
    let sd = StudyDir::prepare(dir.path(), study).expect("prepared");
    sd.run_all(1, false, None, &|_| {}).expect("run");
    let table = Table::collect(&sd).expect("table");
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    let mut unique = names.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), names.len(), "{names:?}");
    for name in ["sprockets.0.speed_rpm", "wall_s", "case_wall_s", "status"] {
        assert!(names.contains(&name), "{name}: {names:?}");
    }
}

#[test]
fn a_failed_case_is_kept_and_run_again_only_when_asked() {
    // Case 1's step is 100 times the paper's: symplectic Euler on the
    // links' 815 MN/m springs with 3 kg rollers is unstable above
    // 2 √(m/K)/2 ≈ 6e-5 s, so the run blows up (or its layout fails).
    let plan = r#"
scene = "x"
set = { "solver.duration_s" = 0.05 }
[[factors]]
path = "solver.dt_s"
[design]
kind = "explicit"
cases = [[1e-5], [1e-3]]
"#;
    let study = Study::from_texts(plan, L60MC_TOML).expect("valid plan");
    let dir = tempfile::tempdir().expect("temp dir");
    let sd = StudyDir::prepare(dir.path(), study).expect("prepared");
    let ran = |retry: bool| {
        let outcomes = std::sync::Mutex::new(Vec::new());
        sd.run_all(2, retry, None, &|o: &CaseOutcome| {
            outcomes.lock().expect("lock").push(o.clone());
        })
        .expect("run");
        let mut v: Vec<(usize, bool)> = outcomes
            .into_inner()
            .expect("lock")
            .into_iter()
            .filter_map(|o| match o {
                CaseOutcome::Ran(s) => Some((s.case, s.ok)),
                _ => None,
            })
            .collect();
        v.sort_unstable();
        v
    };
    assert_eq!(ran(false), [(0, true), (1, false)]);
    let status = sd.status(1).expect("read").expect("finished");
    assert!(
        status.error.as_deref().is_some_and(|e| !e.is_empty()),
        "{status:?}"
    );
    assert_eq!(status.factors, "solver.dt_s = 0.001");
    assert_eq!(ran(false), []);
    assert_eq!(ran(true), [(1, false)]);
    let table = Table::collect(&sd).expect("table");
    let status_col = table
        .columns
        .iter()
        .find(|c| c.name == "status")
        .expect("status");
    // The case that ran ends inside the paper drive's ramp: it is warned
    // (ramp in window), not failed.
    assert_eq!(
        status_col.data,
        ColumnData::Text(vec![Some("warned".into()), Some("failed".into())])
    );
}

/// A duty point samples as a sweep does at its driver speed: the 15-tooth
/// engine sprocket at 4000 rpm passes teeth at 15 × 4000 / 60 = 1000 Hz,
/// exactly the 1 kHz every case used to sample at, so each of its sampled
/// statistics was aliased and the summary warned. The sweep's rule, at
/// least 16 samples per period of twice the largest tooth count (44):
/// 16 · 88 · 4000 / 60 = 93.9 kHz, the slowest whole number of 5 µs steps
/// above it 2 (100 kHz); at 2500 rpm 58.7 kHz, 3 steps (66.7 kHz). What is
/// counted every step — the means, the extremes, the fatigue count — is
/// the same to the bit; the warning is gone. Found as: `chaindrive life`
/// warned of aliasing at the motorcycle's full-throttle point.
#[test]
fn a_duty_point_samples_at_its_driver_speed_and_aliases_nothing() {
    use crate::studies::duty::{DutyCycle, LifeSettings};
    let scene = include_str!("../../tests/data/moto_10b_15_44_560nm.toml");
    let duty: crate::scene::DutyFile = toml::from_str(
        r#"
[[duty]]
name = "town"
hours = 1.0
set = { "sprockets.0.speed_rpm" = 2500.0, "sprockets.1.load_torque_n_m" = -60.0 }
[[duty]]
name = "full throttle"
hours = 1.0
set = { "sprockets.0.speed_rpm" = 4000.0, "sprockets.1.load_torque_n_m" = -560.0 }
"#,
    )
    .expect("points");
    let cycle = DutyCycle::new(&duty.duty, scene).expect("a cycle");
    let settings = LifeSettings {
        duration_s: Some(0.3),
        window_s: Some(0.1),
        checkpoint_every_s: None,
    };
    let plan = cycle.plan_toml(scene, settings).expect("a plan");
    assert!(plan.contains("sample_by_speed = true"), "{plan}");
    let summaries = |plan: &str| {
        let study = Study::from_texts(plan, scene).expect("valid plan");
        let dir = tempfile::tempdir().expect("temp dir");
        let sd = StudyDir::prepare(dir.path(), study).expect("prepared");
        sd.run_all(2, false, None, &|_| {}).expect("run");
        (0..2)
            .map(|k| read_json(&sd.case_dir(k).join("summary.json")))
            .collect::<Vec<_>>()
    };
    let by_speed = summaries(&plan);
    let fixed = summaries(&plan.replace("sample_by_speed = true", "sample_by_speed = false"));
    let rate = |s: &serde_json::Value| s["sample_rate_hz"].as_f64().expect("a rate");
    let aliased = |s: &serde_json::Value| {
        s["warnings"].as_array().is_some_and(|w| {
            w.iter()
                .any(|w| w.as_str().is_some_and(|w| w.starts_with("sample rate")))
        })
    };
    approx::assert_relative_eq!(rate(&by_speed[0]), 1.0 / 15e-6, max_relative = 1e-9);
    approx::assert_relative_eq!(rate(&by_speed[1]), 1.0 / 10e-6, max_relative = 1e-9);
    approx::assert_relative_eq!(rate(&fixed[1]), 1000.0, max_relative = 1e-9);
    assert!(aliased(&fixed[1]), "{}", fixed[1]["warnings"]);
    for (new, old) in by_speed.iter().zip(&fixed) {
        assert!(!aliased(new), "{}", new["warnings"]);
        // The chain's circuits in the window come from the sprockets' mean
        // speed, summed in another order: equal to rounding.
        let circuits = |s: &serde_json::Value| s["fatigue"]["chain_circuits"].as_f64();
        approx::assert_relative_eq!(
            circuits(new).expect("circuits"),
            circuits(old).expect("circuits"),
            max_relative = 1e-12
        );
        let (mut f_new, mut f_old) = (new["fatigue"].clone(), old["fatigue"].clone());
        for f in [&mut f_new, &mut f_old] {
            f.as_object_mut().expect("a block").remove("chain_circuits");
        }
        assert_eq!(f_new, f_old, "the fatigue count");
        for key in ["link_force_max_n", "link_force_min_n"] {
            assert_eq!(new[key], old[key], "{key}");
        }
        // The means are sums over every step, in chunks between samples:
        // equal to rounding.
        let close = |a: &serde_json::Value, b: &serde_json::Value| {
            let (a, b) = (a.as_f64().expect("a mean"), b.as_f64().expect("a mean"));
            assert!(
                (a - b).abs() <= 1e-12 * a.abs().max(b.abs()),
                "{a} against {b}"
            );
        };
        close(&new["driver_mean_power_w"], &old["driver_mean_power_w"]);
        let segments =
            |s: &serde_json::Value| s["segments"].as_array().cloned().unwrap_or_default();
        for (a, b) in segments(new).iter().zip(&segments(old)) {
            close(&a["mean_link_force_n"], &b["mean_link_force_n"]);
        }
        assert_eq!(
            new["rating"]["static_safety_factor"],
            old["rating"]["static_safety_factor"]
        );
    }
}
