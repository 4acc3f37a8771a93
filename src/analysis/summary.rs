//! The run summary: the public contract of `chaindrive run --summary`
//! (`contracts/run-summary.schema.json`). Field names stay; more may be added.
//!
//! - `window_s`: the statistics window ([`StatsWindow`]): by default the
//!   last [`super::DEFAULT_WINDOW_S`] of the run, not before the end of the
//!   scene's last ramp, or the last W seconds chosen; of what ran, where the
//!   run was interrupted.
//! - **Means** (`mean_link_force_n`, `mean_speed_rad_s`, `mean_torque_n_m`,
//!   `driver_mean_power_w`, the guides' and tensioners' means) are counted
//!   every step of the window (`means_every_step`, [`super::means`]), so
//!   they do not depend on the sample rate; a summary of samples alone (a
//!   recording) takes the samples' means and says so (`means_every_step`
//!   false). Extremes (`link_force_min_n`/`max_n`, `max_bearing_force_n`,
//!   the guides' maxima, the tensioners' ranges) follow every step too.
//! - **Sampled statistics**, at `sample_rate_hz`: `link_force_p2p_n`,
//!   `speed_p2p_rad_s`, `mean_link_force_se_n`, `link_force_rms_n`,
//!   `speed_rms_rad_s`, `stationary` (the estimators of [`super::stats`] over
//!   the window's samples: batch means with 20 batches; first against last
//!   third at 3 standard errors) and the spectra. A sample rate near a
//!   multiple of the tooth-passing frequency aliases them, which a warning
//!   says.
//! - `spectrum_window_s`: from the driver's ramp end + 0.5 s to the end (spectra);
//!   the whole run if that is empty. `transverse_peak_hz` is the main peak in
//!   1–50 Hz of the spectrum averaged over segments of
//!   [`super::spectrum::WELCH_SEGMENT`] samples (one spectrum over the whole
//!   window when it is no longer).
//! - `mean_torque_n_m`: mean moment of the chain's contact forces on the
//!   sprocket about its centre (CCW positive). The driver's motor supplies
//!   the opposite.
//! - `max_bearing_force_n`: largest resultant of the chain's contact forces
//!   on the sprocket over the window (every step), i.e. the bearing reaction
//!   without the sprocket's own weight.
//! - `guides[]`: per guide, the mean and the largest value over the window
//!   (every step) of the sum of the rollers' normal forces on the shoe and of
//!   the magnitudes of their friction forces.
//! - `driver_mean_power_w`: mean of −(chain moment on the driver) × ω_driver.
//! - `string_f1_hz`: the moving-string estimate from the segment's own mean
//!   link force, its nominal length, μ = m_r / P and the mean chain speed
//!   |ω_driver| R_driver over the window.

use serde::{Deserialize, Serialize};

use super::means::{Extent, StepSums};
use super::spectrum::peak_in;
use super::stats as estimators;
use super::theory::moving_string_frequency_hz;
use super::window::{StatsWindow, default_start_s};
use super::{SampleRow, Signals};
use crate::model::DriveModel;
use crate::scene::Scene;
use crate::sim::{PowerMeans, RunOutcome, Simulation};

fn stationary_by_default() -> bool {
    true
}

/// A free strand as laid out.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StrandSummary {
    /// 1-based segment number.
    pub segment: usize,
    /// 1-based sprocket it leaves.
    pub from: usize,
    /// 1-based sprocket it reaches.
    pub to: usize,
    /// Length, m.
    pub length_m: f64,
    /// Polar angle of the tangent point on `from`, [0, 2π).
    pub angle_on_from_rad: f64,
    /// Polar angle of the tangent point on `to`, [0, 2π).
    pub angle_on_to_rad: f64,
}

