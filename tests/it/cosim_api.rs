//! The co-simulation's public API: the builder (mounts by name or index,
//! checked; a drive placed at a pose), read-only access and setters,
//! observers, recording a co-simulated run.

use chaindrive::cosim::{ChainDrive, CosimError, Coupling};
use chaindrive::scene::Scene;
use rapier2d_f64::prelude::*;

use super::cosim::conveyor;

/// The conveyor's tail centre in the scene, m.
const TAIL_X_M: f64 = 1.016;

fn data_scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let text = std::fs::read_to_string(&path).expect("scene file");
    Scene::from_toml(&text).expect("scene")
}

fn driven() -> Scene {
    conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0)
}

/// The field of an input error, or a panic naming what came instead.
fn input_field(r: Result<ChainDrive, CosimError>) -> (String, String) {
    match r {
        Err(CosimError::Input { field, message }) => (field, message),
        Err(e) => panic!("expected an input error, got {e}"),
        Ok(_) => panic!("expected an input error, got a drive"),
    }
}

#[test]
fn the_builder_names_an_unknown_sprocket_and_adds_nothing() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let body = w.bodies.insert(RigidBodyBuilder::dynamic());
    let (bodies, colliders) = (w.bodies.len(), w.colliders.len());
    let (field, message) = input_field(
        ChainDrive::builder(&scene)
            .mount("head", body)
            .build(&mut w),
    );
    assert_eq!(field, "mount(\"head\")");
    assert!(
        message.contains("\"driver\"") && message.contains("\"tail\""),
        "{message}"
    );
    assert_eq!((w.bodies.len(), w.colliders.len()), (bodies, colliders));
}

#[test]
fn the_builder_names_an_index_out_of_range() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let body = w.bodies.insert(RigidBodyBuilder::dynamic());
    let (field, message) = input_field(ChainDrive::builder(&scene).mount(2, body).build(&mut w));
    assert_eq!(field, "mount(2)");
    assert!(message.contains("0 to 1"), "{message}");
}

#[test]
fn the_builder_names_a_sprocket_mounted_twice() {
    // The tail by name, then by index, on two bodies at its centre.
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let at_tail = || RigidBodyBuilder::dynamic().translation(Vector::new(TAIL_X_M, 0.0));
    let (a, b) = (w.bodies.insert(at_tail()), w.bodies.insert(at_tail()));
    let (field, message) = input_field(
        ChainDrive::builder(&scene)
            .mount("tail", a)
            .mount(1, b)
            .build(&mut w),
    );
    assert_eq!(field, "mount(1)");
    assert!(message.contains("mounted twice"), "{message}");
}

#[test]
fn the_builder_names_a_coupling_it_cannot_use() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let coupling = Coupling {
        search_speed_m_s: f64::NAN,
        ..Coupling::new(scene.contact())
    };
    let (field, _) = input_field(ChainDrive::builder(&scene).coupling(coupling).build(&mut w));
    assert_eq!(field, "coupling.search_speed_m_s");
}

#[test]
fn the_builder_keeps_the_coupling_it_was_given() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let coupling = Coupling {
        carry_dynamic: false,
        ..Coupling::new(scene.contact())
    };
    let drive = ChainDrive::builder(&scene)
        .coupling(coupling)
        .build(&mut w)
        .expect("drive");
    assert_eq!(*drive.coupling(), coupling);
}

#[test]
fn a_drive_placed_at_a_pose_has_its_rollers_where_the_pose_puts_them() {
    // A drive without gravity is the same drive in any frame: placed at the
    // pose X (turned 90°, moved by (2, 1) m), its tail on the user's body at
    // X · (1.016, 0), each roller body sits at X · p where p is that roller
    // in the same drive inserted at the scene's coordinates, and stays there
    // through 30 frames at 60 Hz (the drive's steps are the same in both
    // frames but for rounding; 1 µm allows for its growth).
    let scene = data_scene("cosim_conveyor_flat.toml");
    let pose = Pose::new(Vector::new(2.0, 1.0), std::f64::consts::FRAC_PI_2);
    let tail_at = pose.transform_point(Vector::new(TAIL_X_M, 0.0));
    let flat = |w: &mut PhysicsWorld, at: Vector| {
        w.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(at)
                .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01))
                .lock_translations(),
        )
    };
    let (mut here, mut there) = (PhysicsWorld::default(), PhysicsWorld::default());
    here.gravity = Vector::ZERO;
    there.gravity = Vector::ZERO;
    let tail_here = flat(&mut here, Vector::new(TAIL_X_M, 0.0));
    let tail_there = flat(&mut there, tail_at);
    let mut reference = ChainDrive::builder(&scene)
        .mount("tail", tail_here)
        .build(&mut here)
        .expect("drive");
    let mut placed = ChainDrive::builder(&scene)
        .mount("tail", tail_there)
        .insert_at(pose)
        .build(&mut there)
        .expect("drive at the pose");
    let worst =
        |reference: &ChainDrive, placed: &ChainDrive, here: &PhysicsWorld, there: &PhysicsWorld| {
            reference
                .roller_bodies()
                .iter()
                .zip(placed.roller_bodies())
                .map(|(&a, &b)| {
                    let want = pose.transform_point(here.bodies[a].translation());
                    (there.bodies[b].translation() - want).length()
                })
                .fold(0.0f64, f64::max)
        };
    assert!(worst(&reference, &placed, &here, &there) < 1e-9);
    let c = placed.model().sprockets[1].center_m;
    assert!((Vector::new(c[0], c[1]) - tail_at).length() < 1e-12);
    let start = here.bodies[reference.roller_bodies()[0]].translation();
    for _ in 0..30 {
        reference.step_world(&mut here, &(), &()).expect("frame");
        placed.step_world(&mut there, &(), &()).expect("frame");
    }
    let moved = (here.bodies[reference.roller_bodies()[0]].translation() - start).length();
    assert!(moved > 0.05, "the chain moved {moved} m");
    let after = worst(&reference, &placed, &here, &there);
    assert!(after < 1e-6, "{after} m from the posed reference");
}

#[test]
fn a_mount_away_from_its_posed_centre_is_an_error() {
    // The tail's body at the scene's (1.016, 0) while the pose moves the
    // tail to (1.016, 0.5).
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let body = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(TAIL_X_M, 0.0)));
    let (field, message) = input_field(
        ChainDrive::builder(&scene)
            .mount("tail", body)
            .insert_at(Pose::translation(0.0, 0.5))
            .build(&mut w),
    );
    assert_eq!(field, "sprockets[1].center_m");
    assert!(message.contains("0.5"), "{message}");
}
