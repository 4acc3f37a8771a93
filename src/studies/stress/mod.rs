//! The stress matrix (`chaindrive bench stress`): hard cases around the
//! paper's drive, each run by every integrator on a ladder of steps, to find
//! where each scheme stops being stable, what the blow-up detectors say when
//! it does, and what a simulated second costs.
//!
//! # The matrix
//!
//! One factor at a time around the paper's drive (the *baseline*: 122
//! rollers, 4 sprockets, 120 rpm, e = 0, D = 250 N·s/m ≈ 0.25 % of the
//! single-link critical damping 2√(m_r K), K_g = 1e9, circular profile),
//! plus the few combinations that matter ([`default_matrix`]): driver speed
//! 30–1200 rpm, restitution 0–1, link damping 0–1 % critical, contact
//! stiffness 1e8–1e10, generated drives ([`crate::scene::generate`]) of 122,
//! 1,000 and 10,000 rollers on two sprockets and 500 rollers on 3, 6 and 10,
//! the real profile on the baseline and the large drives, and a short
//! (0.1 s) ramp on both profiles.
//!
//! # Horizon
//!
//! Each cell runs just long enough to engage every mechanism: the driver
//! ramps up from rest at 25 rad/s² (0.5 s to 120 rpm, `0.5 s × max(1,
//! rpm/120)` in general), then holds its speed for 0.25 s (30 tooth impacts
//! at 120 rpm). A shorter ramp is not a numerical test but a physical
//! overload of the paper's heavy drive: its free sprockets (J = 82 kg·m²)
//! need J α / R ≈ 48 kN of extra chain tension for a 0.1 s ramp, and the
//! circular profile then lets a roller sink 12 mm into its seat at every
//! step size (the `ramp-0.1` cells keep that case, on both profiles).
//!
//! The 10,000-roller drive (a 442 m conveyor) cannot be spun up gently in
//! an affordable horizon: its loop's transit time is 0.6 s, so a ramp
//! shorter than that meets the chain's longitudinal impedance m′c ≈ 50
//! kN·s/m (m′ = m_r/P, c = P √(K/m_r)), 530 kN at 120 rpm's 10.7 m/s. It
//! runs at 12 rpm (≈ 53 kN), ramp 0.05 s and hold 0.05 s; its per-roller
//! cost is compared with 122- and 1,000-roller conveyors run the same way
//! (the `cost-*` cells).
//!
//! # The ladder
//!
//! Every (cell, integrator) runs at dt = 5 µs × 1.5ᵏ up to 1 ms ([`Ladder`]),
//! and goes on two rungs past its first failure to expose non-monotone
//! stability. The largest stable step is the last stable rung below the
//! first failure, refined by one bisection (the geometric mean of the two).
//! Failures *below* a stable step are listed as false alarms. The adaptive
//! scheme's `dt_s` is only a cap: once its mean accepted step is below half
//! the cap on two rungs in a row, larger caps change nothing and the ladder
//! stops there.
//!
//! Each cell is brought to static equilibrium once ([`Simulation::new`] at
//! dt = 10 µs); every run starts from a copy of that state, so the runs of a
//! cell differ only in the scheme and the step.
//!
//! # Blow-up and NaN
//!
//! A run is unstable when a blow-up detector of [`crate::sim`] fires
//! (non-finite state, penetration, link stretch, collapsed adaptive step);
//! its detector and time are kept. Every run is watched by [`NanWatch`]:
//! after every step the sprockets' state and the detectors' maxima, and at
//! every 1 kHz sample (the rate of `chaindrive run`'s outputs) every roller's
//! position, speed, link and contact force. A stable run whose outputs held
//! a NaN breaks a promise and is reported as such.

mod cells;
mod output;

use std::time::Instant;

pub(crate) use cells::{default_matrix, quick_matrix};
pub(crate) use output::{
    BLOWUPS_CSV_HEADER, CSV_HEADER, LIMITS_CSV_HEADER, blowup_csv_rows, csv_rows, first_failure,
    limits_csv_rows, roller_costs,
};

use super::ladder::{Rung, Setting};
use crate::scene::GenerateError;
use crate::scene::StepLimits;
use crate::scene::{Integrator, Scene, SceneError};
use crate::sim::{Observer, Sample, SimError, Simulation};

