//! The paper's study (Pedersen 2005, section 3): the L60MC drive run with both
//! tooth profiles, the quantities of the paper's results measured
//! (docs/model.md, “The paper's values”), compared with the paper and with the
//! analytical references, and written up as a report.
//!
//! Five runs, each of the same length and settings (e = 0 as in the paper):
//!
//! - `circular`: the circular seating profile at the 21 kN pretension;
//! - `real`: the ASA tooth form at the same pretension (rest length settled anew);
//! - `real_same_rest_length`: the ASA tooth form with the circular run's rest
//!   length, re-relaxed to static equilibrium. The real profile seats each
//!   roller about ΔR deeper, so its static tension drops: most likely what
//!   the paper did (docs/model.md, “The real profile and the rest length”);
//! - `circular_friction`, `real_friction`: both profiles at the 21 kN
//!   pretension with pin–bushing friction at every joint
//!   (`assets/l60mc-friction.toml`).
//!
//! [`run_paper_study`] runs them (in parallel threads), [`Findings::measure`]
//! cuts the numbers, [`report_markdown`] writes the report. Figures are drawn
//! by `figures` (feature `figures`). Nothing here is tuned toward the paper's
//! values: every number is measured from the runs.

use std::panic::AssertUnwindSafe;
use std::time::Instant;

use serde::Serialize;

use super::queue::WorkQueue;
use crate::analysis::binder::centrifugal_tension_n;
use crate::analysis::paper_probes::{
    AnalysisError, BinderComparison, DriveFacts, Probes, RunData, binder_comparison,
    segment_force_series, spectrum_with_peaks, transverse_series,
};
use crate::analysis::spectrum::main_peak;
use crate::analysis::theory::string_frequency_hz;
use crate::analysis::{RunSummary, Signals};
use crate::scene::{Integrator, Overrides, ProfileKind, Scene};
use crate::sim::{
    BlowUpLimits, EquilibriumError, Fanout, RelaxSettings, SampleRate, SimError, Simulation,
    StaticEquilibrium, force_residual, free_strand_tension, relax,
};

mod report;

pub(crate) use report::report_markdown;

/// Labels of the runs, in order.
pub(crate) const RUN_LABELS: [&str; 5] = [
    "circular",
    "real",
    "real_same_rest_length",
    "circular_friction",
    "real_friction",
];

/// The paper's drive with pin–bushing friction (docs/model.md, “Joint friction”).
pub(crate) const L60MC_FRICTION_TOML: &str = include_str!("../../../assets/l60mc-friction.toml");

/// Settings of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StudySettings {
    /// Simulated time of each run, s (the paper: 10 s).
    pub duration_s: f64,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Run the three runs in parallel threads.
    pub parallel: bool,
}

impl Default for StudySettings {
    fn default() -> Self {
        Self {
            duration_s: 10.0,
            rate_hz: 1000.0,
            parallel: true,
        }
    }
}

/// Why the study failed.
#[derive(Debug, thiserror::Error)]
pub(crate) enum StudyError {
    /// A run could not be built or blew up.
    #[error("{label} run: {source}")]
    Sim {
        /// Which run.
        label: String,
        /// Why.
        source: SimError,
    },
    /// A run panicked.
    #[error("{0} run: it panicked")]
    Panicked(String),
    /// A requested series could not be cut.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// Bad settings.
    #[error("{0}")]
    Settings(String),
}

