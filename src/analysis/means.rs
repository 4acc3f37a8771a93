//! Integrals over every step, so that no mean the summary reports depends
//! on the sample rate: a quantity that swings at the tooth-passing
//! frequency, sampled at a rate that is a multiple of it (or near one), is
//! sampled at the same few phases of every swing, and its sampled mean is
//! that of those phases, not of the swing.
//!
//! [`StepCounter`] follows every step from the signals' per-step start on
//! and integrates, by the rectangle rule (Σ h_k x_k, x_k at the step's end),
//! each sprocket's speed and chain moment, the driving sprocket's power,
//! each segment's link force (over the steps with a free link), each
//! guide's summed forces and each tensioner arm's reading (with their
//! extremes and the valve's open time). Each sample row carries the
//! integrals over the steps since the previous row ([`StepSums`]), as it
//! carries the extremes since then, so a window of rows has its integrals
//! whatever the window. The power ledger ([`crate::sim::PowerLedger`])
//! integrates by trapezoids over the same steps; the two differ by
//! h (x_first − x_last) / 2T, under 10⁻⁵ of a swing at 10 µs over a second.
//!
//! Per step it costs a few additions per sprocket, guide and tensioner and
//! one per free link; the segments' free runs are found again only when the
//! contact state changed (a roller engaged or left). It allocates nothing
//! per step (a row's integrals are copied out at each sample).
//!
//! It does not sample: peaks-to-peak, RMS, spectra and standard errors are
//! the samples' statistics ([`super::Signals`]).

use serde::{Deserialize, Serialize};

use crate::forces::TensionerReading;
use crate::model::StrandRuns;
use crate::sim::Sample;

/// Integral, smallest and largest value of a quantity over steps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Extent {
    /// Σ h x.
    pub integral: f64,
    /// Smallest value (+∞ over no step).
    pub min: f64,
    /// Largest value (−∞ over no step).
    pub max: f64,
}

impl Default for Extent {
    fn default() -> Self {
        Self {
            integral: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }
}

impl Extent {
    fn add(&mut self, h: f64, x: f64) {
        self.integral += h * x;
        self.min = self.min.min(x);
        self.max = self.max.max(x);
    }

    /// Both together.
    pub(crate) fn merge(&mut self, other: &Self) {
        self.integral += other.integral;
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }
}

/// One tensioner arm's reading over steps.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TensionerSums {
    /// Arm angle, rad.
    pub angle_rad: Extent,
    /// Plunger travel, m.
    pub travel_m: Extent,
    /// Plunger speed, m/s.
    pub plunger_speed_m_s: Extent,
    /// The tensioner's push, N.
    pub plunger_force_n: Extent,
    /// Chamber pressure, Pa.
    pub pressure_pa: Extent,
    /// The chain's force on the shoe, N.
    pub shoe_force_n: Extent,
    /// Time with the check valve open, s.
    pub open_s: f64,
    /// Times the check valve opened.
    pub openings: u64,
}

impl TensionerSums {
    fn add(&mut self, h: f64, r: &TensionerReading, was_open: bool) {
        self.angle_rad.add(h, r.angle_rad);
        self.travel_m.add(h, r.travel_m);
        self.plunger_speed_m_s.add(h, r.plunger_speed_m_s);
        self.plunger_force_n.add(h, r.plunger_force_n);
        self.pressure_pa.add(h, r.pressure_pa);
        self.shoe_force_n.add(h, r.shoe_force_n);
        if r.valve_open {
            self.open_s += h;
            self.openings += u64::from(!was_open);
        }
    }

    /// Both together.
    pub(crate) fn merge(&mut self, other: &Self) {
        self.angle_rad.merge(&other.angle_rad);
        self.travel_m.merge(&other.travel_m);
        self.plunger_speed_m_s.merge(&other.plunger_speed_m_s);
        self.plunger_force_n.merge(&other.plunger_force_n);
        self.pressure_pa.merge(&other.pressure_pa);
        self.shoe_force_n.merge(&other.shoe_force_n);
        self.open_s += other.open_s;
        self.openings += other.openings;
    }
}

/// Integrals over the steps since the previous sample (a [`super::SampleRow`]'s);
/// `duration_s` = 0 where the steps were not followed.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepSums {
    /// Σ h over the steps counted, s.
    pub duration_s: f64,
    /// Each sprocket's ∫ω dt, rad.
    pub omega_rad: Vec<f64>,
    /// Each sprocket's ∫M dt, M the chain's moment on it, N·m·s.
    pub torque_n_m_s: Vec<f64>,
    /// The driving sprocket's ∫ −M ω dt, J.
    pub driver_work_j: f64,
    /// Each segment's ∫F dt over the steps with a free link, N·s.
    pub segment_n_s: Vec<f64>,
    /// Each segment's time with a free link, s.
    pub segment_s: Vec<f64>,
    /// Each shoe's ∫ Σ f_n dt and ∫ Σ |f_t| dt, N·s.
    pub shoe_n_s: Vec<[f64; 2]>,
    /// Each tensioner arm's readings.
    pub tensioners: Vec<TensionerSums>,
}