/// Why the matrix cannot be set up.
#[derive(Debug, thiserror::Error)]
pub(crate) enum StressError {
    /// A generated drive could not be placed.
    #[error("case {case}: {source}")]
    Generate {
        /// The case.
        case: String,
        /// Why.
        source: GenerateError,
    },
    /// A case's scene is invalid (a bug in the matrix).
    #[error("case {case}: {source}")]
    Scene {
        /// The case.
        case: String,
        /// Why.
        source: SceneError,
    },
    /// A case's scene could not be written as TOML.
    #[error("case {case}: writing TOML: {message}")]
    Toml {
        /// The case.
        case: String,
        /// Why.
        message: String,
    },
}

/// The step ladder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ladder {
    /// Smallest step, s.
    pub first_dt_s: f64,
    /// Ratio between rungs.
    pub factor: f64,
    /// Largest step tried, s.
    pub max_dt_s: f64,
    /// Rungs tried past the first failure.
    pub past_failure: usize,
    /// Wall-time budget of one run, s; a run over it is stopped and
    /// reported with the detector `timeout`.
    pub max_wall_s: f64,
}

impl Default for Ladder {
    fn default() -> Self {
        Self {
            first_dt_s: 5e-6,
            factor: 1.5,
            max_dt_s: 1e-3,
            past_failure: 2,
            max_wall_s: 300.0,
        }
    }
}

/// One cell of the matrix: a scene and the integrators to run it with.
#[derive(Clone, Debug)]
pub(crate) struct Case {
    /// Short name, e.g. `baseline`, `rpm-1200`, `gen-10000x2-real`.
    pub name: String,
    /// The validated scene; `solver.duration_s` is the horizon.
    pub scene: Scene,
    /// Integrators to run.
    pub integrators: Vec<Integrator>,
    /// Whether this cell is one of the roller-count series (122, 1,000,
    /// 10,000 rollers, same sprockets) the per-roller cost is read from.
    pub cost_series: bool,
}

/// The parameters a CSV row repeats for its cell.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CaseInfo {
    /// Case name.
    pub name: String,
    /// Rollers.
    pub rollers: usize,
    /// Sprockets.
    pub sprockets: usize,
    /// Driver speed, rpm.
    pub rpm: f64,
    /// Restitution e.
    pub restitution: f64,
    /// Link damping over the single-link critical damping 2√(m_r K).
    pub damping_ratio: f64,
    /// Contact stiffness K_g, N/m^n.
    pub contact_stiffness: f64,
    /// Profile name.
    pub profile: &'static str,
}

impl CaseInfo {
    /// The parameters of `scene`.
    pub(crate) fn of(name: &str, scene: &Scene) -> Self {
        let c = &scene.chain;
        let rpm = scene
            .sprockets
            .iter()
            .find_map(|s| s.speed_law())
            .map_or(0.0, |l| {
                // rpm came in as a round number; undo the rad/s round trip's last bit.
                (l.speed_rad_s * 60.0 / std::f64::consts::TAU * 1e9).round() / 1e9
            });
        Self {
            name: name.to_owned(),
            rollers: c.rollers,
            sprockets: scene.sprockets.len(),
            rpm,
            restitution: scene.contact.restitution,
            damping_ratio: c.damping_n_s_m / (2.0 * (c.roller_mass_kg * c.stiffness_n_m).sqrt()),
            contact_stiffness: scene.contact.stiffness,
            profile: scene.profile_name(),
        }
    }
}

/// How one run ended.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// Reached the horizon.
    Stable,
    /// A blow-up detector fired.
    BlowUp {
        /// Detector name ([`crate::sim::Detector::name`]).
        detector: &'static str,
        /// Simulated time, s.
        t_s: f64,
        /// The body concerned.
        body: String,
        /// The value that tripped it.
        value: f64,
        /// The limit.
        limit: f64,
    },
    /// Stopped at the wall-time budget.
    Timeout {
        /// Simulated time reached, s.
        t_s: f64,
    },
}

impl Verdict {
    /// Whether the run reached its horizon.
    pub(crate) fn is_stable(&self) -> bool {
        matches!(self, Self::Stable)
    }

    /// The detector's name (`timeout` for the budget), empty when stable.
    pub(crate) fn detector(&self) -> &'static str {
        match self {
            Self::Stable => "",
            Self::BlowUp { detector, .. } => detector,
            Self::Timeout { .. } => "timeout",
        }
    }

    /// When the run stopped early, s.
    pub(crate) fn stop_t_s(&self) -> Option<f64> {
        match self {
            Self::Stable => None,
            Self::BlowUp { t_s, .. } | Self::Timeout { t_s } => Some(*t_s),
        }
    }
}

