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
//! What this module does not do: write files, draw figures or print (the
//! command-line tool does), or define what a signal means
//! ([`crate::analysis`]).

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use crate::analysis::orders::{AngleWindow, OrderError, OrderSet, OrderSpectrum};
use crate::analysis::theory::moving_string_frequency_hz;
use crate::analysis::{RunSummary, Signals};
use crate::scene::{Overrides, Role, Scene, SceneError};
use crate::sim::{Observer, Sample, SampleRate, Simulation};

/// Most cases a sweep may have.
pub const MAX_CASES: usize = 100_000;

/// Samples per period of the largest order asked for (the cubic
/// resampling then loses about 10⁻³ of that order's amplitude).
pub const SAMPLES_PER_PERIOD: f64 = 16.0;

/// Transverse modes of each span drawn and searched for crossings.
pub const TRANSVERSE_MODES: u32 = 3;

/// Why a sweep cannot start.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A range of speeds that is not `FROM:TO:STEP` with 0 < FROM ≤ TO and STEP > 0.
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

/// Speeds `FROM:TO:STEP` in rpm (both ends included when STEP divides the
/// span; a last point beyond TO is not added). `what` names the option in errors.
pub fn parse_rpm_range(what: &'static str, text: &str) -> Result<Vec<f64>, SweepError> {
    let bad = |why: &str| SweepError::BadRange {
        what,
        text: text.to_owned(),
        why: format!(
            "{why}; write FROM:TO:STEP in rpm with 0 < FROM ≤ TO and STEP > 0, e.g. 300:3000:100"
        ),
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() != 3 {
        return Err(bad("three numbers separated by ':' are needed"));
    }
    let nums: Vec<f64> = parts
        .iter()
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad("not a number"))?;
    let (from, to, step) = (nums[0], nums[1], nums[2]);
    if !(from.is_finite() && to.is_finite() && step.is_finite()) {
        return Err(bad("not finite"));
    }
    if !(from > 0.0) {
        return Err(bad("FROM must be > 0"));
    }
    if !(to >= from) {
        return Err(bad("TO must not be below FROM"));
    }
    if !(step > 0.0) {
        return Err(bad("STEP must be > 0"));
    }
    let count = ((to - from) / step * (1.0 + 1e-12) + 1e-9).floor() + 1.0;
    if count > MAX_CASES as f64 {
        return Err(bad(&format!("more than {MAX_CASES} speeds")));
    }
    Ok((0..count as usize)
        .map(|i| from + i as f64 * step)
        .collect())
}

