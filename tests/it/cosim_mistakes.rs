//! Mistakes a rapier user makes with a co-simulated drive, each a
//! [`CosimError`] naming its cause before the frame writes anything (or,
//! where the use is legitimate, a warning).

use chaindrive::cosim::{ChainDrive, CosimError, DriveSet, MountSpring};
use chaindrive::scene::Scene;
use rapier2d_f64::prelude::*;

/// A two-sprocket horizontal conveyor: #40 chain (P = 12.7 mm would do; here
/// 25.4 mm), 20 teeth each, centres 40 pitches apart, 100 rollers.
fn conveyor(driver: &str, load_torque_n_m: f64) -> Scene {
    conveyor_in_gravity(-9.81, driver, load_torque_n_m)
}

/// [`conveyor`] with gravity `gravity_y` along y, m/s².
fn conveyor_in_gravity(gravity_y: f64, driver: &str, load_torque_n_m: f64) -> Scene {
    let text = format!(
        r#"
name = "conveyor"
gravity_m_s2 = [0.0, {gravity_y}]
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

fn world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

/// The conveyor driven at 60 rpm (ramped over 0.2 s).
fn driven() -> Scene {
    conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0)
}

/// The field of an input error (a panic on any other error).
fn field_of(e: CosimError) -> String {
    match e {
        CosimError::Input { field, message } => {
            assert!(!message.is_empty());
            field
        }
        other => panic!("not an input error: {other}"),
    }
}

/// The roller bodies' positions, to see that an error wrote nothing.
fn roller_positions(w: &PhysicsWorld, d: &ChainDrive) -> Vec<Vector> {
    d.roller_bodies()
        .iter()
        .map(|&h| w.bodies[h].translation())
        .collect()
}

/// A driven conveyor in `w`, run for `frames` at 60 Hz.
fn running(w: &mut PhysicsWorld, frames: usize) -> ChainDrive {
    let mut d = ChainDrive::insert(&driven(), &[], &mut w.bodies, &mut w.colliders).expect("drive");
    for _ in 0..frames {
        d.step_world(w, &(), &()).expect("frame");
    }
    d
}

#[test]
fn before_step_twice_without_a_world_step_is_an_error() {
    let mut w = world();
    let mut d = running(&mut w, 30);
    let dt = w.integration_parameters.dt;
    d.before_step(&mut w.bodies, &w.colliders, w.gravity, dt)
        .expect("first");
    let before = roller_positions(&w, &d);
    let e = d
        .before_step(&mut w.bodies, &w.colliders, w.gravity, dt)
        .expect_err("twice");
    assert!(e.to_string().contains("before_step again"), "{e}");
    assert_eq!(roller_positions(&w, &d), before);
}

#[test]
fn a_roller_body_removed_by_the_user_is_an_error() {
    let mut w = world();
    let mut d = running(&mut w, 5);
    let h = d.roller_bodies()[73];
    let PhysicsWorld {
        islands,
        bodies,
        colliders,
        impulse_joints,
        multibody_joints,
        soft_bodies,
        ..
    } = &mut w;
    bodies.remove(
        h,
        islands,
        colliders,
        impulse_joints,
        multibody_joints,
        soft_bodies,
        true,
    );
    let e = d.step_world(&mut w, &(), &()).expect_err("removed roller");
    assert_eq!(field_of(e), "rollers[73]");
}

#[test]
fn a_world_gravity_other_than_the_scenes_is_a_warning_once() {
    let mut w = world();
    let mut d = running(&mut w, 3);
    assert!(d.warnings().is_empty(), "{:?}", d.warnings());
    w.gravity = Vector::new(0.0, -9.0);
    for _ in 0..3 {
        d.step_world(&mut w, &(), &()).expect("frame");
    }
    assert_eq!(d.warnings().len(), 1, "{:?}", d.warnings());
    assert!(
        d.warnings()[0].contains("gravity_m_s2"),
        "{:?}",
        d.warnings()
    );
}

#[test]
fn a_nan_world_gravity_is_named() {
    let mut w = world();
    let mut d = running(&mut w, 3);
    w.gravity = Vector::new(f64::NAN, -9.81);
    let before = roller_positions(&w, &d);
    let e = d.step_world(&mut w, &(), &()).expect_err("NaN gravity");
    assert_eq!(field_of(e), "gravity");
    assert_eq!(roller_positions(&w, &d), before);
}

#[test]
fn a_force_law_on_a_mount_with_locked_translations_is_an_error() {
    let mut w = world();
    let motor = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
    );
    let scene = conveyor("role = \"free\"", -1.0);
    let mut d =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    d.set_mount_force(
        d.sprocket(0).expect("sprocket 0"),
        MountSpring {
            anchor_m: Vector::ZERO,
            axis: Vector::X,
            stiffness_n_m: 1e4,
            damping_n_s_m: 0.0,
            preload_n: 0.0,
        },
    )
    .expect("a dynamic mount");
    let e = d.step_world(&mut w, &(), &()).expect_err("locked");
    assert_eq!(field_of(e), "mounts[0]");
}

