//! A drive with no sprocket held at rest: every sprocket free, no driver
//! (a drive whose motor is outside the scene). Turning the whole loop does
//! no work but the sprockets' loads', so such a drive has a rest state only
//! where the loads balance around the loop, and even then its circulation
//! is neutral: Newton's method has nothing that fixes it, and the
//! relaxation takes seconds to bring the slow circulation to rest.
//!
//! The statics therefore hold one sprocket at rest for the solve
//! ([`sprocket_to_hold`]) and let it turn freely again afterwards. Whatever
//! torque that sprocket then takes is what the loads leave unbalanced
//! around the loop (the virtual work of turning the loop by one step is the
//! loads' and that reaction's only). Where it is more than the rounding of
//! a rest state ([`unbalanced`]), the drive has no rest state: the state
//! reached is the one with that sprocket held, and a run warns. What this
//! module does not do: solve anything (the pretension rules do), or choose
//! the sprocket a co-simulation holds (its mounts decide).

use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::Scene;

use super::equilibrium::REST_FORCE;
use super::error::{EquilibriumError, Unbalanced};
use super::relax::RelaxSettings;

/// The sprocket to hold at rest while a drive with no held sprocket
/// settles: the free sprocket with the largest moment of inertia (the first
/// of equal ones), which, once the drive moves, takes the largest part of
/// an unbalanced load as its own acceleration. `None` where a sprocket is
/// held already (a driver, or one held for the solve) or none turns.
pub(crate) fn sprocket_to_hold(model: &DriveModel) -> Option<usize> {
    if model.sprockets.iter().any(|s| s.still_in_statics()) {
        return None;
    }
    model
        .sprockets
        .iter()
        .enumerate()
        .filter(|(_, s)| s.inv_inertia.is_finite() && s.inv_inertia > 0.0)
        .min_by(|a, b| a.1.inv_inertia.total_cmp(&b.1.inv_inertia))
        .map(|(k, _)| k)
}

/// Passes of [`let_go`]: the held sprocket turned to where it takes no
/// torque, the rest length found anew there.
const MAX_PASSES: usize = 4;

/// Lets the sprocket `held`, held for the solve of a drive with no driver,
/// go. Where the loads balance around the loop ([`load_imbalance_n`]
/// within [`REST_FORCE`] of the pretension), turns it to where it takes no
/// torque ([`settle_held_angle`]) and, with the rest-length rule
/// (`pitch_m`: the links' unstretched length the rule starts from), finds
/// the rest length anew there ([`super::settle_rest_length`]), until the
/// held sprocket's torque is within [`REST_FORCE`] of the pretension at its
/// pitch radius: the turn changes the strands' span (their chordal
/// action), so the tension with it. Else records in the returned state the
/// torque it takes ([`Unbalanced`]): no rest state exists. `eq`, `state`
/// and `forces`: the rest state reached with it held. Call before it is
/// released.
#[allow(clippy::too_many_arguments)]
pub(crate) fn let_go(
    scene: &Scene,
    model: &mut DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    held: usize,
    pitch_m: Option<f64>,
    mut eq: super::StaticEquilibrium,
) -> Result<super::StaticEquilibrium, EquilibriumError> {
    let scale_n = scene.chain.pretension_n.abs().max(f64::MIN_POSITIVE);
    let Some(radius_m) = model.sprockets.get(held).map(|s| s.pitch_radius_m) else {
        return Ok(eq);
    };
    let torque = |model: &DriveModel, forces: &ForceGenerator| held_torque_n_m(model, forces, held);
    if load_imbalance_n(scene, model).abs() > REST_FORCE * scale_n {
        let torque_n_m = torque(model, forces);
        eq.unbalanced = Some(Unbalanced {
            sprocket: scene
                .sprockets
                .get(held)
                .map_or_else(|| format!("{}", held + 1), |s| s.name.clone()),
            torque_n_m,
            relative: torque_n_m.abs() / radius_m / scale_n,
        });
        return Ok(eq);
    }
    let names: Vec<&str> = scene.sprockets.iter().map(|s| s.name.as_str()).collect();
    for _ in 0..MAX_PASSES {
        if !(torque(model, forces).abs() > REST_FORCE * scale_n * radius_m) {
            break;
        }
        settle_held_angle(model, state, forces, settings, held, scale_n)?;
        let iterations = eq.iterations;
        eq = match pitch_m {
            Some(pitch_m) => {
                model.rest_length_m = pitch_m;
                super::settle_rest_length(
                    model,
                    state,
                    forces,
                    settings,
                    scene.chain.pretension_n,
                    scene.equilibrium.tension_tolerance,
                    &names,
                )?
            }
            None => {
                let Some(tension_n) = super::free_strand_tension(model, state, forces) else {
                    return Err(EquilibriumError::NoFreeLinks);
                };
                let force_residual = super::force_residual(forces, scale_n);
                super::StaticEquilibrium {
                    tension_n,
                    force_residual,
                    ..eq
                }
            }
        };
        eq.iterations += iterations;
    }
    Ok(eq)
}