/// Runs `scene` with its own settings, sampling at `rate_hz`; with
/// `rest_length_m`, the links' rest length is set to it after the pretension
/// rule and the drive re-relaxed to static equilibrium (the static tension
/// then follows from the geometry).
pub(crate) fn run_scene(
    label: &str,
    scene: &Scene,
    rate_hz: f64,
    rest_length_m: Option<f64>,
) -> Result<RunData, StudyError> {
    let sim_err = |source: SimError| StudyError::Sim {
        label: label.to_owned(),
        source,
    };
    let sampling = SampleRate::new(rate_hz, scene.solver.dt_s)
        .map_err(|e| StudyError::Settings(e.to_string()))?;
    let setup = Instant::now();
    let mut sim = Simulation::new(scene).map_err(sim_err)?;
    if let Some(rest) = rest_length_m {
        sim.model.rest_length_m = rest;
        let settings = RelaxSettings {
            dt_s: scene.solver.dt_s,
            max_time_s: scene.equilibrium.max_relax_s,
            rate_per_s: 60.0,
            rest_speed_m_s: 1e-6,
            max_stretch_m: BlowUpLimits::for_scene(scene).max_stretch_m,
        };
        let residual = relax(&sim.model, &mut sim.state, &mut sim.forces, &settings)
            .map_err(|e| sim_err(e.into()))?;
        let tension = free_strand_tension(&sim.model, &sim.state, &sim.forces)
            .ok_or_else(|| sim_err(EquilibriumError::NoFreeLinks.into()))?;
        sim.equilibrium = StaticEquilibrium {
            tension_n: tension,
            rest_length_m: rest,
            iterations: sim.equilibrium.iterations + 1,
            residual_speed_m_s: residual,
            force_residual: force_residual(&sim.forces, scene.chain.pretension_n),
            beyond_seating_arc: None,
            misfit: None,
            unbalanced: None,
            worn_slack: None,
        };
        sim.sync_world();
    }
    let setup_wall_s = setup.elapsed().as_secs_f64();
    let (every, rate) = (sampling.every, sampling.rate_hz);
    let duration = scene.solver.duration_s;
    let mut signals = Signals::new(&sim.model, rate, (duration - 1.0).max(0.0));
    let mut probes = Probes::new(&sim.model);
    sim.track_power((duration - 1.0).max(0.0));
    let outcome = sim
        .run(
            duration,
            every,
            &mut Fanout::new().with(&mut signals).with(&mut probes),
            None,
        )
        .map_err(sim_err)?;
    let summary = RunSummary::of_run(&sim, &outcome, &signals, setup_wall_s);
    Ok(RunData {
        label: label.to_owned(),
        facts: DriveFacts::new(&sim.scene, &sim.model),
        signals,
        probes,
        summary,
    })
}

/// The three runs of the study.
pub(crate) struct Study {
    /// Settings used.
    pub settings: StudySettings,
    /// `circular`, `real`, `real_same_rest_length` (see [`RUN_LABELS`]).
    pub runs: Vec<RunData>,
    /// Wall time of the whole study, s.
    pub wall_s: f64,
}

/// Runs the paper's drive three times (see the module docs).
pub(crate) fn run_paper_study(settings: &StudySettings) -> Result<Study, StudyError> {
    if !(settings.duration_s > 0.0 && settings.duration_s.is_finite()) {
        return Err(StudyError::Settings(format!(
            "duration must be positive, got {} s",
            settings.duration_s
        )));
    }
    let started = Instant::now();
    // The study as docs/model.md reports it: symplectic Euler at 10 µs.
    let run = |profile| {
        Scene::l60mc()
            .with(&Overrides {
                duration_s: Some(settings.duration_s),
                profile,
                integrator: Some(Integrator::SymplecticEuler),
                ..Overrides::default()
            })
            .map_err(|e| StudyError::Settings(e.to_string()))
    };
    let circular = run(None)?;
    let real = run(Some(ProfileKind::Real))?;
    let with_friction = |profile| {
        Scene::from_toml(L60MC_FRICTION_TOML)
            .and_then(|s| {
                s.with(&Overrides {
                    duration_s: Some(settings.duration_s),
                    profile,
                    ..Overrides::default()
                })
            })
            .map_err(|e| StudyError::Settings(e.to_string()))
    };
    let circular_friction = with_friction(None)?;
    let real_friction = with_friction(Some(ProfileKind::Real))?;
    // The circular run's rest length, from its static equilibrium (cheap next to the runs).
    let rest = Simulation::new(&circular)
        .map_err(|source| StudyError::Sim {
            label: RUN_LABELS[0].to_owned(),
            source,
        })?
        .model
        .rest_length_m;
    let jobs: [(&str, &Scene, Option<f64>); 5] = [
        (RUN_LABELS[0], &circular, None),
        (RUN_LABELS[1], &real, None),
        (RUN_LABELS[2], &real, Some(rest)),
        (RUN_LABELS[3], &circular_friction, None),
        (RUN_LABELS[4], &real_friction, None),
    ];
    let rate = settings.rate_hz;
    // In parallel, all five at once; a run that panics is that run's error.
    let results = WorkQueue::new(&jobs)
        .threads(if settings.parallel { jobs.len() } else { 1 })
        .run(
            |_, &(label, scene, rest)| {
                let run = AssertUnwindSafe(|| run_scene(label, scene, rate, rest));
                Some(
                    std::panic::catch_unwind(run)
                        .unwrap_or_else(|_| Err(StudyError::Panicked(label.to_owned()))),
                )
            },
            |_, _| {},
        );
    let results = results.into_iter().flatten();
    let runs = results.collect::<Result<Vec<_>, _>>()?;
    Ok(Study {
        settings: *settings,
        runs,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// `summary.json`: `{"circular": …, "real": …, "real_same_rest_length": …}`.
pub(crate) fn summaries_json(study: &Study) -> serde_json::Value {
    let map: serde_json::Map<String, serde_json::Value> = study
        .runs
        .iter()
        .map(|r| {
            (
                r.label.clone(),
                serde_json::to_value(&r.summary).unwrap_or(serde_json::Value::Null),
            )
        })
        .collect();
    serde_json::Value::Object(map)
}

/// One segment's measured quantities.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct SegmentFindings {
    /// 1-based segment.
    pub segment: usize,
    /// Mean average link force over the statistics window, N.
    pub mean_n: f64,
    /// Largest |average link force − mean| over the window, N.
    pub amplitude_n: f64,
    /// Main transverse peak in 1–50 Hz, Hz.
    pub peak_hz: f64,
    /// Moving-string estimate from the segment's own mean force, Hz.
    pub moving_string_hz: f64,
    /// The plain string (52) from the segment's own mean force, Hz.
    pub string_52_hz: f64,
    /// Pretension-plus-centrifugal estimate of the mean, N.
    pub static_plus_qc_n: f64,
    /// Highest transverse peaks in 1–200 Hz, (Hz, m), highest first.
    pub peaks: Vec<(f64, f64)>,
}

/// One run's measured quantities.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RunFindings {
    /// Run label.
    pub label: String,
    /// Static tension, N.
    pub static_tension_n: f64,
    /// Rest length, m.
    pub rest_length_m: f64,
    /// Centrifugal tension at the mean chain speed, N.
    pub q_c_n: f64,
    /// Per segment.
    pub segments: Vec<SegmentFindings>,
    /// Per sprocket: the comparison with (49), or why there is none.
    pub binder: Vec<Result<BinderComparison, AnalysisError>>,
    /// Wall time per step, ns.
    pub ns_per_step: f64,
}

/// What the report states, measured from the study.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Findings {
    /// Per run, in [`RUN_LABELS`] order.
    pub runs: Vec<RunFindings>,
}

