//! Design checks: is the chain big enough for the drive? (docs/design-checks.md)
//!
//! - [`rating`]: the catalogue power rating of the chain at the smallest
//!   sprocket's teeth and speed (the formulas behind the ANSI horsepower
//!   tables), the lubrication it assumes, the chain speed, each sprocket's
//!   tooth-passing frequency, the rigid-chain polygonal speed variation, and
//!   the static safety factors of a run's link forces against the chain's
//!   tensile strength.
//!
//! These are pure functions of a scene and, for a run, of its summary: they
//! step nothing and read no signals. Fatigue (rainflow counting of every
//! link's force, an S–N model, Miner's rule), wear and duty cycles are not
//! here yet.

pub mod rating;

pub use rating::{Lubrication, Rating, RatingError, RatingSettings};
