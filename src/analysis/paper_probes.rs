//! The paper's probes: the figure signals (Figs. 16–24) taken from a run,
//! and their comparison with the analytical references.
//!
//! [`Probes`] is an observer that keeps, at every sample, each link's force,
//! each roller's contact force and the sprocket it touches; together with
//! [`Signals`] it makes a [`RunData`], from which the functions here cut
//! the series the figures and the report show:
//!
//! - one link's force over a window (Fig. 16), a segment's average link force
//!   (Fig. 17), a segment's transverse displacement (Figs. 18–19) and its
//!   amplitude spectrum with peaks picked (Figs. 20–21, [`spectrum_with_peaks`]);
//! - one roller's contact force through a chain circuit (Fig. 22);
//! - per sprocket, the simulated contact force of bedded rollers against
//!   Binder's (49) with q_a, q_b, q_c, nb, t_s, t_e taken from the run
//!   (Figs. 23–24, [`binder_comparison`]).
//!
//! Indices: links and rollers count from 0 (link i joins roller i and i + 1),
//! segments and sprockets from 1, as in every output. Every function checks
//! its indices and window and returns an [`AnalysisError`] rather than an
//! empty series. It does not run simulations or draw (`studies::reproduce`, feature `lab`;
//! `figures`).

use super::binder::{BinderInputs, centrifugal_tension_n, placement_times_s};
use super::spectrum::amplitude_spectrum;
use super::{RunSummary, Signals};
use crate::model::DriveModel;
use crate::scene::Scene;
use crate::sim::{Observer, Sample};

/// No sprocket (in [`Probes`]' per-roller sprocket record).
const NONE: u8 = u8::MAX;

/// Why a series cannot be cut from a run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(crate) enum AnalysisError {
    /// Segment number outside 1 … count.
    #[error("unknown segment {segment}: the drive has segments 1 to {count}")]
    UnknownSegment {
        /// Asked.
        segment: usize,
        /// Segments in the drive.
        count: usize,
    },
    /// Sprocket number outside 1 … count.
    #[error("unknown sprocket {sprocket}: the drive has sprockets 1 to {count}")]
    UnknownSprocket {
        /// Asked.
        sprocket: usize,
        /// Sprockets in the drive.
        count: usize,
    },
    /// Roller (or link) index outside 0 … count − 1.
    #[error("unknown {what} {index}: the chain has {what}s 0 to {last}", last = count.saturating_sub(1))]
    UnknownIndex {
        /// "roller" or "link".
        what: &'static str,
        /// Asked.
        index: usize,
        /// Rollers (= links) in the chain.
        count: usize,
    },
    /// The window does not lie within the run or holds too few samples.
    #[error(
        "window [{from_s}, {to_s}] s is outside the run's samples [{run_from_s}, {run_to_s}] s or holds fewer than 2 samples"
    )]
    Window {
        /// Window start, s.
        from_s: f64,
        /// Window end, s.
        to_s: f64,
        /// First sample, s.
        run_from_s: f64,
        /// Last sample, s.
        run_to_s: f64,
    },
    /// A segment has no free link in the window.
    #[error("segment {segment} has no free link in the window")]
    NoFreeLinks {
        /// 1-based segment.
        segment: usize,
    },
    /// No complete contact on a sprocket in the window.
    #[error(
        "no roller made a complete contact with sprocket {sprocket} within [{from_s:.3}, {to_s:.3}] s"
    )]
    NoContact {
        /// 1-based sprocket.
        sprocket: usize,
        /// Window start, s.
        from_s: f64,
        /// Window end, s.
        to_s: f64,
    },
}

/// Per-sample record of every link force and every roller's contact.
#[derive(Clone, Debug, Default)]
pub(crate) struct Probes {
    rollers: usize,
    /// Sample times, s.
    pub t_s: Vec<f64>,
    link_force: Vec<f64>,
    contact_force: Vec<f64>,
    on_sprocket: Vec<u8>,
    centers: Vec<([f64; 2], f64)>,
}

