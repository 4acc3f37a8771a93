//! The co-simulation's public API: the builder (mounts by name or index,
//! checked; a drive placed at a pose), read-only access and setters,
//! observers, recording a co-simulated run.

use super::cosim_tests::conveyor;
use crate::cosim::{ChainDrive, CosimError, Coupling};
use crate::scene::Scene;
use rapier2d_f64::prelude::*;
use std::f64::consts::{PI, TAU};

/// The conveyor's tail centre in the scene, m.
const TAIL_X_M: f64 = 1.016;

fn data_scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let text = std::fs::read_to_string(&path).expect("scene file");
    Scene::from_toml(&text).expect("scene")
}

fn driven() -> Scene {
    conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0)
}

/// The field of an input error, or a panic naming what came instead.
fn input_field(r: Result<ChainDrive, CosimError>) -> (String, String) {
    match r {
        Err(CosimError::Input { field, message }) => (field, message),
        Err(e) => panic!("expected an input error, got {e}"),
        Ok(_) => panic!("expected an input error, got a drive"),
    }
}

#[test]
fn the_builder_names_an_unknown_sprocket_and_adds_nothing() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let body = w.bodies.insert(RigidBodyBuilder::dynamic());
    let (bodies, colliders) = (w.bodies.len(), w.colliders.len());
    let (field, message) = input_field(
        ChainDrive::builder(&scene)
            .mount("head", body)
            .build(&mut w),
    );
    assert_eq!(field, "mount(\"head\")");
    assert!(
        message.contains("\"driver\"") && message.contains("\"tail\""),
        "{message}"
    );
    assert_eq!((w.bodies.len(), w.colliders.len()), (bodies, colliders));
}

#[test]
fn the_builder_names_an_index_out_of_range() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let body = w.bodies.insert(RigidBodyBuilder::dynamic());
    let (field, message) = input_field(ChainDrive::builder(&scene).mount(2, body).build(&mut w));
    assert_eq!(field, "mount(2)");
    assert!(message.contains("0 to 1"), "{message}");
}

#[test]
fn the_builder_names_a_sprocket_mounted_twice() {
    // The tail by name, then by index, on two bodies at its centre.
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let at_tail = || RigidBodyBuilder::dynamic().translation(Vector::new(TAIL_X_M, 0.0));
    let (a, b) = (w.bodies.insert(at_tail()), w.bodies.insert(at_tail()));
    let (field, message) = input_field(
        ChainDrive::builder(&scene)
            .mount("tail", a)
            .mount(1, b)
            .build(&mut w),
    );
    assert_eq!(field, "mount(1)");
    assert!(message.contains("mounted twice"), "{message}");
}

#[test]
fn the_builder_names_a_coupling_it_cannot_use() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let coupling = Coupling {
        search_speed_m_s: f64::NAN,
        ..Coupling::new(scene.contact())
    };
    let (field, _) = input_field(ChainDrive::builder(&scene).coupling(coupling).build(&mut w));
    assert_eq!(field, "coupling.search_speed_m_s");
}

#[test]
fn the_builder_keeps_the_coupling_it_was_given() {
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let coupling = Coupling {
        carry_dynamic: false,
        ..Coupling::new(scene.contact())
    };
    let drive = ChainDrive::builder(&scene)
        .coupling(coupling)
        .build(&mut w)
        .expect("drive");
    assert_eq!(*drive.coupling(), coupling);
}

