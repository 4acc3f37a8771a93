//! A run-up (`chaindrive sweep --run-up FROM:TO --duration S`): one run in
//! which the driver's speed (a governed driver's target) rises linearly from
//! FROM to TO rpm over S seconds after its ramp and a settling time (the
//! scene's `sprockets.run_up`), cut into windows of whole revolutions as it
//! runs. Each window is analysed as a case of a stepped sweep at its mean
//! speed (`analyse_window` in the sweep module), each signal's linear trend taken out
//! of its order spectrum ([`crate::analysis::orders::AngleWindow::spectrum_detrended`]).
//!
//! **Windows.** A window of n revolutions at N rpm on a ramp of r rpm/s
//! lasts 60 n / N s, over which the target speed changes by the fraction
//! 60 n r / N². n is the largest multiple of the order step's denominator D
//! that keeps that fraction within [`RunUpSettings::max_speed_change`], and
//! at least D (at low speed a window of D revolutions may change more; its
//! `speed_change` says by how much). Rows are dropped as each window is
//! analysed, so the memory holds one window whatever the run-up's length.

use std::f64::consts::TAU;
use std::sync::atomic::AtomicBool;

use super::{
    CaseOutcome, DriveInfo, Extra, SweepError, analyse_window, driver_of, sampling_for,
    scene_with_run_up,
};
use crate::analysis::Signals;
use crate::analysis::orders::OrderSet;
use crate::scene::{RunUpFile, Scene};
use crate::sim::{Observer, Sample, Simulation};

/// The default largest change of the target speed over one window.
pub(crate) const DEFAULT_WINDOW_SPEED_CHANGE: f64 = 0.02;

/// A run-up's settings.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RunUpSettings {
    /// Driver speed at the start of the run-up, rpm (a magnitude; the
    /// scene's sense of rotation is kept).
    pub from_rpm: f64,
    /// Driver speed at its end, rpm (> `from_rpm`).
    pub to_rpm: f64,
    /// Time after the driver's ramp to `from_rpm` before the run-up, s.
    pub settle_s: f64,
    /// The run-up's length, s.
    pub duration_s: f64,
    /// Orders analysed.
    pub orders: OrderSet,
    /// Largest change of the target speed over a window, as a fraction of
    /// its speed (module docs).
    pub max_speed_change: f64,
}

impl RunUpSettings {
    /// Ramp rate, rpm per second.
    pub(crate) fn rate_rpm_s(&self) -> f64 {
        (self.to_rpm - self.from_rpm) / self.duration_s
    }

    /// Revolutions per window starting at `rpm` (module docs).
    pub(crate) fn window_revolutions(&self, rpm: f64) -> usize {
        let d = self.orders.denominator() as usize;
        let fit = self.max_speed_change * rpm * rpm / (60.0 * self.rate_rpm_s());
        let n = if fit.is_finite() { fit.max(0.0) } else { 0.0 };
        d * ((n / d as f64).floor() as usize).max(1)
    }

    fn check(&self) -> Result<(), SweepError> {
        let bad_time = |what: &'static str, value: f64, why: &str| SweepError::BadTime {
            what,
            value,
            why: why.to_owned(),
        };
        if !(self.from_rpm.is_finite() && self.from_rpm > 0.0 && self.to_rpm > self.from_rpm) {
            return Err(SweepError::BadRange {
                what: "--run-up",
                text: format!("{}:{}", self.from_rpm, self.to_rpm),
                why: "write FROM:TO in rpm with 0 < FROM < TO, e.g. 300:3000".to_owned(),
            });
        }
        if !(self.settle_s.is_finite() && self.settle_s >= 0.0) {
            return Err(bad_time(
                "--settle",
                self.settle_s,
                "the settling time must be a number of seconds ≥ 0",
            ));
        }
        if !(self.duration_s.is_finite() && self.duration_s > 0.0) {
            return Err(bad_time(
                "--duration",
                self.duration_s,
                "the run-up's length must be a number of seconds > 0",
            ));
        }
        if !(self.max_speed_change.is_finite() && self.max_speed_change > 0.0) {
            return Err(bad_time(
                "--window-change",
                self.max_speed_change,
                "the largest speed change over a window must be a fraction > 0",
            ));
        }
        // The run-up must hold at least one window.
        let revs = 0.5 * (self.from_rpm + self.to_rpm) / 60.0 * self.duration_s;
        let needed = self.window_revolutions(self.from_rpm) as f64;
        if revs < needed * 1.02 {
            return Err(bad_time(
                "--duration",
                self.duration_s,
                &format!(
                    "the run-up turns the driver through {revs:.2} revolutions; a window needs {needed}"
                ),
            ));
        }
        Ok(())
    }
}

/// Collects the samples of the current window and analyses each window as
/// soon as the driver has turned through it.
struct RunUpObserver<'a> {
    signals: Signals,
    info: DriveInfo,
    settings: &'a RunUpSettings,
    start_s: f64,
    theta0: Option<f64>,
    sense: f64,
    extra: Vec<Extra>,
    /// Rotation φ at the current window's start and its revolutions.
    window: Option<(f64, usize)>,
    windows: Vec<CaseOutcome>,
    on_window: &'a (dyn Fn(&CaseOutcome) + Sync),
}