impl Probes {
    /// An empty record for `model`'s drive (the chain's length is taken at
    /// the first sample). Feed it the same samples as the run's [`Signals`]:
    /// the analysis pairs their rows by index.
    pub(crate) fn new(model: &DriveModel) -> Self {
        Self {
            centers: model
                .sprockets
                .iter()
                .map(|s| (s.center_m, s.pitch_radius_m))
                .collect(),
            ..Self::default()
        }
    }

    /// From recorded samples: `rows` of (t, link forces, contact forces,
    /// sprocket index touched or `None`), each of the chain's length.
    pub(crate) fn from_rows(
        rollers: usize,
        rows: impl IntoIterator<Item = (f64, Vec<f64>, Vec<f64>, Vec<Option<usize>>)>,
    ) -> Self {
        let mut p = Self {
            rollers,
            ..Self::default()
        };
        for (t, l, c, s) in rows {
            if l.len() != rollers || c.len() != rollers || s.len() != rollers {
                continue;
            }
            p.t_s.push(t);
            p.link_force.extend(l);
            p.contact_force.extend(c);
            p.on_sprocket.extend(
                s.into_iter()
                    .map(|s| s.and_then(|s| u8::try_from(s).ok()).unwrap_or(NONE)),
            );
        }
        p
    }

    /// Rollers (= links) in the chain.
    pub(crate) fn rollers(&self) -> usize {
        self.rollers
    }

    fn check(&self, what: &'static str, index: usize) -> Result<(), AnalysisError> {
        if index < self.rollers {
            Ok(())
        } else {
            Err(AnalysisError::UnknownIndex {
                what,
                index,
                count: self.rollers,
            })
        }
    }

    /// Force of link `link` at sample `k`, N.
    fn link_at(&self, k: usize, link: usize) -> f64 {
        self.link_force[k * self.rollers + link]
    }

    /// Contact force on roller `r` at sample `k`, N.
    fn contact_at(&self, k: usize, r: usize) -> f64 {
        self.contact_force[k * self.rollers + r]
    }

    /// 0-based sprocket roller `r` touches at sample `k`.
    fn sprocket_at(&self, k: usize, r: usize) -> Option<usize> {
        let s = self.on_sprocket[k * self.rollers + r];
        (s != NONE).then_some(usize::from(s))
    }

    /// Rollers touching 0-based sprocket `s` at sample `k`.
    fn bedded_at(&self, k: usize, s: usize) -> usize {
        let row = &self.on_sprocket[k * self.rollers..(k + 1) * self.rollers];
        row.iter().filter(|&&x| usize::from(x) == s).count()
    }
}

impl Observer for Probes {
    fn sample(&mut self, s: &Sample<'_>) {
        let st = s.state;
        if self.t_s.is_empty() {
            self.rollers = st.rollers();
        }
        if st.rollers() != self.rollers {
            return;
        }
        self.t_s.push(st.t_s);
        self.link_force.extend_from_slice(&s.forces.link_force);
        self.contact_force
            .extend_from_slice(&s.forces.contact_force);
        for i in 0..self.rollers {
            let which = if s.forces.touching[i] {
                // The sprocket whose pitch circle passes nearest the roller's centre.
                self.centers
                    .iter()
                    .enumerate()
                    .map(|(k, (c, r))| (k, ((st.x[i] - c[0]).hypot(st.y[i] - c[1]) - r).abs()))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .and_then(|(k, _)| u8::try_from(k).ok())
                    .unwrap_or(NONE)
            } else {
                NONE
            };
            self.on_sprocket.push(which);
        }
    }
}

/// What the analysis needs to know of the drive.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct DriveFacts {
    /// Tooth count of each sprocket.
    pub teeth: Vec<u32>,
    /// Pitch radius of each sprocket, m.
    pub pitch_radius_m: Vec<f64>,
    /// Roller mass, kg.
    pub roller_mass_kg: f64,
    /// Pitch, m.
    pub pitch_m: f64,
    /// Mass per length, kg/m (over the worn pitch for a worn chain).
    pub mass_per_length_kg_m: f64,
    /// End of the driver's speed ramp, s.
    pub ramp_end_s: f64,
}

