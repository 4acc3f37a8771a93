//! The speed sweep (`chaindrive sweep`): one steady run of a scene per
//! driver speed, in parallel, each measured by its run summary and the order
//! spectra of its signals ([`crate::analysis::orders`]), and the analytical
//! natural frequencies of each span at that speed from the run's own mean
//! tension, so that resonance crossings can be found
//! ([`resonance_crossings`]).
//!
//! Each case is the scene with the driver's `speed_rpm` replaced, run for
//! the driver's ramp + `settle_s` + `window_s`; the statistics and the order
//! spectra cover the last `window_s` (the order spectra its last whole
//! revolutions). A case that blows up is a failed case with its message;
//! the others go on. A stop flag (Ctrl-C) ends the running cases early and
//! starts no more: only complete cases are kept.
//!
//! A run-up ([`run_up`]) is one run whose driver speed ramps slowly
//! (`sprockets.run_up`), cut into short windows of whole revolutions, each
//! analysed as a case at its mean speed.
//!
//! This module runs and schedules the cases; [`report`]'s functions judge
//! them (crossings, worst cases, scalars), [`verdict`] reads each speed's
//! design checks (safety factor, rating margin, fatigue damage), [`runup`] holds the run-up and
//! `campbell` gathers a Campbell diagram's data (feature `figures`).
//!
//! What this module does not do: write files, draw figures or print (the
//! command-line tool does), or define what a signal means
//! ([`crate::analysis`]).

#[cfg(feature = "figures")]
pub(crate) mod campbell;
pub(crate) mod report;
pub(crate) mod runup;
pub(crate) mod speeds;
pub(crate) mod verdict;

pub(crate) use report::{
    CaseFlags, PEAK_MEDIAN_FACTOR, completed, doubt_section, excitation_orders, held_sprockets,
    on_order_grid, order_cut, resonance_crossings, summary_scalars, worst_cases,
};
#[cfg(test)]
pub(crate) use report::{PeakVerdict, SpanMode, judge_peak};
pub(crate) use runup::{DEFAULT_WINDOW_SPEED_CHANGE, RunUpSettings, run_up};
pub(crate) use speeds::{parse_rpm_range, parse_run_up};
pub(crate) use verdict::{verdicts, weakest};

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::queue::WorkQueue;
use crate::analysis::orders::{AngleWindow, OrderError, OrderSet, OrderSpectrum};
use crate::analysis::theory::moving_string_frequency_hz;
use crate::analysis::{RunSummary, SampleRow, Signals};
use crate::scene::{Overrides, Role, Scene, SceneError};
use crate::sim::{Observer, Sample, SampleRate, Simulation};

/// Samples per period of the largest order asked for (the cubic
/// resampling then loses about 10⁻³ of that order's amplitude).
pub(crate) const SAMPLES_PER_PERIOD: f64 = 16.0;

/// Transverse modes of each span drawn and searched for crossings.
pub const TRANSVERSE_MODES: u32 = 3;

/// Why a sweep cannot start.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// Speeds the sweep cannot run: not `FROM:TO:STEP` with 0 < FROM ≤ TO
    /// and STEP > 0 (`chaindrive sweep --rpm`'s syntax), none, or a run-up that does not go up.
    #[error("{what} {text:?}: {why}")]
    BadRange {
        /// The option (`--rpm`, `--run-up`).
        what: &'static str,
        /// As written.
        text: String,
        /// What is wrong and what is allowed.
        why: String,
    },
    /// A time setting that is not allowed.
    #[error("{what} {value}: {why}")]
    BadTime {
        /// The option (`--settle`, `--window`, `--duration`).
        what: &'static str,
        /// The value.
        value: f64,
        /// What is allowed.
        why: String,
    },
    /// The scene has no driver with a prescribed speed.
    #[error("the scene has no sprocket with role = \"driver\" and a speed_rpm to sweep")]
    NoDriver,
    /// The order set.
    #[error(transparent)]
    Orders(#[from] OrderError),
    /// The scene with the swept speed is not valid.
    #[error("at {rpm} rpm: {source}")]
    Scene {
        /// The speed.
        rpm: f64,
        /// Why.
        source: SceneError,
    },
    /// No sample rate is possible with the scene's step.
    #[error("sampling: {0}")]
    Sampling(String),
}

