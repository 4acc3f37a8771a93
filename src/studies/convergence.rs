//! Convergence of the statistics a user reads (`chaindrive bench
//! convergence`): every integrator over a ladder of steps (or tolerances),
//! each run's summary statistics against a fine reference.
//!
//! Trajectories of this impact-driven system part within tens of
//! milliseconds, so a trajectory error over a long run measures that, not the
//! integrator ([`super::work_precision`] keeps its horizon short for this
//! reason). The statistics — means, RMS, spectral peaks, extremes over a
//! window of seconds — are what must converge.
//!
//! # The measure
//!
//! The scene is settled and run with its own settings through `warmup_s`;
//! every run, the reference's included, starts from a copy of that state and
//! runs `duration_s` with its method, sampled at `rate_hz`; its summary
//! ([`RunSummary`]) is taken over the whole `duration_s`. The statistics
//! compared are the rows of [`STATISTICS`], one line each. A statistic is
//! *converged* when it lies within [`REL_TOLERANCE`] of the reference's or
//! within [`SE_TOLERANCE`] of the reference's own standard error; the
//! verdict is the cheapest run (wall time) at which all are; the robust
//! verdict, the cheapest whose finer settings of the same method all are too.
//!
//! # Standard errors
//!
//! Means carry their standard error by batch means, RMS values theirs by the
//! delta method ([`crate::analysis::stats`]). A spectral peak carries half the
//! frequency resolution, 1 / (2 T), in place of a standard error. Extremes
//! (the deepest penetration) carry none: only the relative tolerance applies.
//!
//! # The reference
//!
//! Symplectic Euler at 1 µs by default, below every step of the ladders.

use std::time::Instant;

use super::ladder::{Ladder, LadderError, LadderRun, Rung, Setting, warm};
use super::queue::WorkQueue;
use crate::analysis::stats::{rms_about_mean, rms_standard_error, standard_error};
use crate::analysis::{RunSummary, SampleRow, Signals};
use crate::scene::{Integrator, Scene};
use crate::sim::{SampleRate, Simulation};

/// Relative tolerance of a converged statistic.
pub const REL_TOLERANCE: f64 = 0.01;

/// A converged statistic may instead lie within this many of the reference's standard errors.
pub const SE_TOLERANCE: f64 = 2.0;

/// What to study.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Time run with the scene's own settings before every run, s.
    pub warmup_s: f64,
    /// Simulated time of each run after the warm-up, s.
    pub duration_s: f64,
    /// Sampling rate, Hz.
    pub rate_hz: f64,
    /// Methods and their settings.
    pub ladder: Ladder,
    /// The reference's method and setting.
    pub reference: Rung,
    /// Runs in parallel.
    pub threads: usize,
}

impl Settings {
    /// The default study: the fixed-step schemes from 5 µs to 50 µs (steps
    /// that divide the 1 ms sampling interval), the adaptive scheme from
    /// tolerance 10⁻² to 10⁻⁴; symplectic Euler at 1 µs as the reference.
    pub fn default_for(duration_s: f64) -> Self {
        Self {
            warmup_s: 1.2,
            duration_s,
            rate_hz: 1000.0,
            ladder: Ladder::every_scheme(&[5e-6, 1e-5, 2e-5, 4e-5, 5e-5], &[1e-2, 1e-3, 1e-4]),
            reference: Rung {
                integrator: Integrator::SymplecticEuler,
                setting: Setting::Step(1e-6),
            },
            threads: 2,
        }
    }
}

/// One statistic of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct Statistic {
    /// Name, with its segment or sprocket (`seg1_mean_link_force_n`).
    pub name: String,
    /// Value.
    pub value: f64,
    /// Its standard error (or the stand-in of the module docs), if it has one.
    pub se: Option<f64>,
}

/// What a statistic is measured on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Per {
    /// Each segment (`seg{k}_` prefix).
    Segment,
    /// Each sprocket but the driver, whose speed is prescribed (`sprocket{j}_` prefix).
    Sprocket,
    /// The run.
    Run,
}

/// A run's summary with the samples of its window, for the extractors.
pub struct Measured<'a> {
    /// The summary.
    pub summary: &'a RunSummary,
    /// The window's samples.
    pub rows: &'a [&'a SampleRow],
    /// The driver's index, if the drive has one.
    pub driver: Option<usize>,
}

