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

/// The drive of `scene` settled with nothing held for the solve by the
/// dynamic relaxation alone (every sprocket free: Newton's method does not
/// apply), as the statics did before a sprocket was held for want of a
/// driver: the reference the held solve is compared with. Returns the
/// strands' mean tensions and the equilibrium.
fn relaxed_free(scene: &Scene) -> (Vec<Option<f64>>, super::statics::StaticEquilibrium) {
    use super::statics::settle_rest_length;
    let (mut model, mut state, _) = crate::model::DriveModel::build(scene).expect("builds");
    let mut forces = super::settled::new_forces(scene, &model);
    let settings = super::setup::relax_settings(scene, 1.0);
    let names: Vec<&str> = scene.sprockets.iter().map(|s| s.name.as_str()).collect();
    let eq = settle_rest_length(
        &mut model,
        &mut state,
        &mut forces,
        &settings,
        scene.chain.pretension_n,
        scene.equilibrium.tension_tolerance,
        &names,
    )
    .expect("relaxes");
    (
        crate::test_support::strand_means(&model, &state, forces.output()),
        eq,
    )
}

/// Every sprocket of `sim` turns freely again after the solve, and takes
/// a chain torque within 10⁻⁶ of `pretension_n` at its pitch radius.
fn assert_free_and_at_rest(sim: &Simulation, pretension_n: f64) {
    for (k, sp) in sim.model.sprockets.iter().enumerate() {
        assert!(sp.inv_inertia > 0.0, "sprocket {k} turns freely again");
        let m = sim.forces.output().chain_torque[k];
        assert!(
            m.abs() <= 1e-6 * pretension_n * sp.pitch_radius_m,
            "sprocket {k}: chain torque {m} N·m at rest"
        );
    }
}

#[test]
fn a_drive_without_a_driver_whose_loads_balance_settles_by_newton_at_rest() {
    // assets/bicycle.toml: chainring and rear sprocket both free, no load,
    // gravity on. Turning the loop does no work but the chordal action's,
    // so the drive rests where every sprocket's chain torque vanishes: the
    // solve holds the rear sprocket (the larger inertia), turns it to
    // where it takes no torque and lets it go. Hand calculation: with no
    // load a free sprocket at rest has T_in = T_out (torque / pitch radius
    // = 0), so both strands carry the pretension but for the chain's own
    // weight along them (96 rollers of 3.5 g: 3.3 N in all, so the strands
    // differ by at most that). Each sprocket's torque within 10⁻⁶ of the
    // 50 N pretension at its pitch radius (the solve stops at 10⁻⁷); the
    // roller forces within 10⁻⁶ of it; no relaxation speed left (Newton,
    // where the relaxation takes seconds). Against the relaxation's rest
    // state (the scene's relaxation time allowed): the strand tensions
    // within 0.1 N (0.2 % of the pretension; the relaxation rests wherever
    // its slow circulation stops within 10⁻⁷ of the pretension, the solve
    // at the stable phase).
    let scene = Scene::from_toml(include_str!("../../assets/bicycle.toml")).expect("scene");
    let sim = Simulation::new(&scene).expect("settles");
    let eq = &sim.equilibrium;
    assert!(eq.unbalanced.is_none(), "{eq:?}");
    assert!(eq.warnings().is_empty(), "{:?}", eq.warnings());
    assert!(eq.force_residual <= 1e-6, "{eq:?}");
    assert_eq!(eq.residual_speed_m_s, 0.0, "{eq:?}");
    assert!(((eq.tension_n - 50.0) / 50.0).abs() <= scene.equilibrium.tension_tolerance);
    assert_free_and_at_rest(&sim, 50.0);
    let held = crate::test_support::strand_means(&sim.model, &sim.state, sim.forces.output());
    let weight_n = 96.0 * 0.0035 * 9.81;
    for t in held.iter().flatten() {
        assert!((t - 50.0).abs() <= weight_n, "strand {t} N");
    }
    let (relaxed, _) = relaxed_free(&scene);
    for (a, b) in held.iter().zip(&relaxed) {
        let (a, b) = (a.expect("a free strand"), b.expect("a free strand"));
        eprintln!("strand: held solve {a:.4} N, relaxation {b:.4} N");
        assert!(
            (a - b).abs() <= 0.1,
            "strand: held solve {a} N, relaxation {b} N"
        );
    }
}