/// A sweep's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSettings {
    /// Driver speeds, rpm (magnitudes; the scene's sense of rotation is kept).
    pub rpm: Vec<f64>,
    /// Time after the driver's ramp before the window, s.
    pub settle_s: f64,
    /// Statistics and order window, s.
    pub window_s: f64,
    /// Worker threads.
    pub jobs: usize,
    /// Orders analysed.
    pub orders: OrderSet,
}

/// The largest tooth count of the scene's sprockets.
pub(crate) fn largest_teeth(scene: &Scene) -> u32 {
    scene.sprockets().iter().map(|s| s.teeth).max().unwrap_or(1)
}

/// The default order set: every whole order up to twice the largest tooth count.
pub fn default_orders(scene: &Scene) -> Result<OrderSet, OrderError> {
    OrderSet::new(f64::from(2 * largest_teeth(scene)), 1.0)
}

/// The order spectrum of one signal.
#[derive(Clone, Debug, PartialEq)]
pub struct SignalOrders {
    /// Signal name: `seg{k}_link_force_n`, `seg{k}_transverse_m`,
    /// `omega_{i}_rad_s`, `max_contact_force_n` (k, i 1-based).
    pub signal: String,
    /// Its spectrum.
    pub spectrum: OrderSpectrum,
}

/// The analytical natural frequencies of one span at a case's speed.
#[derive(Clone, Debug, PartialEq)]
pub struct SpanFrequencies {
    /// 1-based segment.
    pub segment: usize,
    /// The mean link force used, N.
    pub tension_n: f64,
    /// Moving-string transverse frequencies, modes 1..=[`TRANSVERSE_MODES`], Hz.
    pub transverse_hz: Vec<f64>,
    /// First axial frequency of the span, Hz (`span_axial_frequency_hz`).
    pub axial_hz: f64,
}

/// First axial (longitudinal) natural frequency of a span held at both
/// sprockets: the links in series form a rod of axial stiffness EA = K P and
/// mass μ per length, whose first fixed–fixed mode is f = (1 / 2L) √(K P / μ).
/// The discrete chain of n = L/P links is within (π/2n)²/6 of it.
pub(crate) fn span_axial_frequency_hz(
    stiffness_n_m: f64,
    pitch_m: f64,
    mass_per_length_kg_m: f64,
    length_m: f64,
) -> f64 {
    if !(stiffness_n_m > 0.0 && pitch_m > 0.0 && mass_per_length_kg_m > 0.0 && length_m > 0.0) {
        return 0.0;
    }
    (stiffness_n_m * pitch_m / mass_per_length_kg_m).sqrt() / (2.0 * length_m)
}

/// A complete case: one speed of a stepped sweep, or one window of a run-up.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    /// The driver's speed asked for (a stepped sweep) or the window's mean
    /// speed (a run-up), rpm.
    pub rpm: f64,
    /// The run summary (statistics over the window); `None` for a run-up's
    /// window, which is part of one run.
    pub summary: Option<RunSummary>,
    /// Relative change of the driver's target speed over the window (0 in a
    /// stepped sweep).
    pub speed_change: f64,
    /// Each segment's mean link force (over its free strand) in the window, N.
    pub segment_mean_n: Vec<f64>,
    /// Smallest link force of any link in the window, N.
    pub link_force_min_n: f64,
    /// Largest link force of any link in the window, N.
    pub link_force_max_n: f64,
    /// Largest contact penetration in the window, m.
    pub max_penetration_m: f64,
    /// Each sprocket's speed fluctuation (RMS about its mean, and in a
    /// run-up about the window's linear trend), rad/s.
    pub speed_rms_rad_s: Vec<f64>,
    /// Mean driver revolutions per second over the analysed revolutions.
    pub rev_per_s: f64,
    /// Whole revolutions analysed.
    pub revolutions: usize,
    /// Largest contact force on any roller over the window's samples, N.
    pub max_contact_force_n: f64,
    /// Each segment's smallest and largest link force (mean over its free
    /// strand) over the window's samples, N; NaN for a segment that had no free link.
    pub segment_range_n: Vec<(f64, f64)>,
    /// The order spectra.
    pub orders: Vec<SignalOrders>,
    /// Each span's analytical frequencies.
    pub spans: Vec<SpanFrequencies>,
}

impl CaseResult {
    /// The spectrum of `signal`, if it was analysed.
    pub(crate) fn signal(&self, signal: &str) -> Option<&OrderSpectrum> {
        self.orders
            .iter()
            .find(|s| s.signal == signal)
            .map(|s| &s.spectrum)
    }
}

