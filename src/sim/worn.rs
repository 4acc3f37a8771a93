//! A worn chain on fixed centres (docs/model.md, "A worn chain"): the new
//! chain is brought to its pretension by the rest-length rule, then every
//! link is lengthened by the wear elongation e, in steps, the drive brought
//! to rest after each. The pretension is not restored: what the chain gained
//! in length is slack, and the static tension falls.
//!
//! What this does not do: choose the rest length (the new chain's rule did),
//! or move a tensioner (the tensioner rules lay the worn chain out at once,
//! [`crate::model::DriveModel::build`], and take its length up).

use super::equilibrium::{
    EquilibriumError, RelaxSettings, StaticEquilibrium, force_residual, free_strand_tension,
};
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};

/// Largest lengthening of the links per step, as a fraction of the static
/// link stretch T₀/K: each step then changes the links' forces by at most
/// this fraction of the pretension, which the equilibrium solver takes from
/// the state before without a violent start.
const STEP_OF_STRETCH: f64 = 0.5;

/// Most steps (an elongation of 15 % on the stiffest chains).
const MAX_STEPS: usize = 400;

/// Relative force residual each step's equilibrium aims at.
const REST_FORCE: f64 = 1e-7;

/// Lengthens the links of `model`, settled as a new chain at the pretension
/// `pretension_n`, from their rest length l₀ to l₀ (1 + `elongation`), and
/// brings the drive to rest at each step (module docs). Returns the worn
/// chain's equilibrium: its static tension and rest length.
pub(crate) fn wear_in(
    model: &mut DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    elongation: f64,
    pretension_n: f64,
) -> Result<StaticEquilibrium, EquilibriumError> {
    let new_rest_m = model.rest_length_m;
    let worn_rest_m = new_rest_m * (1.0 + elongation);
    let step_m = STEP_OF_STRETCH * pretension_n / model.stiffness_n_m;
    let steps = ((worn_rest_m - new_rest_m) / step_m)
        .ceil()
        .clamp(1.0, MAX_STEPS as f64) as usize;
    let scale = pretension_n.abs();
    let mut residual = 0.0;
    for k in 1..=steps {
        model.rest_length_m = if k == steps {
            worn_rest_m
        } else {
            new_rest_m + (worn_rest_m - new_rest_m) * (k as f64 / steps as f64)
        };
        residual = super::newton::settle(
            model,
            state,
            forces,
            settings,
            REST_FORCE * scale,
            0.5 * REST_FORCE * scale,
            false,
        )?;
    }
    Ok(StaticEquilibrium {
        tension_n: free_strand_tension(model, state, forces).ok_or(EquilibriumError::NoFreeLinks)?,
        rest_length_m: worn_rest_m,
        iterations: steps,
        residual_speed_m_s: residual,
        force_residual: force_residual(forces, pretension_n),
        beyond_seating_arc: None,
    })
}