/// The torque out of balance on the sprocket `held`: the chain's torque
/// on it and its load at rest, N·m.
fn held_torque_n_m(model: &DriveModel, forces: &ForceGenerator, held: usize) -> f64 {
    forces
        .output()
        .chain_torque
        .get(held)
        .copied()
        .unwrap_or(0.0)
        + model
            .sprockets
            .get(held)
            .map_or(0.0, |s| s.load_at_rest_n_m())
}

/// What the sprockets' loads at rest leave unbalanced around the loop, N:
/// the sum over the sprockets of the tension jump T_out − T_in that each
/// one's load holds at rest, −w M / R (w = +1 for a counter-clockwise wrap,
/// −1 for a clockwise one; M the load at rest, R the pitch radius). Going
/// once around the loop the jumps must add up to zero for every strand to
/// have one tension: with no driver to take up the rest, a sum that is not
/// zero means no rest state.
pub(crate) fn load_imbalance_n(scene: &Scene, model: &DriveModel) -> f64 {
    scene
        .sprockets
        .iter()
        .zip(&model.sprockets)
        .map(|(s, m)| -s.wrap.sign() * m.load_at_rest_n_m() / m.pitch_radius_m)
        .sum()
}

/// Largest turn of the held sprocket per step of [`settle_held_angle`],
/// times its tooth angle 2π / z.
const MAX_TURN: f64 = 0.25;
/// Steps of [`settle_held_angle`].
const MAX_TURNS: usize = 20;

/// Turns the sprocket `held`, held for the solve of a drive whose loads
/// balance, to where its torque out of balance vanishes, the drive solved
/// anew at each angle ([`super::newton::settle`]): the loop's circulation
/// is neutral only on average; the rollers' weight and their seating on
/// the teeth vary as the loop turns through a pitch, and the drive rests
/// where that variation is balanced. Each turn follows the torque (the
/// sprocket let go turns that way) by a secant step on the torque against
/// the angle where the torque falls as the angle grows (a stable rest
/// state), else by a step that doubles, at most [`MAX_TURN`] of a tooth.
/// Stops when the torque over the pitch radius is within [`REST_FORCE`]
/// of `scale_n`, or after [`MAX_TURNS`] turns.
pub(crate) fn settle_held_angle(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    held: usize,
    scale_n: f64,
) -> Result<(), EquilibriumError> {
    let Some(sp) = model.sprockets.get(held) else {
        return Ok(());
    };
    let radius_m = sp.pitch_radius_m;
    let tooth_rad = std::f64::consts::TAU / f64::from(sp.teeth.max(1));
    let tolerance_n_m = REST_FORCE * scale_n.abs() * radius_m;
    let torque = |forces: &ForceGenerator| held_torque_n_m(model, forces, held);
    let mut previous: Option<(f64, f64)> = None;
    let mut step_rad = 1e-3 * tooth_rad;
    for _ in 0..MAX_TURNS {
        let m = torque(forces);
        if !(m.abs() > tolerance_n_m) {
            break;
        }
        let theta = state.theta[held];
        let secant = previous.and_then(|(t0, m0)| {
            let slope = (m - m0) / (theta - t0);
            (slope < 0.0 && slope.is_finite()).then(|| -m / slope)
        });
        let turn = match secant {
            Some(turn) => turn.clamp(-MAX_TURN * tooth_rad, MAX_TURN * tooth_rad),
            None => {
                let turn = step_rad.copysign(m);
                step_rad = (2.0 * step_rad).min(MAX_TURN * tooth_rad);
                turn
            }
        };
        previous = Some((theta, m));
        state.theta[held] = theta + turn;
        forces.reset_memory();
        forces.evaluate(model, state);
        super::newton::settle(
            model,
            state,
            forces,
            settings,
            REST_FORCE * scale_n.abs(),
            0.5 * REST_FORCE * scale_n.abs(),
            false,
        )?;
    }
    Ok(())
}