/// One case of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub enum CaseOutcome {
    /// Ran to its end.
    Done(Box<CaseResult>),
    /// Blew up, or could not be built or analysed.
    Failed {
        /// The driver's speed, rpm.
        rpm: f64,
        /// Why.
        message: String,
    },
}

impl CaseOutcome {
    /// The case's speed, rpm.
    pub(crate) fn rpm(&self) -> f64 {
        match self {
            Self::Done(r) => r.rpm,
            Self::Failed { rpm, .. } => *rpm,
        }
    }
}

/// What a case samples beyond the [`Signals`] rows, one per row of its
/// window: the driver's angle, the largest contact force and penetration.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Extra {
    theta: f64,
    max_contact: f64,
    penetration: f64,
}

impl Extra {
    fn of(s: &Sample<'_>, driver: usize) -> Self {
        Self {
            theta: s.state.theta[driver],
            max_contact: s.forces.contact_force.iter().fold(0.0f64, |m, &f| m.max(f)),
            penetration: s.forces.max_penetration_m,
        }
    }
}

/// Samples the signals a stepped case needs: the run summary's (the rows
/// bounded to the window, [`Signals::keep_window`]) and, from the window's
/// start on, the [`Extra`]s.
struct CaseObserver {
    signals: Signals,
    driver: usize,
    window_start: f64,
    theta0: Option<f64>,
    extra: Vec<Extra>,
}

impl Observer for CaseObserver {
    fn sample(&mut self, s: &Sample<'_>) {
        self.signals.sample(s);
        self.theta0.get_or_insert(s.state.theta[self.driver]);
        if s.state.t_s >= self.window_start {
            self.extra.push(Extra::of(s, self.driver));
        }
    }
    fn step(&mut self, s: &Sample<'_>) {
        self.signals.step(s);
    }
    fn per_step_from_s(&self) -> f64 {
        self.signals.per_step_from_s()
    }
}

/// The drive's constants a window's analysis needs.
#[derive(Clone, Debug)]
pub(crate) struct DriveInfo {
    driver: usize,
    driver_pitch_radius_m: f64,
    sprockets: usize,
    strand_lengths_m: Vec<f64>,
    mass_per_length_kg_m: f64,
    stiffness_n_m: f64,
    pitch_m: f64,
}

impl DriveInfo {
    pub(crate) fn of(sim: &Simulation) -> Option<Self> {
        let driver = sim.model.driver()?;
        let chain = sim.scene.chain();
        Some(Self {
            driver,
            driver_pitch_radius_m: sim.model.sprockets[driver].pitch_radius_m,
            sprockets: sim.model.sprocket_count(),
            strand_lengths_m: sim.model.path.strands.iter().map(|s| s.length_m).collect(),
            mass_per_length_kg_m: chain.mass_per_length_kg_m(),
            stiffness_n_m: chain.stiffness_n_m,
            // A link's length: a worn chain's links are longer, so stiffer
            // per metre (EA = K P (1 + e)).
            pitch_m: chain.worn_pitch_m(),
        })
    }

    /// Each span's analytical frequencies at the mean link forces `tension_n`
    /// and the driver's `rev_per_s`.
    fn spans(&self, tension_n: &[f64], rev_per_s: f64) -> Vec<SpanFrequencies> {
        let mu = self.mass_per_length_kg_m;
        let speed = rev_per_s * std::f64::consts::TAU * self.driver_pitch_radius_m;
        tension_n
            .iter()
            .zip(&self.strand_lengths_m)
            .enumerate()
            .map(|(k, (&t, &length))| SpanFrequencies {
                segment: k + 1,
                tension_n: t,
                transverse_hz: (1..=TRANSVERSE_MODES)
                    .map(|n| moving_string_frequency_hz(n, t, length, mu, speed))
                    .collect(),
                axial_hz: span_axial_frequency_hz(self.stiffness_n_m, self.pitch_m, mu, length),
            })
            .collect()
    }
}

