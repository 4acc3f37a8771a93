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

/// A 45T/45T ANSI 80 drive whose driven sprocket is a tensioner (2 kN),
/// the chain worn `elongation_pct`, 0.2 s: the driver at 100 rpm, the load
/// ramping to 2180 N·m (12 kN) over 0.5 s. Worn 8 %, beyond the quasi-static
/// ride-over at about 336/45 = 7.5 %, its rollers climb to the tips.
fn tensioned_45(elongation_pct: f64) -> String {
    drive(elongation_pct, "count")
        .replace("teeth = 30", "teeth = 45")
        .replace("pretension_n = 1000.0", "pretension_n = 2000.0")
        .replace("\"rest_length\"", "\"tensioner\"")
        .replace(
            "role = \"free\"",
            "role = \"tensioner\"\nadjust_direction = [1.0, 0.0]",
        )
        .replace("load_torque_n_m = 1500.0", "load_torque_n_m = 2180.0")
        .replace("load_ramp_s = 1.0", "load_ramp_s = 0.5")
        .replace("center_m = [1.0291, 0.0]", "center_m = [0.8382, 0.0]")
        .replace("duration_s = 0.4", "duration_s = 0.2")
}

#[test]
fn a_chain_worn_beyond_the_quasi_static_ride_over_rides_the_tips_and_the_new_one_does_not() {
    let worn = run(&tensioned_45(8.0)).expect("runs");
    assert!(worn.tooth_jumps.is_empty(), "{:?}", worn.tooth_jumps);
    // Both sprockets, several rollers each, from early in the run.
    assert_eq!(worn.tip_rides.len(), 2, "{:?}", worn.tip_rides);
    for (k, ride) in worn.tip_rides.iter().enumerate() {
        assert_eq!(ride.sprocket, k + 1);
        assert!(ride.count >= 3, "{ride:?}");
        assert!(ride.first_t_s > 0.0 && ride.first_t_s <= 0.2, "{ride:?}");
        assert!(ride.first_roller < 111, "{ride:?}");
    }
    let warning = worn
        .warnings
        .iter()
        .find(|w| w.starts_with("tip ride"))
        .expect("the tip-ride warning");
    let first = worn
        .tip_rides
        .iter()
        .min_by(|a, b| a.first_t_s.total_cmp(&b.first_t_s))
        .expect("a ride");
    assert!(
        warning.contains(&format!(
            "roller {} on sprocket {}",
            first.first_roller, first.sprocket
        )),
        "{warning}"
    );
    let new = run(&tensioned_45(0.0)).expect("runs");
    assert!(new.tip_rides.is_empty(), "{:?}", new.tip_rides);
    assert!(!new.warnings.iter().any(|w| w.starts_with("tip ride")));
}

/// The detector on a state set by hand (the 30/30 drive at rest, new): a
/// roller put right above a tooth's tip, 1 µm into it, rides it; 1 µm clear
/// of it, or on the topping curve below the tip-ride radius, it does not; a
/// ride is counted once until the roller lies deep in a gap again.
#[test]
fn a_roller_touching_a_tips_corner_rides_it_and_one_on_the_flank_below_does_not() {
    use crate::geometry::ToothProfile;
    use crate::geometry::v2::{add, norm, polar, scale, sub};
    let scene = Scene::from_toml(&drive(0.0, "count")).expect("valid scene");
    let sim = Simulation::new(&scene).expect("equilibrium");
    let (model, mut state) = (sim.model.clone(), sim.state.clone());
    let mut watch = super::JumpWatch::new(&model, state.rollers());
    watch.look(&model, &state);
    assert!(watch.rides().is_empty(), "{:?}", watch.rides());
    let sp = &model.sprockets[1];
    let ToothProfile::Real(profile) = &sp.profile else {
        panic!("the real profile");
    };
    let (d, pts) = (profile.dimensions(), profile.gap_points());
    let rr = 0.5 * d.roller_diameter_m;
    // Gap-local (ξ, η) of gap 0 to the world: (R_s + η, −ξ) turned by θ.
    let theta = state.theta[1];
    let world = |q: [f64; 2]| {
        let p = [d.pitch_radius_m + q[1], -q[0]];
        let (s, c) = theta.sin_cos();
        [
            sp.center_m[0] + c * p[0] - s * p[1],
            sp.center_m[1] + s * p[0] + c * p[1],
        ]
    };
    let mut put = |state: &mut crate::model::DriveState, q: [f64; 2]| {
        let [x, y] = world(q);
        state.x[0] = x;
        state.y[0] = y;
        watch.look(&model, state);
        watch.rides().to_vec()
    };
    // Above the tip, radially out from it (gap-local: the sprocket frame's
    // (R_s + η, −ξ) normalised, written back as (ξ, η)): a centre radius of
    // tip + R_r, beyond the tip-ride radius.
    let radial_local = {
        let f = pts.f_m;
        let r = [f[0], d.pitch_radius_m + f[1]];
        scale(r, 1.0 / norm(r))
    };
    let rides = put(&mut state, add(pts.f_m, scale(radial_local, rr + 1e-6)));
    assert!(rides.is_empty(), "1 µm clear: {rides:?}");
    let rides = put(&mut state, add(pts.f_m, scale(radial_local, rr - 1e-6)));
    assert_eq!(rides.len(), 1, "1 µm into the tip");
    assert_eq!((rides[0].sprocket, rides[0].roller), (1, 0));
    // Still on it: the same ride.
    let rides = put(&mut state, add(pts.f_m, scale(radial_local, rr - 2e-6)));
    assert_eq!(rides.len(), 1);
    // On the topping curve halfway up, 1 µm into it: below the radius.
    let (zb, fb) = (sub(pts.z_m, pts.b_m), sub(pts.f_m, pts.b_m));
    let t = 0.5 * (zb[1].atan2(zb[0]) + fb[1].atan2(fb[0]));
    let rf = d.topping_radius_m;
    // Seated in the gap (deep): the ride ends; then onto the flank.
    put(&mut state, [0.0, 0.0]);
    let rides = put(&mut state, add(pts.b_m, scale(polar(t), rf + rr - 1e-6)));
    assert_eq!(rides.len(), 1, "on the flank: {rides:?}");
    // Onto the tip again: a second ride.
    let rides = put(&mut state, add(pts.f_m, scale(radial_local, rr - 1e-6)));
    assert_eq!(rides.len(), 2);
    assert!(watch.jumps().is_empty(), "{:?}", watch.jumps());
}
