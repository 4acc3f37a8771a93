//! The analysis of a recorded run: a recording read back by
//! [`crate::record::read`] turned into the analysis's inputs ([`Signals`]
//! rows and [`Probes`]) and measured as [`super::study`] measures a live run
//! (`chaindrive analyze`, which writes the report, the JSON and the
//! figures). Feature `record`.
//!
//! The drive is rebuilt from the attached scene and brought to static
//! equilibrium ([`Simulation::new`], deterministic), which gives the model
//! (strands, sprocket centres), the static tension and the rest length.
//! Statistics use the run summary's windows, so a recording's numbers equal
//! the run's own `--summary` ones. A roller with a positive contact force
//! touches the sprocket whose pitch circle passes nearest its centre (as
//! [`Probes`] decides live); a contact patch whose force is exactly 0 counts
//! as free.
//!
//! Not in a recording, so not reported: wall times, step counts, the largest
//! penetration and the bearing forces (those need every step, a recording
//! has samples). Link-force extremes are over the samples only.
//!
//! Errors: those of reading ([`ReadError`]), a scene that cannot be rebuilt,
//! an unknown link, roller, segment or sprocket, a window outside the run,
//! a measure that needs a channel that was not recorded.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use super::binder::{centrifugal_tension_n, polygonal_speed_variation};
use super::paper_probes::{
    AnalysisError, BinderComparison, DriveFacts, Probes, RunData, Series, binder_comparison,
    link_force_series, roller_contact_series, spectrum_with_peaks, window_indices,
};
use super::spectrum::main_peak;
use super::stats::finite_stats;
use super::summary::{TipRideSummary, ToothJumpSummary};
use super::theory::{moving_string_frequency_hz, string_frequency_hz};
use super::{RunSummary, SampleRow, Signals, StepSums, StrandSummary, SummaryInputs};
use crate::record::Channel;
use crate::record::read::{ReadError, RecordedSample, Recording, read_recording};
use crate::scene::Scene;
use crate::sim::{SimError, Simulation};

/// Why a recording cannot be analysed.
#[derive(Debug, thiserror::Error)]
pub(crate) enum RecordedError {
    /// The recording cannot be read, or lacks what a measure needs.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The attached scene cannot be laid out or brought to equilibrium.
    #[error("the attached scene cannot be rebuilt: {0}")]
    Model(#[from] SimError),
    /// A series could not be cut (unknown index, window outside the run).
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
}

/// A recording read back, ready for analysis.
pub(crate) struct RecordedRun {
    /// The scene, with the run's overrides applied.
    pub scene: Scene,
    /// Signals, probes, the recomputed summary and the drive's facts.
    pub data: RunData,
    /// Topics found in the file.
    pub topics: Vec<String>,
    /// The `chaindrive` metadata record.
    #[allow(
        dead_code,
        reason = "the recording's own record, kept whole for a reader of this struct"
    )]
    pub metadata: BTreeMap<String, String>,
    /// How the run ended (`chaindrive.end` status; `unknown` if absent).
    pub end_status: String,
    /// Whether `/links` was read.
    pub has_links: bool,
    /// Whether `/contacts` and `/rollers` were read.
    pub has_contacts: bool,
}

impl RecordedRun {
    /// Reads the recording at `path` and rebuilds its drive.
    pub(crate) fn read(path: &Path) -> Result<Self, RecordedError> {
        Self::new(read_recording(path)?)
    }