/// Two speeds `FROM:TO` in rpm with 0 < FROM < TO (a run-up).
pub fn parse_run_up(text: &str) -> Result<(f64, f64), SweepError> {
    let bad = |why: &str| SweepError::BadRange {
        what: "--run-up",
        text: text.to_owned(),
        why: format!("{why}; write FROM:TO in rpm with 0 < FROM < TO, e.g. 300:3000"),
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() != 2 {
        return Err(bad("two numbers separated by ':' are needed"));
    }
    let from: f64 = parts[0].trim().parse().map_err(|_| bad("not a number"))?;
    let to: f64 = parts[1].trim().parse().map_err(|_| bad("not a number"))?;
    if !(from.is_finite() && to.is_finite() && from > 0.0 && to > from) {
        return Err(bad("out of range"));
    }
    Ok((from, to))
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
pub fn largest_teeth(scene: &Scene) -> u32 {
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
    /// First axial frequency of the span, Hz ([`span_axial_frequency_hz`]).
    pub axial_hz: f64,
}

/// First axial (longitudinal) natural frequency of a span held at both
/// sprockets: the links in series form a rod of axial stiffness EA = K P and
/// mass μ per length, whose first fixed–fixed mode is f = (1 / 2L) √(K P / μ).
/// The discrete chain of n = L/P links is within (π/2n)²/6 of it.
pub fn span_axial_frequency_hz(
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

/// A complete case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    /// The driver's speed asked for, rpm.
    pub rpm: f64,
    /// Its run summary (statistics over the window).
    pub summary: RunSummary,
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
    pub fn signal(&self, signal: &str) -> Option<&OrderSpectrum> {
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
    pub fn rpm(&self) -> f64 {
        match self {
            Self::Done(r) => r.rpm,
            Self::Failed { rpm, .. } => *rpm,
        }
    }
}

/// Samples the signals every case needs: the run summary's and, for the
/// order analysis, the driver's angle and the largest contact force.
struct CaseObserver {
    signals: Signals,
    driver: usize,
    theta: Vec<f64>,
    max_contact: Vec<f64>,
}

impl Observer for CaseObserver {
    fn sample(&mut self, s: &Sample<'_>) {
        self.signals.sample(s);
        self.theta.push(s.state.theta[self.driver]);
        let peak = s.forces.contact_force.iter().fold(0.0f64, |m, &f| m.max(f));
        self.max_contact.push(peak);
    }
    fn step(&mut self, s: &Sample<'_>) {
        self.signals.step(s);
    }
    fn per_step_from_s(&self) -> f64 {
        self.signals.per_step_from_s()
    }
}

/// A prepared case: its scene and sampling.
struct Case {
    rpm: f64,
    scene: Scene,
    sampling: SampleRate,
}

/// The driver's index and its ramp time, s.
fn driver_of(scene: &Scene) -> Result<(usize, f64), SweepError> {
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
pub fn scene_at(scene: &Scene, rpm: f64, duration_s: f64) -> Result<Scene, SweepError> {
    let (driver, _) = driver_of(scene)?;
    let mut file = scene.file().clone();
    let sp = &mut file.sprockets[driver];
    let sense = if sp.speed_rpm.unwrap_or(1.0) < 0.0 {
        -1.0
    } else {
        1.0
    };
    sp.speed_rpm = Some(sense * rpm);
    let overrides = Overrides {
        duration_s: Some(duration_s),
        ..Overrides::default()
    };
    Scene::from_file_with(file, &overrides).map_err(|source| SweepError::Scene { rpm, source })
}

/// The slowest sample rate of at least 1 kHz and [`SAMPLES_PER_PERIOD`]
/// samples per period of `max_order` at `rpm` that a whole number of steps makes.
fn sampling_for(rpm: f64, max_order: f64, dt_s: f64) -> Result<SampleRate, SweepError> {
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
                "at {slowest} rpm the window turns the driver through {revs:.2} revolutions; the order analysis needs at least {needed} whole ones (a window ≥ {:.3} s)",
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
    let Some(driver) = sim.model.driver() else {
        return failed(SweepError::NoDriver.to_string());
    };
    let mut observer = CaseObserver {
        signals: Signals::new(&sim.model, case.sampling.rate_hz, window_start),
        driver,
        theta: Vec::new(),
        max_contact: Vec::new(),
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
    match analyse(&sim, &observer, &summary, settings, window_start) {
        Ok(mut result) => {
            result.rpm = case.rpm;
            Some(CaseOutcome::Done(Box::new(result)))
        }
        Err(e) => failed(e.to_string()),
    }
}

/// The order spectra and span frequencies of a finished case.
fn analyse(
    sim: &Simulation,
    obs: &CaseObserver,
    summary: &RunSummary,
    settings: &SweepSettings,
    window_start: f64,
) -> Result<CaseResult, OrderError> {
    let rows = &obs.signals.rows;
    let first = rows.partition_point(|r| r.t_s < window_start);
    let rows = &rows[first..];
    let t: Vec<f64> = rows.iter().map(|r| r.t_s).collect();
    // Angles turned since t = 0 (the first sample), so that phases are
    // measured from the driver's position at the start, as the scene's
    // speed harmonics are.
    let theta0 = obs.theta.first().copied().unwrap_or(0.0);
    let theta: Vec<f64> = obs.theta[first..].iter().map(|th| th - theta0).collect();
    let window = AngleWindow::new(&t, &theta, settings.orders)?;
    let mut orders = Vec::new();
    let mut push = |signal: String, x: &[f64]| -> Result<(), OrderError> {
        orders.push(SignalOrders {
            signal,
            spectrum: window.spectrum(x)?,
        });
        Ok(())
    };
    let segments = sim.model.segments.len();
    let mut segment_range_n = vec![(f64::NAN, f64::NAN); segments];
    for (k, range) in segment_range_n.iter_mut().enumerate() {
        for f in rows.iter().filter_map(|r| r.segment_force_n[k]) {
            *range = (range.0.min(f), range.1.max(f));
        }
        // A sample with no free link in the segment carries the last force seen.
        let mut last = rows.iter().find_map(|r| r.segment_force_n[k]);
        if last.is_some() {
            let force: Vec<f64> = rows
                .iter()
                .map(|r| {
                    if let Some(f) = r.segment_force_n[k] {
                        last = Some(f);
                    }
                    last.unwrap_or(0.0)
                })
                .collect();
            push(format!("seg{}_link_force_n", k + 1), &force)?;
        }
        let transverse: Vec<f64> = rows.iter().map(|r| r.transverse_m[k]).collect();
        push(format!("seg{}_transverse_m", k + 1), &transverse)?;
    }
    for i in 0..sim.model.sprocket_count() {
        let omega: Vec<f64> = rows.iter().map(|r| r.omega_rad_s[i]).collect();
        push(format!("omega_{}_rad_s", i + 1), &omega)?;
    }
    let contact = &obs.max_contact[first..];
    push("max_contact_force_n".to_owned(), contact)?;
    let max_contact_force_n = contact.iter().fold(0.0f64, |m, &f| m.max(f));
    let chain = sim.scene.chain();
    let mu = chain.roller_mass_kg / chain.pitch_m;
    let driver = sim.model.driver().unwrap_or(0);
    let speed = summary.sprockets[driver].mean_speed_rad_s.abs()
        * sim.model.sprockets[driver].pitch_radius_m;
    let spans = summary
        .segments
        .iter()
        .zip(&summary.strands)
        .map(|(seg, strand)| SpanFrequencies {
            segment: seg.segment,
            tension_n: seg.mean_link_force_n,
            transverse_hz: (1..=TRANSVERSE_MODES)
                .map(|n| {
                    moving_string_frequency_hz(n, seg.mean_link_force_n, strand.length_m, mu, speed)
                })
                .collect(),
            axial_hz: span_axial_frequency_hz(
                chain.stiffness_n_m,
                chain.pitch_m,
                mu,
                strand.length_m,
            ),
        })
        .collect();
    Ok(CaseResult {
        rpm: 0.0,
        summary: summary.clone(),
        rev_per_s: window.rev_per_s(),
        revolutions: window.revolutions(),
        max_contact_force_n,
        segment_range_n,
        orders,
        spans,
    })
}

/// Runs the sweep: every case on `settings.jobs` threads, `on_case` called
/// as each finishes (from its worker thread). Cases come back in speed order;
/// cases that `stop` cut short or never started are left out.
pub fn run_sweep(
    scene: &Scene,
    settings: &SweepSettings,
    stop: Option<&AtomicBool>,
    on_case: &(dyn Fn(&CaseOutcome) + Sync),
) -> Result<Vec<CaseOutcome>, SweepError> {
    let cases = prepare(scene, settings)?;
    let next = AtomicUsize::new(0);
    let done: Mutex<Vec<(usize, CaseOutcome)>> = Mutex::new(Vec::new());
    let jobs = settings.jobs.clamp(1, cases.len().max(1));
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| {
                loop {
                    if stop.is_some_and(|f| f.load(Ordering::Relaxed)) {
                        break;
                    }
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(case) = cases.get(i) else { break };
                    if let Some(outcome) = run_case(case, settings, stop) {
                        on_case(&outcome);
                        if let Ok(mut d) = done.lock() {
                            d.push((i, outcome));
                        }
                    }
                }
            });
        }
    });
    let mut done = done.into_inner().unwrap_or_else(|e| e.into_inner());
    done.sort_by_key(|(i, _)| *i);
    Ok(done.into_iter().map(|(_, o)| o).collect())
}

/// Which natural frequency of a span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpanMode {
    /// The moving string's transverse mode n (1-based).
    Transverse(u32),
    /// The first axial mode.
    Axial,
}

