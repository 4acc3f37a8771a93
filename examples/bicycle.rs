//! A bicycle's chain drive in a rapier world (`assets/bicycle.toml`): the
//! chainring sits on a crank body turned by the rider's pulsing torque, the
//! rear sprocket on the rear-wheel body, which feels rolling and air drag.
//! Writes `bicycle.mcap`.
//!
//! ```text
//! cargo run --release --example bicycle
//! ```

use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::from_toml(include_str!("../assets/bicycle.toml"))?;
    let mut world = PhysicsWorld::default();
    let axle = |x: f64, y: f64, inertia: f64| {
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(x, y))
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 1.0, inertia))
    };
    let crank = world.bodies.insert(axle(0.0, 0.0, 0.02));
    // The rear wheel, with the rider and bicycle's mass reduced to it: J = m R² ≈ 85 kg · 0.34² m².
    let wheel = world.bodies.insert(axle(-0.4143, 0.03, 10.0));
    let mut drive = ChainDrive::builder(&scene)
        .mount("chainring", crank)
        .mount("rear sprocket", wheel)
        .build(&mut world)?;
    let (chainring, rear) = (
        drive.sprocket("chainring")?,
        drive.sprocket("rear sprocket")?,
    );
    let mut recorder = Recorder::create(
        std::path::Path::new("bicycle.mcap"),
        &scene,
        &RecordOptions {
            channels: Channels::all(),
            scene_file: Some((
                "bicycle.toml".into(),
                include_str!("../assets/bicycle.toml").into(),
            )),
            rate_hz: 60.0,
        },
    )?;
    let frames = 600;
    for frame in 0..frames {
        let t = frame as f64 / 60.0;
        // The rider pushes twice per crank turn: 30 ± 25 N·m, clockwise (forward).
        let cadence = world.bodies[crank].angvel().abs().max(1.0);
        let angle = world.bodies[crank].rotation().angle();
        // Eased in over the first second.
        let rider = -(30.0 + 25.0 * (2.0 * angle).sin()) * (8.0 / cadence).min(1.0) * t.min(1.0);
        let body = &mut world.bodies[crank];
        body.reset_torques(false);
        body.add_torque(rider, true);
        // Rolling resistance and air drag on the wheel (speed v = ω R, R = 0.34 m).
        let w = world.bodies[wheel].angvel();
        let v = w * 0.34;
        let drag = (4.0 + 0.25 * v * v) * 0.34 * w.signum();
        let body = &mut world.bodies[wheel];
        body.reset_torques(false);
        body.add_torque(drag, true);
        drive.step_world(&mut world, &(), &())?;
        recorder.sample(&drive.sample());
        if frame % 120 == 119 {
            let tension = drive
                .sample()
                .forces
                .link_force
                .iter()
                .copied()
                .fold(f64::MIN, f64::max);
            println!(
                "t = {:4.1} s: cadence {:5.1} rpm, wheel {:5.1} km/h, chain tension up to {:5.0} N",
                t,
                drive.sprocket_speed(chainring).abs() * 60.0 / std::f64::consts::TAU,
                drive.sprocket_speed(rear).abs() * 0.34 * 3.6,
                tension
            );
        }
    }
    recorder.finish(RunEnd::Completed)?;
    println!("wrote bicycle.mcap");
    Ok(())
}
