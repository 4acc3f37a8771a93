//! Studies: experiments that drive simulations — many runs of a scene under
//! changed settings — and measure them with [`crate::analysis`].
//!
//! - [`reproduce`]: the paper's study (both tooth profiles, the quantities
//!   the paper reports, compared with it and with the analytical references);
//! - [`stress`]: the stability matrix of hard cases × integrators × steps;
//! - [`work_precision`]: wall time against error for every integrator;
//! - [`convergence`]: the summary statistics of every integrator over a
//!   ladder of steps against a fine reference;
//! - [`sweep`]: one steady run per driver speed, in parallel, with order
//!   spectra and each span's natural frequencies (Campbell diagrams);
//! - [`soak`]: a long run reported window by window, to show there is no drift;
//! - [`fuzz`]: one mutated scene file through parsing, layout and a short run;
//! - [`study`]: a design study (factors × levels of a scene) run here or as
//!   a Slurm job array, its results merged into one table;
//! - [`duty`]: a duty cycle's operating points run as a study and combined
//!   by hours into the chain's life.
//!
//! Every batch of runs goes through one work queue ([`queue`]); the studies
//! that compare integrators share their ladders of settings ([`ladder`]);
//! a run that starts from a settled drive forks it
//! ([`crate::sim::Simulation::fork`]).
//!
//! What a single run's signals mean and how they are measured is
//! [`crate::analysis`]'s business; writing files and printing tables is the
//! command-line tool's (`chaindrive reproduce`, `chaindrive bench …`).

pub(crate) mod convergence;
pub(crate) mod duty;
pub(crate) mod fuzz;
#[cfg(test)]
mod fuzz_tests;
pub(crate) mod jump_margin;
pub(crate) mod ladder;
pub(crate) mod queue;
pub(crate) mod reproduce;
pub(crate) mod soak;
pub(crate) mod stress;
#[cfg(test)]
mod stress_tests;
pub(crate) mod study;
#[cfg(all(test, feature = "cli"))]
mod study_tests;
pub(crate) mod sweep;
#[cfg(test)]
mod sweep_tests;
pub(crate) mod work_precision;
