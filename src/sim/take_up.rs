//! The tensioner rule's search (a sprocket moved along its adjustment
//! direction until the static tension is the pretension) and the take-up of
//! a worn chain after it (docs/model.md, “Pretension and static
//! equilibrium”, “A worn chain”).
//!
//! The static tension T(s) of the drive with the tensioner moved by s grows
//! with s from where the unstretched chain fits: flat while the chain is
//! slack (the real profile's seats give up length before any link is
//! stretched, and a chain that touches no tooth has no strand to measure),
//! then about linearly. The search therefore widens its steps while T stays
//! below the pretension and, once a position above it is known, keeps every
//! step inside the bracket.
//!
//! What this does not do: find where the chain fits (`statics::fit`), settle
//! a drive at one position (`statics::settle`) or lengthen a worn chain's
//! links (`worn`).

use super::settled::{Settled, new_forces};
use super::statics::{self, EquilibriumError, RelaxSettings, StaticEquilibrium};
use super::tension_search::TensionSearch;
use super::worn;
use super::{SimError, fit_sprocket, force_residual, free_strand_tension};
use crate::model::DriveModel;
use crate::scene::{PretensionRule, Role, Scene};

/// Most settled positions the search tries.
const MAX_ITERATIONS: usize = 40;

/// The scene with sprocket `t` moved by `offset_m` along `direction`.
fn moved(scene: &Scene, t: usize, direction: [f64; 2], offset_m: f64) -> Scene {
    let mut moved = scene.clone();
    let c = &mut moved.sprockets[t].center_m;
    c[0] += offset_m * direction[0];
    c[1] += offset_m * direction[1];
    moved
}

/// The tensioner rule: links keep their rest length P; the tensioner's
/// centre first moves along its adjustment direction until the unstretched
/// chain fits the path through the seated rollers ([`fit_sprocket`]; refused
/// only when its travel cannot close the gap), then on from there
/// ([`TensionSearch`]) until the pretension is reached. A load held at rest
/// is checked against the pretension there as under the rest-length rule.
/// Each iterate lays the chain out anew and settles it (Newton's method, the
/// relaxation where it stalls). The returned scene holds the tensioner's
/// final centre, so every output describes the drive simulated.
pub(super) fn settle_tensioner(
    scene: &Scene,
    settings: &RelaxSettings,
) -> Result<Settled, SimError> {
    let Some(t) = scene.tensioner() else {
        return Err(SimError::Equilibrium(EquilibriumError::NoTensioner));
    };
    let Role::Tensioner { direction, .. } = scene.sprockets[t].role else {
        return Err(SimError::Equilibrium(EquilibriumError::NoTensioner));
    };
    let target = scene.chain.pretension_n;
    let tension_at = |offset: f64| -> Result<(Settled, Option<f64>), SimError> {
        let moved = moved(scene, t, direction, offset);
        let (model, mut state, layout) = DriveModel::build(&moved)?;
        let mut forces = new_forces(&moved, &model);
        // Newton at this offset, the relaxation only where it stalls.
        let residual = statics::settle(
            &model,
            &mut state,
            &mut forces,
            settings,
            statics::REST_FORCE * target.abs(),
            0.5 * statics::REST_FORCE * target.abs(),
            true,
        )?;
        // No free strand: the chain touches no tooth, so it is slack.
        let tension = free_strand_tension(&model, &state, &forces);
        let eq = StaticEquilibrium {
            tension_n: tension.unwrap_or(0.0),
            rest_length_m: model.rest_length_m,
            iterations: 0,
            residual_speed_m_s: residual,
            force_residual: force_residual(&forces, target),
            beyond_seating_arc: None,
            misfit: None,
            unbalanced: None,
            worn_slack: None,
        };
        Ok(((moved, model, state, forces, layout, eq), tension))
    };
    // Where the unstretched chain fits; from there, the first step is the
    // move that stretches every link by T₀/K (the path grows by
    // slope · P per metre of move).
    let fit = fit_sprocket(scene, t, direction, scene.chain.rollers).map_err(|reason| {
        EquilibriumError::TensionerFit {
            sprocket: scene.sprockets[t].name.clone(),
            reason: Box::new(reason),
        }
    })?;
    let at_fit = moved(scene, t, direction, fit.offset_m);
    let (_, _, layout) = DriveModel::build(&at_fit)?;
    statics::check_load(&at_fit, &layout)?;
    let first_step_m = (target / scene.chain.stiffness_n_m) * scene.chain.rollers as f64
        / (fit.slope_per_m * scene.chain.pitch_m);
    // At the fit the unstretched chain carries no tension (nothing to relax:
    // no roller presses on a tooth, so no strand could be told from a wrap).
    let mut search = TensionSearch::new(fit.offset_m, 0.0, first_step_m.signum(), target);
    let mut s = fit.offset_m + first_step_m;
    let mut last = 0.0;
    for iteration in 1..=MAX_ITERATIONS {
        let (mut settled, tension) = tension_at(s)?;
        if let Some(t1) = tension
            && ((t1 - target) / target).abs() <= scene.equilibrium.tension_tolerance
        {
            settled.5.iterations = iteration;
            return Ok(settled);
        }
        last = tension.unwrap_or(0.0);
        s = search.next(s, last);
    }
    Err(SimError::Equilibrium(EquilibriumError::NotConverged {
        tension_n: last,
        target_n: target,
        iterations: MAX_ITERATIONS,
    }))
}

/// Lengthens the links of a drive `settled` with its chain new to `worn`'s
/// elongation ([`worn::wear_in`]); the tensioner rule's sprocket moves on
/// to keep the pretension; `check` may refuse each step's rest state
/// ([`worn::wear_in`]). Returns the worn drive, its scene `worn`'s with
/// the tensioner where it ended.
pub(super) fn wear_settled(
    worn: &Scene,
    settled: Settled,
    settings: &RelaxSettings,
    check: &mut worn::StepCheck<'_>,
) -> Result<Settled, SimError> {
    let (mut scene, mut model, mut state, mut forces, layout, _) = settled;
    let e = worn.chain.elongation;
    let chain = &worn.chain;
    let take_up = match (chain.pretension_by, scene.tensioner()) {
        (PretensionRule::Tensioner, Some(t)) => {
            let Role::Tensioner { direction, .. } = scene.sprockets[t].role else {
                return Err(SimError::Equilibrium(EquilibriumError::NoTensioner));
            };
            // The path's gain per metre the sprocket moves, from the fit's
            // slope (pitches per metre) where the new chain sits.
            let fit = fit_sprocket(&scene, t, direction, chain.rollers).map_err(|reason| {
                EquilibriumError::TensionerFit {
                    sprocket: scene.sprockets[t].name.clone(),
                    reason: Box::new(reason),
                }
            })?;
            let norm = direction[0].hypot(direction[1]);
            Some((
                t,
                [direction[0] / norm, direction[1] / norm],
                1.0 / (fit.slope_per_m * chain.pitch_m),
            ))
        }
        _ => None,
    };
    let mut taken = scene.clone();
    let eq = worn::wear_in(
        &mut model,
        &mut state,
        &mut forces,
        settings,
        e,
        chain.pretension_n,
        take_up.map(|(sprocket, direction, travel_per_length)| worn::TakeUp {
            scene: &mut taken,
            sprocket,
            direction,
            travel_per_length,
            tolerance: worn.equilibrium.tension_tolerance,
        }),
        check,
    )?;
    scene = taken;
    scene.chain.elongation = e;
    Ok((scene, model, state, forces, layout, eq))
}