impl SpanMode {
    /// `transverse n` or `axial`.
    pub fn name(&self) -> String {
        match self {
            Self::Transverse(n) => format!("transverse {n}"),
            Self::Axial => "axial".to_owned(),
        }
    }

    /// The signal that responds to this mode in segment `segment` (1-based).
    pub fn response_signal(&self, segment: usize) -> String {
        match self {
            Self::Transverse(_) => format!("seg{segment}_transverse_m"),
            Self::Axial => format!("seg{segment}_link_force_n"),
        }
    }

    fn of(&self, span: &SpanFrequencies) -> f64 {
        match self {
            Self::Transverse(n) => span
                .transverse_hz
                .get(*n as usize - 1)
                .copied()
                .unwrap_or(0.0),
            Self::Axial => span.axial_hz,
        }
    }
}

/// Where an excitation order's frequency meets a span's predicted natural
/// frequency between two swept speeds.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// 1-based segment.
    pub segment: usize,
    /// The mode.
    pub mode: SpanMode,
    /// The excitation order.
    pub order: f64,
    /// The crossing's speed, linearly interpolated between the two cases, rpm.
    pub rpm: f64,
    /// The frequency there, Hz.
    pub frequency_hz: f64,
    /// The signal whose order amplitude is the response.
    pub signal: String,
    /// The case of largest response among the two around the crossing and
    /// their neighbours, rpm.
    pub peak_rpm: f64,
    /// Its amplitude.
    pub peak_amplitude: f64,
    /// Whether the response peaks there: the largest of those four is a
    /// local maximum of the swept response, inside the sweep, and at least
    /// [`PEAK_PROMINENCE`] times the smallest response on either side of it.
    pub response_peaks: bool,
}

