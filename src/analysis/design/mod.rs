//! Design checks: is the chain big enough for the drive, and for how many
//! hours? (docs/design-checks.md)
//!
//! - [`rating`]: the catalogue power rating of the chain at the smallest
//!   sprocket's teeth and speed (the formulas behind the ANSI horsepower
//!   tables), the lubrication it assumes, the chain speed, each sprocket's
//!   tooth-passing frequency, the rigid-chain polygonal speed variation, and
//!   the static safety factors of a run's link forces against the chain's
//!   tensile strength.
//! - [`fatigue`]: the link plates' S–N curve (derived from the rating, or
//!   the scene's own), Miner's damage per hour and the life; the curve with
//!   Goodman's mean-stress correction is [`sn_curve`]'s; [`link_cycles`]
//!   counts every link's force by [`rainflow`] as the steps come.
//! - [`wear`]: Archard's wear at every joint from the sliding counted every
//!   step of a run, the chain's elongation rate (% per 1000 h) and its life
//!   to the allowable elongation.
//! - [`life`]: a life in hours, or infinite.
//!
//! The checks are pure functions of a scene and, for a run, of its summary
//! and of what was counted during it (link cycles, joint sliding): they
//! step nothing and read no sampled signals. Duty cycles are run by `studies::duty`.

pub(crate) mod fatigue;
pub(crate) mod life;
pub(crate) mod link_cycles;
pub(crate) mod rainflow;
pub(crate) mod rating;
pub(crate) mod sn_curve;
pub(crate) mod wear;
#[cfg(test)]
mod wear_tests;

pub(crate) use fatigue::Fatigue;
pub(crate) use life::Life;
pub(crate) use link_cycles::LinkCycles;
pub(crate) use rating::Rating;
pub(crate) use wear::Wear;
