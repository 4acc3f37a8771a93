//! Tooth jumps (docs/model.md, "Tooth jump"): a worn chain on fixed centres
//! under a large load jumps teeth, the same drive with the chain new does
//! not, and `checks.tooth_jump = "stop"` ends the run at the first jump
//! with an error naming it.

use crate::analysis::{RunSummary, StatsWindow};
use crate::scene::Scene;
use crate::sim::{SampleRate, SimError, Simulation};

/// A 30T/30T ANSI 80 drive on fixed centres (the rest-length rule, 1 kN,
/// no gravity), the driver at 100 rpm, the driven sprocket pushed by a
/// load torque rising to 1500 N·m over a second (about 12 kN in the tight
/// strand), the chain `elongation_pct` worn: 2 % gives 56 mm of slack.
fn drive(elongation_pct: f64, action: &str) -> String {
    format!(
        r#"
name = "jumping 30/30 ANSI 80"
gravity_m_s2 = [0.0, 0.0]
profile = "real"

[chain]
designation = "ANSI 80"
rollers = 111
damping_n_s_m = 50.0
pretension_n = 1000.0
pretension_by = "rest_length"
joint_friction = 0.1
elongation_pct = {elongation_pct}

[contact]
stiffness = 1e9
restitution = 0.5
min_approach_speed_m_s = 0.1

[[sprockets]]
name = "driver"
center_m = [0.0, 0.0]
teeth = 30
mass_kg = 2.0
inertia_kg_m2 = 0.02
wrap = "ccw"
role = "driver"
speed_rpm = 100.0
ramp_s = 0.2

[[sprockets]]
name = "driven"
center_m = [1.0291, 0.0]
teeth = 30
mass_kg = 2.0
inertia_kg_m2 = 0.02
wrap = "ccw"
role = "free"
load_torque_n_m = 1500.0
load_ramp_s = 1.0

[solver]
duration_s = 0.4

[checks]
tooth_jump = "{action}"
"#
    )
}

/// Runs `text` to its end and summarises its last 0.2 s.
fn run(text: &str) -> Result<RunSummary, SimError> {
    let scene = Scene::from_toml(text).expect("valid scene");
    let window = StatsWindow::of(&scene, Some(0.2)).expect("window");
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("rate");
    let mut signals = window.observe(&mut sim, sampling.rate_hz);
    let out = sim.run(
        scene.solver().duration_s,
        sampling.every,
        &mut signals,
        None,
    )?;
    Ok(RunSummary::of_run_in(&sim, &out, &signals, 0.0, &window))
}

#[test]
fn a_worn_chain_on_fixed_centres_jumps_teeth_and_the_new_chain_does_not() {
    let new = run(&drive(0.0, "count")).expect("runs");
    assert!(new.tooth_jumps.is_empty(), "{:?}", new.tooth_jumps);
    assert!(!new.warnings.iter().any(|w| w.starts_with("tooth jump")));
    let worn = run(&drive(2.0, "count")).expect("runs");
    let first = worn.tooth_jumps.first().expect("a jump");
    assert!(first.sprocket == 1 || first.sprocket == 2);
    assert!(first.roller < 111);
    assert_eq!(first.gaps.abs(), 1, "{first:?}");
    assert!(first.t_s > 0.0 && first.t_s <= 0.4);
    let warning = worn
        .warnings
        .iter()
        .find(|w| w.starts_with("tooth jump"))
        .expect("the tooth-jump warning");
    assert!(
        warning.contains(&format!("roller {}", first.roller)),
        "{warning}"
    );
    let slack = worn.worn_chain.as_ref().and_then(|c| c.extra_slack_m);
    // N l₀ e: 111 links of (about) the pitch, 2 %: 56 mm.
    let expected = 111.0 * 0.0254 * 0.02;
    let slack = slack.expect("the slack on fixed centres");
    assert!(
        (slack / expected - 1.0).abs() < 0.01,
        "{slack} m against {expected} m"
    );
}

#[test]
fn stop_at_a_tooth_jump_ends_the_run_with_the_jump_named() {
    let err = run(&drive(2.0, "stop")).expect_err("stops at the first jump");
    let SimError::ToothJump(jump) = &err else {
        panic!("not a tooth jump: {err}");
    };
    let msg = err.to_string();
    assert!(msg.contains("tooth jump at t ="), "{msg}");
    assert!(msg.contains(&format!("roller {}", jump.roller)), "{msg}");
    assert!(msg.contains("checks.tooth_jump"), "{msg}");
}
