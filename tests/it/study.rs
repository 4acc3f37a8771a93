//! Design studies (`chaindrive study`): a plan's cases run in parallel,
//! resume, a failed case kept and retried only when asked, bad plans refused
//! before anything runs, and the collected table read back from Parquet.

use std::path::{Path, PathBuf};

use chaindrive::scene::L60MC_TOML;
use chaindrive::studies::study::{CaseOutcome, ColumnData, Study, StudyDir, Table};
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;

use crate::common::{chaindrive, command, read_json, stderr};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Reads a Parquet file back as (column names, rows of fields).
fn read_parquet(path: &Path) -> (Vec<String>, Vec<Vec<Field>>) {
    let file = std::fs::File::open(path).expect("results.parquet");
    let reader = SerializedFileReader::new(file).expect("a Parquet file");
    let names = reader
        .metadata()
        .file_metadata()
        .schema_descr()
        .columns()
        .iter()
        .map(|c| c.name().to_owned())
        .collect();
    let rows = reader
        .get_row_iter(None)
        .expect("rows")
        .map(|r| {
            r.expect("row")
                .get_column_iter()
                .map(|(_, f)| f.clone())
                .collect()
        })
        .collect();
    (names, rows)
}

#[test]
fn a_study_runs_resumes_and_collects() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("s");
    let plan = data("study_small.toml");
    let (plan, out_s) = (plan.to_str().expect("utf-8"), out.to_str().expect("utf-8"));

    let first = chaindrive(&["study", plan, "--out", out_s, "--jobs", "2", "--quiet"]);
    assert!(first.status.success(), "{}", stderr(&first));
    assert!(
        stderr(&first).contains("ran 4 cases now (0 failed), 4 finished, 0 left"),
        "{}",
        stderr(&first)
    );
    // Resume: a finished case is not run again; a missing one is.
    std::fs::remove_dir_all(out.join("cases/2")).expect("remove case 2");
    let again = chaindrive(&["study", plan, "--out", out_s, "--jobs", "2", "--quiet"]);
    let text = stderr(&again);
    assert!(again.status.success(), "{text}");
    assert!(
        text.contains("3 finished before (0 failed), 1 to run"),
        "{text}"
    );
    assert!(text.contains("ran 1 cases now"), "{text}");

    let collect = chaindrive(&["study", "collect", out_s]);
    assert!(collect.status.success(), "{}", stderr(&collect));
    let (names, rows) = read_parquet(&out.join("results.parquet"));
    assert_eq!(
        names,
        [
            "case",
            // As the plan wrote them.
            "chain.pretension_n",
            "sprockets.0.speed_rpm",
            "static_tension_n",
            "max_penetration_m",
            "segments.0.mean_link_force_n",
            "dt_auto",
            "segments.0.stationary",
            "segments.1.stationary",
            "segments.2.stationary",
            "segments.3.stationary",
            "warning_count",
            "warnings",
            "status",
            "case_wall_s",
            "error"
        ]
    );
    assert_eq!(rows.len(), 4);
    // Full factorial, last factor fastest: (15000, 60), (15000, 120), (21000, 60), (21000, 120).
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[0], Field::Long(k as i64));
        let pretension = [15000.0, 15000.0, 21000.0, 21000.0][k];
        assert_eq!(row[1], Field::Double(pretension));
        assert_eq!(row[2], Field::Double([60.0, 120.0][k % 2]));
        // The scene file's contract: chain.pretension_n is the free strands'
        // mean link force at static equilibrium, reached within
        // equilibrium.tension_tolerance = 1e-3 (relative); 2e-3 allowed.
        let Field::Double(tension) = row[3] else {
            panic!("static_tension_n: {:?}", row[3])
        };
        assert!(
            (tension / pretension - 1.0).abs() < 2e-3,
            "case {k}: {tension} N vs {pretension} N"
        );
        assert_flags_match_summary(&out.join(format!("cases/{k}/summary.json")), &names, row);
        assert_eq!(row[15], Field::Null);
    }
    // The CSV holds the same columns and rows.
    let csv = std::fs::read_to_string(out.join("results.csv")).expect("results.csv");
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().map(|h| h.split(',').count()),
        Some(names.len())
    );
    assert_eq!(lines.count(), 4);
    for name in ["static_tension_n", "max_penetration_m"] {
        assert!(
            out.join("main_effects")
                .join(format!("{name}.png"))
                .exists(),
            "{name}"
        );
    }
}