/// How far a peak must rise above the lowest response on each side of it.
pub const PEAK_PROMINENCE: f64 = 1.5;

/// The completed cases, in speed order.
pub fn completed(cases: &[CaseOutcome]) -> Vec<&CaseResult> {
    let mut done: Vec<&CaseResult> = cases
        .iter()
        .filter_map(|c| match c {
            CaseOutcome::Done(r) => Some(r.as_ref()),
            CaseOutcome::Failed { .. } => None,
        })
        .collect();
    done.sort_by(|a, b| a.rpm.total_cmp(&b.rpm));
    done
}

/// The amplitude of `order` in `signal` of each case (0 where absent).
pub fn order_cut(cases: &[&CaseResult], signal: &str, order: f64) -> Vec<f64> {
    cases
        .iter()
        .map(|c| {
            c.signal(signal)
                .and_then(|s| s.at(order))
                .map_or(0.0, |o| o.amplitude)
        })
        .collect()
}

/// Every crossing of an order in `orders` with a span's predicted natural
/// frequency (transverse modes 1..=[`TRANSVERSE_MODES`] and axial) between
/// consecutive completed cases, and whether the response peaks there.
pub fn resonance_crossings(cases: &[CaseOutcome], orders: &[f64]) -> Vec<Crossing> {
    let done = completed(cases);
    let spans = done.first().map_or(0, |c| c.spans.len());
    let modes: Vec<SpanMode> = (1..=TRANSVERSE_MODES)
        .map(SpanMode::Transverse)
        .chain([SpanMode::Axial])
        .collect();
    let mut found = Vec::new();
    for k in 0..spans {
        for mode in &modes {
            for &order in orders {
                let gap = |c: &CaseResult| {
                    let f = c.spans.get(k).map_or(0.0, |s| mode.of(s));
                    (f > 0.0).then_some(order * c.rev_per_s - f)
                };
                for i in 1..done.len() {
                    let (a, b) = (done[i - 1], done[i]);
                    let (Some(ga), Some(gb)) = (gap(a), gap(b)) else {
                        continue;
                    };
                    if ga.signum() == gb.signum() && ga != 0.0 {
                        continue;
                    }
                    let w = if ga == gb { 0.0 } else { ga / (ga - gb) };
                    let rpm = a.rpm + w * (b.rpm - a.rpm);
                    let rev = a.rev_per_s + w * (b.rev_per_s - a.rev_per_s);
                    let segment = k + 1;
                    let signal = mode.response_signal(segment);
                    let cut = order_cut(&done, &signal, order);
                    let lo = i.saturating_sub(2);
                    let hi = (i + 1).min(done.len() - 1);
                    let j = (lo..=hi)
                        .max_by(|&x, &y| cut[x].total_cmp(&cut[y]))
                        .unwrap_or(i);
                    let inside = j > 0 && j + 1 < cut.len();
                    let peaks = inside && {
                        let left = cut[..j].iter().copied().fold(f64::INFINITY, f64::min);
                        let right = cut[j + 1..].iter().copied().fold(f64::INFINITY, f64::min);
                        cut[j] >= cut[j - 1]
                            && cut[j] >= cut[j + 1]
                            && cut[j] >= PEAK_PROMINENCE * left.max(right)
                    };
                    found.push(Crossing {
                        segment,
                        mode: *mode,
                        order,
                        rpm,
                        frequency_hz: order * rev,
                        signal,
                        peak_rpm: done[j].rpm,
                        peak_amplitude: cut[j],
                        response_peaks: peaks,
                    });
                }
            }
        }
    }
    found
}