/// Statistics of one segment over the window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentSummary {
    /// 1-based segment number.
    pub segment: usize,
    /// Mean of the segment's average link force (every step with a free link), N.
    pub mean_link_force_n: f64,
    /// Peak-to-peak of the segment's average link force (samples), N.
    pub link_force_p2p_n: f64,
    /// Standard error of `mean_link_force_n` by batch means (20 batches), N.
    #[serde(default)]
    pub mean_link_force_se_n: f64,
    /// RMS of the segment's average link force about its mean (samples), N.
    #[serde(default)]
    pub link_force_rms_n: f64,
    /// Whether the first and last thirds of the window agree within three
    /// combined standard errors (see `super::stats`).
    #[serde(default = "stationary_by_default")]
    pub stationary: bool,
    /// Main peak of the transverse displacement's spectrum in 1–50 Hz, Hz (0 if none).
    pub transverse_peak_hz: f64,
    /// Moving-string estimate of the first transverse eigenfrequency, Hz.
    pub string_f1_hz: f64,
}

/// Statistics of one sprocket over the window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SprocketSummary {
    /// 1-based sprocket number.
    pub sprocket: usize,
    /// Mean angular speed (every step), rad/s (CCW positive).
    pub mean_speed_rad_s: f64,
    /// Peak-to-peak angular speed (samples), rad/s.
    pub speed_p2p_rad_s: f64,
    /// RMS of the angular speed about its mean (samples), rad/s.
    #[serde(default)]
    pub speed_rms_rad_s: f64,
    /// Mean chain moment on the sprocket, N·m.
    pub mean_torque_n_m: f64,
    /// Largest chain force on the bearing, N.
    pub max_bearing_force_n: f64,
}

/// Mean, smallest and largest value of a quantity over the window.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Range {
    /// Mean.
    pub mean: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
}

impl Range {
    fn of(values: impl Iterator<Item = f64>) -> Self {
        let (mean, min, max) = stats(values);
        Self { mean, min, max }
    }
}

/// One tensioner arm over the statistics window (docs/model.md, “Tensioner
/// arms”).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TensionerSummary {
    /// The arm's name.
    pub tensioner: String,
    /// Arm angle from the scene's pose, rad.
    pub arm_angle_rad: Range,
    /// Plunger travel from the scene's pose, m.
    pub travel_m: Range,
    /// Plunger speed, m/s.
    pub plunger_speed_m_s: Range,
    /// The tensioner's push, N.
    pub plunger_force_n: Range,
    /// Chamber pressure (gauge), Pa (zeros for a spring tensioner).
    pub pressure_pa: Range,
    /// Fraction of the window with the check valve open (every step).
    pub valve_open_fraction: f64,
    /// Times the check valve opened within the window (every step).
    pub valve_openings: u64,
    /// The chain's resultant force on the shoe, N.
    pub shoe_force_n: Range,
}

/// Forces on one guide over the window (docs/model.md, “Guides”).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GuideSummary {
    /// 1-based guide number (`guides[k]` is guide k + 1).
    pub guide: usize,
    /// Its name.
    pub name: String,
    /// Mean of Σ f_n, the rollers' normal forces on the shoe (every step), N.
    pub normal_mean_n: f64,
    /// Largest Σ f_n (every step), N.
    pub normal_max_n: f64,
    /// Mean of Σ |f_t|, the rollers' friction forces on the shoe (every step), N.
    pub friction_mean_n: f64,
    /// Largest Σ |f_t| (every step), N.
    pub friction_max_n: f64,
}

