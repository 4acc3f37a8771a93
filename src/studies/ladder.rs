//! Ladders of integrator settings, shared by the studies that compare
//! integrators ([`super::convergence`], [`super::work_precision`]): the
//! methods compared and the steps (or, for the adaptive scheme, the
//! tolerances) each is run at, the warm start every run begins from, and
//! one run of one rung.
//!
//! What a run measures and how it is judged is each study's own; this
//! module only names the rungs and what every run of a rung reports.

use crate::scene::{Integrator, Overrides, Scene};
use crate::sim::{IntegrationStats, NoObserver, SimError, Simulation};

/// A step size or, for the adaptive scheme, a tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Setting {
    /// A fixed step, s.
    Step(f64),
    /// An error tolerance (the adaptive scheme; its largest step is the
    /// study's sampling interval).
    Tolerance(f64),
}

impl Setting {
    /// `dt=…` or `tol=…`.
    pub(crate) fn label(&self) -> String {
        match self {
            Self::Step(dt) => format!("dt={dt:e}"),
            Self::Tolerance(tol) => format!("tol={tol:e}"),
        }
    }

    /// The step a run is given: the fixed step, or `max_step_s` (the
    /// adaptive scheme's largest step).
    pub(crate) fn step_s(self, max_step_s: f64) -> f64 {
        match self {
            Self::Step(dt) => dt,
            Self::Tolerance(_) => max_step_s,
        }
    }

    /// The step a run of `duration_s` took: the fixed step, or the mean
    /// accepted step of the adaptive scheme over `steps` steps.
    pub(crate) fn mean_step_s(self, duration_s: f64, steps: u64) -> f64 {
        match self {
            Self::Step(dt) => dt,
            Self::Tolerance(_) => duration_s / steps.max(1) as f64,
        }
    }

    /// Whether `self` is finer than `other`: a smaller step, or a smaller
    /// tolerance (never across the two kinds).
    pub(crate) fn finer_than(self, other: Self) -> bool {
        match (self, other) {
            (Self::Step(a), Self::Step(b)) | (Self::Tolerance(a), Self::Tolerance(b)) => a < b,
            _ => false,
        }
    }
}

/// One rung: a method at one setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rung {
    /// The method.
    pub integrator: Integrator,
    /// Its setting.
    pub setting: Setting,
}

impl Rung {
    /// The scene overrides that run this rung; an adaptive scheme's largest
    /// step is `max_step_s`.
    pub(crate) fn overrides(self, max_step_s: f64) -> Overrides {
        Overrides {
            integrator: Some(self.integrator),
            dt_s: Some(self.setting.step_s(max_step_s)),
            tolerance: match self.setting {
                Setting::Step(_) => None,
                Setting::Tolerance(tol) => Some(tol),
            },
            ..Overrides::default()
        }
    }
}

/// The methods a study compares, each with its settings from fine to coarse.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Ladder {
    /// Methods and their settings.
    pub methods: Vec<(Integrator, Vec<Setting>)>,
}

impl Ladder {
    /// Every scheme: the five fixed-step ones at `steps_s`, Dormand–Prince
    /// 5(4) at `tolerances`.
    pub(crate) fn every_scheme(steps_s: &[f64], tolerances: &[f64]) -> Self {
        let steps: Vec<Setting> = steps_s.iter().map(|&d| Setting::Step(d)).collect();
        Self {
            methods: vec![
                (Integrator::SymplecticEuler, steps.clone()),
                (Integrator::ImplicitDamping, steps.clone()),
                (Integrator::VelocityVerlet, steps.clone()),
                (Integrator::VerletImplicitDamping, steps.clone()),
                (Integrator::Rk4, steps),
                (
                    Integrator::DormandPrince45,
                    tolerances.iter().map(|&t| Setting::Tolerance(t)).collect(),
                ),
            ],
        }
    }

    /// Every rung, method by method.
    pub(crate) fn rungs(&self) -> impl Iterator<Item = Rung> + '_ {
        self.methods.iter().flat_map(|(integrator, settings)| {
            settings.iter().map(|&setting| Rung {
                integrator: *integrator,
                setting,
            })
        })
    }
}

