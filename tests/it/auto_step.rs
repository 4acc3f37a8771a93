//! `solver.dt_s = "auto"` and `--dt auto`: the step chosen from the scene's
//! own stiffnesses, masses and damping (docs/model.md, "Time scales and
//! stability"), reported by `check`, `run` and the summary.

use chaindrive::scene::{AUTO_GRID_S, AUTO_SAFETY, Overrides, Scene};

use crate::common::{chaindrive, read_json, stderr};

const FLAT: &str = include_str!("../data/flat_20_40_1000rpm.toml");

/// The flat 20T/40T drive sets no step. Its estimates: links √(m_r/K) =
/// √(0.00775 / 5e7) = 12.45 µs; contact damping 2 m_r / c with c = χ T₀ /
/// δ̇⁻_min, χ = ¾(1 − e²) = 0.5625 (e = 0.5), T₀ = 300 N, δ̇⁻_min = 0.1 m/s:
/// c = 1687.5 N·s/m, 2 m_r / c = 9.185 µs. Half of it, 4.593 µs, rounded
/// down to a whole fraction of 1 ms: 1 ms / 218 = 4.587 µs.
#[test]
fn a_scene_without_dt_gets_the_auto_step() {
    let scene = Scene::from_toml(FLAT).expect("valid");
    let links: f64 = (0.00775f64 / 5e7).sqrt();
    let damping = 2.0 * 0.00775 / (0.5625 * 300.0 / 0.1);
    assert!(damping < links);
    let raw = AUTO_SAFETY * damping;
    approx::assert_relative_eq!(raw, 4.5926e-6, max_relative = 1e-4);
    assert!(scene.solver().dt_auto);
    approx::assert_relative_eq!(scene.solver().dt_s, 1e-3 / 218.0, max_relative = 1e-12);
    assert!(scene.solver().dt_s <= raw);
    assert_eq!(AUTO_GRID_S, 1e-3);
    // The paper's drive keeps its explicit 10 µs …
    assert!(!Scene::l60mc().solver().dt_auto);
    assert_eq!(Scene::l60mc().solver().dt_s, 1e-5);
    // … unless asked for the automatic step.
    let auto = Scene::l60mc()
        .with(&Overrides {
            dt_auto: true,
            ..Overrides::default()
        })
        .expect("valid");
    assert!(auto.solver().dt_auto);
    assert!(auto.solver().dt_s < 1e-5);
}

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

/// The motorcycle drive without its explicit step: stability alone gives
/// ½ · 2 m_r / c = ½ · 2 · 0.02 / (0.5625 · 1000 / 0.5) = 17.8 µs against the
/// links' ½ √(m_r/K) = ½ · 25.8 µs, i.e. 12.9 µs; the impact caps it. Impact
/// (Hertz, n = 3/2): v = 6000 rpm · R₁₅ with R₁₅ = P / (2 sin(π/15)) =
/// 0.038177 m: v = 23.99 m/s; v_i = v sin(24°) = 9.757 m/s; δ_max =
/// (5 m_r v_i² / (4 K_g))^(2/5) = 0.355 mm; t_c = 2.9432 δ_max / v_i =
/// 107 µs. The step: t_c / 16 = 6.70 µs, rounded down to 1 ms / 150.
#[test]
fn the_impact_caps_the_auto_step_of_a_fast_small_sprocket() {
    let text = include_str!("../data/motorcycle_520.toml").replace("dt_s = 4e-6", "");
    let scene = Scene::from_toml(&text).expect("valid");
    let r15 = 0.015875 / (2.0 * (std::f64::consts::PI / 15.0).sin());
    let v = 6000.0 * std::f64::consts::TAU / 60.0 * r15;
    let v_i = v * (std::f64::consts::TAU / 15.0).sin();
    let depth = (5.0 * 0.02 * v_i * v_i / (4.0 * 1e9)).powf(0.4);
    let t_c = 2.9432 * depth / v_i;
    approx::assert_relative_eq!(t_c, 1.071e-4, max_relative = 2e-3);
    let impact =
        chaindrive::scene::impact_duration_s(scene.chain(), scene.contact(), scene.sprockets());
    approx::assert_relative_eq!(impact, t_c, max_relative = 1e-4);
    assert_eq!(chaindrive::scene::AUTO_STEPS_PER_IMPACT, 16.0);
    assert!(scene.solver().dt_auto);
    approx::assert_relative_eq!(scene.solver().dt_s, 1e-3 / 150.0, max_relative = 1e-12);
    // Without the cap: half the links' estimate.
    let links = (0.02f64 / 3e7).sqrt();
    assert!(scene.solver().dt_s < 0.6 * AUTO_SAFETY * links);
}

/// The automatic step divides the sample period of any rate. The flat drive's
/// raw step, 4.5926 µs (above), is 43.55 steps in 0.2 ms: at 5 kHz it becomes
/// 0.2 ms / 44 = 4.545 µs (1 ms / 218 = 4.587 µs would leave 43.6 steps per
/// sample, which the sampler refuses).
#[test]
fn the_auto_step_divides_the_sample_period_of_any_rate() {
    let at = |rate_hz: f64| {
        Scene::from_toml_with(
            FLAT,
            &Overrides {
                sample_rate_hz: Some(rate_hz),
                ..Overrides::default()
            },
        )
        .expect("valid")
    };
    approx::assert_relative_eq!(
        at(5000.0).solver().dt_s,
        0.2e-3 / 44.0,
        max_relative = 1e-12
    );
    // A scene with its own step is the same scene at every rate.
    let paper_at_5k = Scene::l60mc().with(&Overrides {
        sample_rate_hz: Some(5000.0),
        ..Overrides::default()
    });
    assert_eq!(paper_at_5k.expect("valid"), Scene::l60mc());
    // The default rate keeps the step it always had.
    assert_eq!(
        at(1000.0).solver().dt_s,
        Scene::from_toml(FLAT).expect("valid").solver().dt_s
    );
    for rate_hz in [
        300.0, 1000.0, 3000.0, 4096.0, 5000.0, 7000.0, 44_100.0, 2e5, 1e6,
    ] {
        let dt = at(rate_hz).solver().dt_s;
        assert!(dt <= 4.5926e-6, "{rate_hz} Hz: {dt}");
        let sampling = chaindrive::sim::SampleRate::new(rate_hz, dt)
            .unwrap_or_else(|e| panic!("{rate_hz} Hz: {e}"));
        approx::assert_relative_eq!(sampling.rate_hz, rate_hz, max_relative = 1e-9);
    }
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
/// steps (never above their own limit) and an explicit 4 µs. The flat drive
/// with a 0.02 m/s approach-speed floor: contact damping 2 m_r / c with
/// c = 0.5625 · 300 / 0.02 = 8437.5 N·s/m, 1.837 µs; links 12.45 µs. 4 µs
/// exceeds the explicit schemes' limits (RK4's 1.3925 · 1.837 = 2.56 µs),
/// not the implicit scheme's (the links') nor the adaptive one's (none).
#[test]
fn check_and_run_agree_on_the_step_for_every_integrator() {
    let dir = tempfile::tempdir().expect("tmp");
    for integrator in [
        "symplectic_euler",
        "velocity_verlet",
        "rk4",
        "dormand_prince45",
        "implicit_damping",
    ] {
        for dt in ["\"auto\"", "4e-6"] {
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
            let expected =
                dt == "4e-6" && !matches!(integrator, "implicit_damping" | "dormand_prince45");
            assert_eq!(
                exceeds(&check_err).len(),
                usize::from(expected),
                "{integrator}, {dt}: {check_err}"
            );
        }
    }
}
