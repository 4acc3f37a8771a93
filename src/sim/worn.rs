//! A worn chain (docs/model.md, "A worn chain"): the drive is first brought
//! to its pretension with the chain new, by the scene's rule; then every
//! link is lengthened by the wear elongation e, in small steps, the drive
//! brought to rest after each. What takes the length up is the rule's:
//!
//! - **rest length** (fixed centres): nothing; the gained length is slack
//!   and the static tension falls;
//! - **tensioner preload** (arms): the arms, under their preload, as the
//!   equilibrium moves them;
//! - **tensioner** (a sprocket moved along its adjustment direction): the
//!   sprocket moves on with each step by the length the links gained, and at
//!   the end until the pretension is reached again.
//!
//! Starting from the new chain matters: a worn chain laid out at once with
//! every roller on its gap's centreline is free in every gap (a gap widens
//! outwards) and takes up no tension, while lengthening a seated chain moves
//! its rollers onto the flanks as wear does.
//!
//! What this does not do: lay the chain out or choose the new chain's rest
//! length or tensioner position (the pretension rules do).

use super::statics::{
    EquilibriumError, RelaxSettings, StaticEquilibrium, force_residual, free_strand_tension,
};
use super::tension_search::TensionSearch;
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::Scene;

/// Largest lengthening of the links per step, as a fraction of the static
/// link stretch T₀/K: each step then changes the links' forces by at most
/// this fraction of the pretension, which the equilibrium solver takes from
/// the state before without a violent start.
const STEP_OF_STRETCH: f64 = 0.5;

/// Lengthening per step that is always allowed, as a fraction of the
/// pitch: a slack chain's forces hardly change with it, and a chain stiff
/// against its pretension takes it from the state before.
const STEP_OF_PITCH: f64 = 5e-4;

/// Most steps.
const MAX_STEPS: usize = 2000;

/// Relative force residual each step's equilibrium aims at.
const REST_FORCE: f64 = 1e-7;

/// Most corrections of a tensioner's position after the lengthening.
const MAX_CORRECTIONS: usize = 40;

/// A sprocket that takes the worn chain's length up (the tensioner rule).
pub(crate) struct TakeUp<'a> {
    /// The scene whose sprocket moves (its centre follows the model's).
    pub scene: &'a mut Scene,
    /// The sprocket.
    pub sprocket: usize,
    /// Its unit adjustment direction.
    pub direction: [f64; 2],
    /// Its travel per metre of chain the path must gain, m/m.
    pub travel_per_length: f64,
    /// Relative tolerance on the pretension.
    pub tolerance: f64,
}

impl TakeUp<'_> {
    /// Moves the sprocket by `distance_m` along its direction, in the scene
    /// and the model.
    fn shift(&mut self, model: &mut DriveModel, distance_m: f64) -> Result<(), EquilibriumError> {
        let c = &mut self.scene.sprockets[self.sprocket].center_m;
        c[0] += distance_m * self.direction[0];
        c[1] += distance_m * self.direction[1];
        model
            .retrace(self.scene, self.sprocket)
            .map_err(|e| EquilibriumError::TensionerFit {
                sprocket: self.scene.sprockets[self.sprocket].name.clone(),
                reason: Box::new(super::FitError::NoPath(e.to_string())),
            })
    }
}

/// The rest state one lengthening step on, predicted from the two before
/// (`before`, then `last`, a step apart): their positions, angles and arm
/// angles extrapolated linearly, the rest of `last`. Lengthening a step's
/// links on the rest state before compresses them all at once (by K times
/// the step, more than a slack chain's tension), which leaves Newton an
/// indefinite tangent far from the rest state; the prediction starts it
/// within the step's second-order change.
fn extrapolated(before: &DriveState, last: &DriveState) -> DriveState {
    let mut next = last.clone();
    let on = |to: &mut [f64], from: &[f64]| {
        for (a, b) in to.iter_mut().zip(from) {
            *a += *a - b;
        }
    };
    on(&mut next.x, &before.x);
    on(&mut next.y, &before.y);
    on(&mut next.theta, &before.theta);
    on(&mut next.q, &before.q);
    next
}

/// Links of the free strands at `state` (as the static tension counts them).
fn free_links(model: &DriveModel, state: &DriveState, forces: &ForceGenerator) -> usize {
    let runs = model.segments.runs(
        &model.sprockets,
        &state.x,
        &state.y,
        &forces.output().touching,
    );
    (0..model.segments.len())
        .map(|k| runs.links(k).count())
        .sum()
}

/// One step of the lengthening, as [`wear_in`] reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WearStep {
    /// The step, from 1.
    pub step: usize,
    /// Steps in all.
    pub steps: usize,
    /// The links' elongation at this step (a fraction of the new rest
    /// length; the scene's at the last step).
    pub elongation: f64,
}

/// A check of each wear step's rest state ([`wear_in`]): the step, the
/// model, the state and the forces evaluated at it.
pub(crate) type StepCheck<'a> = dyn FnMut(WearStep, &DriveModel, &DriveState, &ForceGenerator) -> Result<(), EquilibriumError>
    + 'a;