/// One run of one rung; `T` is what the study measured.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LadderRun<T> {
    /// The method.
    pub integrator: Integrator,
    /// Its setting.
    pub setting: Setting,
    /// Step (fixed) or mean accepted step (adaptive), s.
    pub dt_s: f64,
    /// Wall time of the run, s.
    pub wall_s: f64,
    /// Simulated time reached, s.
    pub sim_s: f64,
    /// Work counters.
    pub stats: IntegrationStats,
    /// What was measured, or why the run stopped.
    pub outcome: Result<T, String>,
}

impl<T> LadderRun<T> {
    /// A run of `rung` that stopped before measuring anything.
    pub(crate) fn failed(rung: Rung, dt_s: f64, why: String) -> Self {
        Self {
            integrator: rung.integrator,
            setting: rung.setting,
            dt_s,
            wall_s: 0.0,
            sim_s: 0.0,
            stats: IntegrationStats::default(),
            outcome: Err(why),
        }
    }
}

/// The warm start of a ladder: `scene` built, settled and run `warmup_s`
/// with its own settings. Every run of the ladder starts from a copy.
///
/// # Errors
///
/// The drive cannot be laid out or settled, or the warm-up blows up.
pub(crate) fn warm(scene: &Scene, warmup_s: f64) -> Result<Simulation, SimError> {
    let mut sim = Simulation::new(scene)?;
    sim.run(warmup_s, u64::MAX, &mut NoObserver, None)?;
    Ok(sim)
}

/// Why a ladder study could not be made.
#[derive(Debug, thiserror::Error)]
pub(crate) enum LadderError {
    /// The warm start could not be built or run.
    #[error(transparent)]
    Start(#[from] SimError),
    /// The reference run itself failed.
    #[error("the reference run ({method}) failed: {why}")]
    Reference {
        /// Its method and setting.
        method: String,
        /// Why.
        why: String,
    },
}

impl LadderError {
    /// The reference `rung` failed for `why`.
    pub(crate) fn reference(rung: Rung, why: String) -> Self {
        Self::Reference {
            method: format!("{} {}", rung.integrator.name(), rung.setting.label()),
            why,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_adaptive_rung_runs_at_its_tolerance_with_the_largest_step() {
        let rung = Rung {
            integrator: Integrator::DormandPrince45,
            setting: Setting::Tolerance(1e-4),
        };
        let o = rung.overrides(1e-3);
        assert_eq!(o.dt_s, Some(1e-3));
        assert_eq!(o.tolerance, Some(1e-4));
        let fixed = Rung {
            integrator: Integrator::Rk4,
            setting: Setting::Step(2e-5),
        };
        assert_eq!(fixed.overrides(1e-3).dt_s, Some(2e-5));
        assert_eq!(fixed.overrides(1e-3).tolerance, None);
    }

    #[test]
    fn the_mean_step_of_an_adaptive_run_is_its_time_over_its_steps() {
        // 0.1 s in 400 steps: 250 µs; no step at all counts as one.
        assert_eq!(Setting::Tolerance(1e-3).mean_step_s(0.1, 400), 0.1 / 400.0);
        assert_eq!(Setting::Tolerance(1e-3).mean_step_s(0.1, 0), 0.1);
        assert_eq!(Setting::Step(1e-5).mean_step_s(0.1, 7), 1e-5);
    }

    #[test]
    fn finer_compares_only_settings_of_one_kind() {
        assert!(Setting::Step(1e-5).finer_than(Setting::Step(2e-5)));
        assert!(!Setting::Step(2e-5).finer_than(Setting::Step(1e-5)));
        assert!(!Setting::Step(1e-9).finer_than(Setting::Tolerance(1.0)));
    }

    #[test]
    fn rungs_go_method_by_method_fine_to_coarse() {
        let ladder = Ladder::every_scheme(&[1e-5, 2e-5], &[1e-3]);
        let rungs: Vec<Rung> = ladder.rungs().collect();
        assert_eq!(rungs.len(), 5 * 2 + 1);
        assert_eq!(rungs[1].integrator, Integrator::SymplecticEuler);
        assert_eq!(rungs[1].setting, Setting::Step(2e-5));
        assert_eq!(rungs[10].setting, Setting::Tolerance(1e-3));
    }
}
