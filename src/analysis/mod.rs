//! Analysis: the signals of a run, sampled by an observer ([`Signals`]), and
//! the run summary computed from them ([`RunSummary`], the public contract of
//! `chaindrive run --summary`), with the analytical references it compares
//! against (the moving string's eigenfrequency; docs/model.md, “Transverse vibration of
//! a free strand”).
//!
//! Definitions every output shares (docs/model.md, “Segments and strands”):
//! a segment's link force is the mean over the links of its free strand (the
//! rollers in chain order between the last one engaged on its first sprocket
//! and the first one engaged on the next); its transverse displacement is the
//! roller of that strand nearest the nominal strand's middle, signed to the
//! left of the strand's direction. Samples with no free link in
//! a segment carry no segment force and are skipped, never reported as NaN.

#[cfg(test)]
mod analysis_tests;
pub(crate) mod binder;
pub(crate) mod design;
#[cfg(feature = "figures")]
pub(crate) mod figures;
#[cfg(all(test, feature = "cli"))]
mod figures_tests;
mod means;
#[cfg(test)]
mod means_tests;
pub(crate) mod orders;
#[cfg(test)]
mod orders_tests;
pub(crate) mod paper_probes;
#[cfg(test)]
mod rating_tests;
#[cfg(feature = "record")]
pub(crate) mod recorded;
#[cfg(test)]
mod running_tension_tests;
pub(crate) mod spectrum;
#[cfg(test)]
mod statistics_tests;
pub(crate) mod stats;
mod summarise;
mod summary;
pub(crate) mod theory;
pub(crate) mod units;
pub(crate) mod warnings;
mod window;

pub(crate) use means::StepSums;
pub use summary::{
    GuideSummary, Range, RunSummary, SegmentSummary, SprocketSummary, StrandSummary,
    TensionerSummary,
};
pub(crate) use summary::{SummaryInputs, ToothJumpSummary};
pub(crate) use warnings::STATIC_RESIDUAL_TOLERANCE;
#[cfg(test)]
pub(crate) use warnings::{
    ALIAS_BAND_HZ, ALIAS_HARMONICS, ENERGY_BALANCE_TOLERANCE, PENETRATION_FRACTION,
    RUNNING_TENSION_RATIO,
};
#[cfg(feature = "cli")]
pub(crate) use window::DEFAULT_WINDOW_S;
pub use window::{StatsWindow, WindowError};

use serde::{Deserialize, Serialize};

use crate::model::DriveModel;
use crate::sim::{Observer, Sample};
use means::StepCounter;
use spectrum::{WELCH_SEGMENT, Welch};

/// One sample of a run's signals.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SampleRow {
    /// Time, s.
    pub t_s: f64,
    /// Sprocket angular speeds, rad/s.
    pub omega_rad_s: Vec<f64>,
    /// Moment of the chain on each sprocket, N·m (CCW positive).
    pub chain_torque_n_m: Vec<f64>,
    /// Largest chain force on each sprocket's bearing since the previous sample, N.
    pub bearing_max_n: Vec<f64>,
    /// Mean link force of each segment's free strand, N (`None`: no free link).
    pub segment_force_n: Vec<Option<f64>>,
    /// Transverse displacement of each segment's middle, m.
    pub transverse_m: Vec<f64>,
    /// Smallest and largest link force since the previous sample, N.
    pub link_range_n: (f64, f64),
    /// Each tensioner arm's reading (empty without arms).
    pub(crate) tensioners: Vec<crate::forces::TensionerReading>,
    /// Each shoe's forces (the guides', in scene order); empty without.
    pub(crate) shoes: Vec<ShoeSample>,
    /// Integrals over every step since the previous sample, where the steps
    /// were followed ([`Signals::new`]'s `per_step_from_s`); the window's
    /// means are theirs.
    #[serde(default)]
    pub(crate) step_sums: StepSums,
}

/// Segment `k`'s average link force over `rows`, the samples with a free link.
pub(crate) fn segment_series(rows: &[&SampleRow], k: usize) -> Vec<f64> {
    rows.iter()
        .filter_map(|r| r.segment_force_n[k])
        .filter(|v| v.is_finite())
        .collect()
}

