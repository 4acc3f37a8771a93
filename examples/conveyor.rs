//! A conveyor in a rapier world: a two-sprocket chain conveyor
//! (`assets/conveyor.toml`) whose head sprocket sits on a motor body of the
//! user's world, driven by a speed-controlling motor torque, carrying boxes
//! dropped on its upper strand — light ones, and one of 5 kg (250 roller
//! masses). A fixed wear strip under the upper strand (a plain rapier
//! collider) supports the strand where the boxes ride. Writes
//! `conveyor.mcap` (the drive's channels).
//!
//! ```text
//! cargo run --release --example conveyor
//! ```

use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::from_toml(include_str!("../assets/conveyor.toml"))?;
    let mut world = PhysicsWorld::default(); // 60 Hz, gravity −9.81 m/s²
    // The motor: a body turning about a fixed axle, its inertia the scene's.
    let motor = world.bodies.insert(
        RigidBodyBuilder::dynamic()
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.05)),
    );
    let mut drive = ChainDrive::builder(&scene)
        .mount("head (motor)", motor)
        .build(&mut world)?;
    let head = drive.sprocket("head (motor)")?;
    let mut recorder = Recorder::create(
        std::path::Path::new("conveyor.mcap"),
        &scene,
        &RecordOptions {
            channels: Channels::all(),
            scene_file: Some((
                "conveyor.toml".into(),
                include_str!("../assets/conveyor.toml").into(),
            )),
            rate_hz: 60.0,
        },
    )?;
    let radius = drive.model().sprockets[head.index()].pitch_radius_m;
    // The wear strip: its top 0.5 mm below the lowest roller of the upper
    // strand (which sags under its own weight), low friction.
    let s = drive.state();
    let lowest = (0..s.rollers())
        .filter(|&i| s.y[i] > 0.0 && (0.15..0.85).contains(&s.x[i]))
        .map(|i| s.y[i])
        .fold(f64::INFINITY, f64::min);
    let strip_top = lowest - scene.chain().roller_radius_m - 0.0005;
    world.colliders.insert(
        ColliderBuilder::cuboid(0.35, 0.005)
            .translation(Vector::new(0.5, strip_top - 0.005))
            .friction(0.1),
    );
    let target_speed = std::f64::consts::TAU; // 60 rpm: the strand moves at ~0.51 m/s
    let mut boxes = Vec::new();
    let frames = 300;
    for frame in 0..frames {
        // The user's motor controller: torque towards the target speed, limited.
        let omega = world.bodies[motor].angvel();
        let torque = (2.0 * (target_speed - omega)).clamp(-20.0, 20.0);
        let body = &mut world.bodies[motor];
        body.reset_torques(false);
        body.add_torque(torque, true);
        // Drop a 0.1 kg box near the tail every second, a 5 kg one once.
        if frame % 60 == 10 {
            let density = if frame == 130 { 1000.0 } else { 20.0 };
            let b = world
                .bodies
                .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.9, radius + 0.035)));
            world.colliders.insert_with_parent(
                ColliderBuilder::cuboid(0.05, 0.025)
                    .density(density)
                    .friction(0.8),
                b,
                &mut world.bodies,
            );
            boxes.push(b);
        }
        drive.step_world(&mut world, &(), &())?;
        recorder.sample(&drive.sample());
    }
    recorder.finish(RunEnd::Completed)?;
    println!(
        "after {:.1} s: motor at {:.2} rad/s, chain speed {:.3} m/s",
        frames as f64 / 60.0,
        drive.sprocket_speed(head),
        drive.sprocket_speed(head) * radius
    );
    // Boxes push the rollers down, the strip pushes them up (and drags them).
    let sum = drive
        .body_forces()
        .iter()
        .fold([0.0, 0.0], |s, f| [s[0] + f[0], s[1] + f[1]]);
    println!(
        "rollers' mean force from your colliders over the last frame: ({:+.2}, {:+.2}) N",
        sum[0], sum[1]
    );
    for (i, b) in boxes.iter().enumerate() {
        let body = &world.bodies[*b];
        println!(
            "box {i} ({:.1} kg): x = {:+.3} m, y = {:+.3} m, vx = {:+.3} m/s",
            body.mass(),
            body.translation().x,
            body.translation().y,
            body.linvel().x
        );
    }
    println!("wrote conveyor.mcap");
    Ok(())
}