#[test]
fn a_drive_placed_at_a_pose_has_its_rollers_where_the_pose_puts_them() {
    // A drive without gravity is the same drive in any frame: placed at the
    // pose X (turned 90°, moved by (2, 1) m), its tail on the user's body at
    // X · (1.016, 0), each roller body sits at X · p where p is that roller
    // in the same drive inserted at the scene's coordinates, and stays there
    // through 30 frames at 60 Hz (the drive's steps are the same in both
    // frames but for rounding; 1 µm allows for its growth).
    let scene = data_scene("cosim_conveyor_flat.toml");
    let pose = Pose::new(Vector::new(2.0, 1.0), std::f64::consts::FRAC_PI_2);
    let tail_at = pose.transform_point(Vector::new(TAIL_X_M, 0.0));
    let flat = |w: &mut PhysicsWorld, at: Vector| {
        w.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(at)
                .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01))
                .lock_translations(),
        )
    };
    let (mut here, mut there) = (PhysicsWorld::default(), PhysicsWorld::default());
    here.gravity = Vector::ZERO;
    there.gravity = Vector::ZERO;
    let tail_here = flat(&mut here, Vector::new(TAIL_X_M, 0.0));
    let tail_there = flat(&mut there, tail_at);
    let mut reference = ChainDrive::builder(&scene)
        .mount("tail", tail_here)
        .build(&mut here)
        .expect("drive");
    let mut placed = ChainDrive::builder(&scene)
        .mount("tail", tail_there)
        .insert_at(pose)
        .build(&mut there)
        .expect("drive at the pose");
    let worst =
        |reference: &ChainDrive, placed: &ChainDrive, here: &PhysicsWorld, there: &PhysicsWorld| {
            reference
                .roller_bodies()
                .iter()
                .zip(placed.roller_bodies())
                .map(|(&a, &b)| {
                    let want = pose.transform_point(here.bodies[a].translation());
                    (there.bodies[b].translation() - want).length()
                })
                .fold(0.0f64, f64::max)
        };
    assert!(worst(&reference, &placed, &here, &there) < 1e-9);
    let c = placed.model().sprockets[1].center_m;
    assert!((Vector::new(c[0], c[1]) - tail_at).length() < 1e-12);
    let start = here.bodies[reference.roller_bodies()[0]].translation();
    for _ in 0..30 {
        reference.step_world(&mut here, &(), &()).expect("frame");
        placed.step_world(&mut there, &(), &()).expect("frame");
    }
    let moved = (here.bodies[reference.roller_bodies()[0]].translation() - start).length();
    assert!(moved > 0.05, "the chain moved {moved} m");
    let after = worst(&reference, &placed, &here, &there);
    assert!(after < 1e-6, "{after} m from the posed reference");
}

#[test]
fn a_mount_away_from_its_posed_centre_is_an_error() {
    // The tail's body at the scene's (1.016, 0) while the pose moves the
    // tail to (1.016, 0.5).
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let body = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(TAIL_X_M, 0.0)));
    let (field, message) = input_field(
        ChainDrive::builder(&scene)
            .mount("tail", body)
            .insert_at(Pose::translation(0.0, 0.5))
            .build(&mut w),
    );
    assert_eq!(field, "sprockets[1].center_m");
    assert!(message.contains("0.5"), "{message}");
}

