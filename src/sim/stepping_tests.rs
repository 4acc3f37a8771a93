//! The two ways of stepping share one force generator and agree.

use crate::scene::{Overrides, ProfileKind, Stepping};
use crate::sim::Simulation;
use crate::test_support::l60mc;

/// Steps a substepped and a rapier-integrated copy of the same drive
/// `steps` times from the substepped one's current state; returns the largest
/// roller position difference and the fastest roller speed.
fn compare_modes(fast: &mut Simulation, scene: &crate::scene::Scene, steps: usize) -> (f64, f64) {
    let scene = scene
        .with(&Overrides {
            stepping: Some(Stepping::Rapier),
            ..Overrides::default()
        })
        .expect("rapier stepping");
    let mut literal = Simulation::new(&scene).expect("rapier");
    literal.state = fast.state.clone();
    literal.forces = fast.forces.clone();
    literal.sync_world();
    // rapier: one solver iteration; no damping, CCD or sleeping on the drive's bodies.
    assert_eq!(
        literal.world.integration_parameters.num_solver_iterations,
        1
    );
    let dt = scene.solver().dt_s;
    for _ in 0..steps {
        fast.step(dt).expect("stable step");
        literal.step(dt).expect("stable step");
    }
    let worst = (0..fast.state.rollers())
        .map(|i| (fast.state.x[i] - literal.state.x[i]).hypot(fast.state.y[i] - literal.state.y[i]))
        .fold(0.0, f64::max);
    let fastest = (0..fast.state.rollers())
        .map(|i| fast.state.vx[i].hypot(fast.state.vy[i]))
        .fold(0.0, f64::max);
    (worst, fastest)
}

#[test]
fn rapier_integration_agrees_with_substepping() {
    // From static equilibrium, as every run starts: 1000 steps.
    let scene = l60mc(0.0);
    let mut fast = Simulation::new(&scene).expect("substepped");
    let (worst, fastest) = compare_modes(&mut fast, &scene, 1000);
    assert!(
        worst < 1e-9,
        "largest roller position difference {worst:e} m"
    );
    assert!(
        fastest > 1e-3,
        "the chain moves: fastest roller {fastest} m/s"
    );
}

#[test]
fn rapier_integration_agrees_at_full_speed() {
    // At 120 rpm the modes differ by rapier's rotation update alone: it
    // advances a dynamic body's angle by atan(ω dt) instead of ω dt, an error
    // of (ω dt)³/3 per step (5e-12 rad for sprocket 3 at dt = 10 µs), which
    // the contacts then amplify. 1000 steps stay within 1e-7 m.
    let scene = l60mc(1.2);
    let mut fast = Simulation::new(&scene).expect("substepped");
    fast.run(1.2, 1000, &mut crate::sim::NoObserver, None)
        .expect("run");
    let (worst, fastest) = compare_modes(&mut fast, &scene, 1000);
    assert!(
        worst < 1e-7,
        "largest roller position difference {worst:e} m"
    );
    assert!(fastest > 5.0, "fastest roller {fastest} m/s");
}

#[test]
fn substepped_run_writes_poses_into_rapier() {
    let scene = l60mc(0.01);
    let mut sim = Simulation::new(&scene).expect("sim");
    sim.run(0.01, 100, &mut crate::sim::NoObserver, None)
        .expect("run");
    let h = sim.bodies.rollers[5];
    let p = sim.world.bodies[h].translation();
    assert_eq!((p.x, p.y), (sim.state.x[5], sim.state.y[5]));
}

#[test]
fn culling_changes_nothing() {
    // Oracle: with and without reach caching ("culling") the run is bitwise
    // identical. The real profile's reach circles overlap on this drive, so
    // some of its rollers (e.g. 61–62 during the run-up) are in shared runs.
    for profile in [ProfileKind::Circular, ProfileKind::Real] {
        let scene = l60mc(0.0)
            .with(&Overrides {
                profile: Some(profile),
                ..Overrides::default()
            })
            .expect("valid scene");
        let mut a = Simulation::new(&scene).expect("sim");
        let mut b = Simulation::new(&scene).expect("sim");
        b.forces.contact.culling = None;
        let dt = scene.solver().dt_s;
        for _ in 0..25_000 {
            a.step(dt).expect("stable step");
            b.step(dt).expect("stable step");
        }
        assert_eq!(a.state, b.state, "{profile:?}");
        assert_eq!(
            a.forces.output().chain_torque,
            b.forces.output().chain_torque,
            "{profile:?}"
        );
    }
}