impl Measured<'_> {
    fn segment(&self, k: usize) -> Vec<f64> {
        crate::analysis::segment_series(self.rows, k)
    }

    fn speed(&self, j: usize) -> Vec<f64> {
        self.rows.iter().map(|r| r.omega_rad_s[j]).collect()
    }

    fn driver_power(&self) -> Vec<f64> {
        let Some(d) = self.driver else {
            return Vec::new();
        };
        self.rows
            .iter()
            .map(|r| -r.chain_torque_n_m[d] * r.omega_rad_s[d])
            .collect()
    }
}

/// Value and standard error of a statistic of segment, sprocket or run `i`.
pub type Extract = fn(&Measured<'_>, usize) -> (f64, Option<f64>);

/// The statistics compared: name, what it is measured on, how. A field of
/// the summary without a standard error is one line:
/// `("name_w", Per::Run, |m, _| (m.summary.name_w, None))`.
pub const STATISTICS: &[(&str, Per, Extract)] = &[
    ("mean_link_force_n", Per::Segment, |m, k| {
        let s = &m.summary.segments[k];
        (s.mean_link_force_n, Some(s.mean_link_force_se_n))
    }),
    ("link_force_rms_n", Per::Segment, |m, k| {
        let x = m.segment(k);
        (rms_about_mean(&x), Some(rms_standard_error(&x)))
    }),
    ("transverse_peak_hz", Per::Segment, |m, k| {
        let w = m.summary.spectrum_window_s;
        let half_bin = 0.5 / (w[1] - w[0]).max(f64::MIN_POSITIVE);
        (m.summary.segments[k].transverse_peak_hz, Some(half_bin))
    }),
    ("speed_rms_rad_s", Per::Sprocket, |m, j| {
        let x = m.speed(j);
        (rms_about_mean(&x), Some(rms_standard_error(&x)))
    }),
    ("max_penetration_m", Per::Run, |m, _| {
        (m.summary.max_penetration_m, None)
    }),
    ("driver_mean_power_w", Per::Run, |m, _| {
        (
            m.summary.driver_mean_power_w,
            Some(standard_error(&m.driver_power())),
        )
    }),
    ("joint_friction_power_w", Per::Run, |m, _| {
        (m.summary.joint_friction_power_w.unwrap_or(0.0), None)
    }),
];

/// Every statistic of [`STATISTICS`] of a measured run.
pub fn statistics(m: &Measured<'_>) -> Vec<Statistic> {
    let mut out = Vec::new();
    for (name, per, extract) in STATISTICS {
        let (indices, prefix): (Vec<usize>, &str) = match per {
            Per::Segment => ((0..m.summary.segments.len()).collect(), "seg"),
            Per::Sprocket => (
                (0..m.summary.sprockets.len())
                    .filter(|&j| Some(j) != m.driver)
                    .collect(),
                "sprocket",
            ),
            Per::Run => (vec![0], ""),
        };
        for i in indices {
            let (value, se) = extract(m, i);
            let name = if prefix.is_empty() {
                (*name).to_owned()
            } else {
                format!("{prefix}{}_{name}", i + 1)
            };
            out.push(Statistic {
                name,
                value,
                se: se.filter(|s| s.is_finite()),
            });
        }
    }
    out
}

/// One run of one method: its statistics, or why it stopped.
pub type Run = LadderRun<Vec<Statistic>>;

/// One statistic of a run against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Compared {
    /// Name.
    pub name: String,
    /// The run's value (`None`: the run failed).
    pub value: Option<f64>,
    /// The reference's value.
    pub reference: f64,
    /// The reference's standard error, if it has one.
    pub reference_se: Option<f64>,
    /// (value − reference) / |reference| (0 when both are 0, ∞ when only the reference is, or the run failed).
    pub rel_error: f64,
    /// Whether it is converged (module docs).
    pub converged: bool,
}

impl Compared {
    /// |value − reference| in reference standard errors, if defined.
    pub fn se_error(&self) -> Option<f64> {
        let (v, se) = (self.value?, self.reference_se?);
        (se > 0.0).then(|| (v - self.reference).abs() / se)
    }

