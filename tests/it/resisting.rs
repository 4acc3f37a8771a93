//! A resisting load (`resisting_torque_n_m`) against an active one
//! (`load_torque_n_m`) on a co-simulated conveyor that a motor spins up and
//! lets coast: the resisting load stops it and holds it, the active one
//! stops it and turns it backwards. A drive with a prescribed speed gives
//! the resisting load's torque ratio through the chain.

use chaindrive::analysis::{RunSummary, StatsWindow};
use chaindrive::cosim::ChainDrive;
use chaindrive::scene::Scene;
use chaindrive::sim::{SampleRate, Simulation};
use rapier2d_f64::prelude::*;

const PITCH_M: f64 = 0.0254;
const ROLLER_MASS_KG: f64 = 0.02;
const ROLLERS: usize = 100;
/// Each sprocket's (and the motor body's) polar inertia, kg·m².
const INERTIA_KG_M2: f64 = 0.01;

/// A horizontal conveyor of two 20-tooth sprockets 40 pitches apart, both
/// free (a motor body turns the head), the tail's load as `tail_load`.
fn conveyor(tail_load: &str) -> Scene {
    let text = format!(
        r#"
name = "conveyor"
gravity_m_s2 = [0.0, -9.81]
[chain]
rollers = {ROLLERS}
pitch_m = {PITCH_M}
roller_radius_m = 0.00397
roller_mass_kg = {ROLLER_MASS_KG}
stiffness_n_m = 1e7
damping_n_s_m = 5.0
pretension_n = 200.0
[contact]
stiffness = 2e8
restitution = 0.5
min_approach_speed_m_s = 0.1
[[sprockets]]
name = "head"
center_m = [0.0, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = {INERTIA_KG_M2}
wrap = "ccw"
role = "free"
[[sprockets]]
name = "tail"
center_m = [1.016, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = {INERTIA_KG_M2}
wrap = "ccw"
role = "free"
{tail_load}
[solver]
dt_s = 1e-5
"#
    );
    Scene::from_toml(&text).expect("conveyor scene")
}

/// Pitch radius of a 20-tooth sprocket, m: P / (2 sin(π / 20)).
fn pitch_radius_m() -> f64 {
    PITCH_M / (2.0 * (std::f64::consts::PI / 20.0).sin())
}

/// Rigid-chain inertia seen at either sprocket, kg·m²: the motor body's and
/// the tail's (the head sprocket's inertia is the body's), plus every
/// roller moving at ω R.
fn effective_inertia_kg_m2() -> f64 {
    let r = pitch_radius_m();
    2.0 * INERTIA_KG_M2 + ROLLERS as f64 * ROLLER_MASS_KG * r * r
}

/// Least-squares slope of `y` over `t`.
fn slope(t: &[f64], y: &[f64]) -> f64 {
    let n = t.len() as f64;
    let (mt, my) = (t.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = t.iter().zip(y).map(|(a, b)| (a - mt) * (b - my)).sum();
    let sxx: f64 = t.iter().map(|a| (a - mt) * (a - mt)).sum();
    sxy / sxx
}

/// The head's speed at each 1/60 s frame over `frames`: a motor torque
/// `motor_n_m` on the head's body for the first `on_frames`, none after.
fn spin_up_and_coast(scene: &Scene, motor_n_m: f64, on_frames: usize, frames: usize) -> Vec<f64> {
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    };
    let motor = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, INERTIA_KG_M2)),
    );
    let mut drive = ChainDrive::builder(scene)
        .mount("head", motor)
        .build(&mut w)
        .expect("drive");
    w.bodies[motor].add_torque(motor_n_m, true);
    let head = drive.sprocket("head").expect("the head sprocket");
    let mut speeds = Vec::with_capacity(frames);
    for frame in 0..frames {
        if frame == on_frames {
            w.bodies[motor].reset_torques(true);
        }
        drive.step_world(&mut w, &(), &()).expect("frame");
        speeds.push(drive.sprocket_speed(head));
    }
    speeds
}

