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
mod arms;
#[cfg(feature = "cli")]
mod auto_step;
mod catenary;
mod checkpoint;
#[cfg(feature = "cli")]
mod checkpoint_cli;
#[cfg(feature = "cli")]
mod cli;
mod common;
mod cosim;
mod cosim_api;
mod cosim_checks;
mod cosim_mistakes;
mod cosim_mounts;
mod cosim_multi;
mod cosim_parking;
mod designations;
mod detectors;
#[cfg(feature = "cli")]
mod docs_drift;
mod equilibrium;
mod equilibrium_errors;
mod equilibrium_sweep;
mod excitation;
mod fatigue;
#[cfg(feature = "cli")]
mod figures;
mod fit;
mod friction;
#[cfg(feature = "lab")]
mod fuzz;
mod governor;
mod guides;
mod integrators;
mod jumps;
mod layering;
#[cfg(feature = "cli")]
mod life;
mod means;
mod orders;
#[cfg(feature = "cli")]
mod outputs;
mod paper;
mod profile;
mod rating;
#[cfg(feature = "record")]
mod record;
#[cfg(feature = "record")]
mod recorded_settings;
#[cfg(feature = "cli")]
mod recover;
#[cfg(feature = "record")]
mod rerun_view;
mod running_tension;
mod scene_errors;
mod seam;
mod statistics;
#[cfg(feature = "cli")]
mod stderr_lines;
mod stepping;
mod strands;
#[cfg(feature = "lab")]
mod stress;
#[cfg(feature = "cli")]
mod study;
#[cfg(feature = "lab")]
mod sweep;
mod tensioners;
mod threads;
mod users;
mod wear;
