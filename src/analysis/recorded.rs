//! The analysis of a recorded run: an MCAP file written by
//! `chaindrive run --record` read back into the analysis's inputs
//! ([`Signals`] rows and [`Probes`]), measured as [`super::study`] measures a
//! live run, and written up (`chaindrive analyze`). Feature `record`; the
//! figures need `figures` too.
//!
//! What is read, and from where:
//!
//! - the scene: the attached scene file (`Scene::from_toml`), with the run's
//!   overrides taken from the `chaindrive` metadata (profile, dt, stepping,
//!   duration). The drive is rebuilt and brought to static equilibrium
//!   ([`Simulation::new`], deterministic), which gives the model (strands,
//!   sprocket centres), the static tension and the rest length;
//! - `/segments` and `/sprockets` (required): each segment's average link
//!   force and transverse displacement, each sprocket's speed and chain
//!   moment: the [`Signals`] rows. Statistics use the run summary's windows,
//!   so a recording's numbers equal the run's own `--summary` ones;
//! - `/links` (optional): every link's force (the link-force figure);
//! - `/contacts` with `/rollers` (optional): every roller's contact force and
//!   position. A roller with a positive contact force touches the sprocket
//!   whose pitch circle passes nearest its centre (as [`Probes`] decides
//!   live); a contact patch whose force is exactly 0 counts as free.
//!
//! Not in a recording, so not reported: wall times, step counts, the largest
//! penetration and the bearing forces (those need every step, a recording
//! has samples). Link-force extremes are over the samples only.
//!
//! Errors: a file that is not MCAP, a recording without the scene or
//! without the needed channels (naming what is missing and what was found),
//! an unknown link, roller, segment or sprocket, a window outside the run.
//! Nothing is written before every check has passed, and a figure with no
//! data is never drawn.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::binder::{centrifugal_tension_n, polygonal_speed_variation};
use super::spectrum::main_peak;
use super::study::{
    AnalysisError, BinderComparison, DriveFacts, Probes, RunData, Series, binder_comparison,
    link_force_series, roller_contact_series, segment_force_series, spectrum_with_peaks,
    transverse_series, window_indices,
};
use super::theory::{moving_string_frequency_hz, string_frequency_hz};
use super::{RunSummary, SampleRow, Signals, StrandSummary, SummaryInputs};
use crate::record::Channel;
use crate::scene::{Overrides, ProfileKind, Scene, Stepping};
use crate::sim::{SimError, Simulation};

/// The first bytes of every MCAP file.
const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// Why a recording cannot be analysed.
#[derive(Debug, thiserror::Error)]
pub enum RecordedError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The path.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not an MCAP file (or is damaged).
    #[error("{path} is not a readable MCAP recording: {found}")]
    NotMcap {
        /// The path.
        path: String,
        /// What was found instead.
        found: String,
    },
    /// No scene file is attached.
    #[error(
        "the recording has no scene file attached (found attachments: {found}); record it with `chaindrive run --record`"
    )]
    NoScene {
        /// Attachments present.
        found: String,
    },
    /// The attached scene does not parse or validate.
    #[error("the attached scene {name} is invalid: {message}")]
    Scene {
        /// Attachment name.
        name: String,
        /// The scene errors, one per line.
        message: String,
    },
    /// The attached scene cannot be laid out or brought to equilibrium.
    #[error("the attached scene cannot be rebuilt: {0}")]
    Model(#[from] SimError),
    /// Channels the analysis needs are absent.
    #[error(
        "the recording lacks channel(s) {missing} needed for {needed_for}; it has: {found}. Record with `--record-channels all` (or include {channels})"
    )]
    MissingChannels {
        /// Missing topics.
        missing: String,
        /// What needs them.
        needed_for: String,
        /// Topics in the file.
        found: String,
        /// The `--record-channels` names to add.
        channels: String,
    },
    /// A message could not be decoded or does not fit the scene.
    #[error("{topic}: {message}")]
    Decode {
        /// The topic.
        topic: String,
        /// Why.
        message: String,
    },
    /// The recording holds too few samples.
    #[error("the recording holds {samples} sample(s) on {topics}; at least 2 are needed")]
    TooFewSamples {
        /// Samples found.
        samples: usize,
        /// The topics read.
        topics: String,
    },
    /// A series could not be cut (unknown index, window outside the run).
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// A figure could not be drawn.
    #[cfg(feature = "figures")]
    #[error(transparent)]
    Figure(#[from] super::figures::FigureError),
    /// An output could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The path.
        path: String,
        /// Why.
        source: std::io::Error,
    },
}

// ---------------------------------------------------------------------------
// Protobuf wire format (the recording's messages are plain proto3).

enum Wire<'a> {
    Varint(u64),
    Fixed64(u64),
    Bytes(&'a [u8]),
    Fixed32(u32),
}

fn varint(buf: &[u8], at: &mut usize) -> Result<u64, String> {
    let mut v = 0u64;
    for shift in (0..64).step_by(7) {
        let b = *buf.get(*at).ok_or("truncated varint")?;
        *at += 1;
        v |= u64::from(b & 0x7f) << shift;
        if b & 0x80 == 0 {
            return Ok(v);
        }
    }
    Err("varint longer than 10 bytes".to_owned())
}

fn take<'a>(buf: &'a [u8], at: &mut usize, n: usize) -> Result<&'a [u8], String> {
    let end = at.checked_add(n).filter(|&e| e <= buf.len());
    let end = end.ok_or("truncated field")?;
    let s = &buf[*at..end];
    *at = end;
    Ok(s)
}

