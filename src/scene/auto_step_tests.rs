//! `solver.dt_s = "auto"` and `--dt auto`: the step chosen from the scene's
//! own stiffnesses, masses and damping (docs/model.md, "Time scales and
//! stability"), reported by `check`, `run` and the summary.

use crate::scene::{AUTO_GRID_S, AUTO_SAFETY, Overrides, Scene};

const FLAT: &str = include_str!("../../tests/data/flat_20_40_1000rpm.toml");

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

/// The motorcycle drive without its explicit step: stability alone gives
/// ½ · 2 m_r / c with c = χ F / δ̇⁻_min, F = T₀ + M / R₄₅ = 1000 + 220 /
/// 0.113789 = 2933.4 N (the wheel's load on R₄₅ = P / (2 sin(π/45))):
/// ½ · 2 · 0.02 / (0.5625 · 2933.4 / 0.5) = 6.06 µs, below the links'
/// ½ √(m_r/K) = ½ · 25.8 µs and below the impact's cap. Impact
/// (Hertz, n = 3/2): v = 6000 rpm · R₁₅ with R₁₅ = P / (2 sin(π/15)) =
/// 0.038177 m: v = 23.99 m/s; v_i = v sin(24°) = 9.757 m/s; δ_max =
/// (5 m_r v_i² / (4 K_g))^(2/5) = 0.355 mm; t_c = 2.9432 δ_max / v_i =
/// 107 µs, t_c / 16 = 6.70 µs (1 ms / 150, the step before the load was
/// counted). The step: 6.06 µs rounded down to 1 ms / 166.
#[test]
fn the_load_and_the_impact_bound_the_auto_step_of_a_fast_small_sprocket() {
    let text = include_str!("../../tests/data/motorcycle_520.toml").replace("dt_s = 4e-6", "");
    let scene = Scene::from_toml(&text).expect("valid");
    let r15 = 0.015875 / (2.0 * (std::f64::consts::PI / 15.0).sin());
    let v = 6000.0 * std::f64::consts::TAU / 60.0 * r15;
    let v_i = v * (std::f64::consts::TAU / 15.0).sin();
    let depth = (5.0 * 0.02 * v_i * v_i / (4.0 * 1e9)).powf(0.4);
    let t_c = 2.9432 * depth / v_i;
    approx::assert_relative_eq!(t_c, 1.071e-4, max_relative = 2e-3);
    let impact = crate::scene::impact_duration_s(scene.chain(), scene.contact(), scene.sprockets());
    approx::assert_relative_eq!(impact, t_c, max_relative = 1e-4);
    assert_eq!(crate::scene::AUTO_STEPS_PER_IMPACT, 16.0);
    assert!(scene.solver().dt_auto);
    let r45 = 0.015875 / (2.0 * (std::f64::consts::PI / 45.0).sin());
    let damping = 0.5 * 2.0 * 0.02 / (0.5625 * (1000.0 + 220.0 / r45) / 0.5);
    approx::assert_relative_eq!(damping, 6.0605e-6, max_relative = 1e-4);
    assert!(damping < t_c / 16.0);
    approx::assert_relative_eq!(scene.solver().dt_s, 1e-3 / 166.0, max_relative = 1e-12);
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
        let sampling = crate::sim::SampleRate::new(rate_hz, dt)
            .unwrap_or_else(|e| panic!("{rate_hz} Hz: {e}"));
        approx::assert_relative_eq!(sampling.rate_hz, rate_hz, max_relative = 1e-9);
    }
}
