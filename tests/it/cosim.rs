//! The drive inside a user's rapier world: stepped at 1/60 s with other
//! bodies, motors and loads on mounted bodies.

use chaindrive::cosim::ChainDrive;
use chaindrive::scene::Scene;
use chaindrive::sim::Simulation;
use rapier2d_f64::prelude::*;

/// A two-sprocket horizontal conveyor: #40 chain (P = 12.7 mm would do; here
/// 25.4 mm), 20 teeth each, centres 40 pitches apart, 100 rollers.
pub fn conveyor(driver: &str, load_torque_n_m: f64) -> Scene {
    let text = format!(
        r#"
name = "conveyor"
gravity_m_s2 = [0.0, -9.81]
[chain]
rollers = 100
pitch_m = 0.0254
roller_radius_m = 0.00397
roller_mass_kg = 0.02
stiffness_n_m = 1e7
damping_n_s_m = 5.0
pretension_n = 200.0
[contact]
stiffness = 2e8
restitution = 0.5
min_approach_speed_m_s = 0.1
[[sprockets]]
name = "driver"
center_m = [0.0, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
{driver}
[[sprockets]]
name = "tail"
center_m = [1.016, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
role = "free"
load_torque_n_m = {load_torque_n_m}
[solver]
dt_s = 1e-5
"#
    );
    Scene::from_toml(&text).expect("conveyor scene")
}

/// A 2 kg motor body on a fixed axle with the conveyor sprocket's 0.01 kg·m².
fn motor_body() -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic()
        .lock_translations()
        .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01))
}

fn world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

#[test]
fn paper_drive_in_a_60_hz_world_matches_the_standalone_run() {
    let scene = Scene::l60mc();
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    let mut alone = Simulation::new(&scene).expect("standalone");
    let frames = 90; // 1.5 s
    let mut forces_cosim = Vec::new();
    let mut forces_alone = Vec::new();
    for _ in 0..frames {
        drive.step_world(&mut w, &(), &()).expect("frame");
        alone
            .run(
                drive.state.t_s,
                1_000_000,
                &mut chaindrive::sim::NoObserver,
                None,
            )
            .expect("run");
        forces_cosim.push(drive.forces.link_force.clone());
        forces_alone.push(alone.forces.link_force.clone());
    }
    // Same substeps, same forces: the chain evolves as it does standalone.
    assert!((drive.state.t_s - 1.5).abs() < scene.solver.dt_s);
    let worst = (0..drive.state.rollers())
        .map(|i| (drive.state.x[i] - alone.state.x[i]).hypot(drive.state.y[i] - alone.state.y[i]))
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst:e}");
    // Segment-level: mean and peak link force over the last 30 frames within 1%.
    let stats = |rows: &[Vec<f64>]| {
        let all: Vec<f64> = rows[frames - 30..].iter().flatten().copied().collect();
        (
            all.iter().sum::<f64>() / all.len() as f64,
            all.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    let (a, b) = (stats(&forces_cosim), stats(&forces_alone));
    assert!(
        ((a.0 - b.0) / b.0).abs() < 0.01 && ((a.1 - b.1) / b.1).abs() < 0.01,
        "{a:?} vs {b:?}"
    );
    // The rapier bodies follow the chain.
    let p = w.bodies[drive.rollers[7]].translation();
    assert!((p.x - drive.state.x[7]).abs() < 1e-9 && (p.y - drive.state.y[7]).abs() < 1e-9);
}

#[test]
fn stock_contacts_keep_working_next_to_the_drive() {
    let scene = Scene::l60mc();
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    // A ground box beside the drive and a bouncy ball dropped on it.
    let ground = w
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(3.0, -1.0)));
    w.colliders
        .insert_with_parent(ColliderBuilder::cuboid(0.5, 0.1), ground, &mut w.bodies);
    let ball = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 0.0)));
    w.colliders.insert_with_parent(
        ColliderBuilder::ball(0.05).restitution(0.8),
        ball,
        &mut w.bodies,
    );
    let mut lowest = f64::INFINITY;
    let mut bounced_up = false;
    for _ in 0..60 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        let b = &w.bodies[ball];
        lowest = lowest.min(b.translation().y);
        bounced_up |= b.linvel().y > 1.0;
    }
    // Resting height: box top −0.9 + radius 0.05.
    assert!(lowest > -0.86, "the ball went through the box: {lowest}");
    assert!(bounced_up, "the ball did not bounce");
}