    /// Rebuilds a recording's drive (settled as the run did before t = 0)
    /// and turns its samples into [`Signals`], [`Probes`] and the summary;
    /// the run's label is the recording's file stem.
    pub(crate) fn new(recording: Recording) -> Result<Self, RecordedError> {
        let Recording {
            name,
            scene,
            topics,
            metadata: meta,
            end_status,
            tooth_jumps,
            tip_rides,
            has_links,
            has_contacts,
            samples,
            tensioners: _,
        } = recording;
        if samples.len() < 2 {
            return Err(ReadError::TooFewSamples {
                samples: samples.len(),
                topics: topics.join(", "),
            }
            .into());
        }
        let sim = Simulation::new(&scene)?;
        let model = &sim.model;
        let rollers = scene.chain.rollers;
        let n_spr = model.sprocket_count();
        let mut rows = Vec::with_capacity(samples.len());
        let mut probe_rows = Vec::with_capacity(samples.len());
        for sample in samples {
            let RecordedSample {
                t_s,
                segment_force_n,
                transverse_m,
                speed_rad_s,
                chain_torque_n_m,
                link_force_n,
                contacts,
                ..
            } = sample;
            let link_range_n =
                link_force_n
                    .as_ref()
                    .map_or((f64::INFINITY, f64::NEG_INFINITY), |links| {
                        links
                            .iter()
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |r, &f| {
                                (r.0.min(f), r.1.max(f))
                            })
                    });
            let links = link_force_n.unwrap_or_else(|| vec![0.0; rollers]);
            let (contacts, on) = match contacts {
                Some((c, xy)) => {
                    let on: Vec<Option<usize>> = c
                        .iter()
                        .zip(&xy)
                        .map(|(&f, p)| {
                            (f > 0.0)
                                .then(|| {
                                    model
                                        .sprockets
                                        .iter()
                                        .enumerate()
                                        .map(|(k, s)| {
                                            let d =
                                                (p[0] - s.center_m[0]).hypot(p[1] - s.center_m[1]);
                                            (k, (d - s.pitch_radius_m).abs())
                                        })
                                        .min_by(|a, b| a.1.total_cmp(&b.1))
                                        .map(|(k, _)| k)
                                })
                                .flatten()
                        })
                        .collect();
                    (c, on)
                }
                None => (vec![0.0; rollers], vec![None; rollers]),
            };
            rows.push(SampleRow {
                t_s,
                omega_rad_s: speed_rad_s,
                chain_torque_n_m,
                bearing_max_n: vec![0.0; n_spr],
                segment_force_n,
                transverse_m,
                link_range_n,
                tensioners: Vec::new(),
                shoes: Vec::new(),
                // A recording holds samples only: its means are theirs.
                step_sums: StepSums::default(),
            });
            probe_rows.push((t_s, links, contacts, on));
        }
        let rate_hz = meta
            .get("sample_rate_hz")
            .and_then(|v| v.parse::<f64>().ok())
            .filter(|r| r.is_finite() && *r > 0.0)
            .unwrap_or_else(|| {
                let (a, b) = (rows[0].t_s, rows[rows.len() - 1].t_s);
                (rows.len() - 1) as f64 / (b - a).max(1e-12)
            });
        let mut signals = Signals::new(model, rate_hz, 0.0);
        signals.rows = rows;
        let probes = Probes::from_rows(rollers, probe_rows);
        let mut summary = RunSummary::compute(
            &SummaryInputs {
                scene: &sim.scene,
                model,
                static_tension_n: sim.equilibrium.tension_n,
                static_force_residual: None,
                static_unsettled_cause: None,
                steps: 0,
                wall_s: 0.0,
                setup_wall_s: 0.0,
                interrupted: end_status == "interrupted",
                max_penetration_m: 0.0,
            },
            &signals,
        );
        // The mesh's events come from the run's own detectors, which saw
        // every step; the samples could not find them again.
        summary.tooth_jumps = tooth_jumps.iter().map(Into::into).collect();
        summary.tip_rides = TipRideSummary::per_sprocket(&tip_rides);
        let label = Path::new(&name)
            .file_stem()
            .map_or_else(|| name.clone(), |s| s.to_string_lossy().into_owned());
        let facts = DriveFacts::new(&sim.scene, model);
        Ok(Self {
            scene: sim.scene.clone(),
            data: RunData {
                label,
                signals,
                probes,
                summary,
                facts,
            },
            topics,
            metadata: meta,
            end_status,
            has_links,
            has_contacts,
        })
    }
}

