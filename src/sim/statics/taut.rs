//! A chain laid compressed, brought to rest from taut (docs/model.md,
//! “Pretension and static equilibrium”).
//!
//! A chain up to half a pitch longer than its path is laid with its free
//! links shorter than the pitch: every free strand starts compressed, the
//! tangent stiffness is indefinite there (a compressed strand buckles), and
//! Newton from the layout wanders with its stabilising shift on. Here the
//! links' rest length starts short enough that every free strand pulls
//! (the layout's compression turned to tension, plus the largest load
//! torque over its pitch radius, so that no load slackens a strand),
//! Newton settles that taut
//! drive, and the rest length is then lengthened to the pitch in steps,
//! each Newton's start the two rest states before extrapolated: the chain
//! gains its excess length where its loads, gravity and arms put it, through
//! rest states whose tangent stays positive definite. A step Newton does not
//! settle is halved; a successful one lets the next grow.
//!
//! What this does not do: settle a drive whose chain is not laid
//! compressed, or choose the rest length (the pretension rules do).

use super::tension::free_strand_tension;
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};

/// Newton steps per lengthening step before it is halved.
const STEP_ITERATIONS: usize = 20;

/// Lengthening steps in all (halved ones counted) before the
/// continuation gives up.
const MAX_STEPS: usize = 64;

/// The force each step but the last settles to, times the final aim: the
/// next step's prediction needs no more.
const STEP_AIM: f64 = 100.0;

/// First lengthening step, as a share of the whole.
const FIRST_SHARE: f64 = 0.125;

#[cfg(test)]
thread_local! {
    /// Turns the continuation off on this thread: tests compare a solve
    /// with and without it.
    pub(crate) static OFF: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The free strands' mean link force at `state`, N, where it is below zero
/// (a chain laid longer than its path, its free strands compressed);
/// `None` otherwise. Evaluates `forces` at `state`.
pub(super) fn laid_compression(
    model: &DriveModel,
    state: &DriveState,
    forces: &mut ForceGenerator,
) -> Option<f64> {
    forces.reset_memory();
    forces.evaluate(model, state);
    free_strand_tension(model, state, forces).filter(|t| *t < 0.0)
}

/// Brings the drive, laid with its free strands compressed to a mean link
/// force `laid_n` ([`laid_compression`], which left `forces` evaluated at
/// `state`), to rest at the model's rest length within `aim_n` by the
/// continuation of the module docs, from `state`.
/// `solve(model, state, forces, tolerance_n, max_iterations)`: Newton at
/// the model's rest length, true where it converged (`newton`'s).
/// True when it reached the rest state: `state` is then that state and
/// `forces` are evaluated at it. Otherwise `state` is back where it started.
pub(super) fn settle_from_taut(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    laid_n: f64,
    aim_n: f64,
    solve: Solve,
) -> bool {
    #[cfg(test)]
    if OFF.with(std::cell::Cell::get) {
        return false;
    }
    let start = state.clone();
    let reached = lengthen(model, state, forces, laid_n, aim_n, solve);
    if !reached {
        state.clone_from(&start);
    }
    forces.reset_memory();
    forces.evaluate(model, state);
    reached
}

/// Newton at a model's rest length from a state, to a tolerance (N) in at
/// most so many steps: whether it converged.
pub(super) type Solve = fn(&DriveModel, &mut DriveState, &mut ForceGenerator, f64, usize) -> bool;

/// The continuation itself; `state` is left anywhere when it fails.
fn lengthen(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    laid_n: f64,
    aim_n: f64,
    solve: Solve,
) -> bool {
    let k = model.stiffness_n_m;
    let target = model.rest_length_m;
    // The free links' length as laid, and the rest length that stretches
    // them to the taut start's tension.
    let loads_n = model
        .sprockets
        .iter()
        .filter(|s| s.pitch_radius_m > 0.0)
        .map(|s| (s.load_at_rest_n_m() / s.pitch_radius_m).abs())
        .fold(0.0, f64::max);
    let taut_n = laid_n.abs() + loads_n;
    let laid_m = target + laid_n / k;
    let first = laid_m - taut_n / k;
    if !(first < target) {
        return false;
    }
    let step_aim = STEP_AIM * aim_n;
    let mut taut = model.clone();
    taut.rest_length_m = first;
    if !solve(&taut, state, forces, step_aim, 2 * STEP_ITERATIONS) {
        return false;
    }
    let mut at = first;
    let mut before: Option<(f64, DriveState)> = None;
    let mut h = FIRST_SHARE * (target - first);
    let mut trial = state.clone();
    for _ in 0..MAX_STEPS {
        let next = (at + h).min(target);
        let last_step = next >= target;
        // The prediction: the two rest states before, extrapolated to the
        // next rest length.
        trial.clone_from(state);
        if let Some((b, prev)) = &before {
            let ratio = (next - at) / (at - b);
            let on = |to: &mut [f64], now: &[f64], from: &[f64]| {
                for ((t, n), f) in to.iter_mut().zip(now).zip(from) {
                    *t = n + ratio * (n - f);
                }
            };
            on(&mut trial.x, &state.x, &prev.x);
            on(&mut trial.y, &state.y, &prev.y);
            on(&mut trial.theta, &state.theta, &prev.theta);
            on(&mut trial.q, &state.q, &prev.q);
        }
        taut.rest_length_m = next;
        let aim = if last_step { aim_n } else { step_aim };
        if solve(&taut, &mut trial, forces, aim, STEP_ITERATIONS) {
            before = Some((at, std::mem::replace(state, trial.clone())));
            at = next;
            if last_step {
                return true;
            }
            h *= 2.0;
        } else {
            h *= 0.5;
            if h < 1e-6 * (target - first) {
                return false;
            }
        }
    }
    false
}
