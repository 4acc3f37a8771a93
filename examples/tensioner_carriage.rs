//! A sprung tensioner carriage in a rapier world: the conveyor of
//! `assets/conveyor.toml`, its head turned by a kinematic motor body at
//! 2 rad/s, its tail sprocket on a carriage free to slide along the chain's
//! line. A spring of 200 kN/m, preloaded to twice the chain's pretension,
//! holds the carriage out; the user sets the spring's force on the carriage
//! every frame the way rapier documents it (`reset_forces`, then
//! `add_force`), and the drive keeps it through its step.
//!
//! For carriages of several masses it prints how far each moved over 2 s at
//! 60 Hz, or where the coupling gave out. The carriage's translation is
//! integrated with the chain in the substeps; the spring force, set once per
//! frame, is what still acts explicitly (docs/architecture.md, "What holds,
//! what does not").
//!
//! ```text
//! cargo run --release --example tensioner_carriage
//! ```

use chaindrive::cosim::ChainDrive;
use chaindrive::scene::Scene;
use rapier2d_f64::prelude::*;

/// The tail's centre in the scene, m.
const TAIL_X_M: f64 = 1.016;
/// The spring's rate, N/m.
const SPRING_N_M: f64 = 2e5;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::from_toml(include_str!("../assets/conveyor.toml"))?;
    // Twice the pretension: the two strands' pull on the tail at rest.
    let preload_n = 2.0 * scene.chain().pretension_n;
    for mass_kg in [1.0, 2.0, 5.0, 20.0, 50.0, 200.0] {
        let mut world = PhysicsWorld::default(); // 60 Hz, gravity −9.81 m/s²
        let motor = world
            .bodies
            .insert(RigidBodyBuilder::kinematic_velocity_based());
        let carriage = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(TAIL_X_M, 0.0))
                .enabled_translations(true, false)
                .additional_mass_properties(MassProperties::new(Vector::ZERO, mass_kg, 0.01)),
        );
        let mut drive = ChainDrive::insert(
            &scene,
            &[Some(motor), Some(carriage)],
            &mut world.bodies,
            &mut world.colliders,
        )?;
        let mut worst = 0.0f64;
        let mut outcome = Ok(());
        for frame in 0..120 {
            let t = frame as f64 / 60.0;
            world.bodies[motor].set_angvel(2.0 * (t / 0.5).min(1.0), true);
            let x = world.bodies[carriage].translation().x;
            let body = &mut world.bodies[carriage];
            body.reset_forces(false);
            body.add_force(
                Vector::new(preload_n - SPRING_N_M * (x - TAIL_X_M), 0.0),
                true,
            );
            outcome = drive.step_world(&mut world, &(), &());
            if outcome.is_err() {
                break;
            }
            worst = worst.max((world.bodies[carriage].translation().x - TAIL_X_M).abs());
        }
        match outcome {
            Ok(()) => println!(
                "{mass_kg:5.0} kg carriage: held, largest excursion {:.3} mm over 2 s",
                worst * 1e3
            ),
            Err(e) => println!(
                "{mass_kg:5.0} kg carriage: gave out at t = {:.3} s after moving up to {:.3} mm: {}",
                drive.state().t_s,
                worst * 1e3,
                e.to_string()
                    .split("; possible causes")
                    .next()
                    .unwrap_or_default()
            ),
        }
    }
    Ok(())
}
