//! Inserting a drive into a rapier world: the cost of the static
//! equilibrium for the examples' drives (a measurement, printed, not
//! asserted), and a settled drive inserted again without settling anew.

use std::time::Instant;

use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

/// A body turning about a fixed axle at `(x, y)`, of rotational inertia
/// `inertia_kg_m2`.
fn axle(x: f64, y: f64, inertia_kg_m2: f64) -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic()
        .translation(Vector::new(x, y))
        .lock_translations()
        .additional_mass_properties(MassProperties::new(Vector::ZERO, 1.0, inertia_kg_m2))
}

fn asset(name: &str) -> Scene {
    let path = format!("{}/assets/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("asset");
    Scene::from_toml(&text).expect("valid asset")
}

/// The drives the examples and the co-simulation tests insert: a name, the
/// scene, and the bodies to mount (sprocket index, body) in a fresh world.
type Case = (&'static str, Scene, Vec<(usize, RigidBodyBuilder)>);

fn cases() -> Vec<Case> {
    let conveyor = asset("conveyor.toml");
    vec![
        (
            "conveyor, head on a motor body (examples conveyor, motor_joint)",
            conveyor.clone(),
            vec![(0, axle(0.0, 0.0, 0.05))],
        ),
        (
            "conveyor, head kinematic, tail on a carriage (example tensioner_carriage)",
            conveyor.clone(),
            vec![
                (0, RigidBodyBuilder::kinematic_velocity_based()),
                (1, axle(1.016, 0.0, 0.01)),
            ],
        ),
        ("conveyor, no mounts", conveyor, Vec::new()),
        (
            "bicycle, crank and wheel on bodies (example bicycle)",
            asset("bicycle.toml"),
            vec![(0, axle(0.0, 0.0, 0.02)), (1, axle(-0.4143, 0.03, 10.0))],
        ),
        ("paper drive, no mounts (example paper_in_scene)", Scene::l60mc(), Vec::new()),
    ]
}

/// Inserts `case` into a fresh world; the seconds it took.
fn insert(case: &Case) -> (ChainDrive, PhysicsWorld, f64) {
    let (_, scene, mounts) = case;
    let mut world = PhysicsWorld::default();
    let mut builder = ChainDrive::builder(scene);
    for (k, body) in mounts {
        let h = world.bodies.insert(body.clone());
        builder = builder.mount(*k, h);
    }
    let started = Instant::now();
    let drive = builder.build(&mut world).expect("inserted");
    (drive, world, started.elapsed().as_secs_f64())
}

#[test]
#[ignore = "a measurement: cargo test --release --test it insertion_times -- --ignored --nocapture"]
fn insertion_times() {
    for case in cases() {
        let (drive, _, seconds) = insert(&case);
        let eq = drive.equilibrium();
        println!(
            "{:<75} {seconds:>7.3} s  tension {:>8.2} N  residual {:.1e}",
            case.0, eq.tension_n, eq.force_residual
        );
    }
}
