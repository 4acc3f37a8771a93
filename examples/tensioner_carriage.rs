//! A sprung tensioner carriage in a rapier world: the conveyor of
//! `assets/conveyor.toml`, its head turned by a kinematic motor body at
//! 2 rad/s, its tail sprocket on a carriage free to slide along the chain's
//! line. A spring of 200 kN/m, preloaded to twice the chain's pretension,
//! holds the carriage out. For carriages of 1 to 200 kg it prints how far
//! each moved over 2 s at 60 Hz, or where the coupling gave out, with the
//! spring attached three ways:
//!
//! - **held force**: the user sets the spring's force on the carriage every
//!   frame the way rapier documents it (`reset_forces`, then `add_force`);
//!   the drive keeps it through its step, but it is read at the frame's
//!   start and held over the frame while the carriage moves with the chain;
//! - **force law**: the spring given to the drive
//!   (`ChainDrive::set_mount_force` with a `MountSpring`), evaluated in
//!   every substep where the carriage is — the way to attach a spring;
//! - **prismatic**: the sprocket on a hub turning on a revolute joint to a
//!   carriage that slides on a prismatic joint, the spring being the joint's
//!   position motor, imitated in the substeps.
//!
//! A second table runs the 1 kg carriage at preloads around 1000 N: the
//! held force holds or gives out from one newton to the next, the force law
//! holds at every one (docs/architecture.md, "What holds, what does not").
//!
//! ```text
//! cargo run --release --example tensioner_carriage
//! ```

use chaindrive::cosim::MountSpring;
use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

/// The tail's centre in the scene, m.
const TAIL_X_M: f64 = 1.016;
/// The spring's rate, N/m.
const SPRING_N_M: f64 = 2e5;

/// How the spring is attached.
#[derive(Clone, Copy, PartialEq)]
enum Spring {
    Held,
    Law,
    Prismatic,
}

fn run(
    scene: &Scene,
    mass_kg: f64,
    preload_n: f64,
    how: Spring,
) -> Result<String, Box<dyn std::error::Error>> {
    let mut world = PhysicsWorld::default(); // 60 Hz, gravity −9.81 m/s²
    let motor = world
        .bodies
        .insert(RigidBodyBuilder::kinematic_velocity_based());
    let carriage = world.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(TAIL_X_M, 0.0))
            .enabled_translations(true, how == Spring::Prismatic)
            .additional_mass_properties(MassProperties::new(Vector::ZERO, mass_kg, 0.01)),
    );
    let mount = if how == Spring::Prismatic {
        let ground = world.bodies.insert(RigidBodyBuilder::fixed());
        let hub = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(TAIL_X_M, 0.0))
                .additional_mass_properties(MassProperties::new(Vector::ZERO, 0.1, 0.01)),
        );
        let slide = PrismaticJointBuilder::new(Vector::X)
            .local_anchor1(Vector::new(TAIL_X_M, 0.0))
            .motor_position(preload_n / SPRING_N_M, SPRING_N_M, 0.0)
            .motor_model(MotorModel::ForceBased);
        world.impulse_joints.insert(ground, carriage, slide, true);
        world
            .impulse_joints
            .insert(carriage, hub, RevoluteJointBuilder::new(), true);
        hub
    } else {
        carriage
    };
    let mut drive = ChainDrive::insert(
        scene,
        &[Some(motor), Some(mount)],
        &mut world.bodies,
        &mut world.colliders,
    )?;
    if how == Spring::Law {
        drive.set_mount_force(
            drive.sprocket("tail")?,
            MountSpring {
                anchor_m: Vector::new(TAIL_X_M, 0.0),
                axis: Vector::X,
                stiffness_n_m: SPRING_N_M,
                damping_n_s_m: 0.0,
                preload_n,
            },
        )?;
    }
    let mut worst = 0.0f64;
    for frame in 0..120 {
        let t = frame as f64 / 60.0;
        world.bodies[motor].set_angvel(2.0 * (t / 0.5).min(1.0), true);
        if how == Spring::Held {
            let x = world.bodies[carriage].translation().x;
            let body = &mut world.bodies[carriage];
            body.reset_forces(false);
            body.add_force(
                Vector::new(preload_n - SPRING_N_M * (x - TAIL_X_M), 0.0),
                true,
            );
        }
        if let Err(e) = drive.step_world(&mut world, &(), &()) {
            let e = e.to_string();
            let what = e.split("; possible causes").next().unwrap_or_default();
            let what = what.split(" (").next().unwrap_or_default();
            return Ok(format!(
                "gave out at {:.3} s after {:.2} mm ({what})",
                drive.state().t_s,
                worst * 1e3,
            ));
        }
        worst = worst.max((world.bodies[carriage].translation().x - TAIL_X_M).abs());
    }
    Ok(format!("held, {:.3} mm", worst * 1e3))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::from_toml(include_str!("../assets/conveyor.toml"))?;
    // Twice the pretension: the two strands' pull on the tail at rest.
    let preload_n = 2.0 * scene.chain().pretension_n;
    println!("largest carriage excursion over 2 s at 60 Hz, preload {preload_n} N");
    println!("| carriage | held force | force law (substeps) | prismatic + position motor |");
    println!("|---|---|---|---|");
    for mass_kg in [1.0, 2.0, 5.0, 20.0, 50.0, 200.0] {
        println!(
            "| {mass_kg} kg | {} | {} | {} |",
            run(&scene, mass_kg, preload_n, Spring::Held)?,
            run(&scene, mass_kg, preload_n, Spring::Law)?,
            run(&scene, mass_kg, preload_n, Spring::Prismatic)?,
        );
    }
    // The held force's margin: the 1 kg carriage at preloads around it.
    println!("\nthe 1 kg carriage at other preloads");
    println!("| preload | held force | force law (substeps) |");
    println!("|---|---|---|");
    for preload_n in [900.0, 990.0, 999.0, 1000.0, 1001.0, 1010.0, 1100.0] {
        println!(
            "| {preload_n} N | {} | {} |",
            run(&scene, 1.0, preload_n, Spring::Held)?,
            run(&scene, 1.0, preload_n, Spring::Law)?,
        );
    }
    Ok(())
}