    /// |value − reference| over the larger of the two allowances,
    /// [`REL_TOLERANCE`] |reference| and [`SE_TOLERANCE`] × its standard
    /// error: converged exactly when at most 1 (∞ for a failed run).
    pub fn normalized_error(&self) -> f64 {
        let Some(v) = self.value else {
            return f64::INFINITY;
        };
        let d = (v - self.reference).abs();
        let allowed = (REL_TOLERANCE * self.reference.abs())
            .max(SE_TOLERANCE * self.reference_se.unwrap_or(0.0));
        if allowed > 0.0 {
            d / allowed
        } else if d == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

/// The study's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Convergence {
    /// The reference run.
    pub reference: Run,
    /// The ladder runs, method by method.
    pub runs: Vec<Run>,
}

impl Convergence {
    /// A run's statistics against the reference (empty if the reference failed).
    pub fn compare(&self, run: &Run) -> Vec<Compared> {
        let Ok(reference) = &self.reference.outcome else {
            return Vec::new();
        };
        reference
            .iter()
            .map(|r| {
                let value = run
                    .outcome
                    .as_ref()
                    .ok()
                    .and_then(|s| s.iter().find(|s| s.name == r.name))
                    .map(|s| s.value);
                compare_one(r, value)
            })
            .collect()
    }

    /// Whether every statistic of `run` is converged.
    pub fn converged(&self, run: &Run) -> bool {
        run.outcome.is_ok() && self.compare(run).iter().all(|c| c.converged)
    }

    /// The cheapest converged run (wall time), if any.
    pub fn verdict(&self) -> Option<&Run> {
        self.runs
            .iter()
            .filter(|r| self.converged(r))
            .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
    }

    /// The cheapest converged run whose finer settings (smaller step or
    /// tolerance, same method) are all converged too: a converged coarse
    /// run between failing finer ones agrees by chance, not by convergence.
    pub fn robust_verdict(&self) -> Option<&Run> {
        let finer = |a: &Run, b: &Run| a.setting.finer_than(b.setting);
        self.runs
            .iter()
            .filter(|r| {
                self.converged(r)
                    && self
                        .runs
                        .iter()
                        .filter(|o| o.integrator == r.integrator && finer(o, r))
                        .all(|o| self.converged(o))
            })
            .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
    }
}

fn compare_one(r: &Statistic, value: Option<f64>) -> Compared {
    let (rel_error, converged) = match value {
        None => (f64::INFINITY, false),
        Some(v) => {
            let d = v - r.value;
            let rel = if r.value != 0.0 {
                d / r.value.abs()
            } else if d == 0.0 {
                0.0
            } else {
                f64::INFINITY.copysign(d)
            };
            let within_se = r.se.is_some_and(|se| d.abs() <= SE_TOLERANCE * se);
            (rel, rel.abs() <= REL_TOLERANCE || within_se)
        }
    };
    Compared {
        name: r.name.clone(),
        value,
        reference: r.value,
        reference_se: r.se,
        rel_error,
        converged,
    }
}

/// Runs `duration_s` from the warm `base` with one method.
pub fn run_one(base: &Simulation, rung: Rung, settings: &Settings) -> Run {
    let max_step_s = 1.0 / settings.rate_hz;
    let nominal_dt = rung.setting.step_s(max_step_s);
    let mut sim = match base.fork(&rung.overrides(max_step_s)) {
        Ok(sim) => sim,
        Err(e) => return Run::failed(rung, nominal_dt, e.to_string()),
    };
    let sampling = match SampleRate::new(settings.rate_hz, sim.scene.solver.dt_s) {
        Ok(s) => s,
        Err(e) => return Run::failed(rung, nominal_dt, e.to_string()),
    };
    let t0 = sim.state.t_s;
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, t0);
    // The power flow over the whole statistics window (`joint_friction_power_w`).
    sim.track_power(t0);
    let started = Instant::now();
    let outcome = sim.run(t0 + settings.duration_s, sampling.every, &mut signals, None);
    let wall_s = started.elapsed().as_secs_f64();
    let outcome = match outcome {
        Ok(o) => o,
        Err(e) => {
            let mut run = Run::failed(rung, nominal_dt, e.to_string());
            run.wall_s = wall_s;
            run.sim_s = sim.state.t_s - t0;
            return run;
        }
    };
    let summary = RunSummary::of_run_over(&sim, &outcome, &signals, 0.0, settings.duration_s);
    let rows: Vec<&SampleRow> = signals
        .rows
        .iter()
        .filter(|r| r.t_s > summary.window_s[0] && r.t_s <= summary.window_s[1])
        .collect();
    let stats = statistics(&Measured {
        summary: &summary,
        rows: &rows,
        driver: sim.model.driver(),
    });
    let work = sim.integration.stats;
    Run {
        integrator: rung.integrator,
        setting: rung.setting,
        dt_s: rung.setting.mean_step_s(settings.duration_s, work.steps),
        wall_s,
        sim_s: sim.state.t_s - t0,
        stats: work,
        outcome: Ok(stats),
    }
}

