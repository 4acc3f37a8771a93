//! One fuzz case: a mutated scene file taken through parsing, layout, static
//! equilibrium and a few hundred steps, checking the tool's promises — no
//! panic, every rejection explained with a field path (or a line for a
//! syntax error), no NaN in an accepted run. Used by the property test and by
//! `chaindrive bench fuzz`.

use crate::rng::SeededRng;
use crate::scene::mutate::mutate;
use crate::scene::{Overrides, Scene, SceneError};
use crate::sim::{NoObserver, Simulation};

/// How a case ended (all of them acceptable).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FuzzOutcome {
    /// The scene was rejected with explained errors.
    Rejected,
    /// The scene parsed but could not be laid out or settled, with an error.
    Failed,
    /// The run stopped with a blow-up error.
    BlewUp,
    /// The run went through without NaN.
    Ran,
}

/// Mutates `base` with the generator seeded by `seed` and checks the
/// promises. `Err` describes a broken promise.
pub fn run_case(base: &str, seed: u64) -> Result<FuzzOutcome, String> {
    let mut rng = SeededRng::new(seed);
    let text = mutate(base, &mut rng);
    let scene = match Scene::from_toml(&text) {
        Ok(s) => s,
        Err(e) => {
            // A syntax error names its line; every other names its field.
            let unexplained = match &e {
                SceneError::Syntax(s) => (!s.contains("line")).then(|| s.clone()),
                SceneError::Invalid(errors) => errors
                    .iter()
                    .find(|f| f.path.is_empty() || f.message.is_empty())
                    .map(ToString::to_string),
            };
            if let Some(line) = unexplained {
                return Err(format!("seed {seed}: unexplained rejection: {line}"));
            }
            return Ok(FuzzOutcome::Rejected);
        }
    };
    // Short: a capped relaxation and 300 steps are enough to meet NaN.
    let capped = Overrides {
        max_relax_s: Some(scene.equilibrium().max_relax_s.min(0.003)),
        ..Overrides::default()
    };
    let scene = match scene.with(&capped) {
        Ok(s) => s,
        Err(e) => return Err(format!("seed {seed}: the capped scene is refused: {e}")),
    };
    let mut sim = match Simulation::new(&scene) {
        Ok(sim) => sim,
        Err(e) if !e.to_string().is_empty() => return Ok(FuzzOutcome::Failed),
        Err(_) => return Err(format!("seed {seed}: empty error")),
    };
    let until = sim.state.t_s + 300.0 * scene.solver.dt_s;
    match sim.run(until, 100, &mut NoObserver, None) {
        Ok(_) => {
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            if finite(&sim.state.x)
                && finite(&sim.state.y)
                && finite(&sim.forces.output().link_force)
            {
                Ok(FuzzOutcome::Ran)
            } else {
                Err(format!(
                    "seed {seed}: non-finite state after an accepted run"
                ))
            }
        }
        Err(e) => {
            let msg = e.to_string();
            if msg.contains("t = ") {
                Ok(FuzzOutcome::BlewUp)
            } else {
                Err(format!("seed {seed}: unexplained run error: {msg}"))
            }
        }
    }
}