/// One run of one cell with one integrator at one step.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RunRecord {
    /// The integrator.
    pub integrator: Integrator,
    /// The step (the adaptive scheme's cap), s.
    pub dt_s: f64,
    /// Whether this was the bisection refinement rather than a ladder rung.
    pub refinement: bool,
    /// How it ended.
    pub verdict: Verdict,
    /// Simulated time reached, s.
    pub sim_s: f64,
    /// Wall time of the stepping, s.
    pub wall_s: f64,
    /// Integration steps taken (the adaptive scheme's internal steps).
    pub steps: u64,
    /// Force evaluations.
    pub evaluations: u64,
    /// First time an output held a non-finite number, s.
    pub nan_in_output_t_s: Option<f64>,
    /// Largest penetration seen, m.
    pub max_penetration_m: f64,
    /// Largest |link force| seen, N.
    pub max_link_force_n: f64,
}

impl RunRecord {
    /// Wall time per simulated second (over the time reached).
    pub(crate) fn wall_per_sim_s(&self) -> f64 {
        if self.sim_s > 0.0 {
            self.wall_s / self.sim_s
        } else {
            0.0
        }
    }

    /// Wall time per roller and integration step, ns.
    pub(crate) fn ns_per_roller_step(&self, rollers: usize) -> f64 {
        let work = self.steps as f64 * rollers as f64;
        if work > 0.0 {
            self.wall_s * 1e9 / work
        } else {
            0.0
        }
    }
}

/// What the ladder found for one integrator on one cell.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Limit {
    /// The integrator.
    pub integrator: Integrator,
    /// [`StepLimits::for_integrator`]'s estimate, s (∞ for the adaptive scheme).
    pub estimated_dt_s: f64,
    /// Largest stable step below the first failure, refined, s (`None`:
    /// the smallest rung failed).
    pub largest_stable_dt_s: Option<f64>,
    /// The smallest failing step (ladder or refinement), s.
    pub first_unstable_dt_s: Option<f64>,
    /// Steps flagged unstable although a larger step ran stable, s.
    pub false_alarms_dt_s: Vec<f64>,
    /// Wall per simulated second at the largest stable step.
    pub wall_per_sim_s_at_limit: Option<f64>,
    /// Whether the ladder stopped because the adaptive scheme's cap no longer bound.
    pub cap_not_binding: bool,
}

/// A cell's runs.
#[derive(Clone, Debug)]
pub(crate) struct CaseResult {
    /// The cell's parameters.
    pub info: CaseInfo,
    /// Whether the cell is in the roller-count series.
    pub cost_series: bool,
    /// Why the cell could not be settled (no run then).
    pub build_error: Option<String>,
    /// Wall time of the static equilibrium, s.
    #[allow(
        dead_code,
        reason = "for a progress callback; the command's own ignores it"
    )]
    pub settle_wall_s: f64,
    /// Every run, in the order taken.
    pub runs: Vec<RunRecord>,
    /// One per integrator.
    pub limits: Vec<Limit>,
}

/// Watches a run's outputs for non-finite numbers and keeps its peaks.
#[derive(Clone, Debug, Default)]
pub(crate) struct NanWatch {
    /// First time a non-finite number was seen, s.
    pub first_t_s: Option<f64>,
    /// Largest penetration, m.
    pub max_penetration_m: f64,
    /// Largest |link force|, N.
    pub max_link_force_n: f64,
}

impl NanWatch {
    fn flag(&mut self, t_s: f64, finite: bool) {
        if !finite && self.first_t_s.is_none() {
            self.first_t_s = Some(t_s);
        }
    }
}

fn all_finite(xs: &[f64]) -> bool {
    xs.iter().all(|x| x.is_finite())
}

impl Observer for NanWatch {
    fn sample(&mut self, s: &Sample<'_>) {
        let (st, f) = (s.state, s.forces);
        let finite = all_finite(&st.x)
            && all_finite(&st.y)
            && all_finite(&st.vx)
            && all_finite(&st.vy)
            && all_finite(&f.link_force)
            && all_finite(&f.contact_force)
            && all_finite(&f.chain_torque);
        self.flag(st.t_s, finite);
        let peak = f.link_force.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        self.max_link_force_n = self.max_link_force_n.max(peak);
    }