/// The fields of a message: (field number, value).
fn fields(buf: &[u8]) -> Result<Vec<(u64, Wire<'_>)>, String> {
    let mut out = Vec::new();
    let mut at = 0;
    while at < buf.len() {
        let key = varint(buf, &mut at)?;
        let value = match key & 7 {
            0 => Wire::Varint(varint(buf, &mut at)?),
            1 => {
                let b = take(buf, &mut at, 8)?;
                Wire::Fixed64(u64::from_le_bytes(b.try_into().map_err(|_| "bad fixed64")?))
            }
            2 => {
                let n = usize::try_from(varint(buf, &mut at)?).map_err(|_| "length too large")?;
                Wire::Bytes(take(buf, &mut at, n)?)
            }
            5 => {
                let b = take(buf, &mut at, 4)?;
                Wire::Fixed32(u32::from_le_bytes(b.try_into().map_err(|_| "bad fixed32")?))
            }
            w => return Err(format!("unsupported wire type {w}")),
        };
        out.push((key >> 3, value));
    }
    Ok(out)
}

fn double(w: &Wire<'_>) -> Result<f64, String> {
    match w {
        Wire::Fixed64(v) => Ok(f64::from_bits(*v)),
        _ => Err("expected a double".to_owned()),
    }
}

/// Appends a repeated double field's value(s), packed or not.
fn doubles(w: &Wire<'_>, out: &mut Vec<f64>) -> Result<(), String> {
    match w {
        Wire::Fixed64(v) => out.push(f64::from_bits(*v)),
        Wire::Bytes(b) if b.len() % 8 == 0 => out.extend(
            b.chunks_exact(8)
                .filter_map(|c| c.try_into().ok())
                .map(f64::from_le_bytes),
        ),
        _ => return Err("expected repeated doubles".to_owned()),
    }
    Ok(())
}

/// `ChainLinkForces` / `ChainContactForces`: (t, values).
fn decode_forces(buf: &[u8]) -> Result<(f64, Vec<f64>), String> {
    let (mut t, mut v) = (0.0, Vec::new());
    for (n, w) in fields(buf)? {
        match n {
            1 => t = double(&w)?,
            2 => doubles(&w, &mut v)?,
            _ => {}
        }
    }
    Ok((t, v))
}

/// `SprocketSignals`: (t, speeds, chain moments).
fn decode_sprockets(buf: &[u8]) -> Result<(f64, Vec<f64>, Vec<f64>), String> {
    let (mut t, mut angle, mut speed, mut torque) = (0.0, Vec::new(), Vec::new(), Vec::new());
    for (n, w) in fields(buf)? {
        match n {
            1 => t = double(&w)?,
            2 => doubles(&w, &mut angle)?,
            3 => doubles(&w, &mut speed)?,
            4 => doubles(&w, &mut torque)?,
            _ => {}
        }
    }
    Ok((t, speed, torque))
}

/// `SegmentSignals`: (t, forces, transverse displacements), in segment order.
type SegmentsMsg = (f64, Vec<Option<f64>>, Vec<f64>);

fn decode_segments(buf: &[u8]) -> Result<SegmentsMsg, String> {
    let (mut t, mut list) = (0.0, Vec::new());
    for (n, w) in fields(buf)? {
        match (n, w) {
            (1, w) => t = double(&w)?,
            (2, Wire::Bytes(b)) => {
                let (mut seg, mut force, mut transverse) = (0u64, None, 0.0);
                for (m, v) in fields(b)? {
                    match m {
                        1 => {
                            if let Wire::Varint(s) = v {
                                seg = s;
                            }
                        }
                        2 => force = Some(double(&v)?),
                        3 => transverse = double(&v)?,
                        _ => {}
                    }
                }
                list.push((seg, force, transverse));
            }
            (2, _) => return Err("expected a segment message".to_owned()),
            _ => {}
        }
    }
    list.sort_by_key(|s| s.0);
    Ok((
        t,
        list.iter().map(|s| s.1).collect(),
        list.iter().map(|s| s.2).collect(),
    ))
}

/// `foxglove.PointCloud` of f32 x, y: the roller centres.
fn decode_cloud(buf: &[u8]) -> Result<Vec<[f64; 2]>, String> {
    let (mut stride, mut data, mut offsets) = (0usize, &[][..], BTreeMap::new());
    for (n, w) in fields(buf)? {
        match (n, w) {
            (4, Wire::Fixed32(s)) => stride = s as usize,
            (4, Wire::Varint(s)) => stride = usize::try_from(s).map_err(|_| "bad stride")?,
            (5, Wire::Bytes(b)) => {
                let (mut name, mut offset) = (String::new(), 0usize);
                for (m, v) in fields(b)? {
                    match (m, v) {
                        (1, Wire::Bytes(s)) => name = String::from_utf8_lossy(s).into_owned(),
                        (2, Wire::Fixed32(o)) => offset = o as usize,
                        (2, Wire::Varint(o)) => offset = o as usize,
                        _ => {}
                    }
                }
                offsets.insert(name, offset);
            }
            (6, Wire::Bytes(b)) => data = b,
            _ => {}
        }
    }
    let (ox, oy) = (
        offsets.get("x").copied().unwrap_or(0),
        offsets.get("y").copied().unwrap_or(4),
    );
    if stride < 8 || ox + 4 > stride || oy + 4 > stride {
        return Err(format!("unsupported point layout (stride {stride})"));
    }
    let f = |c: &[u8], o: usize| {
        c.get(o..o + 4)
            .and_then(|b| b.try_into().ok())
            .map_or(f64::NAN, |b| f64::from(f32::from_le_bytes(b)))
    };
    Ok(data
        .chunks_exact(stride)
        .map(|c| [f(c, ox), f(c, oy)])
        .collect())
}

// ---------------------------------------------------------------------------
// Reading.

