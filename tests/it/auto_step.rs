//! `solver.dt_s = "auto"` and `--dt auto`: the step chosen from the scene's
//! own stiffnesses, masses and damping (docs/model.md, "Time scales and
//! stability"), reported by `check`, `run` and the summary.

use crate::common::{chaindrive, read_json, stderr};

const FLAT: &str = include_str!("../data/flat_20_40_1000rpm.toml");

/// `--dt auto` on the command line: `check` prints the step, `run` prints
/// it and records `dt_auto` in the summary; an explicit `--dt` is not auto;
/// a word other than `auto` is refused, naming the option.
#[test]
fn dt_auto_on_the_command_line() {
    let dir = tempfile::tempdir().expect("tmp");
    let summary = dir.path().join("s.json");
    let s = summary.to_str().expect("utf8");
    let out = chaindrive(&[
        "run",
        "--quiet",
        "--duration",
        "0.01",
        "--dt",
        "auto",
        "--summary",
        s,
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json = read_json(&summary);
    assert_eq!(json["dt_auto"], true);
    let dt = json["dt_s"].as_f64().expect("dt_s");
    assert!(dt > 0.0 && dt < 1e-5, "{dt}");
    // A whole number of steps per millisecond.
    approx::assert_relative_eq!((1e-3 / dt).round() * dt, 1e-3, max_relative = 1e-9);

    let out = chaindrive(&["run", "--duration", "0.01", "--dt", "auto", "--summary", s]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).contains("(auto:"), "{}", stderr(&out));

    let out = chaindrive(&[
        "run",
        "--quiet",
        "--duration",
        "0.01",
        "--dt",
        "5e-6",
        "--summary",
        s,
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(read_json(&summary)["dt_auto"], false);
    assert_eq!(read_json(&summary)["dt_s"], 5e-6);

    let out = chaindrive(&["check", "--dt", "auto"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("(auto:"));

    let out = chaindrive(&["run", "--dt", "fast"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--dt"), "{}", stderr(&out));
    assert!(stderr(&out).contains("\"auto\""), "{}", stderr(&out));
}

/// `run --rate 5000` on a scene with the automatic step samples on whole
/// steps instead of refusing the rate.
#[test]
fn run_with_an_auto_step_takes_any_rate() {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = dir.path().join("flat.toml");
    std::fs::write(&scene, FLAT).expect("write");
    let summary = dir.path().join("s.json");
    let out = chaindrive(&[
        "run",
        scene.to_str().expect("utf8"),
        "--quiet",
        "--duration",
        "0.004",
        "--rate",
        "5000",
        "--summary",
        summary.to_str().expect("utf8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let json = read_json(&summary);
    approx::assert_relative_eq!(
        json["dt_s"].as_f64().expect("dt_s"),
        0.2e-3 / 44.0,
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(
        json["sample_rate_hz"].as_f64().expect("rate"),
        5000.0,
        max_relative = 1e-9
    );
}

/// `check` and `run` print the same step and the same stability warnings,
/// from the integrator's own estimate, for every integrator: automatic
/// steps, for accuracy and for speed (never above their own limit), and an
/// explicit 4 µs. The flat drive
/// with a 0.02 m/s approach-speed floor: contact damping 2 m_r / c with
/// c = 0.5625 · 300 / 0.02 = 8437.5 N·s/m, 1.837 µs; links 12.45 µs. 4 µs
/// exceeds the explicit schemes' limits (RK4's 1.3925 · 1.837 = 2.56 µs),
/// not the implicit schemes' (the links') nor the adaptive one's (none).
#[test]
fn check_and_run_agree_on_the_step_for_every_integrator() {
    let dir = tempfile::tempdir().expect("tmp");
    for integrator in [
        "symplectic_euler",
        "velocity_verlet",
        "rk4",
        "dormand_prince45",
        "implicit_damping",
        "verlet_implicit_damping",
    ] {
        for dt in ["\"auto\"", "\"speed\"", "4e-6"] {
            let text = FLAT
                .replace(
                    "min_approach_speed_m_s = 0.1",
                    "min_approach_speed_m_s = 0.02",
                )
                .replace(
                    "duration_s = 0.6",
                    &format!("duration_s = 0.0005\nintegrator = \"{integrator}\"\ndt_s = {dt}"),
                );
            let path = dir.path().join(format!("{integrator}.toml"));
            std::fs::write(&path, text).expect("write");
            let p = path.to_str().expect("utf8");
            let check = chaindrive(&["check", p]);
            let run = chaindrive(&["run", p]);
            let check_out = String::from_utf8_lossy(&check.stdout).into_owned();
            let (check_err, run_err) = (stderr(&check), stderr(&run));
            let note = |text: &str| {
                text.lines()
                    .find(|l| l.starts_with("dt = "))
                    .map(str::to_owned)
                    .unwrap_or_else(|| panic!("{integrator}, {dt}: no step in {text}"))
            };
            assert_eq!(note(&check_out), note(&run_err), "{integrator}, {dt}");
            let exceeds = |text: &str| -> Vec<String> {
                text.lines()
                    .filter_map(|l| l.split_once("warning: solver.dt_s"))
                    .map(|(_, w)| w.to_owned())
                    .collect()
            };
            assert_eq!(exceeds(&check_err), exceeds(&run_err), "{integrator}, {dt}");
            let expected = dt == "4e-6"
                && !matches!(
                    integrator,
                    "implicit_damping" | "verlet_implicit_damping" | "dormand_prince45"
                );
            assert_eq!(
                exceeds(&check_err).len(),
                usize::from(expected),
                "{integrator}, {dt}: {check_err}"
            );
        }
    }
}