/// The excitation orders searched for crossings and drawn on a Campbell
/// diagram: 1, 2, the driver's tooth count (the meshing order) and twice it.
pub fn excitation_orders(scene: &Scene) -> Vec<f64> {
    let teeth = driver_of(scene)
        .map(|(i, _)| f64::from(scene.sprockets()[i].teeth))
        .unwrap_or(1.0);
    let mut orders = vec![1.0, 2.0, teeth, 2.0 * teeth];
    orders.dedup();
    orders
}

/// A worst case: where a statistic of the sweep is at its extreme.
#[derive(Clone, Debug, PartialEq)]
pub struct WorstCase {
    /// What.
    pub statistic: String,
    /// The case's speed, rpm.
    pub rpm: f64,
    /// The value.
    pub value: f64,
}

/// The speeds of the largest link force, the smallest link force, the
/// largest contact force, the largest penetration and each sprocket's
/// largest speed fluctuation (RMS).
pub fn worst_cases(cases: &[CaseOutcome]) -> Vec<WorstCase> {
    let done = completed(cases);
    let pick = |statistic: &str, value: &dyn Fn(&CaseResult) -> f64, largest: bool| {
        done.iter()
            .map(|c| (c.rpm, value(c)))
            .filter(|(_, v)| v.is_finite())
            .reduce(|a, b| {
                let better = if largest { b.1 > a.1 } else { b.1 < a.1 };
                if better { b } else { a }
            })
            .map(|(rpm, value)| WorstCase {
                statistic: statistic.to_owned(),
                rpm,
                value,
            })
    };
    let mut out = vec![
        pick(
            "largest link force, N",
            &|c| c.summary.link_force_max_n,
            true,
        ),
        pick(
            "smallest link force, N",
            &|c| c.summary.link_force_min_n,
            false,
        ),
        pick("largest contact force, N", &|c| c.max_contact_force_n, true),
        pick(
            "largest penetration, m",
            &|c| c.summary.max_penetration_m,
            true,
        ),
    ];
    let sprockets = done.first().map_or(0, |c| c.summary.sprockets.len());
    for s in 0..sprockets {
        out.push(pick(
            &format!("sprocket {} speed RMS, rad/s", s + 1),
            &|c| c.summary.sprockets[s].speed_rms_rad_s,
            true,
        ));
    }
    out.into_iter().flatten().collect()
}

/// Every scalar of a case's run summary as `(name, value)`: numbers as they
/// are, booleans as 0/1, per-segment and per-sprocket fields as
/// `segment{k}.field` / `sprocket{i}.field` (1-based), arrays of numbers as
/// `field[i]`; then the sweep's own: `max_contact_force_n`, `rev_per_s`.
pub fn summary_scalars(case: &CaseResult) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    if let Ok(value) = serde_json::to_value(&case.summary) {
        flatten("", &value, &mut out);
    }
    out.push(("max_contact_force_n".to_owned(), case.max_contact_force_n));
    out.push(("rev_per_s".to_owned(), case.rev_per_s));
    out
}

fn flatten(prefix: &str, value: &serde_json::Value, out: &mut Vec<(String, f64)>) {
    use serde_json::Value;
    match value {
        Value::Number(n) => {
            if let Some(v) = n.as_f64().filter(|v| v.is_finite()) {
                out.push((prefix.to_owned(), v));
            }
        }
        Value::Bool(b) => out.push((prefix.to_owned(), f64::from(u8::from(*b)))),
        Value::Object(map) => {
            for (k, v) in map {
                let name = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&name, v, out);
            }
        }
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                let numbered = ["segment", "sprocket"].iter().find_map(|key| {
                    item.get(*key)
                        .and_then(Value::as_u64)
                        .map(|n| format!("{key}{n}"))
                });
                let name = match numbered {
                    // `segments` → `segment3`, `strands` → `strand…` keep their own key.
                    Some(n) if prefix == "segments" || prefix == "sprockets" => n,
                    Some(n) => format!("{prefix}.{n}"),
                    None => format!("{prefix}[{i}]"),
                };
                flatten(&name, item, out);
            }
        }
        Value::String(_) | Value::Null => {}
    }
}