/// Runs the study on `settings.threads` threads. `progress` is called with
/// each finished run (from the calling thread).
///
/// # Errors
///
/// The warm start cannot be made, or the reference run fails.
pub fn study(
    scene: &Scene,
    settings: &Settings,
    mut progress: impl FnMut(&Run),
) -> Result<Convergence, LadderError> {
    let base = warm(scene, settings.warmup_s)?;
    // The reference first: it is the longest.
    let rungs: Vec<Rung> = std::iter::once(settings.reference)
        .chain(settings.ladder.rungs())
        .collect();
    let mut runs = WorkQueue::new(&rungs)
        .threads(settings.threads)
        .run(
            |_, &rung| Some(run_one(&base, rung, settings)),
            |_, run| progress(run),
        )
        .into_iter()
        .flatten();
    let reference = runs
        .next()
        .ok_or_else(|| LadderError::reference(settings.reference, "not run".to_owned()))?;
    if let Err(e) = &reference.outcome {
        return Err(LadderError::reference(settings.reference, e.clone()));
    }
    Ok(Convergence {
        reference,
        runs: runs.collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stat(name: &str, value: f64, se: Option<f64>) -> Statistic {
        Statistic {
            name: name.to_owned(),
            value,
            se,
        }
    }

    #[test]
    fn converged_within_one_percent_or_two_standard_errors() {
        // 100 ± 2: 101 is within 1 %; 103.9 within 2 SE; 104.1 neither.
        let r = stat("a", 100.0, Some(2.0));
        assert!(compare_one(&r, Some(101.0)).converged);
        assert!(compare_one(&r, Some(103.9)).converged);
        let c = compare_one(&r, Some(104.1));
        assert!(!c.converged);
        assert!((c.rel_error - 0.041).abs() < 1e-12);
        assert!((c.se_error().expect("se") - 2.05).abs() < 1e-12);
        // Allowance max(1 % × 100, 2 × 2) = 4: 4.1 / 4.
        assert!((c.normalized_error() - 1.025).abs() < 1e-12);
        assert!(compare_one(&r, Some(103.9)).normalized_error() <= 1.0);
        // No SE: only 1 %.
        let r = stat("b", 100.0, None);
        assert!(!compare_one(&r, Some(101.5)).converged);
        // Zero reference: equal is converged, anything else infinitely wrong, never NaN.
        let z = stat("c", 0.0, None);
        assert_eq!(compare_one(&z, Some(0.0)).rel_error, 0.0);
        assert_eq!(compare_one(&z, Some(-1.0)).rel_error, f64::NEG_INFINITY);
        assert!(!compare_one(&z, None).converged);
    }

    #[test]
    fn the_robust_verdict_needs_every_finer_setting_converged() {
        // Reference 100 ± 1. Steps 10, 20, 40 µs give 100.5 (converged),
        // 103 (not), 100.2 (converged by chance): the verdict is the
        // cheapest, 40 µs; the robust verdict 10 µs.
        let run = |dt: f64, value: f64, wall_s: f64| Run {
            integrator: Integrator::SymplecticEuler,
            setting: Setting::Step(dt),
            dt_s: dt,
            wall_s,
            sim_s: 1.0,
            stats: Default::default(),
            outcome: Ok(vec![stat("a", value, None)]),
        };
        let mut reference = run(1e-6, 100.0, 10.0);
        reference.outcome = Ok(vec![stat("a", 100.0, Some(1.0))]);
        let c = Convergence {
            reference,
            runs: vec![
                run(1e-5, 100.5, 1.0),
                run(2e-5, 103.0, 0.5),
                run(4e-5, 100.2, 0.25),
            ],
        };
        assert_eq!(c.verdict().map(|r| r.dt_s), Some(4e-5));
        assert_eq!(c.robust_verdict().map(|r| r.dt_s), Some(1e-5));
    }
}
