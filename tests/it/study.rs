//! Design studies (`chaindrive study`): a plan's cases run in parallel,
//! resume, a failed case kept and retried only when asked, bad plans refused
//! before anything runs, and the collected table read back from Parquet.

use crate::common::{chaindrive, command, read_json, stderr};
use chaindrive::scene::L60MC_TOML;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;
use std::path::{Path, PathBuf};

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
    std::fs::write(dir.path().join("l60mc.toml"), L60MC_TOML).expect("scene written");
    let write_plan = |name: &str, every: &str| {
        let path = dir.path().join(name);
        let text = plan(every).replace("scene = \"x\"", "scene = \"l60mc.toml\"");
        std::fs::write(&path, text).expect("plan written");
        path.to_str().expect("utf-8").to_owned()
    };
    // The reference: the same case run at once, without checkpoints.
    let whole = dir.path().join("whole");
    let whole_s = whole.to_str().expect("utf-8");
    let o = chaindrive(&[
        "study",
        &write_plan("whole.toml", ""),
        "--out",
        whole_s,
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));

    let every_s = 0.05;
    let out = dir.path().join("killed");
    let out_s = out.to_str().expect("utf-8");
    // Prepared as for a cluster (the job script is written, nothing runs).
    let killed_plan = write_plan("killed.toml", "checkpoint_every_s = 0.05");
    let o = chaindrive(&["study", "slurm", &killed_plan, "--out", out_s]);
    assert!(o.status.success(), "{}", stderr(&o));
    // An array task killed outright (SIGKILL: no handler runs) after its
    // first checkpoint.
    let case = out.join("cases").join("0");
    let ckpt = case.join("checkpoint.ckpt");
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
    assert!(
        !case.join("status.json").exists(),
        "the case is not finished"
    );

    // The task run again (a requeued array task) resumes.
    let again = chaindrive(&["study", "run-case", out_s, "0"]);
    let text = stderr(&again);
    assert!(again.status.success(), "{text}");
    assert!(text.contains("case 0: resuming from"), "{text}");
    let status = read_json(&case.join("status.json"));
    let t = status["resumed_from_s"].as_f64().expect("resumed");
    // At a checkpoint: t = k·S with 0 < k < 6 (dt = 1e-5 s divides S).
    let k = (t / every_s).round();
    assert!(
        (1.0..6.0).contains(&k) && (t - k * every_s).abs() < 1e-9,
        "resumed at t = {t} s"
    );
    assert!(text.contains(&format!("resumed at t = {t} s")), "{text}");
    assert!(!ckpt.exists(), "the finished case keeps no checkpoint");
    let summary = |d: &Path| without_wall_times(read_json(&d.join("cases/0/summary.json")));
    assert_eq!(summary(&out), summary(&whole));
}