/// The run summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// `circular`, `real` or `mixed`.
    pub profile: String,
    /// Contact law name.
    pub contact_law: String,
    /// Integrator name.
    pub integrator: String,
    /// How the chain was stepped (`substepped` or `rapier`).
    pub stepping: String,
    /// Gravity, m/s².
    pub gravity_m_s2: [f64; 2],
    /// Chain step, s.
    pub dt_s: f64,
    /// Whether the step was chosen automatically (`solver.dt_s = "auto"`).
    #[serde(default)]
    pub dt_auto: bool,
    /// Simulated time reached, s.
    pub duration_s: f64,
    /// Whether the run stopped before its planned end.
    pub interrupted: bool,
    /// Statistics window, s.
    pub window_s: [f64; 2],
    /// Whether the window's means were counted every step (false: the
    /// means of the samples, as in a summary of a recording).
    #[serde(default)]
    pub means_every_step: bool,
    /// Spectrum window, s.
    pub spectrum_window_s: [f64; 2],
    /// Sample rate of the signals (and of the sampled statistics), Hz.
    pub sample_rate_hz: f64,
    /// Wall time of the stepping loop, s.
    pub wall_s: f64,
    /// Wall time of layout and static equilibrium, s.
    pub setup_wall_s: f64,
    /// Chain integration steps.
    pub steps: u64,
    /// Wall time per step, ns.
    pub ns_per_step: f64,
    /// Mean free-strand link force at static equilibrium, N.
    pub static_tension_n: f64,
    /// Largest roller force imbalance left at the static equilibrium, as a
    /// fraction of the pretension (absent where unknown: a summary of a
    /// recording). Above `super::STATIC_RESIDUAL_TOLERANCE` the
    /// run starts from a state that is not at rest, and says so in
    /// `warnings`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_force_residual: Option<f64>,
    /// What sets the static tension: the pretension rule (`rest_length`,
    /// `tensioner`, `tensioner_preload`, as `chain.pretension_by`), or
    /// `chain_misfit` where the tensioner arms meant to set it hold no chain
    /// and the chain's fit to its path does (a warning says how). Absent
    /// where unknown (a summary of a recording).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_tension_set_by: Option<String>,
    /// Links' rest length after the pretension rule, m.
    pub rest_length_m: f64,
    /// Smallest link force over the window, N.
    pub link_force_min_n: f64,
    /// Largest link force over the window, N.
    pub link_force_max_n: f64,
    /// Strands as laid out.
    pub strands: Vec<StrandSummary>,
    /// Segment statistics.
    pub segments: Vec<SegmentSummary>,
    /// Sprocket statistics.
    pub sprockets: Vec<SprocketSummary>,
    /// Guide statistics (absent from the JSON without guides).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub guides: Vec<GuideSummary>,
    /// Mean power the driver delivers, W.
    pub driver_mean_power_w: f64,
    /// Largest roller penetration over the run, m.
    pub max_penetration_m: f64,
    /// Mean power dissipated by the joint friction over the window, W
    /// (integrated every step; absent where the run did not count powers).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_friction_power_w: Option<f64>,
    /// Mean power dissipated by the links' dampers over the window, W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub link_damping_power_w: Option<f64>,
    /// Mean power dissipated by the contacts' damping over the window, W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_damping_power_w: Option<f64>,
    /// Mean power absorbed by the load torques over the window, W (positive
    /// for braking loads).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_power_w: Option<f64>,
    /// Load power over driver power (absent without a driver delivering power).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain_efficiency: Option<f64>,
    /// Relative residual of driver power = losses + load power + dE/dt over
    /// the window, against the power flowing through.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy_balance_error: Option<f64>,
    /// Tensioner arms (absent from scenes without them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tensioners: Vec<TensionerSummary>,
    /// The catalogue rating and static safety factors
    /// ([`super::design::rating`]; absent where the smallest sprocket did
    /// not turn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) rating: Option<super::design::Rating>,
    /// Link-plate fatigue from every link's force over the window
    /// ([`super::design::fatigue`]; absent where the chain has no tensile
    /// strength, or the steps were not counted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) fatigue: Option<super::design::Fatigue>,
    /// The wear check ([`super::design::wear`]; absent where the scene
    /// does not ask for it, `checks.wear = true`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) wear: Option<super::design::Wear>,
    /// A worn chain (`chain.elongation_pct` > 0; absent for a new chain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) worn_chain: Option<WornChain>,
    /// Every tooth jump of the run, in order (absent without any).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) tooth_jumps: Vec<ToothJumpSummary>,
    /// Where a result is suspect, one sentence each (docs/model.md, "Warnings").
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// A worn chain as laid out (docs/model.md, "A worn chain").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WornChain {
    /// Wear elongation of every pitch, %.
    pub elongation_pct: f64,
    /// The worn pitch P (1 + e), m.
    pub worn_pitch_m: f64,
    /// On fixed centres (the rest-length rule): the length the chain gained
    /// over the new chain that had the pretension, N l₀ e, m; absent where a
    /// tensioner takes it up.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extra_slack_m: Option<f64>,
}