// ---------------------------------------------------------------------------
// Measuring.

/// What to analyse beyond the defaults.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct AnalyzeOptions {
    /// Link of the link-force figure (0-based); default 0 when `/links` was recorded.
    pub link: Option<usize>,
    /// Roller of the contact figure (0-based); default 0 when `/contacts` was recorded.
    pub roller: Option<usize>,
    /// Draw only this segment's figures (1-based); default every segment.
    pub segment: Option<usize>,
    /// One window (s) for every statistic, spectrum and figure; default the
    /// run summary's windows (see [`RecordedAnalysis`]).
    pub window_s: Option<[f64; 2]>,
}

/// One segment's measured quantities.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct RecordedSegment {
    /// 1-based segment.
    pub segment: usize,
    /// Strand length, m.
    pub length_m: f64,
    /// Samples in the window with a free link.
    pub samples_with_free_links: usize,
    /// Mean of the average link force over the window, N (absent: no free link).
    pub mean_link_force_n: Option<f64>,
    /// Peak-to-peak of the average link force, N.
    pub link_force_p2p_n: Option<f64>,
    /// Largest |average link force − mean|, N.
    pub link_force_amplitude_n: Option<f64>,
    /// Main peak of the transverse spectrum in 1–50 Hz, Hz (0: none), as in the run summary.
    pub transverse_peak_hz: f64,
    /// The moving string's first frequency from the segment's own mean force, Hz.
    pub string_f1_hz: f64,
    /// The plain string (52) from the segment's own mean force, Hz.
    pub string_52_hz: f64,
    /// Largest |transverse displacement − mean| over the spectrum window, m.
    pub transverse_amplitude_m: f64,
    /// Highest local maxima of the transverse spectrum in 1–200 Hz, (Hz, m), highest first.
    pub peaks: Vec<(f64, f64)>,
}

/// One sprocket's contact forces against Binder's (49).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct RecordedBinder {
    /// Complete contacts compared.
    pub contacts: usize,
    /// RMS of (simulated − (49)), N.
    pub rms_n: f64,
    /// RMS of (49) itself, N.
    pub binder_rms_n: f64,
    /// RMS of (simulated − (49) as printed), N.
    pub printed_rms_n: f64,
    /// The latest contact's roller.
    pub example_roller: usize,
    /// Its bedded count nb.
    pub bedded: usize,
    /// Its q_a, N.
    pub q_a_n: f64,
    /// Its q_b, N.
    pub q_b_n: f64,
    /// Its q_c, N.
    pub q_c_n: f64,
}

/// One sprocket's measured quantities.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct RecordedSprocket {
    /// 1-based sprocket.
    pub sprocket: usize,
    /// Tooth count.
    pub teeth: u32,
    /// Mean angular speed, rad/s.
    pub mean_speed_rad_s: f64,
    /// Peak-to-peak angular speed, rad/s.
    pub speed_p2p_rad_s: f64,
    /// Mean chain moment, N·m.
    pub mean_torque_n_m: f64,
    /// Polygonal action: relative strand-speed variation 1 − cos(π/nt).
    pub polygonal_variation: f64,
    /// Contact forces against (49) (absent without `/contacts` or without a complete contact).
    pub binder: Option<RecordedBinder>,
    /// Why there is no comparison.
    pub binder_note: Option<String>,
}

/// One link's force over the statistics window.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct RecordedLink {
    /// 0-based link (roller `link` to `link + 1`).
    pub link: usize,
    /// Mean, N.
    pub mean_n: f64,
    /// Smallest, N.
    pub min_n: f64,
    /// Largest, N.
    pub max_n: f64,
}

