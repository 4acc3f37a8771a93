//! A pile of boxes on a conveyor: three 0.2 kg boxes side by side on the
//! upper strand, two on them, one on top, carried along at chain speed
//! (60 rpm on a 20-tooth sprocket, 0.51 m/s). The boxes' contacts with the
//! rollers and with each other are all resolved in the chain's substeps, so
//! the pile rides as one. Prints each box's speed and its drift from its
//! place in the pile every half second.
//!
//! ```text
//! cargo run --release --example box_pile
//! ```

use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 200 rollers, sprockets 90 pitches (2.286 m) apart, the driver at 60 rpm.
    let scene = Scene::from_toml(
        r#"
name = "long conveyor"
gravity_m_s2 = [0.0, -9.81]
[chain]
rollers = 200
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
role = "driver"
speed_rpm = 60.0
ramp_s = 0.5
[[sprockets]]
name = "tail"
center_m = [2.286, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
role = "free"
[solver]
dt_s = 1e-5
"#,
    )?;
    let mut world = PhysicsWorld::default(); // 60 Hz, gravity −9.81 m/s²
    let mut drive = ChainDrive::insert(&scene, &[], &mut world.bodies, &mut world.colliders)?;
    // Roller tops on the upper strand: R cos(π/20) + r, R the pitch radius.
    let top = 0.0812 * (std::f64::consts::PI / 20.0).cos() + 0.00397;
    let (hx, hy) = (0.05, 0.025);
    let mut boxes = Vec::new();
    for (row, count) in [3usize, 2, 1].into_iter().enumerate() {
        for k in 0..count {
            let x = 1.9 + (k as f64 - (count - 1) as f64 / 2.0) * (2.0 * hx + 1e-3);
            let y = top + hy + 1e-4 + row as f64 * (2.0 * hy + 1e-4);
            let b = world
                .bodies
                .insert(RigidBodyBuilder::dynamic().translation(Vector::new(x, y)));
            world.colliders.insert_with_parent(
                ColliderBuilder::cuboid(hx, hy)
                    .density(0.2 / (4.0 * hx * hy))
                    .friction(0.8),
                b,
                &mut world.bodies,
            );
            boxes.push(b);
        }
    }
    let start: Vec<Vector> = boxes
        .iter()
        .map(|&b| world.bodies[b].translation())
        .collect();
    println!("   t (s)   box speeds (m/s), bottom row first   largest drift in the pile (mm)");
    for frame in 1..=180 {
        drive.step_world(&mut world, &(), &())?;
        if frame % 30 == 0 {
            let base = world.bodies[boxes[0]].translation() - start[0];
            let drift = boxes
                .iter()
                .zip(&start)
                .map(|(&b, s)| (world.bodies[b].translation() - *s - base).length())
                .fold(0.0, f64::max);
            let speeds: Vec<String> = boxes
                .iter()
                .map(|&b| format!("{:6.3}", world.bodies[b].linvel().x))
                .collect();
            println!(
                "{:8.2}   {}   {:8.2}",
                frame as f64 / 60.0,
                speeds.join(" "),
                drift * 1e3
            );
        }
    }
    Ok(())
}
