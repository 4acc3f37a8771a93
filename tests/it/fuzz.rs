//! Property test: mutated scene files never panic; every rejection names a
//! field (or, for a syntax error, a line); every accepted scene either fails
//! with a clear error or runs without NaN. The long version is
//! `chaindrive bench fuzz --cases N`.

use chaindrive::scene::mutate::{Lcg, mutate};
use chaindrive::scene::{L60MC_TOML, Scene, SceneError};
use chaindrive::sim::{NoObserver, Simulation};

/// Checks one mutated scene; returns whether it was accepted and ran.
pub fn check_case(seed: u64) -> bool {
    let mut rng = Lcg::new(seed);
    let text = mutate(L60MC_TOML, &mut rng);
    let mut scene = match Scene::from_toml(&text) {
        Ok(s) => s,
        Err(e) => {
            for line in e.lines() {
                match &e {
                    SceneError::Syntax(_) => assert!(line.contains("line"), "seed {seed}: {line}"),
                    SceneError::Invalid(_) => assert!(
                        line.contains(": ")
                            && (line.contains('.') || line.starts_with("sprockets")),
                        "seed {seed}: {line}"
                    ),
                }
            }
            return false;
        }
    };
    // Short: a capped relaxation and 300 steps are enough to meet NaN or a panic.
    scene.equilibrium.max_relax_s = 0.003;
    let mut sim = match Simulation::new(&scene) {
        Ok(sim) => sim,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return false;
        }
    };
    let until = sim.state.t_s + 300.0 * scene.solver.dt_s;
    match sim.run(until, 100, &mut NoObserver, None) {
        Ok(_) => {
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            assert!(
                finite(&sim.state.x) && finite(&sim.state.y),
                "seed {seed}: non-finite state"
            );
            assert!(
                finite(&sim.forces.link_force),
                "seed {seed}: non-finite force"
            );
            true
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(
                msg.contains("t = ") || msg.contains("equilibrium"),
                "seed {seed}: {msg}"
            );
            false
        }
    }
}

#[test]
fn mutated_scenes_never_panic_and_explain_themselves() {
    let ran = (0..400).filter(|&seed| check_case(seed)).count();
    // Some mutations are harmless (a 10% change of a mass): those scenes must run.
    assert!(ran > 10, "only {ran} of 400 mutated scenes ran");
}