/// A recording read back, ready for analysis.
pub struct RecordedRun {
    /// The scene, with the run's overrides applied.
    pub scene: Scene,
    /// Signals, probes, the recomputed summary and the drive's facts.
    pub data: RunData,
    /// Topics found in the file.
    pub topics: Vec<String>,
    /// The `chaindrive` metadata record.
    pub metadata: BTreeMap<String, String>,
    /// How the run ended (`chaindrive.end` status; `unknown` if absent).
    pub end_status: String,
    /// Whether `/links` was read.
    pub has_links: bool,
    /// Whether `/contacts` and `/rollers` were read.
    pub has_contacts: bool,
}

fn not_mcap(path: &str, bytes: &[u8]) -> RecordedError {
    let found = if bytes.is_empty() {
        "the file is empty".to_owned()
    } else if bytes.starts_with(MCAP_MAGIC) {
        "it starts like MCAP but cannot be read".to_owned()
    } else {
        let head: String = bytes
            .iter()
            .take(16)
            .map(|&b| {
                if b.is_ascii_graphic() || b == b' ' {
                    char::from(b)
                } else {
                    '.'
                }
            })
            .collect();
        format!(
            "it starts with {head:?}, not the MCAP magic \"\\x89MCAP0\\r\\n\" ({} bytes)",
            bytes.len()
        )
    };
    RecordedError::NotMcap {
        path: path.to_owned(),
        found,
    }
}

/// Reads the recording at `path` (see the module documentation).
pub fn read_recording(path: &Path) -> Result<RecordedRun, RecordedError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| RecordedError::Read {
        path: name.clone(),
        source,
    })?;
    read_recording_bytes(&name, &bytes)
}

/// Messages of one topic: log time (ns) → payload.
type Topic<'a> = BTreeMap<u64, std::borrow::Cow<'a, [u8]>>;

