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