/// One tooth jump (docs/model.md, "Tooth jump").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToothJumpSummary {
    /// When it was seen, s (to a sample period).
    pub t_s: f64,
    /// 1-based sprocket number.
    pub sprocket: usize,
    /// The roller, 0-based.
    pub roller: usize,
    /// Gaps moved, counter-clockwise positive.
    pub gaps: i32,
    /// `"ahead"` (in the sprocket's sense of rotation: the chain slipped
    /// forward on it) or `"behind"`.
    pub direction: String,
}

impl From<&crate::sim::ToothJump> for ToothJumpSummary {
    fn from(j: &crate::sim::ToothJump) -> Self {
        Self {
            t_s: j.t_s,
            sprocket: j.sprocket + 1,
            roller: j.roller,
            gaps: j.gaps,
            direction: if j.ahead { "ahead" } else { "behind" }.to_owned(),
        }
    }
}

/// What the summary needs besides the signals.
pub(crate) struct SummaryInputs<'a> {
    /// The scene (names, settings).
    pub scene: &'a Scene,
    /// The model (strands, driver radius).
    pub model: &'a DriveModel,
    /// Static tension, N.
    pub static_tension_n: f64,
    /// The static equilibrium's force residual (relative to the pretension),
    /// where known.
    pub static_force_residual: Option<f64>,
    /// Why the static equilibrium's state is not at rest, where known (a
    /// sentence, for the unsettled-start warning).
    pub static_unsettled_cause: Option<String>,
    /// Steps taken.
    pub steps: u64,
    /// Wall time of the loop, s.
    pub wall_s: f64,
    /// Wall time of setup, s.
    pub setup_wall_s: f64,
    /// Interrupted?
    pub interrupted: bool,
    /// Largest penetration over the run, m.
    pub max_penetration_m: f64,
}

/// Mean and (min, max) of the finite values of an iterator; zeros when empty.
fn stats(values: impl Iterator<Item = f64>) -> (f64, f64, f64) {
    let (mut sum, mut n, mut lo, mut hi) = (0.0, 0usize, f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        sum += v;
        n += 1;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if n == 0 {
        (0.0, 0.0, 0.0)
    } else {
        (sum / n as f64, lo, hi)
    }
}

/// The window's means: the rows' integrals over every step where each row
/// of the window has them, else the samples' means (a recording's rows).
struct WindowMeans<'a> {
    rows: &'a [&'a SampleRow],
    sums: Option<StepSums>,
}

