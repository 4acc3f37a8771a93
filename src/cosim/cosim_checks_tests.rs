//! A drive in a user's world used the way rapier users do: forces set each
//! frame on a mounted body, mistakes in mounts and steps (each an error,
//! never a panic), kinematic mounts, removal, setters mid-run.

use super::cosim_tests::conveyor;
use crate::cosim::{ChainDrive, CosimError};
use crate::scene::Scene;
use rapier2d_f64::prelude::*;

/// The conveyor's tail centre, m (40 pitches of 25.4 mm from the driver).
const TAIL_X_M: f64 = 1.016;

/// The conveyor's chain pretension, N.
const PRETENSION_N: f64 = 200.0;

fn world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

/// A motor-driven conveyor: the driver at 60 rpm, ramped in over 0.2 s.
fn driven() -> Scene {
    conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0)
}

/// A dynamic body of `mass_kg` at `x` on the tail's axis, free along x only,
/// with the scene's sprocket inertia (0.01 kg·m²).
fn carriage(mass_kg: f64) -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic()
        .translation(Vector::new(TAIL_X_M, 0.0))
        .enabled_translations(true, false)
        .additional_mass_properties(MassProperties::new(Vector::ZERO, mass_kg, 0.01))
}

/// Runs `frames` at 60 Hz with the user's force `force(x)` on the tail's
/// carriage set each frame as rapier documents it (`reset_forces`, then
/// `add_force`); the largest excursion of the carriage from its start, m.
fn hold_carriage(
    mass_kg: f64,
    frames: usize,
    force: impl Fn(f64) -> f64,
) -> Result<f64, CosimError> {
    let scene = driven();
    let mut w = world();
    let cart = w.bodies.insert(carriage(mass_kg));
    let mut drive =
        ChainDrive::insert(&scene, &[None, Some(cart)], &mut w.bodies, &mut w.colliders)?;
    let mut worst = 0.0f64;
    for _ in 0..frames {
        let x = w.bodies[cart].translation().x;
        let b = &mut w.bodies[cart];
        b.reset_forces(false);
        b.add_force(Vector::new(force(x), 0.0), true);
        drive.step_world(&mut w, &(), &())?;
        worst = worst.max((w.bodies[cart].translation().x - TAIL_X_M).abs());
    }
    Ok(worst)
}

#[test]
fn a_mounted_bodys_user_force_is_kept_through_the_step() {
    // A 200 kg carriage holding the tail out against the chain with a
    // constant user force equal to the two strands' pretension, 2 T0 = 400 N
    // (force balance on the sprocket; the sag's vertical share is below 1 %).
    // Kept, the carriage stays: an imbalance ΔF moves it only ΔF / k_chain,
    // k_chain = 2 k / 50 = 4e5 N/m for the two strands of 50 links of 1e7 N/m
    // (4 N → 10 µm); the 2 mm tolerance allows a 20 % imbalance. Lost (the
    // force was replaced by the chain's), the chain's 400 N pulls the carriage
    // in until the chain goes slack: measured, a penetration blow-up on
    // roller 85 at 1.17 s.
    let worst = hold_carriage(200.0, 120, |_| 2.0 * PRETENSION_N).expect("run");
    assert!(worst < 0.002, "the carriage moved {worst} m");
}

#[test]
fn a_coupling_blow_up_names_the_coupling_not_the_step() {
    // A 5 kg carriage held out by a stiff spring (2e5 N/m, preload 2 T0)
    // whose force the user sets once per 1/60 s frame: a zero-order hold
    // on a carriage that moves with the chain inside the frame, beyond the
    // explicit coupling's limit; a smaller solver.dt_s cannot help.
    let e = hold_carriage(5.0, 120, |x| 2.0 * PRETENSION_N - 2e5 * (x - TAIL_X_M))
        .expect_err("a spring held over the frame blows a 5 kg carriage up");
    let text = e.to_string();
    assert!(text.contains("coupling's limit"), "{text}");
    assert!(!text.contains("reduce solver.dt_s"), "{text}");
    assert!(!text.contains("a step above the stability limit"), "{text}");
}

fn field_of(e: CosimError) -> String {
    match e {
        CosimError::Input { field, message } => {
            assert!(!message.is_empty());
            field
        }
        other => panic!("not an input error: {other}"),
    }
}