/// The order spectra, ranges and span frequencies of one window: `rows` and
/// `extra` one per sample, `theta0` the driver's angle at t = 0. With
/// `detrend`, each signal's linear trend over the window is taken out first
/// (a run-up's, [`AngleWindow::spectrum_detrended`]). The `rpm` is the
/// window's mean; `summary` is `None`.
pub(crate) fn analyse_window(
    info: &DriveInfo,
    rows: &[SampleRow],
    extra: &[Extra],
    theta0: f64,
    orders: OrderSet,
    detrend: bool,
) -> Result<CaseResult, OrderError> {
    if rows.len() != extra.len() {
        return Err(OrderError::BadInput(format!(
            "{} rows against {} angles",
            rows.len(),
            extra.len()
        )));
    }
    let t: Vec<f64> = rows.iter().map(|r| r.t_s).collect();
    // Angles turned since t = 0, so that phases are measured from the
    // driver's position at the start, as the scene's speed harmonics are.
    let theta: Vec<f64> = extra.iter().map(|e| e.theta - theta0).collect();
    let window = AngleWindow::new(&t, &theta, orders)?;
    // Only the samples of the whole revolutions count in the ranges.
    let first = t.partition_point(|&t| t < window.start_s());
    let mut result = Vec::new();
    let mut push = |signal: String, x: &[f64]| -> Result<(), OrderError> {
        let spectrum = if detrend {
            window.spectrum_detrended(x)?
        } else {
            window.spectrum(x)?
        };
        result.push(SignalOrders { signal, spectrum });
        Ok(())
    };
    let segments = info.strand_lengths_m.len();
    let mut segment_range_n = vec![(f64::NAN, f64::NAN); segments];
    let mut segment_mean_n = vec![f64::NAN; segments];
    for k in 0..segments {
        let held: Vec<f64> = rows[first..]
            .iter()
            .filter_map(|r| r.segment_force_n.get(k).copied().flatten())
            .collect();
        for &f in &held {
            let range = &mut segment_range_n[k];
            *range = (range.0.min(f), range.1.max(f));
        }
        if !held.is_empty() {
            segment_mean_n[k] = held.iter().sum::<f64>() / held.len() as f64;
        }
        // A sample with no free link in the segment carries the last force seen.
        let mut last = rows
            .iter()
            .find_map(|r| r.segment_force_n.get(k).copied().flatten());
        if last.is_some() {
            let force: Vec<f64> = rows
                .iter()
                .map(|r| {
                    if let Some(f) = r.segment_force_n.get(k).copied().flatten() {
                        last = Some(f);
                    }
                    last.unwrap_or(0.0)
                })
                .collect();
            push(format!("seg{}_link_force_n", k + 1), &force)?;
        }
        let transverse: Vec<f64> = rows
            .iter()
            .map(|r| r.transverse_m.get(k).copied().unwrap_or(0.0))
            .collect();
        push(format!("seg{}_transverse_m", k + 1), &transverse)?;
    }
    let mut speed_rms_rad_s = Vec::with_capacity(info.sprockets);
    for i in 0..info.sprockets {
        let omega: Vec<f64> = rows
            .iter()
            .map(|r| r.omega_rad_s.get(i).copied().unwrap_or(0.0))
            .collect();
        push(format!("omega_{}_rad_s", i + 1), &omega)?;
        speed_rms_rad_s.push(if detrend {
            rms_about_line(&t[first..], &omega[first..])
        } else {
            crate::analysis::stats::rms_about_mean(&omega[first..])
        });
    }
    let contact: Vec<f64> = extra.iter().map(|e| e.max_contact).collect();
    push("max_contact_force_n".to_owned(), &contact)?;
    let in_window = &extra[first..];
    let max_contact_force_n = in_window.iter().fold(0.0f64, |m, e| m.max(e.max_contact));
    let max_penetration_m = in_window.iter().fold(0.0f64, |m, e| m.max(e.penetration));
    let (link_force_min_n, link_force_max_n) = rows[first..]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r.link_range_n.0), hi.max(r.link_range_n.1))
        });
    let rev_per_s = window.rev_per_s();
    Ok(CaseResult {
        rpm: 60.0 * rev_per_s,
        summary: None,
        speed_change: 0.0,
        spans: info.spans(&segment_mean_n, rev_per_s),
        segment_mean_n,
        link_force_min_n,
        link_force_max_n,
        max_penetration_m,
        speed_rms_rad_s,
        rev_per_s,
        revolutions: window.revolutions(),
        max_contact_force_n,
        segment_range_n,
        orders: result,
    })
}

/// RMS of `x` about its least-squares line in `t`.
fn rms_about_line(t: &[f64], x: &[f64]) -> f64 {
    let n = x.len().min(t.len());
    if n < 2 {
        return 0.0;
    }
    let nf = n as f64;
    let (tm, xm) = (
        t[..n].iter().sum::<f64>() / nf,
        x[..n].iter().sum::<f64>() / nf,
    );
    let (mut stt, mut stx) = (0.0, 0.0);
    for (ti, xi) in t[..n].iter().zip(&x[..n]) {
        stt += (ti - tm) * (ti - tm);
        stx += (ti - tm) * (xi - xm);
    }
    let slope = if stt > 0.0 { stx / stt } else { 0.0 };
    let ss: f64 = t[..n]
        .iter()
        .zip(&x[..n])
        .map(|(ti, xi)| {
            let r = xi - xm - slope * (ti - tm);
            r * r
        })
        .sum();
    (ss / nf).sqrt()
}

