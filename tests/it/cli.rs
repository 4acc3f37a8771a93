//! The real `chaindrive` binary, driven end to end.

use std::path::Path;

use crate::common::{chaindrive, command, read_json, stderr};

/// Every `required` field of the schema (recursively through `items` and
/// `properties`) is present in `value`, with a finite number where a number is due.
fn check_contract(schema: &serde_json::Value, value: &serde_json::Value, path: &str) {
    if let Some(required) = schema.get("required").and_then(|r| r.as_array()) {
        for field in required {
            let name = field.as_str().expect("field name");
            let v = value
                .get(name)
                .unwrap_or_else(|| panic!("{path}.{name} missing"));
            let sub = &schema["properties"][name];
            match sub.get("type").and_then(|t| t.as_str()) {
                Some("number") => assert!(
                    v.as_f64().is_some_and(f64::is_finite),
                    "{path}.{name} = {v}"
                ),
                Some("integer") => assert!(v.as_u64().is_some(), "{path}.{name} = {v}"),
                Some("string") => assert!(v.is_string(), "{path}.{name} = {v}"),
                Some("boolean") => assert!(v.is_boolean(), "{path}.{name} = {v}"),
                Some("array") => {
                    let items = v
                        .as_array()
                        .unwrap_or_else(|| panic!("{path}.{name} not an array"));
                    for (i, item) in items.iter().enumerate() {
                        check_contract(&sub["items"], item, &format!("{path}.{name}[{i}]"));
                        if sub["items"].get("type").and_then(|t| t.as_str()) == Some("number") {
                            assert!(
                                item.as_f64().is_some_and(f64::is_finite),
                                "{path}.{name}[{i}]"
                            );
                        }
                    }
                }
                _ => {}
            }
        }
    }
}

