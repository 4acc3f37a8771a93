//! A conveyor's head sprocket on a motor shaft held by a rapier revolute
//! joint and driven by the joint's velocity motor (`assets/conveyor.toml`):
//! the shaft is a dynamic body of the user's world, jointed to a fixed
//! frame; the joint's motor brings it to 60 rpm against the chain's inertia
//! and the tail's load. The drive is put together with
//! [`ChainDriveBuilder`](chaindrive::cosim::ChainDriveBuilder), the head
//! mounted by its name. Prints the shaft's and the head sprocket's speeds
//! and the tail's load as it is raised mid-run.
//!
//! The joint holds the shaft's centre in rapier's step, once per frame; the
//! chain's substeps turn it under the joint motor's torque of the frame
//! before (read after rapier's step).
//!
//! ```text
//! cargo run --release --example motor_joint
//! ```

use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::from_toml(include_str!("../assets/conveyor.toml"))?;
    let mut world = PhysicsWorld::default(); // 60 Hz, gravity −9.81 m/s²
    let frame = world.bodies.insert(RigidBodyBuilder::fixed());
    // The shaft at the head's centre (0, 0), its inertia the scene's.
    let shaft = world.bodies.insert(
        RigidBodyBuilder::dynamic().additional_mass_properties(MassProperties::new(
            Vector::ZERO,
            2.0,
            0.05,
        )),
    );
    let target_rad_s = std::f64::consts::TAU; // 60 rpm
    let joint = RevoluteJointBuilder::new()
        .local_anchor1(Vector::ZERO)
        .local_anchor2(Vector::ZERO)
        .motor_velocity(target_rad_s, 5.0)
        .motor_max_force(20.0);
    world.impulse_joints.insert(frame, shaft, joint, true);
    let mut drive = ChainDrive::builder(&scene)
        .mount("head (motor)", shaft)
        .build(&mut world)?;
    let (head, tail) = (drive.sprocket("head (motor)")?, drive.sprocket("tail")?);
    println!("  t (s)   shaft (rad/s)   head (rad/s)   tail load (N·m)");
    let mut load = 0.0;
    for step in 1..=180 {
        if step == 120 {
            // Raised mid-run through the setter (the model is read-only).
            load = -2.0;
            drive.set_load_torque(tail, load)?;
        }
        drive.step_world(&mut world, &(), &())?;
        if step % 20 == 0 {
            println!(
                "{:7.2} {:15.3} {:14.3} {:17.1}",
                drive.state().t_s,
                world.bodies[shaft].angvel(),
                drive.sprocket_speed(head),
                load
            );
        }
    }
    let w = world.bodies[shaft].angvel();
    println!(
        "the shaft turns at {w:.3} rad/s, {:.1} % of the motor's target",
        100.0 * w / target_rad_s
    );
    Ok(())
}