/// Samples kept from one window to the next (the cubic resampling's
/// neighbours at the boundary).
const OVERLAP: usize = 3;

impl RunUpObserver<'_> {
    /// The target speed at `t_s`, rpm.
    fn target_rpm(&self, t_s: f64) -> f64 {
        let s = self.settings;
        let tau = ((t_s - self.start_s) / s.duration_s).clamp(0.0, 1.0);
        s.from_rpm + (s.to_rpm - s.from_rpm) * tau
    }

    fn close_window(&mut self, t_s: f64) {
        let theta0 = self.theta0.unwrap_or(0.0);
        let started = self.signals.rows.first().map_or(t_s, |r| r.t_s);
        let outcome = match analyse_window(
            &self.info,
            &self.signals.rows,
            &self.extra,
            theta0,
            self.settings.orders,
            true,
        ) {
            Ok(mut r) => {
                r.speed_change = (self.target_rpm(t_s) - self.target_rpm(started)) / r.rpm;
                CaseOutcome::Done(Box::new(r))
            }
            Err(e) => CaseOutcome::Failed {
                rpm: self.target_rpm(t_s),
                message: e.to_string(),
            },
        };
        (self.on_window)(&outcome);
        self.windows.push(outcome);
        let keep = self.signals.rows.len().saturating_sub(OVERLAP);
        self.signals.rows.drain(..keep);
        let keep = self.extra.len().saturating_sub(OVERLAP);
        self.extra.drain(..keep);
    }
}

impl Observer for RunUpObserver<'_> {
    fn sample(&mut self, s: &Sample<'_>) {
        let theta = s.state.theta[self.info.driver];
        let theta0 = *self.theta0.get_or_insert(theta);
        let t = s.state.t_s;
        if t < self.start_s {
            return;
        }
        self.signals.sample(s);
        self.extra.push(Extra::of(s, self.info.driver));
        let phi = self.sense * (theta - theta0);
        match self.window {
            None => {
                let n = self.settings.window_revolutions(self.target_rpm(t));
                self.window = Some((phi, n));
            }
            Some((start, n)) if phi >= start + n as f64 * TAU => {
                self.close_window(t);
                let n = self.settings.window_revolutions(self.target_rpm(t));
                // The rows kept start before φ; the next window's whole
                // revolutions end at its last sample, so start counting here.
                self.window = Some((phi, n));
            }
            Some(_) => {}
        }
    }
    fn step(&mut self, s: &Sample<'_>) {
        self.signals.step(s);
    }
    fn per_step_from_s(&self) -> f64 {
        self.signals.per_step_from_s()
    }
}

/// Runs the run-up: the scene with its driver at `from_rpm` for its ramp
/// and `settle_s`, then ramping to `to_rpm` over `duration_s`; every window
/// as a case, in speed order, `on_window` called as each is analysed. A
/// blow-up ends the run: the windows before it are kept and a failed case
/// at the speed it reached closes the list. A run cut short by `stop`
/// keeps its complete windows.
pub(crate) fn run_up(
    scene: &Scene,
    settings: &RunUpSettings,
    stop: Option<&AtomicBool>,
    on_window: &(dyn Fn(&CaseOutcome) + Sync),
) -> Result<Vec<CaseOutcome>, SweepError> {
    settings.check()?;
    let (_, ramp_s) = driver_of(scene)?;
    let start_s = ramp_s + settings.settle_s;
    let end_s = start_s + settings.duration_s;
    let scene = scene_with_run_up(
        scene,
        settings.from_rpm,
        end_s,
        Some(RunUpFile {
            to_rpm: settings.to_rpm,
            duration_s: settings.duration_s,
            start_s: Some(start_s),
        }),
    )?;
    let sampling = sampling_for(
        settings.to_rpm,
        settings.orders.max_order(),
        scene.solver().dt_s,
    )?;
    let failed = |rpm: f64, message: String| CaseOutcome::Failed { rpm, message };
    let mut sim = match Simulation::new(&scene) {
        Ok(s) => s,
        Err(e) => return Ok(vec![failed(settings.from_rpm, e.to_string())]),
    };
    let Some(info) = DriveInfo::of(&sim) else {
        return Err(SweepError::NoDriver);
    };
    let sense = scene.sprockets()[info.driver]
        .speed_law()
        .map_or(1.0, |l| if l.speed_rad_s < 0.0 { -1.0 } else { 1.0 });
    let mut observer = RunUpObserver {
        signals: Signals::new(&sim.model, sampling.rate_hz, start_s),
        info,
        settings,
        start_s,
        theta0: None,
        sense,
        extra: Vec::new(),
        window: None,
        windows: Vec::new(),
        on_window,
    };
    let result = sim.run(end_s, sampling.every, &mut observer, stop);
    let reached = observer.target_rpm(sim.state.t_s);
    let mut windows = observer.windows;
    if let Err(e) = result {
        windows.push(failed(reached, e.to_string()));
    }
    Ok(windows)
}