#[test]
fn a_bogus_or_removed_mount_is_an_error() {
    let scene = driven();
    let mut w = world();
    // A handle from another, larger set: not in this one.
    let mut other = RigidBodySet::new();
    for _ in 0..5 {
        other.insert(RigidBodyBuilder::dynamic());
    }
    let bogus = other.insert(RigidBodyBuilder::dynamic());
    let e = ChainDrive::insert(
        &scene,
        &[None, Some(bogus)],
        &mut w.bodies,
        &mut w.colliders,
    )
    .err()
    .expect("bogus handle");
    assert_eq!(field_of(e), "mounts[1]");
    // A mount removed after insertion.
    let cart = w.bodies.insert(carriage(200.0));
    let mut drive =
        ChainDrive::insert(&scene, &[None, Some(cart)], &mut w.bodies, &mut w.colliders)
            .expect("drive");
    drive.step_world(&mut w, &(), &()).expect("frame");
    w.bodies.remove(
        cart,
        &mut w.islands,
        &mut w.colliders,
        &mut w.impulse_joints,
        &mut w.multibody_joints,
        &mut w.soft_bodies,
        true,
    );
    let e = drive
        .step_world(&mut w, &(), &())
        .expect_err("removed mount");
    assert_eq!(field_of(e), "mounts[1]");
}

#[test]
fn a_nan_or_negative_frame_step_is_an_error() {
    let scene = driven();
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    for dt in [f64::NAN, -1.0 / 60.0, 0.0, f64::INFINITY] {
        let e = drive
            .before_step(&mut w.bodies, &w.colliders, w.gravity, dt)
            .expect_err("bad dt");
        assert_eq!(field_of(e), "dt_s", "dt {dt}");
    }
    // Nothing was changed: the drive still runs.
    drive.step_world(&mut w, &(), &()).expect("frame");
}

#[test]
fn more_mounts_than_sprockets_is_an_error() {
    let scene = driven();
    let mut w = world();
    let e = ChainDrive::insert(&scene, &[None, None, None], &mut w.bodies, &mut w.colliders)
        .err()
        .expect("three mounts for two sprockets");
    assert_eq!(field_of(e), "mounts");
}

#[test]
fn the_same_body_mounted_twice_is_an_error() {
    let scene = conveyor("role = \"free\"", 0.0);
    let mut w = world();
    let b = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().lock_translations());
    let e = ChainDrive::insert(&scene, &[Some(b), Some(b)], &mut w.bodies, &mut w.colliders)
        .err()
        .expect("one body, two sprockets");
    // (It is at the driver's centre, not the tail's: the repeat is found first.)
    assert_eq!(field_of(e), "mounts[1]");
}

#[test]
fn a_mount_off_the_scenes_centre_is_an_error() {
    let scene = driven();
    let mut w = world();
    let cart = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(TAIL_X_M + 0.002, 0.0)));
    let e = ChainDrive::insert(&scene, &[None, Some(cart)], &mut w.bodies, &mut w.colliders)
        .err()
        .expect("2 mm off");
    assert_eq!(field_of(e), "sprockets[1].center_m");
}

#[test]
fn a_kinematic_mount_drives_its_sprocket_at_its_speed() {
    // A kinematic motor at 2 rad/s on the driver of an all-free conveyor:
    // with equal tooth counts the tail turns at the motor's speed (belt
    // kinematics, ω_tail = ω z_driver / z_tail), the same direction.
    let scene = conveyor("role = \"free\"", 0.0);
    let mut w = world();
    let motor = w
        .bodies
        .insert(RigidBodyBuilder::kinematic_velocity_based());
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    const SPEED: f64 = 2.0;
    let (mut tail, mut n) = (0.0, 0.0);
    for frame in 0..90 {
        // Eased in over 0.5 s.
        let t = (frame as f64 + 0.5) / 60.0;
        w.bodies[motor].set_angvel(SPEED * (t / 0.5).min(1.0), true);
        drive.step_world(&mut w, &(), &()).expect("frame");
        if frame >= 60 {
            tail += drive.state().omega[1];
            n += 1.0;
            // The chain's sprocket is the motor's, which rapier turned.
            assert_close(drive.state().omega[0], SPEED, 1e-9);
        }
    }
    let tail = tail / n;
    assert!((tail - SPEED).abs() < 0.02 * SPEED, "tail at {tail} rad/s");
}

fn assert_close(a: f64, b: f64, eps: f64) {
    assert!((a - b).abs() <= eps, "{a} vs {b}");
}