/// Lengthens the links of `model`, settled as a new chain at `pretension_n`,
/// from their rest length l₀ to l₀ (1 + `elongation`), bringing the drive to
/// rest at each step, with `take_up` moving a sprocket where the tensioner
/// rule holds (module docs). After each step's rest state, `check` may
/// refuse it (a rest state the run could not start from, which further
/// wear would not mend): the lengthening stops there with its error.
/// Returns the worn chain's equilibrium.
#[allow(clippy::too_many_arguments)]
pub(crate) fn wear_in(
    model: &mut DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    elongation: f64,
    pretension_n: f64,
    mut take_up: Option<TakeUp<'_>>,
    check: &mut StepCheck<'_>,
) -> Result<StaticEquilibrium, EquilibriumError> {
    let new_rest_m = model.rest_length_m;
    let worn_rest_m = new_rest_m * (1.0 + elongation);
    let step_m =
        (STEP_OF_STRETCH * pretension_n / model.stiffness_n_m).max(STEP_OF_PITCH * new_rest_m);
    let steps = ((worn_rest_m - new_rest_m) / step_m)
        .ceil()
        .clamp(1.0, MAX_STEPS as f64) as usize;
    let scale = pretension_n.abs();
    let settle = |model: &mut DriveModel,
                  state: &mut DriveState,
                  forces: &mut ForceGenerator,
                  guess: Option<&DriveState>| {
        super::statics::settle_from(
            model,
            state,
            forces,
            settings,
            (REST_FORCE * scale, 0.5 * REST_FORCE * scale),
            false,
            guess,
        )
    };
    // The rest state two steps back: with the last one, the prediction of
    // the next (`extrapolated`).
    let mut before: Option<DriveState> = None;
    let mut residual = 0.0;
    // The tension falls by K/n_free per metre of chain the strands gain
    // over their path and rises by that per metre of path: the sprocket's
    // travel per newton, with the links of the free strands (a wrap's
    // rollers ride up their flanks and take their own links' gain).
    // A chain that touches no tooth has no free strand to measure: it is
    // slack, and the take-up goes on tightening it.
    let tension = |model: &DriveModel, state: &DriveState, f: &ForceGenerator| {
        free_strand_tension(model, state, f).unwrap_or(0.0)
    };
    let mut t_now = tension(model, state, forces);
    for k in 1..=steps {
        let rest = if k == steps {
            worn_rest_m
        } else {
            new_rest_m + (worn_rest_m - new_rest_m) * (k as f64 / steps as f64)
        };
        if let Some(t) = &mut take_up {
            // A slack chain (no free strand) gains along all its links.
            let free = match free_links(model, state, forces) {
                0 => state.rollers() as f64,
                n => n as f64,
            };
            let per_n = free * t.travel_per_length / model.stiffness_n_m;
            let gained_m = free * (rest - model.rest_length_m);
            t.shift(
                model,
                gained_m * t.travel_per_length + (pretension_n - t_now) * per_n,
            )?;
            // The contact's kept reach sets assume the centres stood still.
            forces.forget_reach();
        }
        model.rest_length_m = rest;
        let at = WearStep {
            step: k,
            steps,
            elongation: rest / new_rest_m - 1.0,
        };
        super::setup_stage::note_stage(|| {
            format!(
                "the worn chain, wear step {k} of {steps} (links {:.3} % longer than new, the scene's {:.3} %)",
                100.0 * at.elongation,
                100.0 * elongation
            )
        });
        let guess = before.as_ref().map(|b| extrapolated(b, state));
        let last = state.clone();
        residual = settle(model, state, forces, guess.as_ref())?;
        before = Some(last);
        check(at, model, state, forces)?;
        if take_up.is_some() {
            t_now = tension(model, state, forces);
        }
    }
    let mut iterations = steps;
    if let Some(t) = &mut take_up {
        super::setup_stage::note_stage(|| {
            "the worn chain, its tensioner moved back to the pretension".to_owned()
        });
        // Back to the pretension: the tensioner's search from where the
        // lengthening left it, the first move from the links' stiffness.
        let free = free_links(model, state, forces).max(1) as f64;
        let mut search = TensionSearch::new(0.0, t_now, t.travel_per_length.signum(), pretension_n);
        let (mut at, mut next) = (
            0.0,
            (pretension_n - t_now) * free * t.travel_per_length / model.stiffness_n_m,
        );
        for _ in 0..MAX_CORRECTIONS {
            if ((t_now - pretension_n) / pretension_n).abs() <= t.tolerance {
                break;
            }
            t.shift(model, next - at)?;
            at = next;
            forces.forget_reach();
            residual = settle(model, state, forces, None)?;
            iterations += 1;
            t_now = tension(model, state, forces);
            next = search.next(at, t_now);
        }
    }
    // A chain gone slack on fixed centres may touch no tooth at all (no
    // gravity pulls it onto the sprockets): its static tension is nil.
    let tension_n = match (free_strand_tension(model, state, forces), &take_up) {
        (Some(t), _) => t,
        (None, None) => 0.0,
        (None, Some(_)) => return Err(EquilibriumError::NoFreeLinks),
    };
    Ok(StaticEquilibrium {
        tension_n,
        rest_length_m: worn_rest_m,
        iterations,
        residual_speed_m_s: residual,
        force_residual: force_residual(forces, pretension_n),
        beyond_seating_arc: None,
        misfit: None,
        unbalanced: None,
        worn_slack: None,
    })
}
