//! Two threads for large drives: the roller loops split over a worker give
//! the same bits as one thread.

use crate::cosim::ChainDrive;
use crate::scene::DriveSpec;
use crate::scene::{ProfileKind, Scene, StepFile, Threads, ThreadsFile};
use crate::sim::Simulation;
use rapier2d_f64::prelude::*;

/// A generated drive of `rollers` rollers round two sprockets (real
/// profile, driven from rest to 120 rpm over 0.05 s), stepped at 20 µs,
/// with `threads`.
fn drive(rollers: usize, threads: Threads) -> Scene {
    let mut spec = DriveSpec::new(rollers, 2).expect("two sprockets");
    spec.profile = ProfileKind::Real;
    spec.ramp_s = 0.05;
    spec.solver.dt_s = StepFile::Seconds(20e-6);
    spec.solver.threads = ThreadsFile::from(threads);
    spec.equilibrium.max_relax_s = 0.05;
    spec.scene().expect("generated drive")
}

/// Every roller's and sprocket's coordinates and the roller forces, as bits.
fn bits(sim: &Simulation) -> Vec<u64> {
    let s = &sim.state;
    let f = sim.forces.output();
    [
        &s.x,
        &s.y,
        &s.vx,
        &s.vy,
        &s.theta,
        &s.omega,
        &f.fx,
        &f.fy,
        &f.link_force,
    ]
    .into_iter()
    .flat_map(|v| v.iter().map(|x| x.to_bits()))
    .chain([f.max_stretch_m.to_bits(), f.max_roller_speed_m_s.to_bits()])
    .collect()
}

#[test]
fn threads_1_and_2_agree_to_the_bit() {
    // 300 rollers (chunks of 37 and 38), 3000 steps (60 ms, through the
    // ramp: rollers engage and leave both sprockets, the links at the
    // chunks' boundaries and the closing link stretch and swing).
    // The same drive on one thread and split over two must give the same
    // bits at every 500th step: each roller's force is summed in the same
    // order, only on another thread.
    let mut one = Simulation::new(&drive(300, Threads::One)).expect("one thread");
    let mut two = Simulation::new(&drive(300, Threads::Two)).expect("two threads");
    assert_eq!(bits(&one), bits(&two), "after the static equilibrium");
    let dt = one.scene.solver().dt_s;
    for step in 1..=3000 {
        one.step(dt).expect("stable");
        two.step(dt).expect("stable");
        if step % 500 == 0 {
            assert_eq!(bits(&one), bits(&two), "step {step}");
        }
    }
    // The run moved the chain, so the comparison compared something.
    assert!(one.state.omega[0] > 1.0, "driver at {}", one.state.omega[0]);
    assert!(one.forces.output().max_roller_speed_m_s > 1.0);
}

#[test]
fn a_co_simulated_drive_on_two_threads_agrees_to_the_bit() {
    // The same in a 60 Hz rapier world: 30 frames of the drive on one
    // thread and on two, every roller body where the other's is.
    let run = |threads| {
        let scene = drive(300, threads);
        let mut world = PhysicsWorld::default();
        let mut d = ChainDrive::insert(&scene, &[], &mut world.bodies, &mut world.colliders)
            .expect("inserted");
        for _ in 0..30 {
            d.step_world(&mut world, &(), &()).expect("stable frame");
        }
        let s = d.state();
        [&s.x, &s.y, &s.vx, &s.vy, &s.omega]
            .into_iter()
            .flat_map(|v| v.iter().map(|x| x.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(run(Threads::One), run(Threads::Two));
}

#[test]
fn the_threads_setting_is_checked_with_its_path() {
    let mut spec = DriveSpec::new(100, 2).expect("two sprockets");
    spec.solver.threads = ThreadsFile::Count(3);
    let err = spec
        .scene()
        .expect_err("3 threads is not offered")
        .to_string();
    assert!(err.contains("solver.threads"), "{err}");
    assert!(err.contains("1, 2 or \"auto\""), "{err}");
}
