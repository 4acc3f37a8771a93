//! Two conveyors in one rapier world, end to end, stepped together as a
//! [`DriveSet`]: a 250 mm box laid on the first crosses onto the second.
//! Each conveyor's tail sprocket sits on a motor body of the user's world
//! pushing it with 1 N·m. Shows what composes: while the box rests on both
//! chains at the gap, both hold it in the same substeps (their forces on it
//! summed); it keeps its gravity; neither drive takes the other's motor for
//! a box to carry. Prints the box's position and speed every half second,
//! the motors' torques, and the wall time per frame.
//!
//! ```text
//! cargo run --release --example transfer [box length, m (0.25)] [seconds (3)]
//! ```

use chaindrive::cosim::DriveSet;
use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

/// A conveyor of two 20-tooth sprockets, 1" pitch, 100 rollers, its driver
/// at `x0` on the x axis turning at 60 rpm; its upper strand runs towards −x.
fn conveyor(x0: f64) -> Result<Scene, SceneError> {
    let tail = x0 + 1.016;
    Scene::from_toml(&format!(
        r#"
name = "conveyor at {x0} m"
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
center_m = [{x0}, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
role = "driver"
speed_rpm = 60.0
ramp_s = 0.5
[[sprockets]]
name = "tail"
center_m = [{tail}, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
role = "free"
[solver]
dt_s = 1e-5
"#
    ))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let length_m: f64 = args.next().map_or(Ok(0.25), |a| a.parse())?;
    let seconds: f64 = args.next().map_or(Ok(3.0), |a| a.parse())?;
    if !(length_m > 0.0 && length_m.is_finite() && seconds >= 0.0 && seconds.is_finite()) {
        return Err(
            format!("box length {length_m} m, {seconds} s: both positive and finite").into(),
        );
    }
    let frames = (seconds * 60.0).round() as usize;
    let mut world = PhysicsWorld::default(); // 60 Hz, gravity −9.81 m/s²
    // Conveyor A from x = 0 to 1.016 m, B from −1.196 to −0.18 m: their
    // wrapped rollers 10 mm apart.
    let mut set = DriveSet::new();
    let mut motors = Vec::new();
    for x0 in [0.0, -1.196] {
        let motor = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x0 + 1.016, 0.0))
                .lock_translations()
                .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
        );
        world.bodies[motor].add_torque(1.0, true);
        let drive = ChainDrive::insert(
            &conveyor(x0)?,
            &[None, Some(motor)],
            &mut world.bodies,
            &mut world.colliders,
        )?;
        set.push(drive);
        motors.push(motor);
    }
    // A 0.2 kg box, 250 × 50 mm by default, on A's upper strand (roller tops
    // at 84.2 mm). It bridges the 180 mm between the strands' tops; a box
    // shorter than that drops into the valley between the two wraps and is
    // spun there a while.
    let top = 0.0812 * (std::f64::consts::PI / 20.0).cos() + 0.00397;
    let bx = world
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.5, top + 0.0251)));
    world.colliders.insert_with_parent(
        ColliderBuilder::cuboid(length_m / 2.0, 0.025)
            .density(0.2 / 0.05 / length_m)
            .friction(0.8),
        bx,
        &mut world.bodies,
    );
    println!("   t (s)   box x (m)   box y (m)   vx (m/s)   gravity scale   motor torques (N·m)");
    let started = std::time::Instant::now();
    for frame in 1..=frames {
        set.step_world(&mut world, &(), &())?;
        if frame % 30 == 0 {
            let b = &world.bodies[bx];
            println!(
                "{:8.2} {:11.3} {:11.4} {:10.3} {:15} {:>10} {}",
                frame as f64 / 60.0,
                b.translation().x,
                b.translation().y,
                b.linvel().x,
                b.gravity_scale(),
                world.bodies[motors[0]].user_torque(),
                world.bodies[motors[1]].user_torque(),
            );
        }
    }
    let ms = started.elapsed().as_secs_f64() * 1e3 / frames.max(1) as f64;
    println!("{ms:.2} ms of wall time per frame (two drives, 60 Hz)");
    Ok(())
}