#[test]
fn a_nan_user_torque_on_a_mount_is_named_not_a_penetration() {
    let mut w = world();
    let motor = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
    );
    let scene = conveyor("role = \"free\"", -1.0);
    let mut d =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    w.bodies[motor].add_torque(f64::NAN, true);
    let e = d.step_world(&mut w, &(), &()).expect_err("NaN torque");
    let text = e.to_string();
    assert!(text.contains("user torque"), "{text}");
    assert_eq!(field_of(e), "mounts[0]");
}

#[test]
fn before_and_after_step_without_a_world_step_is_named() {
    let mut w = world();
    let mut d = running(&mut w, 30);
    let dt = w.integration_parameters.dt;
    d.before_step(&mut w.bodies, &w.colliders, w.gravity, dt)
        .expect("before");
    let e = d
        .after_step(&mut w.bodies, &w.narrow_phase, dt)
        .expect_err("not stepped");
    assert!(matches!(e, CosimError::World(_)), "{e}");
    assert!(e.to_string().contains("not stepped"), "{e}");
}

#[test]
fn a_world_stepped_without_hooks_while_a_box_rides_the_chain_is_an_error() {
    // Nothing mounted, a box on the upper strand (its top at about
    // 84 mm: pitch radius 81.2 mm cos 9° plus the 4 mm roller).
    let mut w = world();
    let mut d = running(&mut w, 5);
    let b = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.5, 0.111)));
    w.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.025).density(80.0),
        b,
        &mut w.bodies,
    );
    for _ in 0..30 {
        d.step_world(&mut w, &(), &()).expect("frame");
    }
    assert!(d.carries(b), "the box rides the chain");
    let dt = w.integration_parameters.dt;
    d.before_step(&mut w.bodies, &w.colliders, w.gravity, dt)
        .expect("before");
    w.step_with_events(&(), &());
    let e = d
        .after_step(&mut w.bodies, &w.narrow_phase, dt)
        .expect_err("no hooks");
    assert!(e.to_string().contains("without the drive's hooks"), "{e}");
}

#[test]
fn a_drive_from_another_world_in_a_set_is_named_before_anything_is_written() {
    // Two worlds built alike: the second drive's handles name the first
    // drive's bodies in this world.
    let mut w = world();
    let mut other = world();
    let a = running(&mut w, 10);
    let b =
        ChainDrive::insert(&driven(), &[], &mut other.bodies, &mut other.colliders).expect("drive");
    let before = roller_positions(&w, &a);
    let mut set = DriveSet::new();
    set.push(a);
    set.push(b);
    let e = set.step_world(&mut w, &(), &()).expect_err("another world");
    // One sentence (before: a run of 30 spaces inside it).
    let text = e.to_string();
    assert!(text.contains("inserted into another world ("), "{text}");
    assert_eq!(field_of(e), "drives[1]");
    assert_eq!(roller_positions(&w, &set.drives()[0]), before);
}

/// A sprocket on the user's dynamic body turns faster than rapier's default
/// angular speed cap (π/4 per step: 47.12 rad/s at 60 Hz). The 16B drive's
/// 19-tooth driver at 1200 rpm turns the 38-tooth sprocket, mounted on a
/// flywheel held by a revolute joint, at 1200 × 19/38 = 600 rpm = 62.83
/// rad/s by the teeth. Without the cap lifted, rapier's step held the body
/// at 47.12 rad/s and the chain's sprocket swung between 41 and 54 rad/s
/// with link forces four times the running ones; the body as built by the
/// user (no `allow_fast_rotation`) now turns with its sprocket.
#[test]
fn a_mounted_sprocket_turns_faster_than_rapiers_angular_speed_cap() {
    let text = include_str!("../data/designation_16b.toml")
        .replace("speed_rpm = 100.0", "speed_rpm = 1200.0");
    let scene = Scene::from_toml(&text).expect("valid scene");
    let centre = scene.sprockets()[1].center_m;
    let mut world = PhysicsWorld::default();
    let at = Vector::new(centre[0], centre[1]);
    let frame = world
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(at));
    let wheel = world.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(at)
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 3.0, 0.02)),
    );
    world
        .impulse_joints
        .insert(frame, wheel, RevoluteJointBuilder::new(), true);
    let mut drive = ChainDrive::builder(&scene)
        .mount(1usize, wheel)
        .build(&mut world)
        .expect("drive");
    let by_teeth = 1200.0 * std::f64::consts::TAU / 60.0 * 19.0 / 38.0;
    let cap = std::f64::consts::FRAC_PI_4 * 60.0;
    assert!(by_teeth > 1.3 * cap, "{by_teeth} against {cap}");
    let (mut sprocket, mut body, mut n) = (0.0, 0.0, 0.0);
    for f in 0..60 {
        drive.step_world(&mut world, &(), &()).expect("frame");
        if f >= 30 {
            sprocket += drive.state().omega[1];
            body += world.bodies[wheel].angvel();
            n += 1.0;
        }
    }
    let (sprocket, body) = (sprocket / n, body / n);
    assert!(
        (sprocket - by_teeth).abs() < 0.01 * by_teeth,
        "sprocket {sprocket} rad/s against {by_teeth}"
    );
    assert!(
        (body - by_teeth).abs() < 0.01 * by_teeth,
        "body {body} rad/s against {by_teeth}"
    );
}