/// A prepared case: its scene and sampling.
struct Case {
    rpm: f64,
    scene: Scene,
    sampling: SampleRate,
}

/// The driver's index and its ramp time, s.
pub(crate) fn driver_of(scene: &Scene) -> Result<(usize, f64), SweepError> {
    scene
        .sprockets()
        .iter()
        .enumerate()
        .find_map(|(i, s)| match s.role {
            Role::Driver(law) => Some((i, law.ramp_s)),
            _ => None,
        })
        .ok_or(SweepError::NoDriver)
}

/// `scene` with the driver at `rpm` (its sense kept) run for `duration_s`.
pub(crate) fn scene_at(scene: &Scene, rpm: f64, duration_s: f64) -> Result<Scene, SweepError> {
    scene_with_run_up(scene, rpm, duration_s, None)
}

/// `scene` with the driver at `rpm` (its sense kept), then the run-up
/// `run_up` (its `to_rpm` a magnitude, given the sense here), run for
/// `duration_s`.
pub(crate) fn scene_with_run_up(
    scene: &Scene,
    rpm: f64,
    duration_s: f64,
    run_up: Option<crate::scene::RunUpFile>,
) -> Result<Scene, SweepError> {
    let (driver, _) = driver_of(scene)?;
    let mut file = scene.file().clone();
    let sp = &mut file.sprockets[driver];
    let sense = if sp.speed_rpm.unwrap_or(1.0) < 0.0 {
        -1.0
    } else {
        1.0
    };
    sp.speed_rpm = Some(sense * rpm);
    sp.run_up = run_up.map(|r| crate::scene::RunUpFile {
        to_rpm: sense * r.to_rpm,
        ..r
    });
    let overrides = Overrides {
        duration_s: Some(duration_s),
        ..Overrides::default()
    };
    Scene::from_file_with(file, &overrides).map_err(|source| SweepError::Scene { rpm, source })
}

/// The slowest sample rate of at least 1 kHz and [`SAMPLES_PER_PERIOD`]
/// samples per period of `max_order` at `rpm` that a whole number of steps makes.
pub(crate) fn sampling_for(rpm: f64, max_order: f64, dt_s: f64) -> Result<SampleRate, SweepError> {
    let needed = (SAMPLES_PER_PERIOD * max_order * rpm / 60.0).max(1000.0);
    let every = (1.0 / (needed * dt_s)).floor().max(1.0);
    SampleRate::new(1.0 / (every * dt_s), dt_s).map_err(|e| SweepError::Sampling(e.to_string()))
}

fn check_times(settings: &SweepSettings) -> Result<(), SweepError> {
    if !(settings.settle_s.is_finite() && settings.settle_s >= 0.0) {
        return Err(SweepError::BadTime {
            what: "--settle",
            value: settings.settle_s,
            why: "the settling time must be a number of seconds ≥ 0".to_owned(),
        });
    }
    if !(settings.window_s.is_finite() && settings.window_s > 0.0) {
        return Err(SweepError::BadTime {
            what: "--window",
            value: settings.window_s,
            why: "the window must be a number of seconds > 0".to_owned(),
        });
    }
    if settings.rpm.is_empty() {
        return Err(SweepError::BadRange {
            what: "--rpm",
            text: String::new(),
            why: "no speed to run".to_owned(),
        });
    }
    // The window must hold D whole revolutions at the slowest speed.
    let slowest = settings.rpm.iter().copied().fold(f64::INFINITY, f64::min);
    let revs = settings.window_s * slowest / 60.0;
    let needed = f64::from(settings.orders.denominator());
    if revs < needed * 1.02 {
        return Err(SweepError::BadTime {
            what: "--window",
            value: settings.window_s,
            why: format!(
                "at {slowest} rpm the window turns the driver through {revs:.2} revolutions; the order analysis needs {needed} whole ones and 2 % to spare, {:.2} revolutions (a window ≥ {:.3} s)",
                needed * 1.02,
                needed * 1.02 * 60.0 / slowest
            ),
        });
    }
    Ok(())
}