    fn step(&mut self, s: &Sample<'_>) {
        let (st, f) = (s.state, s.forces);
        let finite = st.t_s.is_finite()
            && all_finite(&st.theta)
            && all_finite(&st.omega)
            && f.max_penetration_m.is_finite()
            && f.max_stretch_m.is_finite();
        self.flag(st.t_s, finite);
        self.max_penetration_m = self.max_penetration_m.max(f.max_penetration_m);
        self.max_link_force_n = self
            .max_link_force_n
            .max(f.max_stretch_m * s.model.stiffness_n_m);
    }

    fn per_step_from_s(&self) -> f64 {
        0.0
    }
}

/// Runs `base`'s drive with `integrator` at `dt_s` to the scene's horizon.
pub(crate) fn run_one(
    base: &Simulation,
    integrator: Integrator,
    dt_s: f64,
    max_wall_s: f64,
) -> RunRecord {
    /// Simulated time between wall-budget checks, s.
    const CHUNK_S: f64 = 0.01;
    let horizon = base.scene.solver.duration_s;
    let rung = Rung {
        integrator,
        setting: Setting::Step(dt_s),
    };
    // The adaptive scheme's `dt_s` is its cap: the step it is given.
    let mut sim = match base.fork(&rung.overrides(dt_s)) {
        Ok(sim) => sim,
        // Only a step the scene refuses (not finite, not positive) lands here.
        Err(e) => {
            return RunRecord {
                integrator,
                dt_s,
                refinement: false,
                sim_s: 0.0,
                verdict: Verdict::BlowUp {
                    detector: "error",
                    t_s: base.state.t_s,
                    body: e.to_string(),
                    value: 0.0,
                    limit: 0.0,
                },
                wall_s: 0.0,
                steps: 0,
                evaluations: 0,
                nan_in_output_t_s: None,
                max_penetration_m: 0.0,
                max_link_force_n: 0.0,
            };
        }
    };
    let mut watch = NanWatch::default();
    let every = (1e-3 / dt_s).round().max(1.0) as u64;
    let started = Instant::now();
    let mut verdict = Verdict::Stable;
    while sim.state.t_s < horizon - 0.5 * dt_s {
        let until = (sim.state.t_s + CHUNK_S).min(horizon);
        match sim.run(until, every, &mut watch, None) {
            Ok(_) => {}
            Err(SimError::BlowUp {
                t_s,
                detector,
                body,
                value,
                limit,
                ..
            }) => {
                verdict = Verdict::BlowUp {
                    detector,
                    t_s,
                    body,
                    value,
                    limit,
                };
                break;
            }
            // `run` fails only by a blow-up; anything else is reported as a detector too.
            Err(other) => {
                verdict = Verdict::BlowUp {
                    detector: "error",
                    t_s: sim.state.t_s,
                    body: other.to_string(),
                    value: 0.0,
                    limit: 0.0,
                };
                break;
            }
        }
        if started.elapsed().as_secs_f64() > max_wall_s {
            verdict = Verdict::Timeout { t_s: sim.state.t_s };
            break;
        }
    }
    let wall_s = started.elapsed().as_secs_f64();
    RunRecord {
        integrator,
        dt_s,
        refinement: false,
        sim_s: sim.state.t_s.max(0.0),
        verdict,
        wall_s,
        steps: sim.integration.stats.steps,
        evaluations: sim.integration.stats.evaluations,
        nan_in_output_t_s: watch.first_t_s,
        max_penetration_m: watch.max_penetration_m,
        max_link_force_n: watch.max_link_force_n,
    }
}

/// The adaptive scheme's first rung (5 µs × 1.5⁴ ≈ 25 µs on the default ladder).
pub(crate) const ADAPTIVE_FIRST_RUNG: i32 = 4;