#[cfg(feature = "record")]
#[test]
fn a_recorded_co_simulation_states_its_real_duration_and_draws_a_moving_mount_where_it_is() {
    // The conveyor (scene duration 5 s unless its file says otherwise) with
    // its tail on a kinematic arm swinging ±3 mm across the chain at 2 Hz,
    // run 1 s at 60 Hz and recorded through a Fanout with a second observer
    // (a frame counter). Read back: the metadata gives the run's 1 s and
    // the 1/60 s frame step, not the scene's duration; the tail's recorded
    // centre is the arm's position at each frame (the chain's clock ends a
    // frame within one 10 µs substep of the world's, at most 0.04 m/s away:
    // under 1 µm). Before, every frame drew the tail at its first position.
    use crate::record::read::read_recording_bytes;
    use crate::record::{RecordOptions, Recorder, RunEnd};
    use crate::sim::{Fanout, Observer, Sample};
    use std::f64::consts::TAU;
    const AMPLITUDE_M: f64 = 0.003;
    const HZ: f64 = 2.0;
    const FRAMES: usize = 60;
    struct Count(usize);
    impl Observer for Count {
        fn sample(&mut self, _: &Sample<'_>) {
            self.0 += 1;
        }
    }
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 12.0\nramp_s = 0.2", 0.0);
    assert!((scene.solver().duration_s - 1.0).abs() > 0.5);
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    };
    let arm = w.bodies.insert(
        RigidBodyBuilder::kinematic_velocity_based().translation(Vector::new(TAIL_X_M, 0.0)),
    );
    let mut drive = ChainDrive::builder(&scene)
        .mount("tail", arm)
        .build(&mut w)
        .expect("drive");
    let dt = w.integration_parameters.dt;
    let options = RecordOptions {
        scene_file: Some((
            "conveyor.toml".to_owned(),
            scene.source_toml().expect("scene text").as_bytes().to_vec(),
        )),
        rate_hz: 1.0 / dt,
        ..RecordOptions::default()
    };
    let mut recorder = Recorder::co_simulated(
        std::io::Cursor::new(Vec::new()),
        drive.scene(),
        &options,
        dt,
    )
    .expect("recorder");
    let mut count = Count(0);
    let mut arm_y = vec![0.0];
    {
        let mut observers = Fanout::new().with(&mut recorder).with(&mut count);
        drive.observe(&mut observers);
        for frame in 0..FRAMES {
            let t = frame as f64 * dt;
            let v = AMPLITUDE_M * TAU * HZ * (TAU * HZ * t).cos();
            w.bodies[arm].set_linvel(Vector::new(0.0, v), true);
            let law = drive.model().sprockets[0].speed_law.expect("driver");
            w.bodies[arm].set_angvel(0.5 * (law.speed_at(t) + law.speed_at(t + dt)), true);
            drive
                .step_world_observed(&mut w, &(), &(), &mut observers)
                .expect("frame");
            arm_y.push(w.bodies[arm].translation().y);
        }
    }
    assert_eq!(count.0, FRAMES + 1);
    let bytes = recorder
        .finish(RunEnd::Completed)
        .expect("finish")
        .into_inner();
    let rec = read_recording_bytes("cosim.mcap", &bytes).expect("read back");
    let number = |k: &str| -> f64 { rec.metadata[k].parse().expect(k) };
    assert!(
        (number("duration_s") - 1.0).abs() < 2e-5,
        "{:?}",
        rec.metadata
    );
    assert!((number("frame_dt_s") - dt).abs() < 1e-15);
    assert_eq!(rec.samples.len(), FRAMES + 1);
    let mut swing = 0.0f64;
    for (s, want) in rec.samples.iter().zip(&arm_y) {
        let c = s.sprocket_centers_m[1];
        assert!(
            (c[1] - want).abs() < 1e-6,
            "at {} s: {} m, arm at {want} m",
            s.t_s,
            c[1]
        );
        assert!((c[0] - TAIL_X_M).abs() < 1e-9);
        swing = swing.max(c[1].abs());
    }
    assert!(swing > 0.8 * AMPLITUDE_M, "recorded swing {swing} m");
}