impl<'a> WindowMeans<'a> {
    fn of(rows: &'a [&'a SampleRow]) -> Self {
        // The first row may hold the step where the counting began (its
        // sums then start after it), or none where the window starts on it.
        let every_step = rows.len() > 1 && rows[1..].iter().all(|r| r.step_sums.duration_s > 0.0);
        let sums = every_step.then(|| {
            let mut sums = StepSums::default();
            for r in rows {
                sums.merge(&r.step_sums);
            }
            sums
        });
        Self { rows, sums }
    }

    /// Integral over the counted time, or the samples' mean.
    fn mean(&self, integral: impl Fn(&StepSums) -> f64, sample: impl Fn(&SampleRow) -> f64) -> f64 {
        match &self.sums {
            Some(s) => integral(s) / s.duration_s,
            None => stats(self.rows.iter().map(|r| sample(r))).0,
        }
    }

    fn speed_rad_s(&self, j: usize) -> f64 {
        self.mean(|s| at(&s.omega_rad, j), |r| r.omega_rad_s[j])
    }

    fn torque_n_m(&self, j: usize) -> f64 {
        self.mean(|s| at(&s.torque_n_m_s, j), |r| r.chain_torque_n_m[j])
    }

    fn driver_power_w(&self, driver: usize) -> f64 {
        self.mean(
            |s| s.driver_work_j,
            |r| -r.chain_torque_n_m[driver] * r.omega_rad_s[driver],
        )
    }

    /// Over the steps (samples) with a free link; 0 without any.
    fn segment_force_n(&self, k: usize) -> f64 {
        match &self.sums {
            Some(s) if at(&s.segment_s, k) > 0.0 => at(&s.segment_n_s, k) / at(&s.segment_s, k),
            Some(_) => 0.0,
            None => stats(self.rows.iter().filter_map(|r| r.segment_force_n[k])).0,
        }
    }

    /// Guide `k`'s mean Σ f_n and Σ |f_t|.
    fn shoe_n(&self, k: usize) -> [f64; 2] {
        let shoe = |s: &StepSums, i: usize| s.shoe_n_s.get(k).map_or(0.0, |f| f[i]);
        let sample = |r: &SampleRow, i: usize| {
            r.shoes
                .get(k)
                .map_or(f64::NAN, |f| [f.normal_n, f.friction_n][i])
        };
        [0, 1].map(|i| self.mean(|s| shoe(s, i), |r| sample(r, i)))
    }

    fn tensioner(&self, name: &str, k: usize) -> TensionerSummary {
        let Some(sums) = &self.sums else {
            return tensioner_of_samples(name, k, self.rows);
        };
        let arm = sums.tensioners.get(k).cloned().unwrap_or_default();
        let d = sums.duration_s;
        let range = |e: Extent| Range {
            mean: e.integral / d,
            min: e.min,
            max: e.max,
        };
        TensionerSummary {
            tensioner: name.to_owned(),
            arm_angle_rad: range(arm.angle_rad),
            travel_m: range(arm.travel_m),
            plunger_speed_m_s: range(arm.plunger_speed_m_s),
            plunger_force_n: range(arm.plunger_force_n),
            pressure_pa: range(arm.pressure_pa),
            valve_open_fraction: arm.open_s / d,
            valve_openings: arm.openings,
            shoe_force_n: range(arm.shoe_force_n),
        }
    }
}

fn at(v: &[f64], i: usize) -> f64 {
    v.get(i).copied().unwrap_or(0.0)
}

/// Tensioner arm `k`'s statistics over the samples `rows`.
fn tensioner_of_samples(name: &str, k: usize, rows: &[&SampleRow]) -> TensionerSummary {
    let readings: Vec<_> = rows.iter().filter_map(|r| r.tensioners.get(k)).collect();
    let range =
        |f: fn(&crate::forces::TensionerReading) -> f64| Range::of(readings.iter().map(|r| f(r)));
    let open = readings.iter().filter(|r| r.valve_open).count();
    let openings = readings
        .windows(2)
        .filter(|w| !w[0].valve_open && w[1].valve_open)
        .count();
    TensionerSummary {
        tensioner: name.to_owned(),
        arm_angle_rad: range(|r| r.angle_rad),
        travel_m: range(|r| r.travel_m),
        plunger_speed_m_s: range(|r| r.plunger_speed_m_s),
        plunger_force_n: range(|r| r.plunger_force_n),
        pressure_pa: range(|r| r.pressure_pa),
        valve_open_fraction: if readings.is_empty() {
            0.0
        } else {
            open as f64 / readings.len() as f64
        },
        valve_openings: openings as u64,
        shoe_force_n: range(|r| r.shoe_force_n),
    }
}

impl RunSummary {
    /// The summary of a run of `sim` that ended with `outcome`, from the
    /// signals sampled along it, over the default window
    /// ([`StatsWindow`]); `setup_wall_s` is the wall time of
    /// [`Simulation::new`].
    pub fn of_run(
        sim: &Simulation,
        outcome: &RunOutcome,
        signals: &Signals,
        setup_wall_s: f64,
    ) -> Self {
        Self::summarise(sim, outcome, signals, setup_wall_s, None)
    }

    /// The summary of a run prepared by [`StatsWindow::observe`], over that
    /// window (its last `length_s`; of what ran, where the run was
    /// interrupted). A study or sweep that lets its plan set a window calls
    /// [`StatsWindow::of`] with it (`None`: the default), `observe`, runs,
    /// and calls this.
    pub fn of_run_in(
        sim: &Simulation,
        outcome: &RunOutcome,
        signals: &Signals,
        setup_wall_s: f64,
        window: &StatsWindow,
    ) -> Self {
        Self::summarise(sim, outcome, signals, setup_wall_s, Some(window.length_s()))
    }