#[test]
fn a_resisting_load_stops_a_coasting_conveyor_and_holds_it_where_an_active_one_reverses_it() {
    // Motor 3 N·m for 0.5 s against 1 N·m at the tail, then coasting for
    // 1.5 s. Rigid chain, equal sprockets: J ω' = T_m − T_r while the motor
    // pulls, −T_r while it coasts (stopping after (T_m − T_r) t_on / T_r =
    // 1 s), then 0 for a resisting load and −T_r for an active one.
    let (motor, load) = (3.0, 1.0);
    let (on, frames) = (30, 120);
    let dt = 1.0 / 60.0;
    let j = effective_inertia_kg_m2();
    let resisting = spin_up_and_coast(
        &conveyor(&format!("resisting_torque_n_m = {load}")),
        motor,
        on,
        frames,
    );
    let t: Vec<f64> = (1..=frames).map(|k| k as f64 * dt).collect();
    let up = slope(&t[5..on], &resisting[5..on]);
    let down = slope(&t[on + 5..on + 50], &resisting[on + 5..on + 50]);
    // The chain's own losses (link and contact damping as the rollers
    // enter and leave the wraps) act in both phases: the difference of the
    // two slopes, T_m / J, does not see them, each slope alone does (the
    // coasting slope is ~5 % steeper than −T_r / J at this speed).
    let (up_expected, down_expected) = ((motor - load) / j, -load / j);
    assert!(
        ((up - down) / (motor / j) - 1.0).abs() < 0.03,
        "spin-up {up} minus coasting {down} rad/s², rigid chain T_m / J = {}",
        motor / j
    );
    assert!(
        ((up - up_expected) / up_expected).abs() < 0.05,
        "spin-up {up} rad/s², rigid chain {up_expected}"
    );
    assert!(
        ((down - down_expected) / down_expected).abs() < 0.08,
        "coasting {down} rad/s², rigid chain {down_expected}"
    );
    let peak = resisting.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let last_quarter = &resisting[frames - 20..];
    assert!(
        last_quarter.iter().all(|w| w.abs() < 0.02 * peak),
        "the resisting load did not hold the stopped conveyor: {last_quarter:?} rad/s (peak {peak})"
    );

    let active = spin_up_and_coast(
        &conveyor(&format!("load_torque_n_m = {}", -load)),
        motor,
        on,
        frames,
    );
    // While both turn forwards the two loads are the same torque.
    let active_down = slope(&t[on + 5..on + 50], &active[on + 5..on + 50]);
    assert!(
        ((active_down - down) / down).abs() < 0.01,
        "coasting against the active load {active_down}, the resisting one {down} rad/s²"
    );
    // Stopped at about 1.5 s, then 0.5 s backwards at T_r / J.
    let backwards = -load / j * 0.5;
    let end = active[frames - 1];
    assert!(
        ((end - backwards) / backwards).abs() < 0.15,
        "the active load turned the conveyor back to {end} rad/s, rigid chain {backwards}"
    );
}

#[test]
fn a_resisting_load_at_a_prescribed_speed_takes_its_torque_through_the_teeth_ratio() {
    // 20-tooth driver at 300 rpm, 40-tooth driven sprocket resisting with
    // 20 N·m: the driver's mean torque is 20 × 20 / 40 = 10 N·m, as under
    // an active load of −20 N·m (the driven sprocket turns forwards).
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/resisting_20_40.toml"
    ))
    .expect("scene");
    let scene = Scene::from_toml(&text).expect("valid");
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a whole number of steps");
    let window = StatsWindow::of(&scene, Some(0.5)).expect("window");
    let mut signals = window.observe(&mut sim, sampling.rate_hz);
    let out = sim
        .run(
            scene.solver().duration_s,
            sampling.every,
            &mut signals,
            None,
        )
        .expect("run");
    let summary = RunSummary::of_run_in(&sim, &out, &signals, 0.0, &window);
    let json = serde_json::to_value(&summary).expect("json");
    let torque = json["sprockets"][0]["mean_torque_n_m"]
        .as_f64()
        .expect("torque");
    assert!(
        ((torque.abs() - 10.0) / 10.0).abs() < 0.01,
        "driver's mean torque {torque} N·m, 20 x 20 / 40 = 10 N·m"
    );
}
