//! Statistics that say how sure they are: the summary's standard errors,
//! RMS and stationarity on runs and synthetic signals, `run --window`, and
//! `bench convergence` end to end.

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