    /// [`RunSummary::of_run`] with a statistics window of the last
    /// `window_s` (the whole run if it is shorter).
    pub fn of_run_over(
        sim: &Simulation,
        outcome: &RunOutcome,
        signals: &Signals,
        setup_wall_s: f64,
        window_s: f64,
    ) -> Self {
        Self::summarise(sim, outcome, signals, setup_wall_s, Some(window_s))
    }

    fn summarise(
        sim: &Simulation,
        outcome: &RunOutcome,
        signals: &Signals,
        setup_wall_s: f64,
        window_s: Option<f64>,
    ) -> Self {
        let mut summary = Self::compute_in(
            &SummaryInputs {
                scene: &sim.scene,
                model: &sim.model,
                static_tension_n: sim.equilibrium.tension_n,
                static_force_residual: Some(sim.equilibrium.force_residual),
                static_unsettled_cause: sim
                    .equilibrium
                    .beyond_seating_arc
                    .as_ref()
                    .map(ToString::to_string),
                steps: outcome.steps,
                wall_s: outcome.wall_s,
                setup_wall_s,
                interrupted: outcome.interrupted,
                max_penetration_m: outcome.max_penetration_m,
            },
            signals,
            window_s,
            sim.power.as_ref().and_then(|p| p.means()),
        );
        let eq = &sim.equilibrium;
        summary.static_tension_set_by = Some(eq.tension_set_by(&sim.scene).to_owned());
        summary
            .warnings
            .extend(eq.misfit.as_ref().map(ToString::to_string));
        summary.warnings.extend(sim.unmeshed_warning());
        summary.wear = sim.sliding.as_ref().and_then(|s| {
            let speeds: Vec<f64> = summary
                .sprockets
                .iter()
                .map(|p| p.mean_speed_rad_s)
                .collect();
            super::design::Wear::of_run(&sim.scene, s, &speeds)
        });
        if let Some(w) = summary
            .wear
            .as_ref()
            .and_then(|w| w.vibration_warning(sim.scene.chain.joint_friction.is_some()))
        {
            summary.warnings.push(w);
        }
        summary.worn_chain = worn_chain(&sim.scene, &sim.model);
        summary.tooth_jumps = sim.jumps.jumps().iter().map(Into::into).collect();
        if let Some(w) = super::warnings::tooth_jumps(&summary.tooth_jumps) {
            summary.warnings.push(w);
        }
        summary
    }

    /// Computes the summary of a run from its signals, over the default
    /// window ([`StatsWindow`]).
    pub(crate) fn compute(inputs: &SummaryInputs<'_>, signals: &Signals) -> Self {
        Self::compute_in(inputs, signals, None, None)
    }

    /// Computes the summary of a run from its signals, statistics over the
    /// last `window_s` (the whole run if it is shorter; a window that is not
    /// a positive number is the default).
    #[cfg(test)]
    pub(crate) fn compute_over(
        inputs: &SummaryInputs<'_>,
        signals: &Signals,
        window_s: f64,
    ) -> Self {
        Self::compute_full(inputs, signals, window_s, None)
    }

    /// Computes the summary of a run from its signals, statistics over the
    /// last `window_s` (a window that is not a positive number is the
    /// default), and, where it was counted, the window's power flow
    /// ([`crate::sim::PowerLedger`]).
    #[cfg(test)]
    pub(crate) fn compute_full(
        inputs: &SummaryInputs<'_>,
        signals: &Signals,
        window_s: f64,
        flow: Option<PowerMeans>,
    ) -> Self {
        let chosen = (window_s.is_finite() && window_s > 0.0).then_some(window_s);
        Self::compute_in(inputs, signals, chosen, flow)
    }