#[test]
fn a_new_governor_target_is_a_speed_step_the_governor_follows_critically_damped() {
    // The torque-driven 20T/40T drive (governor at 5 Hz bandwidth, critically
    // damped) in a 60 Hz world, at 300 rpm after 1 s; then set_governor_target
    // to 200 rpm. With the target angle continuous, the angle error
    // e = Θ_ref − φ obeys J ë + K_p ė + K_i e = J Δω δ(t) (rigid chain), so
    // e = Δω t e^(−ω_n t) and ω = ω_new − Δω (1 − ω_n t) e^(−ω_n t): the speed
    // falls below 200 rpm by at most |Δω| e^(−2) = 13.5 rpm (at t = 2/ω_n,
    // 64 ms) and settles. The chain's compliance and the frames' sampling
    // allow half as much again: ≥ 180 rpm, and within 1 % of 200 rpm after
    // 1 s. (Had the target angle jumped to 200 rpm × t, the integral action
    // would have met an 8.9 rad error at once: K_i · 8.9 rad of torque.)
    let scene = data_scene("governed_driver_20_40.toml");
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    };
    let mut drive = ChainDrive::builder(&scene).build(&mut w).expect("drive");
    let rpm = |w: f64| w * 60.0 / std::f64::consts::TAU;
    for _ in 0..60 {
        drive.step_world(&mut w, &(), &()).expect("frame");
    }
    let before = rpm(drive.state().omega[0]);
    assert!((before - 300.0).abs() < 3.0, "{before} rpm");
    drive
        .set_governor_target(200.0 / 60.0 * std::f64::consts::TAU)
        .expect("target");
    let mut lowest = f64::INFINITY;
    for _ in 0..60 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        lowest = lowest.min(rpm(drive.state().omega[0]));
    }
    let after = rpm(drive.state().omega[0]);
    assert!(lowest >= 180.0, "fell to {lowest} rpm");
    assert!((after - 200.0).abs() < 2.0, "{after} rpm");
    // Not a governed drive: an error naming the governor.
    let mut w2 = PhysicsWorld::default();
    let mut plain = ChainDrive::builder(&driven())
        .build(&mut w2)
        .expect("drive");
    match plain.set_governor_target(1.0) {
        Err(CosimError::Input { field, .. }) => assert_eq!(field, "governor"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn sprockets_are_found_by_name_or_index_and_read_through_their_ids() {
    // A 1 N·m load on the free tail: at rest the chain holds it, so the
    // chain's torque on the tail is +1 N·m (moment balance about its axle).
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", -1.0);
    let mut w = PhysicsWorld::default();
    let drive = ChainDrive::builder(&scene).build(&mut w).expect("drive");
    let tail = drive.sprocket("tail").expect("by name");
    assert_eq!(drive.sprocket(1).expect("by index"), tail);
    assert_eq!(tail.index(), 1);
    let names: Vec<&str> = drive.sprockets().map(|(_, n)| n).collect();
    assert_eq!(names, ["driver", "tail"]);
    match drive.sprocket("head") {
        Err(CosimError::Input { field, message }) => {
            assert_eq!(field, "sprocket(\"head\")");
            assert!(message.contains("\"driver\", \"tail\""), "{message}");
        }
        other => panic!("expected an input error, got {other:?}"),
    }
    assert!(drive.sprocket(2).is_err());
    let torque = drive.chain_torque_on_sprocket(tail);
    assert!(
        (torque - 1.0).abs() < 0.01,
        "chain torque on the tail {torque} N·m"
    );
    // The chain's pull on the tail's centre points back at the driver.
    assert!(drive.chain_force_on_sprocket(tail).x < -300.0);
    assert_eq!(drive.sprocket_speed(tail), drive.state().omega[1]);
    assert_eq!(drive.sprocket_angle(tail), drive.state().theta[1]);
    assert_eq!(drive.sprocket_body(tail), drive.handles.sprockets()[1]);
    let s = drive.state();
    let n = drive.roller_count();
    assert_eq!(n, s.x.len());
    assert_eq!(drive.roller_position(7), Some(Vector::new(s.x[7], s.y[7])));
    assert_eq!(
        drive.roller_velocity(7),
        Some(Vector::new(s.vx[7], s.vy[7]))
    );
    assert_eq!(drive.roller_position(n), None);
    assert_eq!(drive.roller_positions().len(), n);
    assert!(drive.roller_positions().zip(&s.y).all(|(p, &y)| p.y == y));
}

#[test]
#[cfg(feature = "record")]
fn the_users_bodies_are_recorded_as_frames_beside_the_chain() {
    use crate::record::{RecordOptions, Recorder, RunEnd};
    use foxglove::schemas::FrameTransforms;
    use prost::Message as _;
    // A body the user moves along a line, recorded as frame "carriage" on
    // `/tf`; a name of the drive's own frames is not taken.
    let scene = driven();
    let mut w = PhysicsWorld::default();
    let mut drive = ChainDrive::builder(&scene).build(&mut w).expect("drive");
    let body = w.bodies.insert(
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(Vector::new(0.3, 0.5))
            .linvel(Vector::new(0.6, 0.0))
            .angvel(2.0),
    );
    let dt = w.integration_parameters.dt;
    let options = RecordOptions {
        rate_hz: 1.0 / dt,
        ..RecordOptions::default()
    };
    let mut recorder = Recorder::co_simulated(
        std::io::Cursor::new(Vec::new()),
        drive.scene(),
        &options,
        dt,
    )
    .expect("recorder");
    let mut poses = Vec::new();
    for _ in 0..10 {
        let b = &w.bodies[body];
        let pose = (b.translation(), b.rotation().angle());
        recorder.body_frame("carriage", pose.0, pose.1);
        recorder.body_frame("sprocket1", Vector::new(9.0, 9.0), 0.0);
        recorder.body_frame("ghost", Vector::new(f64::NAN, 0.0), 0.0);
        poses.push(pose);
        drive
            .step_world_observed(&mut w, &(), &(), &mut recorder)
            .expect("frame");
    }
    let bytes = recorder
        .finish(RunEnd::Completed)
        .expect("finish")
        .into_inner();
    let mut seen = Vec::new();
    for m in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
        let m = m.expect("a message");
        if m.channel.topic != "/tf" {
            continue;
        }
        let tf = FrameTransforms::decode(&m.data[..]).expect("FrameTransforms");
        let names: Vec<&str> = tf
            .transforms
            .iter()
            .map(|t| t.child_frame_id.as_str())
            .collect();
        assert_eq!(names, ["sprocket1", "sprocket2", "carriage"]);
        let spr = tf.transforms[0].translation.as_ref().expect("translation");
        assert!(
            spr.x.abs() < 1e-12 && spr.y.abs() < 1e-12,
            "sprocket1 moved"
        );
        let c = &tf.transforms[2];
        let (t, q) = (
            c.translation.as_ref().expect("xy"),
            c.rotation.as_ref().expect("q"),
        );
        seen.push((t.x, t.y, 2.0 * q.z.atan2(q.w)));
    }
    // One /tf per sample after the first body_frame (the first frame's
    // sample is taken after the step, with the pose set before it).
    assert_eq!(seen.len(), poses.len());
    for ((x, y, th), (p, a)) in seen.iter().zip(&poses) {
        assert!(
            (x - p.x).abs() < 1e-12 && (y - p.y).abs() < 1e-12,
            "{x} {y} vs {p:?}"
        );
        assert!((th - a).abs() < 1e-12, "{th} vs {a}");
    }
    // The body moved: the recorded frames are not all one pose.
    assert!(seen[9].0 - seen[0].0 > 0.08);
}

#[test]
fn a_drive_set_hands_each_drive_to_its_own_observer_after_every_frame() {
    use crate::cosim::DriveSet;
    use crate::sim::{Observer, Sample};
    /// Each sample's time and first sprocket speed.
    #[derive(Default)]
    struct Speeds(Vec<(f64, f64)>);
    impl Observer for Speeds {
        fn sample(&mut self, s: &Sample<'_>) {
            self.0.push((s.state.t_s, s.state.omega[0]));
        }
    }
    // Two drives far apart, at 60 and 30 rpm.
    let fast = driven();
    let slow = conveyor("role = \"driver\"\nspeed_rpm = 30.0\nramp_s = 0.2", 0.0);
    let mut w = PhysicsWorld::default();
    let mut set = DriveSet::new();
    set.push(ChainDrive::builder(&fast).build(&mut w).expect("fast"));
    set.push(
        ChainDrive::builder(&slow)
            .insert_at(Pose::translation(0.0, 2.0))
            .build(&mut w)
            .expect("slow"),
    );
    let (mut a, mut b) = (Speeds::default(), Speeds::default());
    match set.step_world_observed(&mut w, &(), &(), &mut [&mut a]) {
        Err(CosimError::Input { field, .. }) => assert_eq!(field, "observers"),
        other => panic!("expected an input error, got {other:?}"),
    }
    assert_eq!(
        set.drives()[0].state().t_s,
        0.0,
        "stepped despite the error"
    );
    for _ in 0..30 {
        set.step_world_observed(&mut w, &(), &(), &mut [&mut a, &mut b])
            .expect("frame");
    }
    assert_eq!((a.0.len(), b.0.len()), (30, 30));
    let dt = w.integration_parameters.dt;
    for (k, (sa, sb)) in a.0.iter().zip(&b.0).enumerate() {
        // The chain ends each frame within a substep (1e-5 s) of the world.
        assert!(
            (sa.0 - (k + 1) as f64 * dt).abs() <= 1e-5 && sb.0 == sa.0,
            "{sa:?} {sb:?}"
        );
    }
    // After the 0.2 s ramp each follows its own speed law: 2π and π rad/s.
    let (wa, wb) = (a.0[29].1, b.0[29].1);
    assert!(
        (wa - TAU).abs() < 0.05 * TAU && (wb - PI).abs() < 0.05 * PI,
        "{wa} {wb}"
    );
}
