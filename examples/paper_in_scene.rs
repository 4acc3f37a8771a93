//! The paper's drive placed inside a larger rapier scene stepped at 60 Hz:
//! the drive substeps itself at its own 10 µs inside every frame while balls
//! bounce on a floor beside it (stock rapier contacts, untouched). Prints the
//! wall time per rendered frame; writes `paper_in_scene.mcap`.
//!
//! ```text
//! cargo run --release --example paper_in_scene [FRAMES]
//! ```

use chaindrive::prelude::*;
use chaindrive::scene::L60MC_TOML;
use rapier2d_f64::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::l60mc();
    let mut world = PhysicsWorld::default();
    let floor = world
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(3.0, -1.2)));
    world
        .colliders
        .insert_with_parent(ColliderBuilder::cuboid(1.5, 0.1), floor, &mut world.bodies);
    for k in 0..5 {
        let ball = world.bodies.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(2.0 + 0.4 * f64::from(k), 1.0)),
        );
        world.colliders.insert_with_parent(
            ColliderBuilder::ball(0.08).restitution(0.7),
            ball,
            &mut world.bodies,
        );
    }
    let mut drive = ChainDrive::insert(&scene, &[], &mut world.bodies, &mut world.colliders)?;
    let mut recorder = Recorder::create(
        std::path::Path::new("paper_in_scene.mcap"),
        &scene,
        &RecordOptions {
            channels: Channels::all(),
            scene_file: Some(("l60mc.toml".into(), L60MC_TOML.into())),
            rate_hz: 60.0,
        },
    )?;
    // Frames to run (first argument), 3 s by default.
    let frames: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(180);
    let started = std::time::Instant::now();
    for _ in 0..frames {
        drive.step_world(&mut world, &(), &())?;
        recorder.sample(&drive.sample());
    }
    let wall = started.elapsed().as_secs_f64();
    recorder.finish(RunEnd::Completed)?;
    let frame_s = wall / f64::from(frames);
    println!(
        "{frames} frames of 1/60 s: {:.2} ms wall per frame, {:.1}x faster than real time",
        frame_s * 1e3,
        (1.0 / 60.0) / frame_s
    );
    let t = drive.stage_times();
    let per = |s: f64| s / t.frames.max(1) as f64 * 1e3;
    println!(
        "per frame: chain substeps {:.3} ms ({:.2} µs per substep), rapier step {:.3} ms, \
         sync {:.3} ms, collider search {:.3} ms",
        per(t.substeps_s),
        t.substeps_s / (drive.state().t_s / scene.solver().dt_s).max(1.0) * 1e6,
        per(t.world_s),
        per(t.sync_s),
        per(t.search_s),
    );
    println!(
        "driver at {:.3} rad/s; wrote paper_in_scene.mcap",
        drive.sprocket_speed(drive.sprocket("crankshaft")?)
    );
    Ok(())
}