impl DriveFacts {
    /// From a scene and its model.
    pub(crate) fn new(scene: &Scene, model: &DriveModel) -> Self {
        Self {
            teeth: model.sprockets.iter().map(|s| s.teeth).collect(),
            pitch_radius_m: model.sprockets.iter().map(|s| s.pitch_radius_m).collect(),
            roller_mass_kg: scene.chain.roller_mass_kg,
            pitch_m: scene.chain.pitch_m,
            mass_per_length_kg_m: scene.chain.mass_per_length_kg_m(),
            ramp_end_s: scene
                .sprockets
                .iter()
                .filter_map(|s| s.speed_law())
                .map(|l| l.ramp_s)
                .fold(0.0, f64::max),
        }
    }
}

/// A finished run, ready for analysis.
pub(crate) struct RunData {
    /// Name in figures and the report (e.g. "circular").
    pub label: String,
    /// Sampled signals.
    pub signals: Signals,
    /// Per-link and per-roller samples.
    pub probes: Probes,
    /// The run's summary.
    pub summary: RunSummary,
    /// The drive.
    pub facts: DriveFacts,
}

impl RunData {
    /// The window of steady speed for contact statistics: the driver's ramp
    /// end to the end of the run (the whole run if that is under 0.1 s).
    pub(crate) fn steady_window_s(&self) -> [f64; 2] {
        let (first, last) = (
            self.probes.t_s.first().copied().unwrap_or(0.0),
            self.probes.t_s.last().copied().unwrap_or(0.0),
        );
        if self.facts.ramp_end_s + 0.1 < last {
            [self.facts.ramp_end_s.max(first), last]
        } else {
            [first, last]
        }
    }

    /// The window for spectra: the summary's `spectrum_window_s`, or the
    /// whole run if that is under 0.2 s.
    pub(crate) fn spectrum_window_s(&self) -> [f64; 2] {
        let w = self.summary.spectrum_window_s;
        if w[1] - w[0] >= 0.2 {
            w
        } else {
            [self.probes.t_s.first().copied().unwrap_or(0.0), w[1]]
        }
    }
}

/// A sampled signal.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Series {
    /// Times, s.
    pub t_s: Vec<f64>,
    /// Values (unit by context).
    pub value: Vec<f64>,
}

impl Series {
    /// The points (time since `t0`, value), in SI units.
    pub(crate) fn points(&self, t0: f64) -> Vec<(f64, f64)> {
        self.t_s
            .iter()
            .zip(&self.value)
            .map(|(t, v)| (t - t0, *v))
            .collect()
    }

    /// Mean of the values (0 if empty).
    pub(crate) fn mean(&self) -> f64 {
        if self.value.is_empty() {
            0.0
        } else {
            self.value.iter().sum::<f64>() / self.value.len() as f64
        }
    }

    /// Largest |value − mean|: the "amplitude up to" of the paper (0 if empty).
    pub(crate) fn amplitude(&self) -> f64 {
        let m = self.mean();
        self.value.iter().map(|v| (v - m).abs()).fold(0.0, f64::max)
    }
}

/// Sample indices of `t` within `window`, or the window error.
pub(crate) fn window_indices(
    t: &[f64],
    window_s: [f64; 2],
) -> Result<std::ops::Range<usize>, AnalysisError> {
    let (first, last) = (t.first().copied(), t.last().copied());
    let err = AnalysisError::Window {
        from_s: window_s[0],
        to_s: window_s[1],
        run_from_s: first.unwrap_or(0.0),
        run_to_s: last.unwrap_or(0.0),
    };
    let (Some(first), Some(last)) = (first, last) else {
        return Err(err);
    };
    // Half a sample of slack at both ends for rounding of the sample clock.
    let slack = if t.len() > 1 {
        0.5 * (last - first) / (t.len() - 1) as f64
    } else {
        0.0
    };
    if !(window_s[0] < window_s[1]) || window_s[0] < first - slack || window_s[1] > last + slack {
        return Err(err);
    }
    let a = t.partition_point(|&x| x < window_s[0] - 1e-12);
    let b = t.partition_point(|&x| x <= window_s[1] + 1e-12);
    if b < a + 2 {
        return Err(err);
    }
    Ok(a..b)
}

