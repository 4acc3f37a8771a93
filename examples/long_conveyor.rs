//! A 10,000-roller conveyor in a rapier world stepped at 60 Hz: the paper's
//! chain (88.9 mm pitch, 889 m of it) round two sprockets, the real tooth
//! profile, driven at 12 rpm (the strand at 1.1 m/s) and substepped at
//! 50 µs, below the links' 57 µs stability limit (benches/README.md). Prints
//! the time to insert the drive, the wall time per frame and the real-time
//! factor, and where a frame's time goes.
//!
//! ```text
//! cargo run --release --example long_conveyor [FRAMES] [ROLLERS] [START]
//! ```
//!
//! The drive splits its rollers over two threads when it is large enough
//! (`[solver] threads`, default `"auto"`); `CHAINDRIVE_THREADS=1` in the
//! environment runs it on one thread for comparison. The rollers no
//! collider can reach are parked out of rapier's step
//! (`ChainDrive::set_parking`); `CHAINDRIVE_PARKING=0` keeps every roller
//! body in it. `START` is `moving` (the default: the drive starts at its
//! running speed, `ChainDriveBuilder::start_moving`) or the driver's ramp
//! from rest in seconds (`0.5`: the start-up wave then swings the tail for
//! seconds, benches/README.md); the last line compares the tail sprocket's
//! speed with the driver's times the teeth ratio.

use chaindrive::prelude::*;
use chaindrive::scene::DriveSpec;
use chaindrive::scene::{ProfileKind, StepFile, Threads, ThreadsFile};
use rapier2d_f64::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    // Frames to run (first argument), 2 s by default; rollers (second).
    let frames: u32 = args.next().and_then(|a| a.parse().ok()).unwrap_or(120);
    let rollers: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(10_000);
    // Started moving (third argument `moving`, the default), or the
    // driver's ramp from rest, s.
    let ramp_s: Option<f64> = args.next().and_then(|a| a.parse().ok());
    let mut spec = DriveSpec::new(rollers, 2)?;
    spec.name = format!("conveyor, {rollers} rollers");
    spec.profile = ProfileKind::Real;
    spec.speed_rpm = 12.0;
    spec.ramp_s = ramp_s.unwrap_or(0.5);
    spec.solver.dt_s = StepFile::Seconds(50e-6);
    // A chain this long has modes slower than any affordable relaxation:
    // 0.5 s leaves it within 1e-3 of the pretension.
    spec.equilibrium.max_relax_s = 0.5;
    if let Ok(t) = std::env::var("CHAINDRIVE_THREADS") {
        spec.solver.threads = ThreadsFile::from(t.parse::<Threads>()?);
    }
    let scene = spec.scene()?;

    let mut world = PhysicsWorld::default(); // 60 Hz
    let started = std::time::Instant::now();
    let mut builder = ChainDrive::builder(&scene);
    if ramp_s.is_none() {
        builder = builder.start_moving();
    }
    let mut drive = builder.build(&mut world)?;
    let insert_s = started.elapsed().as_secs_f64();
    // Rollers no collider of the world can reach leave rapier's step
    // (`ChainDrive::set_parking`); `CHAINDRIVE_PARKING=0` keeps them all in.
    drive.set_parking(std::env::var("CHAINDRIVE_PARKING").map_or(true, |v| v != "0"));
    println!(
        "{rollers} rollers, 2 sprockets, dt {} µs ({} substeps per 1/60 s frame), {} thread(s), \
         {}: inserted in {insert_s:.2} s",
        scene.solver().dt_s * 1e6,
        ((1.0 / 60.0) / scene.solver().dt_s).round(),
        scene.solver().threads.count(rollers),
        match ramp_s {
            Some(r) => format!("ramped from rest over {r} s"),
            None => "started moving".to_owned(),
        },
    );

    let started = std::time::Instant::now();
    // Each frame's wall time: on a shared machine the fastest frames show
    // what an idle one would do.
    let mut frame_ms = Vec::with_capacity(frames as usize);
    for _ in 0..frames {
        let frame_started = std::time::Instant::now();
        drive.step_world(&mut world, &(), &())?;
        frame_ms.push(frame_started.elapsed().as_secs_f64() * 1e3);
    }
    let wall = started.elapsed().as_secs_f64();
    frame_ms.sort_by(f64::total_cmp);
    let frame_s = wall / f64::from(frames);
    let steps = drive.state().t_s / scene.solver().dt_s;
    println!(
        "{frames} frames of 1/60 s: {:.2} ms wall per frame, real-time factor {:.2} \
         (simulated / wall)",
        frame_s * 1e3,
        (1.0 / 60.0) / frame_s
    );
    if let (Some(fastest), Some(median)) = (frame_ms.first(), frame_ms.get(frame_ms.len() / 2)) {
        println!("frames: fastest {fastest:.2} ms, median {median:.2} ms");
    }
    let t = drive.stage_times();
    let per = |s: f64| s / t.frames.max(1) as f64 * 1e3;
    println!(
        "per frame: chain substeps {:.2} ms ({:.2} ns per roller-step), rapier step {:.2} ms, \
         sync {:.2} ms, collider search {:.2} ms",
        per(t.substeps_s),
        t.substeps_s / (steps.max(1.0) * rollers as f64) * 1e9,
        per(t.world_s),
        per(t.sync_s),
        per(t.search_s),
    );
    println!(
        "parking {}: {} of {rollers} roller bodies parked",
        if drive.parking() { "on" } else { "off" },
        drive.parked_rollers()
    );
    // The tail sprocket turns with the driver when its speed is the
    // driver's times the teeth ratio.
    let ratio = f64::from(spec.teeth[0]) / f64::from(spec.teeth[1]);
    let (driver, tail) = (drive.sprocket(0)?, drive.sprocket(1)?);
    let (driver, tail) = (drive.sprocket_speed(driver), drive.sprocket_speed(tail));
    println!(
        "driver at {driver:.3} rad/s, tail sprocket at {tail:.3} rad/s \
         ({:.1} % of the driver's speed times the teeth ratio)",
        100.0 * tail / (driver * ratio)
    );
    Ok(())
}