#[test]
fn motor_torque_against_a_load_gives_tension_difference_t_over_r() {
    let torque = 10.0;
    let scene = conveyor("role = \"free\"", -torque);
    let mut w = world();
    let motor = w.bodies.insert(motor_body());
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    w.bodies[motor].add_torque(torque, true);
    let (mut lower, mut upper, mut n) = (0.0, 0.0, 0.0);
    for frame in 0..180 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        if frame >= 60 {
            // Strand 1 runs along the bottom from sprocket 1 to 2, strand 2 back on top.
            let mut seg = [None; 2];
            drive.model.segments.mean_forces(
                &drive.state.x,
                &drive.state.y,
                &drive.forces.link_force,
                &drive.forces.touching,
                &mut seg,
            );
            if let [Some(a), Some(b)] = seg {
                lower += a;
                upper += b;
                n += 1.0;
            }
        }
    }
    let r = drive.model.sprockets[0].pitch_radius_m;
    let diff = (upper - lower) / n;
    // Motor CCW: it pulls the upper strand (leaving the tail) tight.
    assert!(
        ((diff.abs() - torque / r) / (torque / r)).abs() < 0.02,
        "difference {diff} N, T/R = {} N",
        torque / r
    );
}

#[test]
fn box_on_the_upper_strand_moves_at_chain_speed() {
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.5", 0.0);
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    let r = drive.model.sprockets[0].pitch_radius_m;
    let top = r + 0.00397;
    // A 0.1 kg box near the tail; the upper strand carries it towards the driver.
    let bx = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.9, top + 0.03)));
    w.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.025)
            .density(20.0)
            .friction(0.8),
        bx,
        &mut w.bodies,
    );
    let mut speeds = Vec::new();
    for frame in 0..75 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        if frame >= 45 {
            speeds.push(w.bodies[bx].linvel().x);
        }
    }
    let v_chain = std::f64::consts::TAU * r; // 60 rpm
    let v_box = speeds.iter().sum::<f64>() / speeds.len() as f64;
    // The upper strand runs from sprocket 2 back to 1: towards −x.
    assert!(
        ((v_box + v_chain) / v_chain).abs() < 0.05,
        "box {v_box} m/s, chain {v_chain} m/s"
    );
}

#[test]
fn motor_spin_up_is_consistent_with_the_chain_reaction() {
    let torque = 1.0;
    let scene = conveyor("role = \"free\"", 0.0);
    let mut w = world();
    let motor = w.bodies.insert(motor_body());
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    w.bodies[motor].add_torque(torque, true);
    let frames = 30;
    for _ in 0..frames {
        drive.step_world(&mut w, &(), &()).expect("frame");
    }
    let t = frames as f64 / 60.0;
    let alpha = drive.state.omega[0] / t;
    // Rigid-chain estimate: J_eff = J1 + J2 (equal sprockets) + m_chain R².
    let r = drive.model.sprockets[0].pitch_radius_m;
    let j_eff = 0.01 + 0.01 + 100.0 * 0.02 * r * r;
    let expected = torque / j_eff;
    assert!(
        ((alpha - expected) / expected).abs() < 0.05,
        "α = {alpha}, expected {expected}"
    );
    // And the body the user sees turns with the chain's sprocket.
    assert!(
        (w.bodies[motor].angvel() - drive.state.omega[0]).abs() < 0.05 * drive.state.omega[0].abs()
    );
}