/// The row's flags are the case's summary.json's: `dt_auto`, each
/// segment's `stationary`, the warnings (count and text), and `status`
/// `warned` exactly when a warning or a segment that is not stationary
/// makes its numbers doubtful, else `ok`.
fn assert_flags_match_summary(summary: &Path, names: &[String], row: &[Field]) {
    let summary = read_json(summary);
    let col = |name: &str| {
        let i = names.iter().position(|n| n == name);
        row[i.unwrap_or_else(|| panic!("no column {name}"))].clone()
    };
    assert_eq!(col("dt_auto"), Field::Bool(summary["dt_auto"] == true));
    let segments = summary["segments"].as_array().expect("segments");
    let mut drifting = false;
    for (k, s) in segments.iter().enumerate() {
        let stationary = s["stationary"].as_bool().expect("stationary");
        drifting |= !stationary;
        assert_eq!(
            col(&format!("segments.{k}.stationary")),
            Field::Bool(stationary)
        );
    }
    let warnings: Vec<&str> = summary["warnings"]
        .as_array()
        .expect("warnings")
        .iter()
        .map(|w| w.as_str().expect("text"))
        .collect();
    assert_eq!(col("warning_count"), Field::Long(warnings.len() as i64));
    let text = if warnings.is_empty() {
        Field::Null
    } else {
        Field::Str(warnings.join(" | "))
    };
    assert_eq!(col("warnings"), text);
    let status = if warnings.is_empty() && !drifting {
        "ok"
    } else {
        "warned"
    };
    assert_eq!(col("status"), Field::Str(status.to_owned()));
}

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

#[test]
fn bad_plans_are_refused_before_anything_runs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let good = std::fs::read_to_string(data("study_small.toml")).expect("plan");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/l60mc.toml");
    let good = good.replace(
        "\"../../assets/l60mc.toml\"",
        &format!("{:?}", scene.to_str().expect("utf-8")),
    );
    for (name, plan, expected) in [
        (
            "unknown_path",
            good.replace(
                "path = \"chain.pretension_n\"",
                "path = \"chain.tension_n\"",
            ),
            "factors[0].levels[0]: chain.tension_n: no such field",
        ),
        (
            "wrong_type",
            good.replace("levels = [60, 120]", "levels = [60, \"fast\"]"),
            "factors[1].levels[1]: sprockets[0].speed_rpm: a string does not fit this field",
        ),
        (
            "bad_checkpoint_period",
            good.replace("set = {", "checkpoint_every_s = -1\nset = {"),
            "checkpoint_every_s: -1: allowed: a number of simulated seconds > 0",
        ),
        (
            "negative_window",
            good.replace("set = {", "window_s = -1\nset = {"),
            "window_s: -1: allowed: a statistics window of simulated seconds > 0",
        ),
        (
            "nan_window",
            good.replace("set = {", "window_s = nan\nset = {"),
            "window_s: nan: allowed: a statistics window of simulated seconds > 0",
        ),
        (
            "text_window",
            good.replace("set = {", "window_s = \"last\"\nset = {"),
            "window_s: \"last\": allowed: a statistics window of simulated seconds > 0",
        ),
        (
            "window_longer_than_the_run",
            good.replace("set = {", "window_s = 0.5\nset = {"),
            "case 0 (chain.pretension_n = 15000, sprockets.0.speed_rpm = 60): window_s = 0.5 s is longer than the run (solver.duration_s = 0.2 s)",
        ),
        (
            "empty_design",
            good.replace("levels = [60, 120]", "levels = []"),
            "factors[1].levels: is empty",
        ),
    ] {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, plan).expect("write plan");
        let out = dir.path().join(name);
        let o = chaindrive(&[
            "study",
            path.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        assert!(!o.status.success(), "{name}");
        assert!(stderr(&o).contains(expected), "{name}: {}", stderr(&o));
        assert!(!out.exists(), "{name}: the study's directory was created");
    }
}