/// Prepares every case (scene and sampling) so that a bad setting fails
/// before anything runs.
fn prepare(scene: &Scene, settings: &SweepSettings) -> Result<Vec<Case>, SweepError> {
    check_times(settings)?;
    let (_, ramp_s) = driver_of(scene)?;
    let duration = ramp_s + settings.settle_s + settings.window_s;
    settings
        .rpm
        .iter()
        .map(|&rpm| {
            let scene = scene_at(scene, rpm, duration)?;
            let sampling = sampling_for(rpm, settings.orders.max_order(), scene.solver().dt_s)?;
            Ok(Case {
                rpm,
                scene,
                sampling,
            })
        })
        .collect()
}

/// Runs one case to its end (`None` if `stop` ended it early).
fn run_case(
    case: &Case,
    settings: &SweepSettings,
    stop: Option<&AtomicBool>,
) -> Option<CaseOutcome> {
    let failed = |message: String| {
        Some(CaseOutcome::Failed {
            rpm: case.rpm,
            message,
        })
    };
    let setup = Instant::now();
    let mut sim = match Simulation::new(&case.scene) {
        Ok(s) => s,
        Err(e) => return failed(e.to_string()),
    };
    let setup_wall_s = setup.elapsed().as_secs_f64();
    let duration = case.scene.solver().duration_s;
    let window_start = (duration - settings.window_s).max(0.0);
    sim.track_power(window_start);
    let Some(info) = DriveInfo::of(&sim) else {
        return failed(SweepError::NoDriver.to_string());
    };
    let mut signals = Signals::new(&sim.model, case.sampling.rate_hz, window_start);
    // Memory bounded by the window, whatever the settling time and speed.
    signals.keep_window(settings.window_s);
    // The fatigue check's count, where the chain has the data it needs.
    signals.count_fatigue_of(&case.scene);
    let mut observer = CaseObserver {
        signals,
        driver: info.driver,
        window_start,
        theta0: None,
        extra: Vec::new(),
    };
    let outcome = match sim.run(duration, case.sampling.every, &mut observer, stop) {
        Ok(o) => o,
        Err(e) => return failed(e.to_string()),
    };
    if outcome.interrupted {
        return None;
    }
    let summary = RunSummary::of_run_over(
        &sim,
        &outcome,
        &observer.signals,
        setup_wall_s,
        settings.window_s,
    );
    let rows = &observer.signals.rows;
    let first = rows.partition_point(|r| r.t_s < window_start);
    let analysed = analyse_window(
        &info,
        &rows[first..],
        &observer.extra,
        observer.theta0.unwrap_or(0.0),
        settings.orders,
        false,
    );
    match analysed {
        Ok(mut result) => {
            // The summary's statistics follow every step of the window.
            result.rpm = case.rpm;
            result.link_force_min_n = summary.link_force_min_n;
            result.link_force_max_n = summary.link_force_max_n;
            result.max_penetration_m = summary.max_penetration_m;
            result.segment_mean_n = summary
                .segments
                .iter()
                .map(|s| s.mean_link_force_n)
                .collect();
            result.speed_rms_rad_s = summary
                .sprockets
                .iter()
                .map(|s| s.speed_rms_rad_s)
                .collect();
            let speed =
                summary.sprockets[info.driver].mean_speed_rad_s.abs() / std::f64::consts::TAU;
            result.spans = info.spans(&result.segment_mean_n, speed);
            result.summary = Some(summary);
            Some(CaseOutcome::Done(Box::new(result)))
        }
        Err(e) => failed(e.to_string()),
    }
}

/// Runs the sweep: every case on `settings.jobs` threads, the fastest
/// speeds first (they take the longest: more tooth impacts per second of
/// the same run), `on_case` called on the calling thread as each finishes.
/// Cases come back in speed order; cases that `stop` cut short or never
/// started are left out.
///
/// # Errors
///
/// A setting is not allowed or a case's scene is not valid (before anything runs).
pub fn run_sweep(
    scene: &Scene,
    settings: &SweepSettings,
    stop: Option<&AtomicBool>,
    on_case: &(dyn Fn(&CaseOutcome) + Sync),
) -> Result<Vec<CaseOutcome>, SweepError> {
    let cases = prepare(scene, settings)?;
    Ok(WorkQueue::new(&cases)
        .threads(settings.jobs)
        .stop(stop)
        .costliest_first(|case| case.rpm)
        .run(|_, case| run_case(case, settings, stop), |_, c| on_case(c))
        .into_iter()
        .flatten()
        .collect())
}
