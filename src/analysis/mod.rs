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

pub mod binder;
#[cfg(feature = "figures")]
pub mod figures;
pub mod orders;
#[cfg(feature = "record")]
pub mod recorded;
pub mod spectrum;
pub mod stats;
pub mod study;
mod summary;
pub mod theory;
mod warnings;

pub(crate) use summary::segment_series;
pub use summary::{
    DEFAULT_WINDOW_S, RunSummary, SegmentSummary, SprocketSummary, StrandSummary, SummaryInputs,
};
pub use warnings::{ENERGY_BALANCE_TOLERANCE, PENETRATION_FRACTION, RUNNING_TENSION_RATIO};

use crate::model::DriveModel;
use crate::sim::{Observer, Sample};

/// One sample of a run's signals.
#[derive(Clone, Debug, PartialEq)]
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
}

/// Samples a run's signals into memory (and optionally hands each row on).
pub struct Signals {
    /// Rows in time order.
    pub rows: Vec<SampleRow>,
    /// Samples per second.
    pub rate_hz: f64,
    per_step_from_s: f64,
    link_range: (f64, f64),
    bearing_max: Vec<f64>,
    scratch: Vec<Option<f64>>,
}

impl Signals {
    /// A sampler at `rate_hz` that also follows every step from `per_step_from_s`
    /// on (for link-force extremes and bearing peaks that samples would miss).
    pub fn new(model: &DriveModel, rate_hz: f64, per_step_from_s: f64) -> Self {
        Self {
            rows: Vec::new(),
            rate_hz,
            per_step_from_s,
            link_range: (f64::INFINITY, f64::NEG_INFINITY),
            bearing_max: vec![0.0; model.sprocket_count()],
            scratch: vec![None; model.segments.len()],
        }
    }

    fn track_extremes(&mut self, s: &Sample<'_>) {
        for &f in &s.forces.link_force {
            self.link_range.0 = self.link_range.0.min(f);
            self.link_range.1 = self.link_range.1.max(f);
        }
        for (m, f) in self.bearing_max.iter_mut().zip(&s.forces.chain_force) {
            *m = m.max(f[0].hypot(f[1]));
        }
    }
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
        });
        self.link_range = (f64::INFINITY, f64::NEG_INFINITY);
        self.bearing_max.fill(0.0);
    }

    fn step(&mut self, s: &Sample<'_>) {
        self.track_extremes(s);
    }

    fn per_step_from_s(&self) -> f64 {
        self.per_step_from_s
    }
}