impl Findings {
    /// Measures the study.
    pub(crate) fn measure(study: &Study) -> Result<Self, StudyError> {
        let runs = study
            .runs
            .iter()
            .map(measure_run)
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { runs })
    }
}

fn measure_run(data: &RunData) -> Result<RunFindings, StudyError> {
    let s = &data.summary;
    let driver_speed = s
        .sprockets
        .first()
        .map_or(0.0, |sp| sp.mean_speed_rad_s.abs());
    let v = driver_speed * data.facts.pitch_radius_m.first().copied().unwrap_or(0.0);
    let q_c = centrifugal_tension_n(data.facts.roller_mass_kg, v, data.facts.pitch_m);
    let mu = data.facts.roller_mass_kg / data.facts.pitch_m;
    let mut segments = Vec::new();
    for (strand, seg) in s.strands.iter().zip(&s.segments) {
        let force = segment_force_series(data, seg.segment, s.window_s)?;
        let transverse = transverse_series(data, seg.segment, data.spectrum_window_s())?;
        let picked = spectrum_with_peaks(&transverse, s.sample_rate_hz, [1.0, 200.0], 6, 2.0);
        // The summary's peak, over the same window (which may be the whole run when short).
        let peak_hz =
            main_peak(&transverse.value, s.sample_rate_hz, 1.0, 50.0).map_or(0.0, |p| p.0);
        segments.push(SegmentFindings {
            segment: seg.segment,
            mean_n: force.mean(),
            amplitude_n: force.amplitude(),
            peak_hz,
            moving_string_hz: seg.string_f1_hz,
            string_52_hz: string_frequency_hz(
                1,
                force.mean(),
                strand.length_m,
                mu * strand.length_m,
            ),
            static_plus_qc_n: s.static_tension_n + q_c,
            peaks: picked.peaks,
        });
    }
    let binder = (1..=data.facts.teeth.len())
        .map(|k| binder_comparison(data, k, data.steady_window_s()))
        .collect();
    Ok(RunFindings {
        label: data.label.clone(),
        static_tension_n: s.static_tension_n,
        rest_length_m: s.rest_length_m,
        q_c_n: q_c,
        segments,
        binder,
        ns_per_step: s.ns_per_step,
    })
}