#[test]
fn a_frame_step_other_than_the_worlds_is_an_error() {
    let scene = driven();
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    for _ in 0..30 {
        drive.step_world(&mut w, &(), &()).expect("frame");
    }
    // The chain runs; the world steps 1/60 s, the drive is told 1/30 s.
    drive
        .before_step(&mut w.bodies, &w.colliders, w.gravity, 1.0 / 30.0)
        .expect("before");
    w.step_with_events(&drive.hooks(&()), &());
    let e = drive
        .after_step(&mut w.bodies, &w.narrow_phase, 1.0 / 30.0)
        .expect_err("1/30 against 1/60");
    assert!(matches!(e, CosimError::World(_)), "{e}");
    assert!(e.to_string().contains("another dt"), "{e}");
}

#[test]
fn a_world_stepped_without_the_drives_hooks_is_an_error() {
    let scene = conveyor("role = \"free\"", -1.0);
    let mut w = world();
    let motor = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
    );
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    let dt = w.integration_parameters.dt;
    drive
        .before_step(&mut w.bodies, &w.colliders, w.gravity, dt)
        .expect("before");
    w.step_with_events(&(), &());
    let e = drive
        .after_step(&mut w.bodies, &w.narrow_phase, dt)
        .expect_err("no hooks");
    assert!(e.to_string().contains("without the drive's hooks"), "{e}");
}

#[test]
fn remove_leaves_the_users_sets_as_they_were() {
    let scene = conveyor("role = \"free\"", -1.0);
    let mut w = world();
    let motor = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
    );
    let ground = w
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(0.5, -0.5)));
    w.colliders
        .insert_with_parent(ColliderBuilder::cuboid(1.0, 0.05), ground, &mut w.bodies);
    let (bodies, colliders) = (w.bodies.len(), w.colliders.len());
    let motor_colliders = w.bodies[motor].colliders().to_vec();
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    assert_eq!(w.bodies.len(), bodies + 101); // 100 rollers and the tail
    for _ in 0..10 {
        let b = &mut w.bodies[motor];
        b.reset_torques(false);
        b.add_torque(2.0, true);
        drive.step_world(&mut w, &(), &()).expect("frame");
    }
    drive.remove(&mut w);
    assert_eq!((w.bodies.len(), w.colliders.len()), (bodies, colliders));
    assert_eq!(w.bodies[motor].colliders(), &motor_colliders[..]);
    // The user's torque is still on the motor, and the world steps on.
    assert_eq!(w.bodies[motor].user_torque(), 2.0);
    for _ in 0..3 {
        w.step();
    }
    assert!(w.bodies[motor].angvel() > 0.0);
}

#[test]
fn insert_keeps_a_mounted_bodys_rotation() {
    let scene = conveyor("role = \"free\"", 0.0);
    let mut w = world();
    let motor = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .rotation(0.7)
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
    );
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    assert_eq!(w.bodies[motor].rotation().angle(), 0.7);
    let theta0 = drive.state().theta[0];
    drive.step_world(&mut w, &(), &()).expect("frame");
    // It turns with the chain from where it was.
    let turned = drive.state().theta[0] - theta0;
    let angle = w.bodies[motor].rotation().angle();
    assert!(
        (angle - (0.7 + turned)).abs() < 1e-9,
        "{angle} vs {}",
        0.7 + turned
    );
}