#[test]
fn run_writes_summary_and_series_matching_the_contract() {
    let dir = tempfile::tempdir().expect("tmp");
    let summary = dir.path().join("summary.json");
    let series = dir.path().join("series.csv");
    let out = chaindrive(&[
        "run",
        "--duration",
        "1.2",
        "--rate",
        "500",
        "--summary",
        summary.to_str().expect("utf8"),
        "--series",
        series.to_str().expect("utf8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let value = read_json(&summary);
    let schema: serde_json::Value =
        serde_json::from_str(include_str!("../data/run-summary.schema.json")).expect("schema");
    check_contract(&schema, &value, "summary");
    assert_eq!(
        value["scene"],
        "MAN B&W L60MC camshaft chain (Pedersen 2005)"
    );
    assert_eq!(value["profile"], "circular");
    assert_eq!(value["strands"].as_array().map(Vec::len), Some(4));
    assert_eq!(value["interrupted"], false);
    let csv = std::fs::read_to_string(&series).expect("series");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(header[0], "t_s");
    for name in [
        "omega_1_rad_s",
        "omega_4_rad_s",
        "seg1_link_force_n",
        "seg4_transverse_m",
    ] {
        assert!(header.contains(&name), "{name} in {header:?}");
    }
    // t = 0 plus one row per 1/500 s.
    let rows = lines.count();
    assert!((rows as i64 - 601).abs() <= 1, "{rows} rows");
}

#[test]
fn a_rate_the_step_does_not_divide_is_refused() {
    // 1/(3000 Hz · 1e-5 s) = 33.3 steps: no whole number of steps samples at
    // 3 kHz, and a run at another rate would not be the one asked for.
    let dir = tempfile::tempdir().expect("tmp");
    let summary = dir.path().join("s.json");
    let out = chaindrive(&[
        "run",
        "--rate",
        "3000",
        "--dt",
        "1e-5",
        "--duration",
        "0.01",
        "--quiet",
        "--summary",
        summary.to_str().expect("utf8"),
    ]);
    assert!(
        !out.status.success(),
        "accepted; the summary says sample_rate_hz = {}",
        read_json(&summary)["sample_rate_hz"]
    );
    let err = stderr(&out);
    assert!(err.contains("--rate") && err.contains("3000"), "{err}");
    assert!(err.contains("1e-5"), "the step is named: {err}");
    assert!(!summary.exists(), "nothing simulated");
}

#[test]
fn bad_scene_names_file_field_and_reason() {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = dir.path().join("bad.toml");
    let text = chaindrive::scene::L60MC_TOML
        .replace("roller_mass_kg = 3.01", "roller_mass_kg = -3.01")
        .replace("restitution = 0.0 ", "restitution = 1.5 ")
        .replace("teeth = 28", "teeth = 0");
    std::fs::write(&scene, text).expect("write");
    let summary = dir.path().join("s.json");
    let out = chaindrive(&[
        "run",
        scene.to_str().expect("utf8"),
        "--summary",
        summary.to_str().expect("utf8"),
    ]);
    assert!(!out.status.success());
    let err = stderr(&out);
    for needle in [
        "bad.toml",
        "chain.roller_mass_kg",
        "contact.restitution",
        "sprockets[2].teeth",
    ] {
        assert!(err.contains(needle), "{needle} in:\n{err}");
    }
    // One line per error.
    assert!(err.lines().count() >= 3, "{err}");
    assert!(!summary.exists(), "no summary for a rejected scene");
}

#[test]
fn unknown_field_and_syntax_errors_are_reported() {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = dir.path().join("typo.toml");
    std::fs::write(
        &scene,
        chaindrive::scene::L60MC_TOML.replace("mass_kg = 850.0", "mas_kg = 850.0"),
    )
    .expect("write");
    let out = chaindrive(&["check", scene.to_str().expect("utf8")]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(err.contains("typo.toml") && err.contains("mas_kg"), "{err}");
}

#[test]
fn unwritable_output_fails_before_simulating() {
    let out = chaindrive(&["run", "--summary", "/nonexistent-dir/x/summary.json"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("summary") && err.contains("/nonexistent-dir/x/summary.json"),
        "{err}"
    );
    assert!(out.stdout.is_empty(), "nothing simulated");
}

#[test]
fn blow_up_is_an_error_naming_time_body_and_detector() {
    // 0.2 ms is beyond every explicit stability limit of the links (60 µs;
    // docs/model.md, “Time scales and stability”).
    let dir = tempfile::tempdir().expect("tmp");
    let summary = dir.path().join("s.json");
    let out = chaindrive(&[
        "run",
        "--dt",
        "2e-4",
        "--duration",
        "1",
        "--summary",
        summary.to_str().expect("utf8"),
    ]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(err.contains("blew up") || err.contains("blow-up"), "{err}");
    assert!(!err.contains("NaN"), "{err}");
    assert!(
        !Path::new(&summary).exists(),
        "no summary presented for a failed run"
    );
}

#[test]
fn check_prints_the_layout() {
    let out = chaindrive(&["check"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("1.8797") && text.contains("2.2312"), "{text}");
}

#[test]
fn a_write_failure_during_the_run_is_an_error() {
    // /dev/full accepts the open and fails every write: a disk that fills up mid-run.
    if !Path::new("/dev/full").exists() {
        return;
    }
    let out = chaindrive(&["run", "--duration", "0.3", "--series", "/dev/full"]);
    assert!(
        !out.status.success(),
        "a failed write must not look like success"
    );
    let err = stderr(&out);
    assert!(err.contains("series"), "{err}");
}

#[test]
fn sigint_and_sigterm_end_the_run_with_a_summary_marked_interrupted() {
    for signal in ["-INT", "-TERM"] {
        let dir = tempfile::tempdir().expect("tmp");
        let summary = dir.path().join("s.json");
        let series = dir.path().join("s.csv");
        let mut child = command()
            .args(["run", "--duration", "60", "--quiet"])
            .args(["--summary", summary.to_str().expect("utf8")])
            .args(["--series", series.to_str().expect("utf8")])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("spawn");
        // Wait until the run has written samples, then signal it.
        let started = std::time::Instant::now();
        while std::fs::metadata(&series).map_or(0, |m| m.len()) < 20_000 {
            assert!(started.elapsed().as_secs() < 60, "no samples written");
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        let kill = std::process::Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .expect("kill");
        assert!(kill.success());
        let status = child.wait().expect("wait");
        assert_eq!(status.code(), Some(130), "{signal}");
        let value = read_json(&summary);
        assert_eq!(value["interrupted"], true, "{signal}");
        let t = value["duration_s"].as_f64().expect("duration");
        assert!(t > 0.0 && t < 60.0, "{signal}: {t}");
        // The series holds every sample up to the interruption.
        let rows = std::fs::read_to_string(&series)
            .expect("series")
            .lines()
            .count()
            - 1;
        assert!(
            (rows as f64 - (t * 1000.0 + 1.0)).abs() <= 1.0,
            "{rows} rows for {t} s"
        );
    }
}

#[test]
fn a_bad_override_names_its_option() {
    let out = chaindrive(&["run", "--dt=0", "--duration", "0.1"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("--dt (solver.dt_s): must be > 0, got 0"),
        "{err}"
    );
    assert!(out.stdout.is_empty(), "nothing simulated");
}