/// One shoe's forces at a sample ([`crate::forces::ShoeForces`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct ShoeSample {
    /// Σ f_n over its contacts at the sample, N.
    pub normal_n: f64,
    /// Σ |f_t| at the sample, N.
    pub friction_n: f64,
    /// Largest Σ f_n since the previous sample, N.
    pub normal_max_n: f64,
    /// Largest Σ |f_t| since the previous sample, N.
    pub friction_max_n: f64,
}

/// Samples a run's signals into memory, with the integrals and extremes of
/// every step from `per_step_from_s` on (`SampleRow::step_sums`: no mean
/// depends on the sample rate).
///
/// By default every row is kept. [`Signals::keep_window`] bounds the memory
/// whatever the run's length: only the rows of the statistics window are
/// kept, and the transverse spectra are averaged as the samples arrive
/// (`spectrum::Welch`); the summary is the same either way.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Signals {
    /// Rows in time order (the last ones only, with [`Signals::keep_window`]).
    pub rows: Vec<SampleRow>,
    /// Samples per second.
    pub rate_hz: f64,
    per_step_from_s: f64,
    link_range: (f64, f64),
    bearing_max: Vec<f64>,
    scratch: Vec<Option<f64>>,
    shoes: Vec<ShoeSample>,
    /// The spectra's start unless the run ends before it: the driver's ramp
    /// end + 0.5 s (see [`RunSummary`]).
    spectrum_from_s: f64,
    bounded: Option<Bounded>,
    /// Integrals over every step from `per_step_from_s` on, handed to each row.
    #[serde(default)]
    counter: StepCounter,
    /// Every link's force rainflow-counted over the same steps, where asked
    /// for ([`Signals::count_fatigue`]).
    #[serde(default)]
    fatigue: Option<design::LinkCycles>,
}

/// What [`Signals`] keeps instead of every row.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Bounded {
    /// Rows kept (the statistics window's and a few more).
    rows: usize,
    /// Whether rows were dropped.
    trimmed: bool,
    /// Each segment's transverse spectrum from `spectrum_from_s` on.
    transverse: Vec<Welch>,
    /// Each segment's transverse spectrum from the start, while the run has
    /// not passed `spectrum_from_s` (the spectrum of a shorter run).
    early: Option<Vec<Welch>>,
}

impl Signals {
    /// A sampler at `rate_hz` that also follows every step from `per_step_from_s`
    /// on: the statistics window's means, and the link-force extremes and
    /// bearing peaks that samples would miss ([`StatsWindow::observe`] makes
    /// one for a window).
    pub fn new(model: &DriveModel, rate_hz: f64, per_step_from_s: f64) -> Self {
        Self {
            rows: Vec::new(),
            rate_hz,
            per_step_from_s,
            link_range: (f64::INFINITY, f64::NEG_INFINITY),
            bearing_max: vec![0.0; model.sprocket_count()],
            scratch: vec![None; model.segments.len()],
            shoes: Vec::new(),
            spectrum_from_s: model
                .sprockets
                .iter()
                .filter_map(|s| s.speed_law)
                .map(|l| l.ramp_s)
                .fold(0.0, f64::max)
                + 0.5,
            bounded: None,
            counter: StepCounter::default(),
            fatigue: None,
        }
    }

    /// Counts every link's force for the fatigue check over the steps
    /// followed, on the S–N curve of `cycles` ([`design::link_cycles`]).
    /// Call before the first step.
    pub(crate) fn count_fatigue(&mut self, cycles: design::LinkCycles) {
        self.fatigue = Some(cycles);
    }

    /// Counts every link's force for the fatigue check where `scene` gives
    /// its link plates an S–N curve (a chain with a designation); nothing
    /// otherwise. Call before the first step.
    pub fn count_fatigue_of(&mut self, scene: &crate::scene::Scene) {
        if let Ok((curve, _)) = design::fatigue::curve_of_scene(scene) {
            let links = scene.chain().rollers;
            self.count_fatigue(design::LinkCycles::new(curve, links));
        }
    }

    /// The fatigue count, where asked for.
    pub(crate) fn fatigue(&self) -> Option<&design::LinkCycles> {
        self.fatigue.as_ref()
    }

    /// Keeps only the rows of the last `window_s` (and a few more), and
    /// averages the transverse spectra as the samples arrive: the memory no
    /// longer grows with the run. Call before the first sample.
    pub fn keep_window(&mut self, window_s: f64) {
        let segments = self.scratch.len();
        let welch = || vec![Welch::new(self.rate_hz, WELCH_SEGMENT); segments];
        self.bounded = Some(Bounded {
            rows: rows_kept(window_s, self.rate_hz),
            trimmed: false,
            transverse: welch(),
            early: Some(welch()),
        });
    }

