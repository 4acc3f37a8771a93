//! Integration tests: one binary, one module per topic. Every expected
//! number comes from outside the code under test (the paper's Table 4,
//! closed forms, the public contract), with its source in a comment.
//!
//! Modules that drive the `chaindrive` binary, read MCAP recordings or draw
//! figures need the features that build those (`cli`, `record`, `figures`);
//! `cargo test --no-default-features` runs the rest.

mod analysis;
#[cfg(feature = "cli")]
mod analyze;
#[cfg(feature = "cli")]
mod arms;
#[cfg(feature = "cli")]
mod auto_step;
mod checkpoint;
#[cfg(feature = "cli")]
mod checkpoint_cli;
#[cfg(feature = "cli")]
mod cli;
mod common;
mod cosim_mistakes;
mod cosim_multi;
mod detectors;
#[cfg(feature = "cli")]
mod docs_drift;
mod fatigue;
#[cfg(feature = "cli")]
mod figures;
mod fit;
mod integrators;
mod layering;
#[cfg(feature = "cli")]
mod life;
#[cfg(feature = "cli")]
mod outputs;
mod profile;
#[cfg(feature = "record")]
mod record;
#[cfg(feature = "cli")]
mod recover;
mod statistics;
#[cfg(feature = "cli")]
mod stderr_lines;
mod stress;
#[cfg(feature = "cli")]
mod study;
#[cfg(feature = "lab")]
mod sweep;
mod users;
#[cfg(feature = "cli")]
mod worn;
#[cfg(feature = "cli")]
mod worn_tensioned;
