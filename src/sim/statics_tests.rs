//! The static equilibrium with sprockets held for the solve
//! ([`Simulation::new_holding`], the entry point for a co-simulation's
//! mounted sprockets) and with
//! a tensioner sprocket.

use crate::scene::Scene;
use crate::sim::Simulation;

#[test]
fn a_held_sprocket_takes_the_load_of_a_free_one_at_rest() {
    // assets/conveyor.toml: both sprockets free (in a co-simulation the head
    // is the motor's body), the tail loaded with -0.5 N·m, gravity on. Held
    // at the head, the drive has a rest state: the tail at rest balances its
    // load with the chain's torque, chain torque + load = 0 (the head's
    // reaction is whatever it takes). Without holding, no sprocket reacts
    // the load and no such rest state exists. Tolerance: 10⁻³ of the load
    // (the solve stops at 10⁻⁷ of the 500 N pretension times the pitch
    // radius, 4 µN·m).
    let scene = Scene::from_toml(include_str!("../../assets/conveyor.toml")).expect("scene");
    let sim = Simulation::new_holding(&scene, &[true]).expect("settles");
    let tail = &sim.model.sprockets[1];
    let load_n_m = tail.load_at_rest_n_m();
    assert_eq!(load_n_m, -0.5);
    let chain_n_m = sim.forces.output().chain_torque[1];
    assert!(
        (chain_n_m + load_n_m).abs() <= 1e-3 * load_n_m.abs(),
        "tail: chain torque {chain_n_m} N·m against a load of {load_n_m} N·m"
    );
    assert!(
        sim.equilibrium.force_residual <= 1e-6,
        "{:?}",
        sim.equilibrium
    );
    // The head turns freely again after the solve.
    assert!(sim.model.sprockets[0].inv_inertia > 0.0);
    assert_eq!(sim.state.omega[0], 0.0);
}

#[test]
fn a_serpentine_with_a_tensioner_sprocket_settles_by_newton() {
    // tests/data/serpentine_08b_5.toml: five sprockets, the tensioner
    // sprocket placed by the tensioner rule, loads of -5 N·m (pump) and
    // -2 N·m (fan). At rest every free sprocket balances its load with the
    // chain's torque (the idler and the tensioner carry none), within 10⁻³
    // of the larger load; the static tension is the pretension within the
    // scene's tolerance. Each of the rule's iterates is solved by Newton's
    // method, which ends with no roller speed left (a dynamic relaxation
    // leaves a small one: the drive settled that way needs seconds).
    let scene =
        Scene::from_toml(include_str!("../../tests/data/serpentine_08b_5.toml")).expect("scene");
    let sim = Simulation::new(&scene).expect("settles");
    let eq = &sim.equilibrium;
    assert!(
        ((eq.tension_n - 300.0) / 300.0).abs() <= scene.equilibrium.tension_tolerance,
        "{eq:?}"
    );
    assert!(eq.force_residual <= 1e-6, "{eq:?}");
    assert_eq!(eq.residual_speed_m_s, 0.0, "{eq:?}");
    let torque = &sim.forces.output().chain_torque;
    for (k, load_n_m) in [(1, -5.0), (2, -2.0), (3, 0.0), (4, 0.0)] {
        assert_eq!(sim.model.sprockets[k].load_at_rest_n_m(), load_n_m);
        assert!(
            (torque[k] + load_n_m).abs() <= 5e-3,
            "sprocket {k}: chain torque {} N·m against a load of {load_n_m} N·m",
            torque[k]
        );
    }
}
