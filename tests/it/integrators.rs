//! The integrators: observed orders of convergence on a smooth run, the
//! adaptive scheme's tolerance, energy conservation of the symplectic
//! schemes, and the implicit scheme's stability where explicit ones fail.

#[cfg(feature = "cli")]
use crate::common::{chaindrive, command, stderr};

#[cfg(feature = "cli")]
#[test]
fn work_precision_bench_writes_its_contract() {
    let dir = tempfile::tempdir().expect("tmp");
    let out = command()
        .args([
            "bench",
            "work-precision",
            "--quick",
            "--warmup",
            "0.05",
            "--horizon",
            "0.002",
            "--profile",
            "real",
            "--out",
        ])
        .arg(dir.path())
        .output()
        .expect("binary runs");
    assert!(out.status.success(), "{}", stderr(&out));
    let csv = std::fs::read_to_string(dir.path().join("work_precision.csv")).expect("csv");
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("integrator,setting,dt_s,wall_s,horizon_s,error,order")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // Two settings of each of the six schemes.
    assert_eq!(rows.len(), 12, "{csv}");
    for name in [
        "symplectic_euler",
        "velocity_verlet",
        "rk4",
        "dormand_prince45",
        "implicit_damping",
        "verlet_implicit_damping",
    ] {
        assert_eq!(rows.iter().filter(|r| r[0] == name).count(), 2, "{name}");
    }
    for r in &rows {
        assert_eq!(r.len(), 7, "{r:?}");
        let error: f64 = r[5].parse().expect("error is a number");
        assert!(error.is_finite() && error >= 0.0, "{r:?}");
        assert_eq!(r[4].parse::<f64>().expect("horizon"), 0.002);
    }
    assert!(dir.path().join("work_precision.png").exists());
    assert!(dir.path().join("work_precision.md").exists());
}

#[cfg(feature = "cli")]
#[test]
fn run_timings_account_for_the_stepping_loop() {
    let out = chaindrive(&["run", "--duration", "0.05", "--quiet", "--timings"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let shares: Vec<f64> = [
        "links",
        "contacts",
        "integrator",
        "blow-up checks",
        "observers",
    ]
    .iter()
    .map(|stage| {
        let line = text
            .lines()
            .find(|l| l.starts_with(stage))
            .unwrap_or_else(|| panic!("no {stage} line in\n{text}"));
        let share = line.split_whitespace().rev().nth(1).expect("share");
        share.parse::<f64>().expect("a number")
    })
    .collect();
    // The five stages partition the loop: their shares sum to 100 % (rounding).
    // (Which stage is largest is a timing, measured by the benches, not here.)
    let sum: f64 = shares.iter().sum();
    assert!((sum - 100.0).abs() < 0.5, "{shares:?}");
    assert!(
        shares.iter().all(|s| (0.0..=100.0).contains(s)),
        "{shares:?}"
    );
}