impl StepSums {
    /// Zero sums for the drive `s` shows.
    fn sized(s: &Sample<'_>) -> Self {
        let (sprockets, segments) = (s.state.omega.len(), s.model.segments.len());
        Self {
            duration_s: 0.0,
            omega_rad: vec![0.0; sprockets],
            torque_n_m_s: vec![0.0; sprockets],
            driver_work_j: 0.0,
            segment_n_s: vec![0.0; segments],
            segment_s: vec![0.0; segments],
            shoe_n_s: vec![[0.0; 2]; s.forces.shoes.len()],
            tensioners: vec![TensionerSums::default(); s.forces.tensioners.len()],
        }
    }

    /// Adds `other`, the sums of the steps after these (same drive).
    pub(crate) fn merge(&mut self, other: &Self) {
        let add = |a: &mut Vec<f64>, b: &[f64]| {
            a.resize(a.len().max(b.len()), 0.0);
            a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
        };
        self.duration_s += other.duration_s;
        add(&mut self.omega_rad, &other.omega_rad);
        add(&mut self.torque_n_m_s, &other.torque_n_m_s);
        self.driver_work_j += other.driver_work_j;
        add(&mut self.segment_n_s, &other.segment_n_s);
        add(&mut self.segment_s, &other.segment_s);
        self.shoe_n_s
            .resize(self.shoe_n_s.len().max(other.shoe_n_s.len()), [0.0; 2]);
        for (a, b) in self.shoe_n_s.iter_mut().zip(&other.shoe_n_s) {
            a[0] += b[0];
            a[1] += b[1];
        }
        self.tensioners.resize(
            self.tensioners.len().max(other.tensioners.len()),
            TensionerSums::default(),
        );
        for (a, b) in self.tensioners.iter_mut().zip(&other.tensioners) {
            a.merge(b);
        }
    }

    /// Back to zero, keeping the sizes.
    fn clear(&mut self) {
        self.duration_s = 0.0;
        self.driver_work_j = 0.0;
        for v in [
            &mut self.omega_rad,
            &mut self.torque_n_m_s,
            &mut self.segment_n_s,
            &mut self.segment_s,
        ] {
            v.fill(0.0);
        }
        self.shoe_n_s.fill([0.0; 2]);
        self.tensioners.fill(TensionerSums::default());
    }
}

/// Follows every step and integrates ([module docs](self)); kept in a
/// checkpoint with the signals, so a resumed run sums the same steps.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct StepCounter {
    /// The last step's end, s (`None` before the first step followed).
    last_s: Option<f64>,
    sums: StepSums,
    /// Each tensioner's valve at the last step.
    was_open: Vec<bool>,
    /// The segments' free runs and the contact state they were found for.
    touching: Vec<bool>,
    runs: Option<StrandRuns>,
    /// How many times the runs were found (a reader's cue that they changed).
    #[serde(default)]
    runs_found: u64,
}

impl StepCounter {
    /// Counts the step that ended at `s` (the first one followed only marks
    /// the time: the sums cover the steps after it).
    pub fn step(&mut self, s: &Sample<'_>) {
        let t = s.state.t_s;
        let Some(last) = self.last_s.replace(t) else {
            self.sums = StepSums::sized(s);
            self.was_open = s.forces.tensioners.iter().map(|r| r.valve_open).collect();
            return;
        };
        let h = t - last;
        let sums = &mut self.sums;
        sums.duration_s += h;
        let (omega, torque) = (&s.state.omega, &s.forces.chain_torque);
        for (a, w) in sums.omega_rad.iter_mut().zip(omega) {
            *a += h * w;
        }
        for (a, m) in sums.torque_n_m_s.iter_mut().zip(torque) {
            *a += h * m;
        }
        if let Some(d) = s.model.driving() {
            sums.driver_work_j -= h * torque[d] * omega[d];
        }
        for (a, f) in sums.shoe_n_s.iter_mut().zip(&s.forces.shoes) {
            a[0] += h * f.normal_n;
            a[1] += h * f.friction_n;
        }
        let arms = sums.tensioners.iter_mut().zip(&s.forces.tensioners);
        for ((a, r), open) in arms.zip(&mut self.was_open) {
            a.add(h, r, *open);
            *open = r.valve_open;
        }
        self.add_segments(h, s);
    }

    fn add_segments(&mut self, h: f64, s: &Sample<'_>) {
        let touching = &s.forces.touching;
        if self.runs.is_none() || self.touching != *touching {
            let segments = &s.model.segments;
            self.runs = Some(segments.runs(&s.model.sprockets, &s.state.x, &s.state.y, touching));
            self.runs_found += 1;
            self.touching.clone_from(touching);
        }
        let Some(runs) = &self.runs else {
            return;
        };
        let sums = &mut self.sums;
        let each = sums.segment_n_s.iter_mut().zip(&mut sums.segment_s);
        for (k, (a, time)) in each.enumerate() {
            // The segment's mean link force, as the samples take it
            // ([`crate::model::Segments::mean_forces`]).
            let (sum, count) = runs.force_sum(k, &s.forces.link_force);
            let f = sum / count as f64;
            if count > 0 && f.is_finite() {
                *a += h * f;
                *time += h;
            }
        }
    }

    /// The segments' free runs at the last step followed (`None` before
    /// the second), with the number of times they were found so far (which
    /// changes when they may have).
    pub fn runs(&self) -> Option<(u64, &StrandRuns)> {
        self.runs.as_ref().map(|r| (self.runs_found, r))
    }

    /// The sums since the last call, for a sample row (empty before the
    /// first step followed).
    pub fn take(&mut self) -> StepSums {
        let out = self.sums.clone();
        self.sums.clear();
        out
    }
}
