//! The statics: the drive at rest before t = 0. The relaxation
//! (`relax`), the pretension rule's iteration around it (`equilibrium`),
//! Newton's settling of the last digits (`newton`), the circular profile's
//! rim where no rest state exists (`feasibility`), and moving one sprocket
//! until the chain fits its path (`fit`); their errors in `error`. Nothing
//! here steps a run: that is the rest of `sim`.

#[cfg(test)]
mod arms_tests;
mod counts;
mod equilibrium;
mod error;
mod feasibility;
mod fit;
mod free;
mod hold;
mod misfit;
#[cfg(test)]
pub(crate) use error::BeyondSeatingArc;
mod newton;
mod relax;
mod tangent;
mod taut;
mod tension;

pub(crate) use counts::count_verdicts;
#[cfg(test)]
pub(crate) use counts::fitting_counts;
pub use equilibrium::StaticEquilibrium;
pub(crate) use equilibrium::{REST_FORCE, force_residual, settle_preload, settle_rest_length};
pub use error::{EquilibriumError, FitError};
pub(crate) use feasibility::{check_chain_length, check_load};
pub(crate) use fit::{
    FIT_TOLERANCE_M, arm_take_up_of, default_direction, fit_sprocket, needed_pitches_of,
};
pub(crate) use free::{let_go, sprocket_to_hold};
pub(crate) use misfit::{misfit_tension, worn_slack};
pub(crate) use newton::{settle, settle_from};
#[cfg(test)]
pub(crate) use relax::RELAXATIONS;
pub(crate) use relax::{RelaxSettings, relax};
pub(crate) use tension::free_strand_tension;