fn check_segment(data: &RunData, segment: usize) -> Result<usize, AnalysisError> {
    let count = data.summary.strands.len();
    if (1..=count).contains(&segment) {
        Ok(segment - 1)
    } else {
        Err(AnalysisError::UnknownSegment { segment, count })
    }
}

fn check_sprocket(data: &RunData, sprocket: usize) -> Result<usize, AnalysisError> {
    let count = data.facts.teeth.len();
    if (1..=count).contains(&sprocket) {
        Ok(sprocket - 1)
    } else {
        Err(AnalysisError::UnknownSprocket { sprocket, count })
    }
}

/// The force of link `link` (roller `link` to `link + 1`) over a window (Fig. 16), N.
pub(crate) fn link_force_series(
    data: &RunData,
    link: usize,
    window_s: [f64; 2],
) -> Result<Series, AnalysisError> {
    data.probes.check("link", link)?;
    let range = window_indices(&data.probes.t_s, window_s)?;
    Ok(Series {
        t_s: data.probes.t_s[range.clone()].to_vec(),
        value: range.map(|k| data.probes.link_at(k, link)).collect(),
    })
}

/// A segment's average link force over a window (Fig. 17), N; samples with no
/// free link are left out.
pub(crate) fn segment_force_series(
    data: &RunData,
    segment: usize,
    window_s: [f64; 2],
) -> Result<Series, AnalysisError> {
    let k = check_segment(data, segment)?;
    let t: Vec<f64> = data.signals.rows.iter().map(|r| r.t_s).collect();
    let range = window_indices(&t, window_s)?;
    let mut s = Series::default();
    for r in &data.signals.rows[range] {
        if let Some(f) = r.segment_force_n[k] {
            s.t_s.push(r.t_s);
            s.value.push(f);
        }
    }
    if s.value.is_empty() {
        return Err(AnalysisError::NoFreeLinks { segment });
    }
    Ok(s)
}

/// A segment's transverse displacement over a window (Figs. 18–19), m.
pub(crate) fn transverse_series(
    data: &RunData,
    segment: usize,
    window_s: [f64; 2],
) -> Result<Series, AnalysisError> {
    let k = check_segment(data, segment)?;
    let t: Vec<f64> = data.signals.rows.iter().map(|r| r.t_s).collect();
    let range = window_indices(&t, window_s)?;
    let rows = &data.signals.rows[range];
    Ok(Series {
        t_s: rows.iter().map(|r| r.t_s).collect(),
        value: rows.iter().map(|r| r.transverse_m[k]).collect(),
    })
}

/// One roller's contact force over a window (Fig. 22), N, with the 1-based
/// sprocket it touches at each sample (0: none).
pub(crate) fn roller_contact_series(
    data: &RunData,
    roller: usize,
    window_s: [f64; 2],
) -> Result<(Series, Vec<usize>), AnalysisError> {
    data.probes.check("roller", roller)?;
    let range = window_indices(&data.probes.t_s, window_s)?;
    let on = range
        .clone()
        .map(|k| data.probes.sprocket_at(k, roller).map_or(0, |s| s + 1))
        .collect();
    Ok((
        Series {
            t_s: data.probes.t_s[range.clone()].to_vec(),
            value: range.map(|k| data.probes.contact_at(k, roller)).collect(),
        },
        on,
    ))
}

/// An amplitude spectrum with its highest local maxima.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PickedSpectrum {
    /// Frequencies, Hz.
    pub freq_hz: Vec<f64>,
    /// Amplitudes (the signal's unit), see [`super::spectrum`] for the normalisation.
    pub amplitude: Vec<f64>,
    /// Peaks (frequency, amplitude), highest first.
    pub peaks: Vec<(f64, f64)>,
}