#[test]
fn insert_keeps_a_mounted_bodys_speed() {
    // A motor already at 6.27 rad/s on the head of an all-free, unloaded
    // conveyor: the chain joins it in belt motion, so with no load the motor
    // keeps its speed (angular momentum of an unloaded belt drive) but for
    // what the roller impacts and link damping dissipate (measured: 3 % over
    // 0.5 s), and the tail of equal tooth count turns at the same speed
    // (belt kinematics). Over the first 1/6 s: within 2 % on the mean,
    // 5 % at any frame (polygonal action: 1 − cos(π/20) ≈ 1.2 % per sprocket).
    // Set to the chain's rest instead (no belt motion), the motor was at 0 rad/s
    // after one frame (measured: −2e-8 rad/s).
    const SPEED: f64 = 6.27;
    let scene = conveyor("role = \"free\"", 0.0);
    let mut w = world();
    let spinning = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .angvel(SPEED)
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
    );
    let mut drive = ChainDrive::insert(&scene, &[Some(spinning)], &mut w.bodies, &mut w.colliders)
        .expect("drive");
    let (mut motor_mean, mut tail_mean) = (0.0, 0.0);
    for frame in 0..10 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        let (motor, tail) = (w.bodies[spinning].angvel(), drive.state().omega[1]);
        for (what, speed) in [("motor", motor), ("tail", tail)] {
            assert!(
                (speed - SPEED).abs() < 0.05 * SPEED,
                "frame {frame}: {what} at {speed} rad/s"
            );
        }
        motor_mean += motor / 10.0;
        tail_mean += tail / 10.0;
    }
    assert!(
        (motor_mean - SPEED).abs() < 0.02 * SPEED,
        "motor at {motor_mean} rad/s"
    );
    assert!(
        (tail_mean - SPEED).abs() < 0.02 * SPEED,
        "tail at {tail_mean} rad/s"
    );
    // A second mount at rest cannot share that chain: an error.
    let mut w = world();
    let head = w
        .bodies
        .insert(RigidBodyBuilder::kinematic_velocity_based().angvel(SPEED));
    let tail = w.bodies.insert(
        RigidBodyBuilder::kinematic_velocity_based().translation(Vector::new(TAIL_X_M, 0.0)),
    );
    let e = ChainDrive::insert(
        &scene,
        &[Some(head), Some(tail)],
        &mut w.bodies,
        &mut w.colliders,
    )
    .err()
    .expect("mounts at speeds the chain cannot share");
    assert_eq!(field_of(e), "mounts[1]");
}

#[test]
fn set_load_torque_and_driver_speed_hold_from_frame_to_frame() {
    // The driver at 60 rpm, then set to 2 rad/s; a load of −10 N·m set on
    // the free tail. In steady running the tail's speed is the driver's
    // (equal tooth counts) and the load is balanced by the strands' tension
    // difference τ / R (moment balance on the tail, R its pitch radius).
    let torque = 10.0;
    let scene = driven();
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    drive
        .set_load_torque(drive.sprocket(1).expect("tail"), -torque)
        .expect("load");
    drive.set_driver_speed(2.0).expect("speed");
    assert!(drive.sprocket(2).is_err());
    assert!(
        drive
            .set_load_torque(drive.sprocket(1).expect("tail"), f64::NAN)
            .is_err()
    );
    let (mut lower, mut upper, mut n, mut tail) = (0.0, 0.0, 0.0, 0.0);
    for frame in 0..120 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        if frame >= 60 {
            let seg =
                crate::test_support::strand_means(drive.model(), drive.state(), drive.forces());
            if let [Some(a), Some(b)] = seg[..] {
                lower += a;
                upper += b;
                n += 1.0;
            }
            tail += drive.state().omega[1];
        }
    }
    assert!(
        (tail / 60.0 - 2.0).abs() < 0.02 * 2.0,
        "tail {} rad/s",
        tail / 60.0
    );
    let r = drive.model().sprockets[1].pitch_radius_m;
    let diff = ((upper - lower) / n).abs();
    assert!(
        ((diff - torque / r) / (torque / r)).abs() < 0.03,
        "difference {diff} N, τ/R = {} N",
        torque / r
    );
}

#[test]
fn a_dynamic_mounts_inertia_is_its_bodys() {
    // A motor body of J = 1 kg·m² (the scene says 0.01) on the head of the
    // all-free, unloaded conveyor, under τ = 1 N·m for 0.5 s. The drive's
    // reduced inertia at the motor (equal tooth counts, every roller moving
    // at ω R): J + J_tail + m_chain R², m_chain = 100 × 0.02 kg, so
    // ω(t) = τ t / (J + J_tail + m_chain R²) ≈ 0.489 rad/s at 0.5 s. With the
    // scene's 0.01 kg·m² it would be 30 times as fast. 3 % allows for the
    // strands' sag and the polygonal action.
    const J: f64 = 1.0;
    let scene = conveyor("role = \"free\"", 0.0);
    let mut w = world();
    let motor = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, J)),
    );
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    let r = drive.model().sprockets[0].pitch_radius_m;
    for _ in 0..30 {
        let b = &mut w.bodies[motor];
        b.reset_torques(false);
        b.add_torque(1.0, true);
        drive.step_world(&mut w, &(), &()).expect("frame");
    }
    let expected = 1.0 * 0.5 / (J + 0.01 + 100.0 * 0.02 * r * r);
    let omega = w.bodies[motor].angvel();
    assert!(
        ((omega - expected) / expected).abs() < 0.03,
        "motor at {omega} rad/s, expected {expected} rad/s"
    );
}