/// One roller's contact force over its window.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct RecordedRoller {
    /// 0-based roller.
    pub roller: usize,
    /// Window, s.
    pub window_s: [f64; 2],
    /// Largest contact force, N.
    pub max_n: f64,
    /// Fraction of the samples in contact.
    pub in_contact: f64,
    /// 1-based sprockets touched, in order of first touch.
    pub sprockets: Vec<usize>,
}

/// The analysis of a recording: `analysis.json` (`chaindrive analyze`).
///
/// Windows, as in the run summary: statistics over `window_s` (the last
/// second, samples with window start < t ≤ end); spectra over
/// `spectrum_window_s` (ramp end + 0.5 s to the end, or the whole run when
/// that holds under 0.2 s, where the run summary would report no peak);
/// contact comparisons over `contact_window_s` (ramp end to the end). A
/// given window replaces all three.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct RecordedAnalysis {
    /// The recording's file name.
    pub recording: String,
    /// Scene name.
    pub scene: String,
    /// Profile (`circular`, `real`, `mixed`).
    pub profile: String,
    /// Chain step, s.
    pub dt_s: f64,
    /// Sample rate, Hz.
    pub sample_rate_hz: f64,
    /// Samples read.
    pub samples: usize,
    /// First and last sample, s.
    pub run_s: [f64; 2],
    /// How the run ended.
    pub end_status: String,
    /// Topics in the file.
    pub channels: Vec<String>,
    /// Statistics window, s.
    pub window_s: [f64; 2],
    /// Spectrum window, s.
    pub spectrum_window_s: [f64; 2],
    /// Contact window, s.
    pub contact_window_s: [f64; 2],
    /// Static tension of the rebuilt drive, N.
    pub static_tension_n: f64,
    /// Links' rest length, m.
    pub rest_length_m: f64,
    /// Mean chain speed |ω_driver| R_driver over the window, m/s.
    pub chain_speed_m_s: f64,
    /// Centrifugal tension m_r V²/P, N.
    pub q_c_n: f64,
    /// Smallest link force over the window's samples, N (needs `/links`).
    pub link_force_min_sampled_n: Option<f64>,
    /// Largest link force over the window's samples, N (needs `/links`).
    pub link_force_max_sampled_n: Option<f64>,
    /// Strands as laid out.
    pub strands: Vec<StrandSummary>,
    /// Per segment.
    pub segments: Vec<RecordedSegment>,
    /// Per sprocket.
    pub sprockets: Vec<RecordedSprocket>,
    /// The chosen link (needs `/links`).
    pub link: Option<RecordedLink>,
    /// The chosen roller (needs `/contacts` and `/rollers`).
    pub roller: Option<RecordedRoller>,
    /// The run's tooth jumps, as its detector recorded them.
    pub tooth_jumps: Vec<ToothJumpSummary>,
    /// The tip rides of its rollers, per sprocket, as recorded.
    pub tip_rides: Vec<TipRideSummary>,
    /// What was left out, and why.
    pub notes: Vec<String>,
    /// The full comparisons, for the figures.
    #[serde(skip)]
    pub binder: Vec<Option<BinderComparison>>,
}

fn missing_for(what: &str, missing: &[&str], run: &RecordedRun) -> RecordedError {
    ReadError::missing_channels(what, missing, &run.topics).into()
}

impl RecordedRun {
    fn t(&self) -> Vec<f64> {
        self.data.signals.rows.iter().map(|r| r.t_s).collect()
    }