/// The amplitude spectrum of a uniformly sampled series ([`amplitude_spectrum`]:
/// mean removed, Hann window, scaled so a sine of amplitude A peaks at ≈ A) and
/// its `count` highest local maxima in [lo_hz, hi_hz], each at least `min_gap_hz`
/// from a higher one.
pub(crate) fn spectrum_with_peaks(
    series: &Series,
    rate_hz: f64,
    band_hz: [f64; 2],
    count: usize,
    min_gap_hz: f64,
) -> PickedSpectrum {
    let (freq_hz, amplitude) = amplitude_spectrum(&series.value, rate_hz);
    let mut maxima: Vec<(f64, f64)> = (1..freq_hz.len().saturating_sub(1))
        .filter(|&k| freq_hz[k] >= band_hz[0] && freq_hz[k] <= band_hz[1])
        .filter(|&k| amplitude[k] > amplitude[k - 1] && amplitude[k] >= amplitude[k + 1])
        .map(|k| (freq_hz[k], amplitude[k]))
        .collect();
    maxima.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut peaks: Vec<(f64, f64)> = Vec::new();
    for m in maxima {
        if peaks.len() >= count {
            break;
        }
        if peaks.iter().all(|p| (p.0 - m.0).abs() >= min_gap_hz) {
            peaks.push(m);
        }
    }
    PickedSpectrum {
        freq_hz,
        amplitude,
        peaks,
    }
}

/// One roller's complete contact with a sprocket.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ContactInterval {
    /// The roller.
    pub roller: usize,
    /// First sample index in contact.
    pub first: usize,
    /// Last sample index in contact.
    pub last: usize,
}

/// Complete contacts of every roller with 0-based sprocket `s`, starting and
/// ending within `range` (not at its edges). Gaps shorter than `merge` samples
/// (a roller's rebounds at seating) do not split a contact.
fn contact_intervals(
    p: &Probes,
    s: usize,
    range: std::ops::Range<usize>,
    merge: usize,
) -> Vec<ContactInterval> {
    let mut out = Vec::new();
    for r in 0..p.rollers {
        let mut current: Option<(usize, usize)> = None;
        for k in range.clone() {
            if p.sprocket_at(k, r) == Some(s) {
                current = match current {
                    Some((a, b)) if k - b <= merge => Some((a, k)),
                    Some((a, b)) => {
                        out.push(ContactInterval {
                            roller: r,
                            first: a,
                            last: b,
                        });
                        Some((k, k))
                    }
                    None => Some((k, k)),
                };
            }
        }
        if let Some((a, b)) = current
            && b + merge < range.end
        {
            out.push(ContactInterval {
                roller: r,
                first: a,
                last: b,
            });
        }
    }
    // A contact that was already under way at the window's start is not complete.
    out.retain(|c| c.first > range.start && c.last > c.first + 1);
    out.sort_by_key(|c| c.first);
    out
}

/// One contact compared with (49).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ContactExample {
    /// The roller.
    pub roller: usize,
    /// Contact start and end, s.
    pub t_start_s: f64,
    /// Contact end, s.
    pub t_end_s: f64,
    /// The simulated contact force over the contact, N.
    pub simulated: Series,
    /// Binder's inputs from the run.
    pub inputs: BinderInputs,
    /// (51)'s times, s.
    pub binder_t_s: Vec<f64>,
    /// (49), consistent form, N.
    pub binder_n: Vec<f64>,
    /// (49) as printed, N.
    pub printed_n: Vec<f64>,
}

impl ContactExample {
    /// (49)'s points (time since the contact's start, force N).
    pub(crate) fn binder_points(&self) -> Vec<(f64, f64)> {
        self.binder_t_s
            .iter()
            .zip(&self.binder_n)
            .map(|(t, f)| (t - self.t_start_s, *f))
            .collect()
    }
}

