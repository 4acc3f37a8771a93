//! Computing the run summary ([`RunSummary`], whose fields and their
//! meaning `summary` states) from a run's signals: the windows, the means
//! counted every step, the sampled statistics, each part of the drive in
//! turn, then the design checks and the warnings that read the summary.

use super::means::{Extent, StepSums};
use super::spectrum::peak_in;
use super::stats as estimators;
use super::summary::{
    GuideSummary, Range, RunSummary, SegmentSummary, SprocketSummary, StrandSummary, SummaryInputs,
    TensionerSummary, WornChain,
};
use super::theory::moving_string_frequency_hz;
use super::window::{StatsWindow, default_start_s};
use super::{SampleRow, Signals};
use crate::model::DriveModel;
use crate::scene::Scene;
use crate::sim::{PowerMeans, RunOutcome, Simulation};

/// A range's mean and extremes over the finite values.
impl Range {
    pub(super) fn of(values: impl Iterator<Item = f64>) -> Self {
        let (mean, min, max) = stats(values);
        Self { mean, min, max }
    }
}

/// Mean and (min, max) of the finite values of an iterator; zeros when empty.
fn stats(values: impl Iterator<Item = f64>) -> (f64, f64, f64) {
    estimators::finite_stats(values).map_or((0.0, 0.0, 0.0), |(mean, lo, hi, _)| (mean, lo, hi))
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
        summary
            .warnings
            .extend(eq.unbalanced.as_ref().map(ToString::to_string));
        summary
            .warnings
            .extend(eq.worn_slack.as_ref().map(ToString::to_string));
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
        summary.tip_rides = super::summary::TipRideSummary::per_sprocket(sim.jumps.rides());
        if let Some(w) = super::warnings::tip_rides(&summary.tip_rides) {
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
        let mass_per_length = scene.chain.mass_per_length_kg_m();
        let segments = segment_summaries(
            &strands,
            &means,
            &in_window,
            signals,
            spectrum_window,
            mass_per_length,
            chain_speed,
        );
        let sprockets = sprocket_summaries(model, &means, &in_window);
        let guides = guide_summaries(scene, &means, &in_window);
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
            tip_rides: Vec::new(),
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
            power_flow: flow,
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

/// Each strand's segment over the window: its link force's mean (every
/// step), spread and uncertainty (samples), and its transverse peak against
/// the moving-string estimate at the chain's speed.
fn segment_summaries(
    strands: &[StrandSummary],
    means: &WindowMeans<'_>,
    in_window: &[&SampleRow],
    signals: &Signals,
    spectrum_window: [f64; 2],
    mass_per_length: f64,
    chain_speed: f64,
) -> Vec<SegmentSummary> {
    strands
        .iter()
        .enumerate()
        .map(|(k, strand)| {
            let mean = means.segment_force_n(k);
            let series = super::segment_series(in_window, k);
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
        .collect()
}

/// Each sprocket's speed, torque and bearing force over the window.
fn sprocket_summaries(
    model: &DriveModel,
    means: &WindowMeans<'_>,
    in_window: &[&SampleRow],
) -> Vec<SprocketSummary> {
    (0..model.sprocket_count())
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
        .collect()
}

/// Each guide's normal and friction force over the window.
fn guide_summaries(
    scene: &Scene,
    means: &WindowMeans<'_>,
    in_window: &[&SampleRow],
) -> Vec<GuideSummary> {
    scene
        .guides
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let at = |r: &&SampleRow| r.shoes.get(k).copied();
            let (_, _, normal_max) = stats(in_window.iter().filter_map(at).map(|s| s.normal_max_n));
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
        .collect()
}