    fn missing_contacts(&self) -> Vec<&'static str> {
        [Channel::Contacts.topic(), Channel::Rollers.topic()]
            .into_iter()
            .filter(|t| !self.topics.iter().any(|f| f == t))
            .collect()
    }

    /// Checks `options` against the recording: indices, channels, window.
    pub(crate) fn check(&self, options: &AnalyzeOptions) -> Result<(), RecordedError> {
        let rollers = self.data.probes.rollers();
        if let Some(link) = options.link {
            if link >= rollers {
                return Err(AnalysisError::UnknownIndex {
                    what: "link",
                    index: link,
                    count: rollers,
                }
                .into());
            }
            if !self.has_links {
                return Err(missing_for(
                    &format!("link {link}'s force"),
                    &[Channel::Links.topic()],
                    self,
                ));
            }
        }
        if let Some(roller) = options.roller {
            if roller >= rollers {
                return Err(AnalysisError::UnknownIndex {
                    what: "roller",
                    index: roller,
                    count: rollers,
                }
                .into());
            }
            if !self.has_contacts {
                return Err(missing_for(
                    &format!("roller {roller}'s contact force"),
                    &self.missing_contacts(),
                    self,
                ));
            }
        }
        if let Some(segment) = options.segment {
            let count = self.data.summary.strands.len();
            if !(1..=count).contains(&segment) {
                return Err(AnalysisError::UnknownSegment { segment, count }.into());
            }
        }
        if let Some(w) = options.window_s {
            window_indices(&self.t(), w)?;
        }
        Ok(())
    }

    fn roller_window(&self, options: &AnalyzeOptions, window: [f64; 2]) -> [f64; 2] {
        if let Some(w) = options.window_s {
            return w;
        }
        let d = &self.data;
        let driver = d
            .summary
            .sprockets
            .first()
            .map_or(0.0, |s| s.mean_speed_rad_s);
        let v = driver.abs() * d.facts.pitch_radius_m.first().copied().unwrap_or(0.0);
        let circuit = if v > 0.0 {
            d.probes.rollers() as f64 * d.facts.pitch_m / v
        } else {
            1.0
        };
        let first = d.probes.t_s.first().copied().unwrap_or(0.0);
        [(window[1] - circuit).max(first), window[1]]
    }

    /// Measures the recording (after [`Self::check`]).
    pub(crate) fn analyze(
        &self,
        options: &AnalyzeOptions,
    ) -> Result<RecordedAnalysis, RecordedError> {
        self.check(options)?;
        let d = &self.data;
        let s = &d.summary;
        let rows = &d.signals.rows;
        let t = self.t();
        let run_s = [t[0], t[t.len() - 1]];
        let window = options.window_s.unwrap_or(s.window_s);
        let spectrum_window = options.window_s.unwrap_or_else(|| d.spectrum_window_s());
        let contact_window = options.window_s.unwrap_or_else(|| d.steady_window_s());
        let mut notes = Vec::new();
        // The run summary's convention: window start < t ≤ end (stats), start ≤ t ≤ end (spectra).
        let in_window: Vec<&SampleRow> = rows
            .iter()
            .filter(|r| r.t_s > window[0] && r.t_s <= window[1])
            .collect();
        let in_spectrum: Vec<&SampleRow> = rows
            .iter()
            .filter(|r| r.t_s >= spectrum_window[0] && r.t_s <= spectrum_window[1])
            .collect();
        if in_window.len() < 2 {
            return Err(AnalysisError::Window {
                from_s: window[0],
                to_s: window[1],
                run_from_s: run_s[0],
                run_to_s: run_s[1],
            }
            .into());
        }
        let driver = self
            .scene
            .sprockets
            .iter()
            .position(|sp| sp.speed_law().is_some())
            .unwrap_or(0);
        let omega_driver = finite_stats(in_window.iter().map(|r| r.omega_rad_s[driver]))
            .map_or(0.0, |v| v.0)
            .abs();
        let chain_speed = omega_driver * d.facts.pitch_radius_m.get(driver).copied().unwrap_or(0.0);
        let q_c = centrifugal_tension_n(d.facts.roller_mass_kg, chain_speed, d.facts.pitch_m);
        let segments = self.segments(&in_window, &in_spectrum, window, chain_speed, &mut notes);
        let (sprockets, binder) = self.sprockets(&in_window, contact_window);
        let link = self.link(options, window, &mut notes)?;
        let roller = self.roller(options, window, &mut notes)?;
        let (lo, hi) = if self.has_links {
            (
                finite_stats(in_window.iter().map(|r| r.link_range_n.0)).map(|v| v.1),
                finite_stats(in_window.iter().map(|r| r.link_range_n.1)).map(|v| v.2),
            )
        } else {
            (None, None)
        };
        Ok(RecordedAnalysis {
            recording: d.label.clone(),
            scene: s.scene.clone(),
            profile: s.profile.clone(),
            dt_s: s.dt_s,
            sample_rate_hz: s.sample_rate_hz,
            samples: rows.len(),
            run_s,
            end_status: self.end_status.clone(),
            channels: self.topics.clone(),
            window_s: window,
            spectrum_window_s: spectrum_window,
            contact_window_s: contact_window,
            static_tension_n: s.static_tension_n,
            rest_length_m: s.rest_length_m,
            chain_speed_m_s: chain_speed,
            q_c_n: q_c,
            link_force_min_sampled_n: lo,
            link_force_max_sampled_n: hi,
            strands: s.strands.clone(),
            segments,
            sprockets,
            link,
            roller,
            tooth_jumps: s.tooth_jumps.clone(),
            tip_rides: s.tip_rides.clone(),
            notes,
            binder,
        })
    }

    /// Each free strand's link force over `in_window` and its transverse
    /// spectrum over `in_spectrum`, against the string theory at the chain's
    /// speed; a strand without a free link in `window` gets a note.
    fn segments(
        &self,
        in_window: &[&SampleRow],
        in_spectrum: &[&SampleRow],
        window: [f64; 2],
        chain_speed: f64,
        notes: &mut Vec<String>,
    ) -> Vec<RecordedSegment> {
        let d = &self.data;
        let mu = d.facts.mass_per_length_kg_m;
        let mut segments = Vec::new();
        let s = &d.summary;
        for (k, strand) in s.strands.iter().enumerate() {
            let force = finite_stats(in_window.iter().filter_map(|r| r.segment_force_n[k]));
            let amplitude = force.and_then(|(m, _, _, _)| {
                in_window
                    .iter()
                    .filter_map(|r| r.segment_force_n[k])
                    .map(|f| (f - m).abs())
                    .reduce(f64::max)
            });
            if force.is_none() {
                notes.push(format!(
                    "segment {}: no free link in the window [{:.3}, {:.3}] s",
                    k + 1,
                    window[0],
                    window[1]
                ));
            }
            let transverse: Vec<f64> = in_spectrum.iter().map(|r| r.transverse_m[k]).collect();
            let peak = main_peak(&transverse, d.signals.rate_hz, 1.0, 50.0).map_or(0.0, |p| p.0);
            let series = Series {
                t_s: in_spectrum.iter().map(|r| r.t_s).collect(),
                value: transverse,
            };
            let picked = spectrum_with_peaks(&series, d.signals.rate_hz, [1.0, 200.0], 6, 2.0);
            let mean = force.map_or(0.0, |f| f.0);
            segments.push(RecordedSegment {
                segment: k + 1,
                length_m: strand.length_m,
                samples_with_free_links: force.map_or(0, |f| f.3),
                mean_link_force_n: force.map(|f| f.0),
                link_force_p2p_n: force.map(|f| f.2 - f.1),
                link_force_amplitude_n: amplitude,
                transverse_peak_hz: peak,
                string_f1_hz: moving_string_frequency_hz(1, mean, strand.length_m, mu, chain_speed),
                string_52_hz: if mean > 0.0 {
                    string_frequency_hz(1, mean, strand.length_m, mu * strand.length_m)
                } else {
                    0.0
                },
                transverse_amplitude_m: series.amplitude(),
                peaks: picked.peaks,
            });
        }
        segments
    }

    /// Each sprocket's speed and torque over `in_window`, and its contact
    /// forces against Binder's over `contact_window` where recorded.
    fn sprockets(
        &self,
        in_window: &[&SampleRow],
        contact_window: [f64; 2],
    ) -> (Vec<RecordedSprocket>, Vec<Option<BinderComparison>>) {
        let d = &self.data;
        let mut sprockets = Vec::new();
        let mut binder = Vec::new();
        for (k, &teeth) in d.facts.teeth.iter().enumerate() {
            let speed = finite_stats(in_window.iter().map(|r| r.omega_rad_s[k]));
            let torque = finite_stats(in_window.iter().map(|r| r.chain_torque_n_m[k]));
            let (b, note) = if self.has_contacts {
                match binder_comparison(d, k + 1, contact_window) {
                    Ok(b) => (Some(b), None),
                    Err(e) => (None, Some(e.to_string())),
                }
            } else {
                (
                    None,
                    Some(format!(
                        "not recorded: needs {}",
                        self.missing_contacts().join(", ")
                    )),
                )
            };
            sprockets.push(RecordedSprocket {
                sprocket: k + 1,
                teeth,
                mean_speed_rad_s: speed.map_or(0.0, |v| v.0),
                speed_p2p_rad_s: speed.map_or(0.0, |v| v.2 - v.1),
                mean_torque_n_m: torque.map_or(0.0, |v| v.0),
                polygonal_variation: polygonal_speed_variation(teeth),
                binder: b.as_ref().map(|b| {
                    let i = &b.example.inputs;
                    RecordedBinder {
                        contacts: b.contacts,
                        rms_n: b.rms_n,
                        binder_rms_n: b.binder_rms_n,
                        printed_rms_n: b.printed_rms_n,
                        example_roller: b.example.roller,
                        bedded: i.bedded,
                        q_a_n: i.q_a_n,
                        q_b_n: i.q_b_n,
                        q_c_n: i.q_c_n,
                    }
                }),
                binder_note: note,
            });
            binder.push(b);
        }
        (sprockets, binder)
    }

    /// The chosen link's force over `window`, where the links were recorded.
    fn link(
        &self,
        options: &AnalyzeOptions,
        window: [f64; 2],
        notes: &mut Vec<String>,
    ) -> Result<Option<RecordedLink>, RecordedError> {
        let d = &self.data;
        Ok(if self.has_links {
            let l = options.link.unwrap_or(0);
            let series = link_force_series(d, l, window)?;
            finite_stats(series.value.iter().copied()).map(|(mean, lo, hi, _)| RecordedLink {
                link: l,
                mean_n: mean,
                min_n: lo,
                max_n: hi,
            })
        } else {
            notes.push(format!(
                "link forces: not recorded (needs {})",
                Channel::Links.topic()
            ));
            None
        })
    }

    /// The chosen roller's contact force, where the contacts were recorded.
    fn roller(
        &self,
        options: &AnalyzeOptions,
        window: [f64; 2],
        notes: &mut Vec<String>,
    ) -> Result<Option<RecordedRoller>, RecordedError> {
        let d = &self.data;
        Ok(if self.has_contacts {
            let r = options.roller.unwrap_or(0);
            let w = self.roller_window(options, window);
            let (series, on) = roller_contact_series(d, r, w)?;
            let mut touched: Vec<usize> = Vec::new();
            for &s in &on {
                if s > 0 && touched.last() != Some(&s) && !touched.contains(&s) {
                    touched.push(s);
                }
            }
            Some(RecordedRoller {
                roller: r,
                window_s: w,
                max_n: series.value.iter().copied().fold(0.0, f64::max),
                in_contact: on.iter().filter(|&&s| s > 0).count() as f64 / on.len().max(1) as f64,
                sprockets: touched,
            })
        } else {
            notes.push(format!(
                "contact forces: not recorded (needs {})",
                self.missing_contacts().join(", ")
            ));
            None
        })
    }
}