/// The simulated contact forces on one sprocket against (49).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BinderComparison {
    /// 1-based sprocket.
    pub sprocket: usize,
    /// Complete contacts compared.
    pub contacts: usize,
    /// RMS of (simulated − (49)) over every analytical point of every contact, N.
    pub rms_n: f64,
    /// RMS of the (49) values themselves, N (for a relative measure).
    pub binder_rms_n: f64,
    /// RMS of (simulated − (49) as printed), N.
    pub printed_rms_n: f64,
    /// The latest contact, for the figure.
    pub example: ContactExample,
}

/// Compares the contact force of every roller that made a complete contact
/// with `sprocket` within `window_s` with Binder's (49) (consistent form).
/// A contact is complete when it starts and ends inside the window; gaps of up
/// to one tooth period (rebounds at seating) do not split it, and contacts
/// shorter than two tooth periods are left out.
///
/// Per contact: t_s and t_e are its first and last sample in contact; nb the
/// mean number of rollers bedded on the sprocket during it, rounded; q_a and
/// q_b the mean average link forces of the entering and leaving segments
/// during it (the chain travels in scene order: segment k − 1 enters sprocket
/// k, segment k leaves it); q_c from the mean chain speed |ω_s| R_s during it.
/// The simulated value at the analytical point t_i is the mean of the roller's
/// contact force over the samples within half a spacing (t_e − t_s)/(nb − 1)
/// of t_i, so the comparison is of the quasi-static level, not of the impact
/// ringing.
pub(crate) fn binder_comparison(
    data: &RunData,
    sprocket: usize,
    window_s: [f64; 2],
) -> Result<BinderComparison, AnalysisError> {
    let s = check_sprocket(data, sprocket)?;
    let p = &data.probes;
    let range = window_indices(&p.t_s, window_s)?;
    let rows = &data.signals.rows;
    let n_seg = data.summary.strands.len();
    let (entering, leaving) = ((s + n_seg - 1) % n_seg, s % n_seg);
    let dt = (p.t_s[range.end - 1] - p.t_s[range.start]) / (range.len() - 1) as f64;
    // Merge gaps shorter than a quarter of the tooth period at the sprocket's mean speed.
    let omega_mean = range
        .clone()
        .filter_map(|k| rows.get(k).map(|r| r.omega_rad_s[s].abs()))
        .sum::<f64>()
        / range.len() as f64;
    let tooth_period = if omega_mean > 0.0 {
        std::f64::consts::TAU / (f64::from(data.facts.teeth[s]) * omega_mean)
    } else {
        0.01
    };
    // A seating roller may rebound (Lankarani–Nikravesh at e = 0 still returns
    // ≈ 0.66 of the approach speed): gaps up to a tooth period do not split a
    // contact, and a contact shorter than two tooth periods is such a rebound.
    let merge = ((tooth_period / dt).round() as usize).max(1);
    let shortest = 2.0 * tooth_period;
    let intervals: Vec<ContactInterval> = contact_intervals(p, s, range.clone(), merge)
        .into_iter()
        .filter(|c| p.t_s[c.last] - p.t_s[c.first] >= shortest)
        .collect();
    let none = AnalysisError::NoContact {
        sprocket,
        from_s: window_s[0],
        to_s: window_s[1],
    };
    let (mut sq, mut sq_binder, mut sq_printed) = (0.0, 0.0, 0.0);
    let (mut points, mut contacts) = (0usize, 0usize);
    let mut example = None;
    for c in &intervals {
        let span = c.first..=c.last;
        let mean = |f: &dyn Fn(usize) -> Option<f64>| {
            let (sum, n) = span
                .clone()
                .filter_map(f)
                .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
            (n > 0).then(|| sum / n as f64)
        };
        let Some(bedded) = mean(&|k| Some(p.bedded_at(k, s) as f64)) else {
            continue;
        };
        let bedded = (bedded.round() as usize).max(1);
        let (Some(q_a), Some(q_b), Some(omega)) = (
            mean(&|k| rows.get(k).and_then(|r| r.segment_force_n[entering])),
            mean(&|k| rows.get(k).and_then(|r| r.segment_force_n[leaving])),
            mean(&|k| rows.get(k).map(|r| r.omega_rad_s[s].abs())),
        ) else {
            continue;
        };
        let v = omega * data.facts.pitch_radius_m[s];
        let inputs = BinderInputs {
            teeth: data.facts.teeth[s],
            bedded,
            q_a_n: q_a,
            q_b_n: q_b,
            q_c_n: centrifugal_tension_n(data.facts.roller_mass_kg, v, data.facts.pitch_m),
        };
        let (t0, t1) = (p.t_s[c.first], p.t_s[c.last]);
        let times = placement_times_s(t0, t1, bedded);
        let binder = inputs.contact_forces();
        let printed = super::binder::printed_contact_forces(&inputs);
        let half = if bedded > 1 {
            0.5 * (t1 - t0) / (bedded - 1) as f64
        } else {
            0.5 * (t1 - t0)
        };
        for ((ti, bi), pi) in times.iter().zip(&binder).zip(&printed) {
            let sim = mean(&|k| ((p.t_s[k] - ti).abs() <= half).then(|| p.contact_at(k, c.roller)))
                .unwrap_or_else(|| {
                    let k = (c.first..=c.last)
                        .min_by(|&a, &b| (p.t_s[a] - ti).abs().total_cmp(&(p.t_s[b] - ti).abs()))
                        .unwrap_or(c.first);
                    p.contact_at(k, c.roller)
                });
            sq += (sim - bi) * (sim - bi);
            sq_binder += bi * bi;
            sq_printed += (sim - pi) * (sim - pi);
            points += 1;
        }
        contacts += 1;
        example = Some(ContactExample {
            roller: c.roller,
            t_start_s: t0,
            t_end_s: t1,
            simulated: Series {
                t_s: p.t_s[span.clone()].to_vec(),
                value: span.map(|k| p.contact_at(k, c.roller)).collect(),
            },
            binder_t_s: times,
            binder_n: binder,
            printed_n: printed,
            inputs,
        });
    }
    let example = example.ok_or(none)?;
    Ok(BinderComparison {
        sprocket,
        contacts,
        rms_n: (sq / points as f64).sqrt(),
        binder_rms_n: (sq_binder / points as f64).sqrt(),
        printed_rms_n: (sq_printed / points as f64).sqrt(),
        example,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The window is said as the report says its windows, in ms: the
    /// recording of a flat drive, whose back-side idler takes 0.15 pitches
    /// of wrap, was reported "within [0.2, 1.2000000000000002] s".
    #[test]
    fn no_contact_names_its_window_in_milliseconds() {
        let e = AnalysisError::NoContact {
            sprocket: 3,
            from_s: 0.2,
            to_s: 0.2 + 1.0,
        };
        assert_eq!(
            e.to_string(),
            "no roller made a complete contact with sprocket 3 within [0.200, 1.200] s"
        );
    }

    #[test]
    fn window_checks() {
        let t: Vec<f64> = (0..11).map(|i| f64::from(i) * 0.1).collect();
        assert_eq!(window_indices(&t, [0.2, 0.5]), Ok(2..6));
        assert!(window_indices(&t, [0.5, 2.0]).is_err());
        assert!(window_indices(&t, [-1.0, 0.5]).is_err());
        assert!(window_indices(&t, [0.5, 0.5]).is_err());
        assert!(window_indices(&[], [0.0, 1.0]).is_err());
    }

    #[test]
    fn intervals_merge_short_gaps_and_drop_incomplete_ones() {
        // 1 roller; touches sprocket 0 at samples 2..=4, 6..=8 (gap 1), and from 12 to the end.
        let on: Vec<Option<usize>> = (0..15)
            .map(|k| ((2..=4).contains(&k) || (6..=8).contains(&k) || k >= 12).then_some(0))
            .collect();
        let p = Probes::from_rows(
            1,
            on.into_iter()
                .enumerate()
                .map(|(k, s)| (k as f64, vec![0.0], vec![1.0], vec![s])),
        );
        let c = contact_intervals(&p, 0, 0..15, 2);
        assert_eq!(
            c,
            vec![ContactInterval {
                roller: 0,
                first: 2,
                last: 8
            }]
        );
    }
}