#[test]
fn a_drive_without_a_driver_whose_loads_do_not_balance_is_named_at_once() {
    // assets/conveyor.toml: both sprockets free, the tail loaded with
    // -0.5 N·m. With no driver nothing reacts the load: no rest state
    // exists. Hand calculation: the loads' tension jumps −w M / R around
    // the loop add up to 0.5 / 0.0812 = 6.2 N, not zero; held for the solve,
    // the head (the larger inertia, 0.05 against 0.01 kg·m²) takes the
    // load, the same tooth count giving it −0.5 N·m (the loop turned by
    // one pitch, the tail's load does the work the head's reaction undoes).
    // The rest state is the held one, the warning names the head and the
    // torque, and no relaxation runs (it ran for 8–12 s).
    let scene = Scene::from_toml(include_str!("../../assets/conveyor.toml")).expect("scene");
    let sim = Simulation::new(&scene).expect("settles");
    let eq = &sim.equilibrium;
    let unbalanced = eq.unbalanced.as_ref().expect("named");
    assert_eq!(unbalanced.sprocket, "head (motor)");
    assert!(
        (unbalanced.torque_n_m + 0.5).abs() <= 1e-3,
        "{unbalanced:?}"
    );
    assert!(eq.warnings().iter().any(|w| w.contains("no rest state")));
    assert_eq!(eq.residual_speed_m_s, 0.0, "{eq:?}");
    assert!(eq.force_residual <= 1e-6, "{eq:?}");
    assert!(sim.model.sprockets[0].inv_inertia > 0.0);
}

#[test]
fn a_worn_chain_on_a_drive_without_a_driver_hangs_at_rest_as_its_catenary() {
    // assets/bicycle.toml on the real tooth form, the chain worn 1 %
    // (96 links gain 12.2 mm on fixed centres): the strands go slack and
    // hang under their weight. The chain is worn with the rear sprocket
    // still held for the solve (a drive with no driver), then that sprocket
    // is turned to where it takes no torque and let go. Hand calculation,
    // the shallow catenary (a parabola; the strands lie within 4° of
    // level): a strand of span L sagging d under w = m g / P per metre
    // carries H = w L² / (8 d), here about 2 N against the new chain's
    // 50 N; L and d are measured from the rollers' positions (the chord
    // between the strand's end rollers, the largest distance of a roller
    // from it). The strand's mean link force exceeds H by the weight
    // along half the sag (w d / 3 on average, 1 %), and the parabola
    // misses the catenary by (d/L)² (0.4 %): within 5 %.
    let text = include_str!("../../assets/bicycle.toml").replacen(
        "[chain]",
        "profile = \"real\"\n\n[chain]\nelongation_pct = 1.0",
        1,
    );
    let scene = Scene::from_toml(&text).expect("scene");
    assert!((scene.chain.elongation - 0.01).abs() < 1e-12);
    let sim = Simulation::new(&scene).expect("settles");
    let eq = &sim.equilibrium;
    assert!(eq.unbalanced.is_none(), "{eq:?}");
    assert!(eq.force_residual <= 1e-6, "{eq:?}");
    assert_free_and_at_rest(&sim, 50.0);
    let (x, y) = (&sim.state.x, &sim.state.y);
    let n = x.len();
    let runs = sim
        .model
        .segments
        .runs(&sim.model.sprockets, x, y, &sim.forces.output().touching);
    let means = crate::test_support::strand_means(&sim.model, &sim.state, sim.forces.output());
    let w = 0.0035 * 9.81 / 0.0127;
    for (k, mean) in means.iter().enumerate() {
        let rollers: Vec<usize> = runs.links(k).flat_map(|i| [i, (i + 1) % n]).collect();
        let (a, b) = (rollers[0], rollers[rollers.len() - 1]);
        let (dx, dy) = (x[b] - x[a], y[b] - y[a]);
        let span = dx.hypot(dy);
        let sag = rollers
            .iter()
            .map(|&i| ((x[i] - x[a]) * dy - (y[i] - y[a]) * dx).abs() / span)
            .fold(0.0, f64::max);
        let h = w * span * span / (8.0 * sag);
        let mean = mean.expect("a free strand");
        eprintln!("strand {k}: span {span:.4} m, sag {sag:.4} m, H {h:.3} N, mean {mean:.3} N");
        assert!(h < 5.0, "strand {k} hangs slack: H {h} N");
        assert!(
            ((mean - h) / h).abs() <= 0.05,
            "strand {k}: mean link force {mean} N against the catenary's {h} N"
        );
    }
}