    /// These signals, continued in a run resumed from a checkpoint to
    /// another end, whose statistics window ([`StatsWindow`] of that end)
    /// is `window_s` long, followed step by step from `per_step_from_s`. Rows and spectra are
    /// kept (the spectra do not depend on the end). If the window's start
    /// moved, what was tracked step by step starts anew, as in a run with
    /// this window from the start, which by the last step `last` (`None`
    /// before the first) has tracked at most that step: the window must
    /// start after the step before it
    /// (`Snapshot::window_restarts` of the checkpoint). `last`
    /// comes with whether it was sampled (its row's extremes are then its
    /// own).
    pub fn continue_window(
        &mut self,
        model: &DriveModel,
        per_step_from_s: f64,
        window_s: f64,
        last: Option<(&Sample<'_>, bool)>,
    ) {
        if let Some(b) = &mut self.bounded {
            b.rows = rows_kept(window_s, self.rate_hz);
        }
        if per_step_from_s.to_bits() == self.per_step_from_s.to_bits() {
            return;
        }
        // Every step-by-step accumulator as `new` makes it (a fatigue count
        // from nothing); no row holds integrals yet (the steps before the
        // window were not followed).
        let fresh = Self::new(model, self.rate_hz, per_step_from_s);
        *self = Self {
            rows: std::mem::take(&mut self.rows),
            bounded: self.bounded.take(),
            fatigue: self.fatigue.as_ref().map(design::LinkCycles::anew),
            ..fresh
        };
        for row in &mut self.rows {
            row.step_sums = StepSums::default();
        }
        let Some((s, sampled)) = last else {
            return;
        };
        if s.state.t_s >= per_step_from_s {
            self.step(s);
        }
        if sampled {
            // The row taken at the last step holds what was tracked since
            // the sample before it: in this window, that step alone (and
            // the integrals' start, where the window holds it).
            self.track_extremes(s);
            if let Some(row) = self.rows.last_mut() {
                row.step_sums = self.counter.take();
                row.link_range_n = self.link_range;
                row.bearing_max_n.clone_from(&self.bearing_max);
                for (r, m) in row.shoes.iter_mut().zip(&self.shoes) {
                    r.normal_max_n = m.normal_max_n;
                    r.friction_max_n = m.friction_max_n;
                }
            }
            self.link_range = (f64::INFINITY, f64::NEG_INFINITY);
            self.bearing_max.fill(0.0);
            self.shoes.fill(ShoeSample::default());
        }
    }

    /// The amplitude spectrum of segment `k`'s transverse displacement over
    /// the spectrum window `window_s` ([`RunSummary::spectrum_window_s`]):
    /// averaged segments ([`spectrum::welch_spectrum`]) of the rows, or of the
    /// samples as they arrived where rows were dropped.
    pub(crate) fn transverse_spectrum(&self, k: usize, window_s: [f64; 2]) -> (Vec<f64>, Vec<f64>) {
        if let Some(b) = self.bounded.as_ref().filter(|b| b.trimmed) {
            let streams = if window_s[0] > 0.0 {
                Some(&b.transverse)
            } else {
                b.early.as_ref()
            };
            return streams
                .and_then(|s| s.get(k))
                .map_or((Vec::new(), Vec::new()), Welch::spectrum);
        }
        let x: Vec<f64> = self
            .rows
            .iter()
            .filter(|r| r.t_s >= window_s[0] && r.t_s <= window_s[1])
            .map(|r| r.transverse_m[k])
            .collect();
        spectrum::welch_spectrum(&x, self.rate_hz, WELCH_SEGMENT)
    }

    /// With [`Signals::keep_window`]: feeds the spectra, drops old rows.
    fn bound(&mut self) {
        let Some(b) = &mut self.bounded else {
            return;
        };
        let Some(row) = self.rows.last() else {
            return;
        };
        if row.t_s >= self.spectrum_from_s {
            for (w, x) in b.transverse.iter_mut().zip(&row.transverse_m) {
                w.push(*x);
            }
        }
        if row.t_s > self.spectrum_from_s {
            b.early = None;
        }
        if let Some(early) = &mut b.early {
            for (w, x) in early.iter_mut().zip(&row.transverse_m) {
                w.push(*x);
            }
        }
        // Drop the oldest rows in bulk, when twice as many are held.
        if self.rows.len() >= 2 * b.rows {
            self.rows.drain(..self.rows.len() - b.rows);
            b.trimmed = true;
        }
    }

    fn track_extremes(&mut self, s: &Sample<'_>) {
        let (low, high) = range_of(&s.forces.link_force);
        self.link_range.0 = self.link_range.0.min(low);
        self.link_range.1 = self.link_range.1.max(high);
        for (m, f) in self.bearing_max.iter_mut().zip(&s.forces.chain_force) {
            // `hypot` only where the force may exceed the maximum: the plain
            // square sum is within a few ulps of |f|², and a force 10⁻⁹ below
            // the maximum cannot raise it.
            let square = f[0] * f[0] + f[1] * f[1];
            if !(square < *m * *m * (1.0 - 1e-9)) {
                *m = m.max(f[0].hypot(f[1]));
            }
        }
        self.shoes
            .resize(s.forces.shoes.len(), ShoeSample::default());
        for (m, f) in self.shoes.iter_mut().zip(&s.forces.shoes) {
            m.normal_max_n = m.normal_max_n.max(f.normal_n);
            m.friction_max_n = m.friction_max_n.max(f.friction_n);
        }
    }
}

/// Rows kept for a statistics window of `window_s` at `rate_hz` (and a few more).
fn rows_kept(window_s: f64, rate_hz: f64) -> usize {
    let rows = (window_s.max(0.0) * rate_hz).ceil();
    if rows.is_finite() {
        rows as usize + 8
    } else {
        8
    }
}

/// The smallest and largest of `values` ((∞, −∞) when empty), in four
/// independent lanes of plain comparisons, which the compiler turns into
/// packed `min` and `max`. A NaN is dropped, as by `f64::min`/`f64::max`.
fn range_of(values: &[f64]) -> (f64, f64) {
    let smaller = |m: f64, v: f64| if v < m { v } else { m };
    let larger = |m: f64, v: f64| if v > m { v } else { m };
    let mut low = [f64::INFINITY; 4];
    let mut high = [f64::NEG_INFINITY; 4];
    let chunks = values.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for k in 0..4 {
            low[k] = smaller(low[k], c[k]);
            high[k] = larger(high[k], c[k]);
        }
    }
    let low = rest
        .iter()
        .chain(&low)
        .fold(f64::INFINITY, |m, &v| smaller(m, v));
    let high = rest
        .iter()
        .chain(&high)
        .fold(f64::NEG_INFINITY, |m, &v| larger(m, v));
    (low, high)
}