/// Runs one integrator's ladder on a settled cell; `report` sees every run.
pub(crate) fn run_ladder(
    base: &Simulation,
    integrator: Integrator,
    ladder: &Ladder,
    report: &mut dyn FnMut(&RunRecord),
) -> (Vec<RunRecord>, Limit) {
    let mut runs: Vec<RunRecord> = Vec::new();
    let mut last_stable: Option<f64> = None;
    let mut first_fail: Option<f64> = None;
    let mut past = 0;
    let mut loose_caps = 0;
    let mut cap_not_binding = false;
    // Below its own step a cap only makes the adaptive scheme a costly
    // fixed-step one: its ladder starts at the fifth rung (25 µs).
    let mut rung = if integrator.is_adaptive() {
        ADAPTIVE_FIRST_RUNG
    } else {
        0
    };
    loop {
        let dt = ladder.first_dt_s * ladder.factor.powi(rung);
        if dt > ladder.max_dt_s * (1.0 + 1e-9) {
            break;
        }
        let r = run_one(base, integrator, dt, ladder.max_wall_s);
        report(&r);
        let stable = r.verdict.is_stable();
        if stable && integrator.is_adaptive() && r.steps > 0 {
            let mean_step = r.sim_s / r.steps as f64;
            loose_caps = if mean_step < 0.5 * dt {
                loose_caps + 1
            } else {
                0
            };
        }
        runs.push(r);
        match (stable, first_fail) {
            (true, None) => last_stable = Some(dt),
            (false, None) => first_fail = Some(dt),
            _ => {}
        }
        if first_fail.is_some() {
            past += 1;
            if past > ladder.past_failure {
                break;
            }
        }
        if loose_caps >= 2 {
            cap_not_binding = true;
            break;
        }
        rung += 1;
    }
    let mut largest = last_stable;
    let mut first_unstable = first_fail;
    if let (Some(a), Some(b)) = (last_stable, first_fail) {
        let mid = (a * b).sqrt();
        let mut r = run_one(base, integrator, mid, ladder.max_wall_s);
        r.refinement = true;
        report(&r);
        if r.verdict.is_stable() {
            largest = Some(mid);
        } else {
            first_unstable = Some(mid);
        }
        runs.push(r);
    }
    let max_stable_any = runs
        .iter()
        .filter(|r| r.verdict.is_stable())
        .map(|r| r.dt_s)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut false_alarms: Vec<f64> = runs
        .iter()
        .filter(|r| !r.verdict.is_stable() && r.dt_s < max_stable_any)
        .map(|r| r.dt_s)
        .collect();
    false_alarms.sort_by(f64::total_cmp);
    let wall_at_limit = largest.and_then(|l| {
        runs.iter()
            .find(|r| r.dt_s == l && r.verdict.is_stable())
            .map(RunRecord::wall_per_sim_s)
    });
    let limit = Limit {
        integrator,
        estimated_dt_s: StepLimits::of(&base.scene).for_integrator(integrator),
        largest_stable_dt_s: largest,
        first_unstable_dt_s: first_unstable,
        false_alarms_dt_s: false_alarms,
        wall_per_sim_s_at_limit: wall_at_limit,
        cap_not_binding,
    };
    (runs, limit)
}

/// What a cell's progress callback hears.
pub(crate) enum Progress<'a> {
    /// The cell settled (or failed to), after this many wall seconds.
    Settled {
        /// The cell.
        info: &'a CaseInfo,
        /// Wall time, s.
        wall_s: f64,
        /// Why it failed, if it did.
        error: Option<&'a str>,
    },
    /// One run finished.
    Run {
        /// The cell.
        #[allow(
            dead_code,
            reason = "for a progress callback; the command's own ignores it"
        )]
        info: &'a CaseInfo,
        /// The run.
        #[allow(
            dead_code,
            reason = "for a progress callback; the command's own ignores it"
        )]
        run: &'a RunRecord,
    },
    /// One integrator's ladder finished.
    Ladder {
        /// The cell.
        info: &'a CaseInfo,
        /// What it found.
        limit: &'a Limit,
    },
}

/// Settles a cell and runs every integrator's ladder.
pub(crate) fn run_case(
    case: &Case,
    ladder: &Ladder,
    progress: &mut dyn FnMut(Progress<'_>),
) -> CaseResult {
    let info = CaseInfo::of(&case.name, &case.scene);
    let started = Instant::now();
    let base = Simulation::new(&case.scene);
    let settle_wall_s = started.elapsed().as_secs_f64();
    let mut result = CaseResult {
        info,
        cost_series: case.cost_series,
        build_error: None,
        settle_wall_s,
        runs: Vec::new(),
        limits: Vec::new(),
    };
    let base = match base {
        Ok(b) => b,
        Err(e) => {
            let msg = e.to_string();
            progress(Progress::Settled {
                info: &result.info,
                wall_s: settle_wall_s,
                error: Some(&msg),
            });
            result.build_error = Some(msg);
            return result;
        }
    };
    progress(Progress::Settled {
        info: &result.info,
        wall_s: settle_wall_s,
        error: None,
    });
    for &integrator in &case.integrators {
        let info = &result.info;
        let (runs, limit) = run_ladder(&base, integrator, ladder, &mut |r| {
            progress(Progress::Run { info, run: r });
        });
        progress(Progress::Ladder {
            info,
            limit: &limit,
        });
        result.runs.extend(runs);
        result.limits.push(limit);
    }
    result
}