/// The summary without its wall times (they differ from run to run).
fn without_wall_times(mut v: serde_json::Value) -> serde_json::Value {
    fn strip(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(m) => {
                for key in ["wall_s", "setup_wall_s", "ns_per_step"] {
                    m.remove(key);
                }
                m.values_mut().for_each(strip);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    strip(&mut v);
    v
}

#[test]
fn a_killed_case_resumes_from_its_checkpoint_bit_for_bit() {
    // One case of the paper's drive, 0.3 s, checkpointed every 0.05 s.
    let plan = |every: &str| {
        format!(
            r#"
scene = "x"
set = {{ "solver.duration_s" = 0.3 }}
{every}
[[factors]]
path = "chain.pretension_n"
[design]
kind = "explicit"
cases = [[21000]]
"#
        )
    };
    let dir = tempfile::tempdir().expect("temp dir");
    // The reference: the same case run at once, without checkpoints.
    let whole = Study::from_texts(&plan(""), L60MC_TOML).expect("valid plan");
    let whole = StudyDir::prepare(&dir.path().join("whole"), whole).expect("prepared");
    assert!(matches!(
        whole.run_case(0, false, None).expect("run"),
        CaseOutcome::Ran(ref s) if s.ok
    ));

    let every_s = 0.05;
    let study = Study::from_texts(&plan("checkpoint_every_s = 0.05"), L60MC_TOML).expect("plan");
    assert_eq!(study.checkpoint_every_s, Some(every_s));
    let out = dir.path().join("killed");
    let sd = StudyDir::prepare(&out, study).expect("prepared");
    let out_s = out.to_str().expect("utf-8");
    // An array task killed outright (SIGKILL: no handler runs) after its
    // first checkpoint.
    let ckpt = sd.case_dir(0).join("checkpoint.ckpt");
    let mut task = command()
        .args(["study", "run-case", out_s, "0"])
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("run-case starts");
    let started = std::time::Instant::now();
    while !ckpt.exists() {
        assert!(
            task.try_wait().expect("wait").is_none(),
            "the task ended before its first checkpoint"
        );
        assert!(started.elapsed().as_secs() < 300, "no checkpoint written");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    task.kill().expect("SIGKILL");
    task.wait().expect("reaped");
    assert_eq!(
        sd.status(0).expect("read"),
        None,
        "the case is not finished"
    );

    // The task run again (a requeued array task) resumes.
    let again = chaindrive(&["study", "run-case", out_s, "0"]);
    let text = stderr(&again);
    assert!(again.status.success(), "{text}");
    assert!(text.contains("case 0: resuming from"), "{text}");
    let status = sd.status(0).expect("read").expect("finished");
    let t = status.resumed_from_s.expect("resumed");
    // At a checkpoint: t = k·S with 0 < k < 6 (dt = 1e-5 s divides S).
    let k = (t / every_s).round();
    assert!(
        (1.0..6.0).contains(&k) && (t - k * every_s).abs() < 1e-9,
        "resumed at t = {t} s"
    );
    assert!(text.contains(&format!("resumed at t = {t} s")), "{text}");
    assert!(!ckpt.exists(), "the finished case keeps no checkpoint");
    let summary = |d: &StudyDir| without_wall_times(read_json(&d.case_dir(0).join("summary.json")));
    assert_eq!(summary(&sd), summary(&whole));
}