impl Observer for Signals {
    fn sample(&mut self, s: &Sample<'_>) {
        self.track_extremes(s);
        let st = s.state;
        let segments = &s.model.segments;
        let runs = segments.runs(&s.model.sprockets, &st.x, &st.y, &s.forces.touching);
        segments.mean_forces(&runs, &s.forces.link_force, &mut self.scratch);
        let transverse = (0..segments.len())
            .map(|k| segments.transverse(k, &runs, &st.x, &st.y))
            .collect();
        self.rows.push(SampleRow {
            t_s: st.t_s,
            omega_rad_s: st.omega.clone(),
            chain_torque_n_m: s.forces.chain_torque.clone(),
            bearing_max_n: self.bearing_max.clone(),
            segment_force_n: self.scratch.clone(),
            transverse_m: transverse,
            link_range_n: self.link_range,
            tensioners: s.forces.tensioners.clone(),
            shoes: self
                .shoes
                .iter()
                .zip(&s.forces.shoes)
                .map(|(m, f)| ShoeSample {
                    normal_n: f.normal_n,
                    friction_n: f.friction_n,
                    ..*m
                })
                .collect(),
            step_sums: self.counter.take(),
        });
        self.bound();
        self.link_range = (f64::INFINITY, f64::NEG_INFINITY);
        self.bearing_max.fill(0.0);
        self.shoes.fill(ShoeSample::default());
    }

    fn step(&mut self, s: &Sample<'_>) {
        self.track_extremes(s);
        self.counter.step(s);
        if let Some(f) = &mut self.fatigue {
            f.step(
                s.state.t_s,
                &s.forces.link_force,
                self.counter.runs(),
                s.model.segments.len(),
            );
        }
    }

    fn per_step_from_s(&self) -> f64 {
        self.per_step_from_s
    }
}
