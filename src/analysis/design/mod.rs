//! Design checks: is the chain big enough for the drive? (docs/design-checks.md)
//!
//! - [`rating`]: the catalogue power rating of the chain at the smallest
//!   sprocket's teeth and speed (the formulas behind the ANSI horsepower
//!   tables), the lubrication it assumes, the chain speed, each sprocket's
//!   tooth-passing frequency, the rigid-chain polygonal speed variation, and
//!   the static safety factors of a run's link forces against the chain's
//!   tensile strength.
//!
//! - [`wear`]: Archard's wear at every joint from the sliding counted every
//!   step of a run, the chain's elongation rate (% per 1000 h) and its life
//!   to the allowable elongation.
//! - [`life`]: a life in hours, or infinite.
//!
//! These are pure functions of a scene and, for a run, of its summary and
//! of what was counted during it: they step nothing and read no sampled
//! signals. Fatigue (rainflow counting of every link's force, an S–N model,
//! Miner's rule) and duty cycles are not here yet.

pub mod life;
pub mod rating;
pub mod wear;

pub use life::Life;
pub use rating::{Lubrication, Rating, RatingError, RatingSettings};
pub use wear::{Wear, WearModel};
