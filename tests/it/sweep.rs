//! The speed sweep (`studies::sweep`, `chaindrive sweep`): bad settings are
//! clear errors, a swept span's transverse response peaks where the
//! meshing order crosses its first transverse frequency (closed form), and
//! the speeds whose runs warned are flagged in every table and the report.

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