/// Reads a recording held in memory; `name` is used in messages and as the run's label.
pub fn read_recording_bytes(name: &str, bytes: &[u8]) -> Result<RecordedRun, RecordedError> {
    if !bytes.starts_with(MCAP_MAGIC) {
        return Err(not_mcap(name, bytes));
    }
    // Top-level records: metadata, attachments (outside chunks).
    let mut metadata: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    let mut attachments: Vec<(String, String, Vec<u8>)> = Vec::new();
    let reader = mcap::read::LinearReader::new(bytes).map_err(|e| RecordedError::NotMcap {
        path: name.to_owned(),
        found: e.to_string(),
    })?;
    for record in reader {
        // A file cut short (a killed run) still yields what precedes the damage.
        let Ok(record) = record else { break };
        match record {
            mcap::records::Record::Metadata(m) => {
                metadata.insert(m.name, m.metadata);
            }
            mcap::records::Record::Attachment { header, data, .. } => {
                attachments.push((header.name, header.media_type, data.into_owned()));
            }
            _ => {}
        }
    }
    let mut topics: BTreeMap<String, Topic<'_>> = BTreeMap::new();
    let stream = mcap::MessageStream::new(bytes).map_err(|e| RecordedError::NotMcap {
        path: name.to_owned(),
        found: e.to_string(),
    })?;
    for m in stream {
        let Ok(m) = m else { break };
        topics
            .entry(m.channel.topic.clone())
            .or_default()
            .insert(m.log_time, m.data);
    }
    let found: Vec<String> = topics.keys().cloned().collect();
    let found_text = if found.is_empty() {
        "no messages".to_owned()
    } else {
        found.join(", ")
    };
    let meta = metadata.remove("chaindrive").unwrap_or_default();
    let end_status = metadata
        .get("chaindrive.end")
        .and_then(|m| m.get("status"))
        .cloned()
        .unwrap_or_else(|| "unknown (no end record)".to_owned());

    // The scene and its overrides.
    let Some((scene_name, _, scene_bytes)) = attachments
        .iter()
        .find(|a| a.1 == "application/toml" || a.0.ends_with(".toml"))
    else {
        return Err(RecordedError::NoScene {
            found: if attachments.is_empty() {
                "none".to_owned()
            } else {
                attachments
                    .iter()
                    .map(|a| format!("{} ({})", a.0, a.1))
                    .collect::<Vec<_>>()
                    .join(", ")
            },
        });
    };
    let text = String::from_utf8_lossy(scene_bytes);
    // The run's own settings, where the recording states them sensibly.
    let number = |key: &str| meta.get(key).and_then(|v| v.parse::<f64>().ok());
    let overrides = Overrides {
        profile: meta.get("profile").and_then(|p| ProfileKind::parse(p)),
        dt_s: number("dt_s").filter(|dt| dt.is_finite() && *dt > 0.0),
        duration_s: number("duration_s").filter(|d| d.is_finite() && *d >= 0.0),
        stepping: meta.get("stepping").and_then(|s| Stepping::from_name(s)),
        ..Overrides::default()
    };
    let scene = Scene::from_toml_with(&text, &overrides).map_err(|e| RecordedError::Scene {
        name: scene_name.clone(),
        message: e.lines().join("; "),
    })?;

    // Required channels.
    let required = [Channel::Segments, Channel::Sprockets];
    let missing: Vec<Channel> = required
        .iter()
        .copied()
        .filter(|c| !topics.contains_key(c.topic()))
        .collect();
    if !missing.is_empty() {
        return Err(RecordedError::MissingChannels {
            missing: missing
                .iter()
                .map(|c| c.topic())
                .collect::<Vec<_>>()
                .join(", "),
            needed_for: "segment forces, transverse displacements and sprocket speeds".to_owned(),
            found: found_text,
            channels: missing
                .iter()
                .map(|c| c.name())
                .collect::<Vec<_>>()
                .join(","),
        });
    }
    let has_links = topics.contains_key(Channel::Links.topic());
    let has_contacts = topics.contains_key(Channel::Contacts.topic())
        && topics.contains_key(Channel::Rollers.topic());

    // The drive, rebuilt and settled as the run did before t = 0.
    let sim = Simulation::new(&scene)?;
    let model = &sim.model;
    let rollers = scene.chain.rollers;
    let (n_seg, n_spr) = (model.segments.len(), model.sprocket_count());

    // Samples present on every channel read.
    let mut used = vec![Channel::Segments.topic(), Channel::Sprockets.topic()];
    if has_links {
        used.push(Channel::Links.topic());
    }
    if has_contacts {
        used.push(Channel::Contacts.topic());
        used.push(Channel::Rollers.topic());
    }
    let empty = Topic::new();
    let get = |t: &str| topics.get(t).unwrap_or(&empty);
    let times: Vec<u64> = get(Channel::Segments.topic())
        .keys()
        .copied()
        .filter(|t| used.iter().all(|u| get(u).contains_key(t)))
        .collect();
    if times.len() < 2 {
        return Err(RecordedError::TooFewSamples {
            samples: times.len(),
            topics: used.join(", "),
        });
    }
    let bad = |topic: &str, t_ns: u64, message: String| RecordedError::Decode {
        topic: topic.to_owned(),
        message: format!("message at t = {} s: {message}", t_ns as f64 * 1e-9),
    };
    let shape = |topic: &str, t_ns: u64, what: &str, got: usize, want: usize| {
        bad(
            topic,
            t_ns,
            format!("{got} {what}, but the attached scene has {want}"),
        )
    };

    let mut rows = Vec::with_capacity(times.len());
    let mut probe_rows = Vec::with_capacity(times.len());
    for &t_ns in &times {
        let seg_topic = Channel::Segments.topic();
        let spr_topic = Channel::Sprockets.topic();
        let (t_s, force, transverse) = get(seg_topic)
            .get(&t_ns)
            .map(|d| decode_segments(d))
            .transpose()
            .map_err(|e| bad(seg_topic, t_ns, e))?
            .unwrap_or_default();
        if force.len() != n_seg {
            return Err(shape(seg_topic, t_ns, "segments", force.len(), n_seg));
        }
        let (_, speed, torque) = get(spr_topic)
            .get(&t_ns)
            .map(|d| decode_sprockets(d))
            .transpose()
            .map_err(|e| bad(spr_topic, t_ns, e))?
            .unwrap_or_default();
        if speed.len() != n_spr || torque.len() != n_spr {
            return Err(shape(
                spr_topic,
                t_ns,
                "sprocket values",
                speed.len(),
                n_spr,
            ));
        }
        let links = if has_links {
            let topic = Channel::Links.topic();
            let (_, l) = get(topic)
                .get(&t_ns)
                .map(|d| decode_forces(d))
                .transpose()
                .map_err(|e| bad(topic, t_ns, e))?
                .unwrap_or_default();
            if l.len() != rollers {
                return Err(shape(topic, t_ns, "link forces", l.len(), rollers));
            }
            l
        } else {
            vec![0.0; rollers]
        };
        let (contacts, on) = if has_contacts {
            let topic = Channel::Contacts.topic();
            let (_, c) = get(topic)
                .get(&t_ns)
                .map(|d| decode_forces(d))
                .transpose()
                .map_err(|e| bad(topic, t_ns, e))?
                .unwrap_or_default();
            if c.len() != rollers {
                return Err(shape(topic, t_ns, "contact forces", c.len(), rollers));
            }
            let topic = Channel::Rollers.topic();
            let xy = get(topic)
                .get(&t_ns)
                .map(|d| decode_cloud(d))
                .transpose()
                .map_err(|e| bad(topic, t_ns, e))?
                .unwrap_or_default();
            if xy.len() != rollers {
                return Err(shape(topic, t_ns, "roller positions", xy.len(), rollers));
            }
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
                                    let d = (p[0] - s.center_m[0]).hypot(p[1] - s.center_m[1]);
                                    (k, (d - s.pitch_radius_m).abs())
                                })
                                .min_by(|a, b| a.1.total_cmp(&b.1))
                                .map(|(k, _)| k)
                        })
                        .flatten()
                })
                .collect();
            (c, on)
        } else {
            (vec![0.0; rollers], vec![None; rollers])
        };
        let link_range_n = if has_links {
            links
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |r, &f| {
                    (r.0.min(f), r.1.max(f))
                })
        } else {
            (f64::INFINITY, f64::NEG_INFINITY)
        };
        rows.push(SampleRow {
            t_s,
            omega_rad_s: speed,
            chain_torque_n_m: torque,
            bearing_max_n: vec![0.0; n_spr],
            segment_force_n: force,
            transverse_m: transverse,
            link_range_n,
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
    let summary = RunSummary::compute(
        &SummaryInputs {
            scene: &sim.scene,
            model,
            static_tension_n: sim.equilibrium.tension_n,
            steps: 0,
            wall_s: 0.0,
            setup_wall_s: 0.0,
            interrupted: end_status == "interrupted",
            max_penetration_m: 0.0,
        },
        &signals,
    );
    let label = Path::new(name)
        .file_stem()
        .map_or_else(|| name.to_owned(), |s| s.to_string_lossy().into_owned());
    let facts = DriveFacts::new(&sim.scene, model);
    Ok(RecordedRun {
        scene: sim.scene.clone(),
        data: RunData {
            label,
            signals,
            probes,
            summary,
            facts,
        },
        topics: found,
        metadata: meta,
        end_status,
        has_links,
        has_contacts,
    })
}

// ---------------------------------------------------------------------------
// Measuring.

/// What to analyse beyond the defaults.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AnalyzeOptions {
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
pub struct RecordedSegment {
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
pub struct RecordedBinder {
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
pub struct RecordedSprocket {
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
pub struct RecordedLink {
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
pub struct RecordedRoller {
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
pub struct RecordedAnalysis {
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
    /// What was left out, and why.
    pub notes: Vec<String>,
    /// The full comparisons, for the figures.
    #[serde(skip)]
    pub binder: Vec<Option<BinderComparison>>,
}

/// Mean, min, max of finite values (`None` when there is none).
fn stats(values: impl Iterator<Item = f64>) -> Option<(f64, f64, f64, usize)> {
    let (mut sum, mut n, mut lo, mut hi) = (0.0, 0usize, f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        sum += v;
        n += 1;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (n > 0).then(|| (sum / n as f64, lo, hi, n))
}

fn missing_for(what: &str, missing: &[&str], run: &RecordedRun) -> RecordedError {
    let channels: Vec<&str> = missing
        .iter()
        .filter_map(|t| {
            Channel::ALL
                .iter()
                .find(|c| c.topic() == *t)
                .map(|c| c.name())
        })
        .collect();
    RecordedError::MissingChannels {
        missing: missing.join(", "),
        needed_for: what.to_owned(),
        found: run.topics.join(", "),
        channels: channels.join(","),
    }
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
    pub fn check(&self, options: &AnalyzeOptions) -> Result<(), RecordedError> {
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
    pub fn analyze(&self, options: &AnalyzeOptions) -> Result<RecordedAnalysis, RecordedError> {
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
        let omega_driver = stats(in_window.iter().map(|r| r.omega_rad_s[driver]))
            .map_or(0.0, |v| v.0)
            .abs();
        let chain_speed = omega_driver * d.facts.pitch_radius_m.get(driver).copied().unwrap_or(0.0);
        let q_c = centrifugal_tension_n(d.facts.roller_mass_kg, chain_speed, d.facts.pitch_m);
        let mu = d.facts.roller_mass_kg / d.facts.pitch_m;

        let mut segments = Vec::new();
        for (k, strand) in s.strands.iter().enumerate() {
            let force = stats(in_window.iter().filter_map(|r| r.segment_force_n[k]));
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

        let mut sprockets = Vec::new();
        let mut binder = Vec::new();
        for (k, &teeth) in d.facts.teeth.iter().enumerate() {
            let speed = stats(in_window.iter().map(|r| r.omega_rad_s[k]));
            let torque = stats(in_window.iter().map(|r| r.chain_torque_n_m[k]));
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

        let link = if self.has_links {
            let l = options.link.unwrap_or(0);
            let series = link_force_series(d, l, window)?;
            stats(series.value.iter().copied()).map(|(mean, lo, hi, _)| RecordedLink {
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
        };
        let roller = if self.has_contacts {
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
        };
        let (lo, hi) = if self.has_links {
            (
                stats(in_window.iter().map(|r| r.link_range_n.0)).map(|v| v.1),
                stats(in_window.iter().map(|r| r.link_range_n.1)).map(|v| v.2),
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
            notes,
            binder,
        })
    }
}

// ---------------------------------------------------------------------------
// The report.

fn opt(v: Option<f64>, digits: usize) -> String {
    v.filter(|v| v.is_finite())
        .map_or_else(|| "—".to_owned(), |v| format!("{v:.digits$}"))
}

/// The report (Markdown): the run, a table per segment and per sprocket, the
/// chosen link and roller, what was left out, and the figures (file stem and
/// caption, drawn beside the report).
pub fn report_markdown(a: &RecordedAnalysis, figures: &[(String, String)]) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Analysis of the recording `{}`\n", a.recording);
    let _ = writeln!(
        md,
        "Scene **{}**, {} profile, dt = {} s, {} samples at {} Hz from {:.3} s to {:.3} s; \
         the run ended: {}. Channels: {}.\n",
        a.scene,
        a.profile,
        a.dt_s,
        a.samples,
        a.sample_rate_hz,
        a.run_s[0],
        a.run_s[1],
        a.end_status,
        a.channels.join(", ")
    );
    let _ = writeln!(
        md,
        "Statistics over [{:.3}, {:.3}] s, spectra over [{:.3}, {:.3}] s, contacts over \
         [{:.3}, {:.3}] s. Static tension of the rebuilt drive {:.1} N (rest length {:.7} m); \
         mean chain speed {:.3} m/s, centrifugal tension q_c = {:.1} N. Link force over the \
         window's samples: {} … {} N.\n",
        a.window_s[0],
        a.window_s[1],
        a.spectrum_window_s[0],
        a.spectrum_window_s[1],
        a.contact_window_s[0],
        a.contact_window_s[1],
        a.static_tension_n,
        a.rest_length_m,
        a.chain_speed_m_s,
        a.q_c_n,
        opt(a.link_force_min_sampled_n, 1),
        opt(a.link_force_max_sampled_n, 1)
    );
    let _ = writeln!(md, "## Segments\n");
    let _ = writeln!(
        md,
        "Average link force over the free strand's links; transverse displacement of the \
         strand's middle. `moving string`: f₁ = (1/2l) c (1 − V²/c²), c² = F/μ, from the \
         segment's own mean force; `(52)`: the string at rest.\n"
    );
    let _ = writeln!(
        md,
        "| segment | length (m) | mean link force (N) | peak-to-peak (N) | amplitude (N) | transverse peak 1–50 Hz (Hz) | moving string (Hz) | peak vs string | (52) (Hz) | transverse amplitude (mm) | spectral peaks 1–200 Hz |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
    for s in &a.segments {
        let vs = if s.string_f1_hz > 0.0 && s.transverse_peak_hz > 0.0 {
            format!(
                "{:+.1} %",
                100.0 * (s.transverse_peak_hz - s.string_f1_hz) / s.string_f1_hz
            )
        } else {
            "—".to_owned()
        };
        let peaks: Vec<String> = s
            .peaks
            .iter()
            .take(4)
            .map(|(f, amp)| format!("{f:.1} Hz ({:.2} mm)", amp * 1e3))
            .collect();
        let _ = writeln!(
            md,
            "| {} | {:.4} | {} | {} | {} | {:.2} | {:.2} | {} | {:.2} | {:.3} | {} |",
            s.segment,
            s.length_m,
            opt(s.mean_link_force_n, 1),
            opt(s.link_force_p2p_n, 1),
            opt(s.link_force_amplitude_n, 1),
            s.transverse_peak_hz,
            s.string_f1_hz,
            vs,
            s.string_52_hz,
            s.transverse_amplitude_m * 1e3,
            if peaks.is_empty() {
                "none".to_owned()
            } else {
                peaks.join(", ")
            }
        );
    }
    md.push('\n');
    let _ = writeln!(md, "## Sprockets\n");
    let _ = writeln!(
        md,
        "Contact forces against Binder's (49) (consistent form; q_a, q_b, q_c, nb, t_s, t_e \
         from each complete contact, see `chaindrive::analysis::study::binder_comparison`). \
         Polygonal action: the strand-speed variation 1 − cos(π/nt) at constant ω.\n"
    );
    let _ = writeln!(
        md,
        "| sprocket | teeth | mean speed (rad/s) | speed p2p (rad/s) | mean chain moment (N·m) | polygonal 1 − cos(π/nt) | contacts | RMS vs (49) (N) | RMS of (49) (N) | relative | RMS vs printed (49) (N) | example nb, q_a, q_b, q_c (N) |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    for s in &a.sprockets {
        let tail = match (&s.binder, &s.binder_note) {
            (Some(b), _) => format!(
                "{} | {:.1} | {:.1} | {:.0} % | {:.1} | {}, {:.0}, {:.0}, {:.0}",
                b.contacts,
                b.rms_n,
                b.binder_rms_n,
                100.0 * b.rms_n / b.binder_rms_n.max(1e-9),
                b.printed_rms_n,
                b.bedded,
                b.q_a_n,
                b.q_b_n,
                b.q_c_n
            ),
            (None, note) => format!(
                "— | {} | | | | ",
                note.as_deref().unwrap_or("no comparison")
            ),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {:.4} | {:.4} | {:.1} | {:.5} | {tail} |",
            s.sprocket,
            s.teeth,
            s.mean_speed_rad_s,
            s.speed_p2p_rad_s,
            s.mean_torque_n_m,
            s.polygonal_variation
        );
    }
    md.push('\n');
    if let Some(l) = &a.link {
        let _ = writeln!(
            md,
            "Link {} (roller {} to {}): mean {:.1} N, {:.1} … {:.1} N over the statistics window.\n",
            l.link,
            l.link,
            l.link + 1,
            l.mean_n,
            l.min_n,
            l.max_n
        );
    }
    if let Some(r) = &a.roller {
        let on: Vec<String> = r.sprockets.iter().map(ToString::to_string).collect();
        let _ = writeln!(
            md,
            "Roller {} over [{:.3}, {:.3}] s: largest contact force {:.1} N, in contact {:.0} % \
             of the samples, sprockets touched: {}.\n",
            r.roller,
            r.window_s[0],
            r.window_s[1],
            r.max_n,
            100.0 * r.in_contact,
            if on.is_empty() {
                "none".to_owned()
            } else {
                on.join(", ")
            }
        );
    }
    if !a.notes.is_empty() {
        let _ = writeln!(md, "## Left out\n");
        for n in &a.notes {
            let _ = writeln!(md, "- {n}");
        }
        md.push('\n');
    }
    let _ = writeln!(
        md,
        "Not in a recording, so not reported: wall times, step counts, the largest \
         penetration, bearing forces (they need every step; a recording holds samples).\n"
    );
    if !figures.is_empty() {
        let _ = writeln!(md, "## Figures\n");
        for (stem, caption) in figures {
            let _ = writeln!(md, "**{stem}**: {caption}\n\n![{caption}]({stem}.png)\n");
        }
    }
    md
}

// ---------------------------------------------------------------------------
// Figures and files.

/// The single-run figures: the chosen link's force, each segment's average
/// link force, transverse displacement and spectrum, the chosen roller's
/// contact force, and each sprocket's latest complete contact against (49).
/// A figure whose data is absent (channel not recorded, no free link, no
/// complete contact) is not drawn; the report says why. Returns each
/// figure's stem and caption, and the paths written.
#[cfg(feature = "figures")]
pub fn recorded_figures(
    run: &RecordedRun,
    a: &RecordedAnalysis,
    options: &AnalyzeOptions,
    dir: &Path,
) -> Result<(FigureList, Vec<std::path::PathBuf>), RecordedError> {
    use super::figures::{Mark, Plot, Trace, save};

    /// A plot of one signal over time, drawn as a line.
    fn time_plot(title: String, y_label: &str, label: String, points: Vec<(f64, f64)>) -> Plot {
        Plot {
            title,
            x_label: "t (s)".into(),
            y_label: y_label.into(),
            traces: vec![Trace {
                label,
                points,
                mark: Mark::Line,
                color: 0,
            }],
            notes: Vec::new(),
        }
    }
    let d = &run.data;
    let mut out = Vec::new();
    let mut paths = Vec::new();
    let pts = |s: &Series, scale: f64, t0: f64| -> Vec<(f64, f64)> {
        s.t_s
            .iter()
            .zip(&s.value)
            .map(|(t, v)| (t - t0, v * scale))
            .collect()
    };
    let mut emit = |plot: Plot, stem: String| -> Result<(), RecordedError> {
        paths.extend(save(&plot, dir, &stem)?);
        out.push((stem, plot.title));
        Ok(())
    };
    if let Some(l) = &a.link {
        let s = link_force_series(d, l.link, a.window_s)?;
        emit(
            time_plot(
                format!("force of link {}", l.link),
                "link force (kN)",
                d.label.clone(),
                pts(&s, 1e-3, 0.0),
            ),
            format!("link{}_force", l.link),
        )?;
    }
    for seg in &a.segments {
        let k = seg.segment;
        if options.segment.is_some_and(|s| s != k) {
            continue;
        }
        if seg.mean_link_force_n.is_some() {
            let s = segment_force_series(d, k, a.window_s)?;
            emit(
                time_plot(
                    format!("average link force of segment {k}"),
                    "average link force (kN)",
                    format!("{} (mean {:.2} kN)", d.label, s.mean() * 1e-3),
                    pts(&s, 1e-3, 0.0),
                ),
                format!("segment{k}_force"),
            )?;
        }
        let s = transverse_series(d, k, a.spectrum_window_s)?;
        emit(
            time_plot(
                format!("transverse displacement of the middle of segment {k}"),
                "displacement (mm)",
                d.label.clone(),
                pts(&s, 1e3, 0.0),
            ),
            format!("segment{k}_transverse"),
        )?;
        let picked = spectrum_with_peaks(&s, d.signals.rate_hz, [1.0, 200.0], 5, 2.0);
        let spectrum: Vec<(f64, f64)> = picked
            .freq_hz
            .iter()
            .zip(&picked.amplitude)
            .filter(|(f, _)| **f <= 200.0)
            .map(|(f, amp)| (*f, amp * 1e3))
            .collect();
        if spectrum.len() >= 2 {
            let mut traces = vec![Trace {
                label: d.label.clone(),
                points: spectrum,
                mark: Mark::Line,
                color: 0,
            }];
            if !picked.peaks.is_empty() {
                traces.push(Trace {
                    label: "peaks".into(),
                    points: picked
                        .peaks
                        .iter()
                        .map(|(f, amp)| (*f, amp * 1e3))
                        .collect(),
                    mark: Mark::Dots,
                    color: 1,
                });
            }
            if seg.string_f1_hz > 0.0 {
                let top = picked.peaks.first().map_or(0.0, |p| p.1 * 1e3);
                traces.push(Trace {
                    label: format!("moving string f₁ = {:.2} Hz", seg.string_f1_hz),
                    points: vec![(seg.string_f1_hz, 0.0), (seg.string_f1_hz, top)],
                    mark: Mark::Crosses,
                    color: 2,
                });
            }
            emit(
                Plot {
                    title: format!("amplitude spectrum of segment {k}'s transverse displacement"),
                    x_label: "frequency (Hz)".into(),
                    y_label: "amplitude (mm)".into(),
                    traces,
                    notes: picked
                        .peaks
                        .iter()
                        .take(3)
                        .map(|(f, amp)| (*f + 1.5, amp * 1e3, format!("{f:.1} Hz")))
                        .collect(),
                },
                format!("segment{k}_spectrum"),
            )?;
        }
    }
    if let Some(r) = &a.roller {
        let (s, _) = roller_contact_series(d, r.roller, r.window_s)?;
        emit(
            time_plot(
                format!("contact force on roller {}", r.roller),
                "contact force (kN)",
                d.label.clone(),
                pts(&s, 1e-3, 0.0),
            ),
            format!("roller{}_contact", r.roller),
        )?;
    }
    for (k, b) in a.binder.iter().enumerate() {
        let Some(b) = b else { continue };
        let ex = &b.example;
        emit(
            Plot {
                title: format!(
                    "contact force on a roller bedded on sprocket {}, and Binder's (49)",
                    k + 1
                ),
                x_label: "time since contact start (s)".into(),
                y_label: "contact force (kN)".into(),
                traces: vec![
                    Trace {
                        label: format!("roller {}", ex.roller),
                        points: pts(&ex.simulated, 1e-3, ex.t_start_s),
                        mark: Mark::Line,
                        color: 0,
                    },
                    Trace {
                        label: format!("(49) (nb = {})", ex.inputs.bedded),
                        points: ex
                            .binder_t_s
                            .iter()
                            .zip(&ex.binder_n)
                            .map(|(t, f)| (t - ex.t_start_s, f * 1e-3))
                            .collect(),
                        mark: Mark::Dots,
                        color: 1,
                    },
                ],
                notes: Vec::new(),
            },
            format!("sprocket{}_contact_vs_binder", k + 1),
        )?;
    }
    Ok((out, paths))
}

/// Figures drawn: (file stem, caption).
pub type FigureList = Vec<(String, String)>;

/// What [`write_analysis`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    /// `DIR/report.md`.
    pub report: std::path::PathBuf,
    /// `DIR/analysis.json`.
    pub json: std::path::PathBuf,
    /// Figures: (stem, caption); each as PNG and SVG.
    pub figures: Vec<(String, String)>,
}

/// Reads the recording at `path`, checks `options`, measures, and writes
/// `dir/report.md`, `dir/analysis.json` and the figures. Nothing is written
/// (not even `dir`) before the recording and the options have passed every
/// check; if drawing or writing fails, what was written is removed.
#[cfg(feature = "figures")]
pub fn write_analysis(
    path: &Path,
    options: &AnalyzeOptions,
    dir: &Path,
) -> Result<(RecordedAnalysis, Written), RecordedError> {
    let run = read_recording(path)?;
    let analysis = run.analyze(options)?;
    let write_err = |p: &Path| {
        let path = p.display().to_string();
        move |source| RecordedError::Write { path, source }
    };
    std::fs::create_dir_all(dir).map_err(write_err(dir))?;
    let (figures, paths) = match recorded_figures(&run, &analysis, options, dir) {
        Ok(f) => f,
        Err(e) => {
            // Figures of the failed call are not left to look like a result.
            remove_known_stems(dir, &analysis);
            return Err(e);
        }
    };
    let json = dir.join("analysis.json");
    let report = dir.join("report.md");
    let text = serde_json::to_string_pretty(&analysis).map_err(|e| RecordedError::Write {
        path: json.display().to_string(),
        source: std::io::Error::other(e),
    });
    let result = text.and_then(|text| std::fs::write(&json, text + "\n").map_err(write_err(&json)));
    let result = result.and_then(|()| {
        std::fs::write(&report, report_markdown(&analysis, &figures)).map_err(write_err(&report))
    });
    if let Err(e) = result {
        for p in paths.iter().chain([&json, &report]) {
            let _ = std::fs::remove_file(p);
        }
        return Err(e);
    }
    Ok((
        analysis,
        Written {
            report,
            json,
            figures,
        },
    ))
}

/// Removes the figure files this analysis may have drawn.
#[cfg(feature = "figures")]
fn remove_known_stems(dir: &Path, a: &RecordedAnalysis) {
    let mut stems: BTreeSet<String> = BTreeSet::new();
    if let Some(l) = &a.link {
        stems.insert(format!("link{}_force", l.link));
    }
    if let Some(r) = &a.roller {
        stems.insert(format!("roller{}_contact", r.roller));
    }
    for s in &a.segments {
        for what in ["force", "transverse", "spectrum"] {
            stems.insert(format!("segment{}_{what}", s.segment));
        }
    }
    for s in &a.sprockets {
        stems.insert(format!("sprocket{}_contact_vs_binder", s.sprocket));
    }
    for stem in stems {
        for ext in ["png", "svg"] {
            let _ = std::fs::remove_file(dir.join(format!("{stem}.{ext}")));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wire_reader_reads_packed_and_unpacked_doubles() {
        // field 1 = 1.5 (fixed64), field 2 = [2.0] unpacked, field 2 = [3.0, 4.0] packed.
        let mut buf = vec![0x09];
        buf.extend(1.5f64.to_le_bytes());
        buf.push(0x11);
        buf.extend(2.0f64.to_le_bytes());
        buf.extend([0x12, 16]);
        buf.extend(3.0f64.to_le_bytes());
        buf.extend(4.0f64.to_le_bytes());
        let (t, v) = decode_forces(&buf).expect("decodes");
        assert_eq!(t, 1.5);
        assert_eq!(v, vec![2.0, 3.0, 4.0]);
        assert!(decode_forces(&buf[..5]).is_err());
    }

    #[test]
    fn derived_messages_decode() {
        use crate::record::{SegmentSignal, SegmentSignals, SprocketSignals};
        use foxglove::Encode;
        let msg = SegmentSignals {
            t_s: 0.25,
            segments: vec![
                SegmentSignal {
                    segment: 1,
                    link_force_n: Some(21e3),
                    transverse_m: -1e-3,
                },
                SegmentSignal {
                    segment: 2,
                    link_force_n: None,
                    transverse_m: 2e-3,
                },
            ],
        };
        let mut buf = Vec::new();
        msg.encode(&mut buf).expect("encodes");
        let (t, f, d) = decode_segments(&buf).expect("decodes");
        assert_eq!(t, 0.25);
        assert_eq!(f, vec![Some(21e3), None]);
        assert_eq!(d, vec![-1e-3, 2e-3]);
        let msg = SprocketSignals {
            t_s: 1.0,
            angle_rad: vec![0.1, 0.2],
            speed_rad_s: vec![12.0, -3.0],
            chain_torque_n_m: vec![5.0, 6.0],
        };
        buf.clear();
        msg.encode(&mut buf).expect("encodes");
        let (t, speed, torque) = decode_sprockets(&buf).expect("decodes");
        assert_eq!((t, speed, torque), (1.0, vec![12.0, -3.0], vec![5.0, 6.0]));
    }

    #[test]
    fn point_cloud_decodes() {
        use foxglove::Encode;
        use foxglove::schemas::{PackedElementField, PointCloud, packed_element_field};
        let mut data = Vec::new();
        for (x, y) in [(1.0f32, 0.5f32), (-2.5, 3.0)] {
            data.extend(x.to_le_bytes());
            data.extend(y.to_le_bytes());
            data.extend(0.0f32.to_le_bytes());
        }
        let field = |name: &str, offset: u32| PackedElementField {
            name: name.to_owned(),
            offset,
            r#type: packed_element_field::NumericType::Float32 as i32,
        };
        let cloud = PointCloud {
            point_stride: crate::record::POINT_STRIDE,
            fields: vec![field("x", 0), field("y", 4), field("z", 8)],
            data: foxglove::bytes::Bytes::from(data),
            ..PointCloud::default()
        };
        let mut buf = Vec::new();
        cloud.encode(&mut buf).expect("encodes");
        let xy = decode_cloud(&buf).expect("decodes");
        assert_eq!(xy, vec![[1.0, 0.5], [-2.5, 3.0]]);
    }

    #[test]
    fn not_mcap_names_what_was_found() {
        let e = read_recording_bytes("x.mcap", b"name = \"a scene\"\n").err();
        let text = e.map(|e| e.to_string()).unwrap_or_default();
        assert!(text.contains("not a readable MCAP"), "{text}");
        assert!(text.contains("name = "), "{text}");
    }
}