    fn compute_in(
        inputs: &SummaryInputs<'_>,
        signals: &Signals,
        window_s: Option<f64>,
        flow: Option<PowerMeans>,
    ) -> Self {
        let scene = inputs.scene;
        let model = inputs.model;
        let rows = &signals.rows;
        let t_end = rows.last().map_or(0.0, |r| r.t_s);
        let start = match window_s {
            Some(length) => (t_end - length).max(0.0),
            None => default_start_s(scene, t_end),
        };
        let window = [start, t_end];
        let ramp = scene
            .sprockets
            .iter()
            .filter_map(|s| s.speed_law())
            .map(|l| l.ramp_s)
            .fold(0.0, f64::max);
        let spectrum_window = if ramp + 0.5 < t_end {
            [ramp + 0.5, t_end]
        } else {
            [0.0, t_end]
        };
        // Rows in the window; the first row's extremes and integrals cover
        // the steps before it, so skip it.
        let in_window: Vec<&SampleRow> = rows
            .iter()
            .filter(|r| r.t_s > window[0] && r.t_s <= window[1])
            .collect();
        let means = WindowMeans::of(&in_window);
        let (_, link_min, _) = stats(in_window.iter().map(|r| r.link_range_n.0));
        let (_, _, link_max) = stats(in_window.iter().map(|r| r.link_range_n.1));
        // The chain's speed from the driver; in a drive without one, the mean
        // over the sprockets (each passes the same chain length per unit time).
        let chain_speed_at =
            |j: usize| means.speed_rad_s(j).abs() * model.sprockets[j].pitch_radius_m;
        let chain_speed = match model.driving() {
            Some(driver) => chain_speed_at(driver),
            None => {
                let count = model.sprocket_count();
                (0..count).map(chain_speed_at).sum::<f64>() / count as f64
            }
        };
        let strands = strand_summaries(model);
        let mass_per_length = scene.chain.roller_mass_kg / scene.chain.pitch_m;
        let segments = strands
            .iter()
            .enumerate()
            .map(|(k, strand)| {
                let mean = means.segment_force_n(k);
                let series = super::segment_series(&in_window, k);
                let (_, lo, hi) = stats(series.iter().copied());
                let (freqs, amps) = signals.transverse_spectrum(k, spectrum_window);
                let peak = peak_in(&freqs, &amps, 1.0, 50.0).map_or(0.0, |p| p.0);
                SegmentSummary {
                    segment: k + 1,
                    mean_link_force_n: mean,
                    link_force_p2p_n: hi - lo,
                    mean_link_force_se_n: estimators::standard_error(&series),
                    link_force_rms_n: estimators::rms_about_mean(&series),
                    stationary: estimators::stationarity(&series).stationary,
                    transverse_peak_hz: peak,
                    string_f1_hz: moving_string_frequency_hz(
                        1,
                        mean,
                        strand.length_m,
                        mass_per_length,
                        chain_speed,
                    ),
                }
            })
            .collect();
        let sprockets = (0..model.sprocket_count())
            .map(|s| {
                let speeds: Vec<f64> = in_window
                    .iter()
                    .map(|r| r.omega_rad_s[s])
                    .filter(|v| v.is_finite())
                    .collect();
                let (_, lo, hi) = stats(speeds.iter().copied());
                let (_, _, bearing) = stats(in_window.iter().map(|r| r.bearing_max_n[s]));
                SprocketSummary {
                    sprocket: s + 1,
                    mean_speed_rad_s: means.speed_rad_s(s),
                    speed_p2p_rad_s: hi - lo,
                    speed_rms_rad_s: estimators::rms_about_mean(&speeds),
                    mean_torque_n_m: means.torque_n_m(s),
                    max_bearing_force_n: bearing,
                }
            })
            .collect();
        let guides = scene
            .guides
            .iter()
            .enumerate()
            .map(|(k, g)| {
                let at = |r: &&SampleRow| r.shoes.get(k).copied();
                let (_, _, normal_max) =
                    stats(in_window.iter().filter_map(at).map(|s| s.normal_max_n));
                let (_, _, friction_max) =
                    stats(in_window.iter().filter_map(at).map(|s| s.friction_max_n));
                let [normal, friction] = means.shoe_n(k);
                GuideSummary {
                    guide: k + 1,
                    name: g.name.clone(),
                    normal_mean_n: normal,
                    normal_max_n: normal_max,
                    friction_mean_n: friction,
                    friction_max_n: friction_max,
                }
            })
            .collect();
        // No driver, no driver power (the drive is moved by load torques only).
        let power = model
            .driving()
            .map_or(0.0, |driver| means.driver_power_w(driver));
        let mut summary = RunSummary {
            scene: scene.name.clone(),
            profile: scene.profile_name().to_owned(),
            contact_law: scene.contact.law.name().to_owned(),
            integrator: scene.solver.integrator.name().to_owned(),
            stepping: scene.solver.stepping.name().to_owned(),
            gravity_m_s2: scene.gravity_m_s2,
            dt_s: scene.solver.dt_s,
            dt_auto: scene.solver.dt_auto,
            duration_s: t_end,
            interrupted: inputs.interrupted,
            window_s: window,
            means_every_step: means.sums.is_some(),
            spectrum_window_s: spectrum_window,
            sample_rate_hz: signals.rate_hz,
            wall_s: inputs.wall_s,
            setup_wall_s: inputs.setup_wall_s,
            steps: inputs.steps,
            ns_per_step: if inputs.steps > 0 {
                inputs.wall_s * 1e9 / inputs.steps as f64
            } else {
                0.0
            },
            static_tension_n: inputs.static_tension_n,
            static_force_residual: inputs.static_force_residual,
            static_tension_set_by: None,
            rest_length_m: model.rest_length_m,
            link_force_min_n: link_min,
            link_force_max_n: link_max,
            strands,
            segments,
            sprockets,
            guides,
            driver_mean_power_w: power,
            max_penetration_m: inputs.max_penetration_m,
            joint_friction_power_w: flow.map(|p| p.mean.joint_friction_w),
            link_damping_power_w: flow.map(|p| p.mean.link_damping_w),
            contact_damping_power_w: flow.map(|p| p.mean.contact_damping_w),
            load_power_w: flow.map(|p| p.mean.load_w),
            chain_efficiency: flow
                .filter(|p| p.mean.driver_w > 0.0)
                .map(|p| p.mean.load_w / p.mean.driver_w),
            energy_balance_error: flow.map(|p| p.balance_error()),
            tensioners: scene
                .tensioners
                .iter()
                .enumerate()
                .map(|(k, t)| means.tensioner(&t.name, k))
                .collect(),
            rating: None,
            fatigue: None,
            wear: None,
            worn_chain: None,
            tooth_jumps: Vec::new(),
            warnings: Vec::new(),
        };
        summary.rating = super::design::rating::of_run(scene, &summary);
        summary.fatigue = signals
            .fatigue()
            .and_then(|cycles| super::design::fatigue::of_run(scene, &summary, cycles));
        summary.warnings = super::warnings::of_run(&super::warnings::Judged {
            scene,
            summary: &summary,
            window_rows: &in_window,
            chain_speed_m_s: chain_speed,
            unsettled_cause: inputs.static_unsettled_cause.as_deref(),
        });
        summary
    }
}

/// A worn chain's block: its elongation, pitch and, on fixed centres, the
/// slack it gained (N l₀ e with l₀ = l / (1 + e), l the worn rest length).
fn worn_chain(scene: &Scene, model: &DriveModel) -> Option<WornChain> {
    let chain = &scene.chain;
    let e = chain.elongation;
    (e > 0.0).then(|| WornChain {
        elongation_pct: 100.0 * e,
        worn_pitch_m: chain.worn_pitch_m(),
        extra_slack_m: (chain.pretension_by == crate::scene::PretensionRule::RestLength)
            .then(|| chain.rollers as f64 * model.rest_length_m * e / (1.0 + e)),
    })
}

/// The strands as laid out.
fn strand_summaries(model: &DriveModel) -> Vec<StrandSummary> {
    model
        .path
        .strands
        .iter()
        .enumerate()
        .map(|(k, s)| StrandSummary {
            segment: k + 1,
            from: s.from + 1,
            to: s.to + 1,
            length_m: s.length_m,
            angle_on_from_rad: s.angle_on_from_rad,
            angle_on_to_rad: s.angle_on_to_rad,
        })
        .collect()
}
