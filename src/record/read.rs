//! Reading a recording back: an MCAP file written by [`super::Recorder`]
//! (`chaindrive run --record`) decoded into its scene and its samples.
//!
//! What is read, and from where:
//!
//! - the scene: the attached scene file (`Scene::from_toml_given`), with
//!   the tables it read attached beside it (a recording made before they
//!   were reads them from files, relative to the working directory) and the
//!   run's overrides taken from the `chaindrive` metadata (profile, dt,
//!   stepping, integrator, contact law, duration): the scene as it was run,
//!   not as its file reads;
//! - `/segments` and `/sprockets` (required): each segment's average link
//!   force and transverse displacement, each sprocket's speed and chain
//!   moment;
//! - `/links` (optional): every link's force;
//! - `/contacts` with `/rollers` (optional): every roller's contact force
//!   and position.
//!
//! Only the samples present on every channel read are kept. The messages
//! are decoded with `prost`: Foxglove's own type for its schema
//! (`foxglove.PointCloud`), and for the run's signals mirrors of the schemas
//! derived from [`super::SegmentSignals`] and its kin (field numbers in
//! declaration order). A file cut
//! short (a killed run) yields what precedes the damage.
//!
//! What it does not do: rebuild the drive or measure anything (that is
//! `crate::analysis::recorded`).
//!
//! Errors: a file that is not MCAP, a recording without the scene or
//! without the needed channels (naming what is missing and what was found),
//! a message that does not decode or does not fit the scene, too few samples.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

use foxglove::schemas::{FrameTransforms, PointCloud};
use prost::Message as _;

use super::Channel;
use crate::scene::{ContactLaw, Integrator, Overrides, ProfileKind, Scene, Stepping};

/// The first bytes of every MCAP file.
const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// Why a recording cannot be read.
#[derive(Debug, thiserror::Error)]
pub(crate) enum ReadError {
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
    /// Channels that are needed are absent.
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
}

impl ReadError {
    /// `missing` topics (of [`Channel`]s) needed for `needed_for`, with the
    /// topics `found` in the file.
    pub(crate) fn missing_channels(needed_for: &str, missing: &[&str], found: &[String]) -> Self {
        let channels: Vec<&str> = missing
            .iter()
            .filter_map(|t| {
                Channel::ALL
                    .iter()
                    .find(|c| c.topic() == *t)
                    .map(|c| c.name())
            })
            .collect();
        Self::MissingChannels {
            missing: missing.join(", "),
            needed_for: needed_for.to_owned(),
            found: found.join(", "),
            channels: channels.join(","),
        }
    }
}

// ---------------------------------------------------------------------------
// The run's own messages (`super::messages`), mirrored for decoding.

/// `ChainLinkForces` / `ChainContactForces`.
#[derive(Clone, PartialEq, prost::Message)]
struct ForcesPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(double, repeated, tag = "2")]
    force_n: Vec<f64>,
}

/// `SprocketSignals`.
#[derive(Clone, PartialEq, prost::Message)]
struct SprocketsPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(double, repeated, tag = "2")]
    angle_rad: Vec<f64>,
    #[prost(double, repeated, tag = "3")]
    speed_rad_s: Vec<f64>,
    #[prost(double, repeated, tag = "4")]
    chain_torque_n_m: Vec<f64>,
}

/// `SegmentSignal` (its segment read as any varint, as written: `uint32`).
#[derive(Clone, PartialEq, prost::Message)]
struct SegmentPb {
    #[prost(uint64, tag = "1")]
    segment: u64,
    #[prost(double, optional, tag = "2")]
    link_force_n: Option<f64>,
    #[prost(double, tag = "3")]
    transverse_m: f64,
}

/// `SegmentSignals`.
#[derive(Clone, PartialEq, prost::Message)]
struct SegmentsPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(message, repeated, tag = "2")]
    segments: Vec<SegmentPb>,
}

/// `TensionerSignal` (its arm number read as any varint, as written: `uint32`).
#[derive(Clone, PartialEq, prost::Message)]
struct TensionerPb {
    #[prost(uint64, tag = "1")]
    tensioner: u64,
    #[prost(double, tag = "2")]
    travel_m: f64,
    #[prost(double, tag = "3")]
    speed_m_s: f64,
    #[prost(double, tag = "4")]
    pressure_pa: f64,
    #[prost(bool, tag = "5")]
    valve_open: bool,
    #[prost(double, tag = "6")]
    arm_angle_rad: f64,
    #[prost(double, tag = "7")]
    shoe_force_n: f64,
    #[prost(double, tag = "8")]
    plunger_force_n: f64,
}

/// `TensionerSignals`.
#[derive(Clone, PartialEq, prost::Message)]
struct TensionersPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(message, repeated, tag = "2")]
    tensioners: Vec<TensionerPb>,
}

/// `TensionerSignals`, its arms in arm order.
fn decode_tensioners(buf: &[u8]) -> Result<super::TensionerSignals, String> {
    let mut m = TensionersPb::decode(buf).map_err(|e| e.to_string())?;
    m.tensioners.sort_by_key(|t| t.tensioner);
    let tensioners = m
        .tensioners
        .into_iter()
        .map(|t| {
            Ok(super::TensionerSignal {
                tensioner: u32::try_from(t.tensioner)
                    .map_err(|_| format!("arm number {} out of range", t.tensioner))?,
                travel_m: t.travel_m,
                speed_m_s: t.speed_m_s,
                pressure_pa: t.pressure_pa,
                valve_open: t.valve_open,
                arm_angle_rad: t.arm_angle_rad,
                shoe_force_n: t.shoe_force_n,
                plunger_force_n: t.plunger_force_n,
            })
        })
        .collect::<Result<_, String>>()?;
    Ok(super::TensionerSignals {
        t_s: m.t_s,
        tensioners,
    })
}

/// `ChainLinkForces` / `ChainContactForces`: (t, values).
fn decode_forces(buf: &[u8]) -> Result<(f64, Vec<f64>), String> {
    let m = ForcesPb::decode(buf).map_err(|e| e.to_string())?;
    Ok((m.t_s, m.force_n))
}

/// `SprocketSignals`: (t, speeds, chain moments).
fn decode_sprockets(buf: &[u8]) -> Result<(f64, Vec<f64>, Vec<f64>), String> {
    let m = SprocketsPb::decode(buf).map_err(|e| e.to_string())?;
    Ok((m.t_s, m.speed_rad_s, m.chain_torque_n_m))
}

/// `SegmentSignals`: (t, forces, transverse displacements), in segment order.
type SegmentsMsg = (f64, Vec<Option<f64>>, Vec<f64>);

fn decode_segments(buf: &[u8]) -> Result<SegmentsMsg, String> {
    let mut m = SegmentsPb::decode(buf).map_err(|e| e.to_string())?;
    m.segments.sort_by_key(|s| s.segment);
    Ok((
        m.t_s,
        m.segments.iter().map(|s| s.link_force_n).collect(),
        m.segments.iter().map(|s| s.transverse_m).collect(),
    ))
}

/// `foxglove.PointCloud` of f32 x, y: the roller centres.
/// The sprocket frames' translations (`sprocket1`, ... in order), m.
fn decode_centers(buf: &[u8], sprockets: usize) -> Result<Vec<[f64; 2]>, String> {
    let tf = FrameTransforms::decode(buf).map_err(|e| e.to_string())?;
    Ok((0..sprockets)
        .map(|k| {
            let frame = super::visual::sprocket_frame(k);
            tf.transforms
                .iter()
                .find(|t| t.child_frame_id == frame)
                .and_then(|t| t.translation.as_ref())
                .map_or([f64::NAN; 2], |v| [v.x, v.y])
        })
        .collect())
}

fn decode_cloud(buf: &[u8]) -> Result<Vec<[f64; 2]>, String> {
    let cloud = PointCloud::decode(buf).map_err(|e| e.to_string())?;
    let stride = cloud.point_stride as usize;
    let offsets: BTreeMap<&str, usize> = cloud
        .fields
        .iter()
        .map(|f| (f.name.as_str(), f.offset as usize))
        .collect();
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
    Ok(cloud
        .data
        .chunks_exact(stride)
        .map(|c| [f(c, ox), f(c, oy)])
        .collect())
}

// ---------------------------------------------------------------------------
// Reading.

/// One sample present on every channel read.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RecordedSample {
    /// Simulated time, s.
    pub t_s: f64,
    /// Mean link force of each segment's free strand, N (`None`: no free link).
    pub segment_force_n: Vec<Option<f64>>,
    /// Transverse displacement of each segment's middle, m.
    pub transverse_m: Vec<f64>,
    /// Sprocket angular speeds, rad/s.
    pub speed_rad_s: Vec<f64>,
    /// Moment of the chain on each sprocket, N·m.
    pub chain_torque_n_m: Vec<f64>,
    /// Every link's force, N (`/links` recorded).
    pub link_force_n: Option<Vec<f64>>,
    /// Every roller's contact force, N, and centre, m (`/contacts` and `/rollers` recorded).
    pub contacts: Option<(Vec<f64>, Vec<[f64; 2]>)>,
    /// Each sprocket's centre, m, from `/tf` (empty where it was not
    /// recorded at this sample's time).
    pub sprocket_centers_m: Vec<[f64; 2]>,
}

/// A recording read back.
pub(crate) struct Recording {
    /// The name it was read under (its path).
    pub name: String,
    /// The attached scene, with the run's overrides applied.
    pub scene: Scene,
    /// Topics found in the file.
    pub topics: Vec<String>,
    /// The `chaindrive` metadata record.
    pub metadata: BTreeMap<String, String>,
    /// How the run ended (`chaindrive.end` status; `unknown` if absent).
    pub end_status: String,
    /// The run's tooth jumps (the `chaindrive.tooth_jumps` metadata record: `count` and one
    /// entry per jump; empty when it had none).
    #[allow(
        dead_code,
        reason = "read for the record's users; no command prints it yet"
    )]
    pub tooth_jumps: BTreeMap<String, String>,
    /// Whether `/links` was read.
    pub has_links: bool,
    /// Whether `/contacts` and `/rollers` were read.
    pub has_contacts: bool,
    /// The samples, in time order (at least 2).
    pub samples: Vec<RecordedSample>,
    /// Every `/tensioners` message, in time order, each with one entry per
    /// tensioner arm of the scene in arm order (empty: no arms, or the
    /// channel was not recorded).
    #[cfg_attr(not(test), allow(dead_code))] // read by the tests
    pub tensioners: Vec<super::TensionerSignals>,
}

fn not_mcap(path: &str, bytes: &[u8]) -> ReadError {
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
    ReadError::NotMcap {
        path: path.to_owned(),
        found,
    }
}

/// Whether the MCAP file held in `bytes` is complete: it ends with a footer
/// that points at a summary section (the index seeking readers need) and
/// with the closing magic. A recording whose process was killed outright is
/// not; [`super::recover::recover`] rewrites it whole.
pub(crate) fn is_complete_mcap(bytes: &[u8]) -> bool {
    // Footer record: opcode 0x02, length u64, summary_start u64,
    // summary_offset_start u64, summary_crc u32 (29 bytes), then the magic.
    const FOOTER: usize = 1 + 8 + 8 + 8 + 4;
    let n = bytes.len();
    if n < MCAP_MAGIC.len() * 2 + FOOTER || !bytes.ends_with(MCAP_MAGIC) {
        return false;
    }
    let footer = &bytes[n - MCAP_MAGIC.len() - FOOTER..n - MCAP_MAGIC.len()];
    let summary_start = footer
        .get(9..17)
        .and_then(|b| <[u8; 8]>::try_from(b).ok())
        .map_or(0, u64::from_le_bytes);
    footer[0] == 0x02 && summary_start != 0
}

/// Whether the MCAP file at `path` is complete ([`is_complete_mcap`]),
/// reading only its last bytes.
pub(crate) fn is_complete_mcap_file(path: &Path) -> std::io::Result<bool> {
    use std::io::{Read, Seek, SeekFrom};
    let mut f = std::fs::File::open(path)?;
    let n = f.seek(SeekFrom::End(0))?;
    let tail = n.min(64);
    f.seek(SeekFrom::Start(n - tail))?;
    let mut buf = Vec::with_capacity(tail as usize);
    f.read_to_end(&mut buf)?;
    Ok(is_complete_mcap(&buf))
}

/// Reads the recording at `path` (see the module documentation).
pub(crate) fn read_recording(path: &Path) -> Result<Recording, ReadError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| ReadError::Read {
        path: name.clone(),
        source,
    })?;
    read_recording_bytes(&name, &bytes)
}

/// Messages of one topic: log time (ns) → payload.
type Topic<'a> = BTreeMap<u64, Cow<'a, [u8]>>;

/// Reads a recording held in memory; `name` is used in messages: its
/// records, the scene it carries, the channels it needs, then its samples
/// and the tensioner arms' states.
pub(crate) fn read_recording_bytes(name: &str, bytes: &[u8]) -> Result<Recording, ReadError> {
    if !bytes.starts_with(MCAP_MAGIC) {
        return Err(not_mcap(name, bytes));
    }
    let (mut metadata, attachments) = top_level_records(name, bytes)?;
    let topics = messages_by_topic(name, bytes)?;
    let found: Vec<String> = topics.keys().cloned().collect();
    let meta = metadata.remove("chaindrive").unwrap_or_default();
    let end_status = metadata
        .get("chaindrive.end")
        .and_then(|m| m.get("status"))
        .cloned()
        .unwrap_or_else(|| "unknown (no end record)".to_owned());
    let tooth_jumps = metadata.remove(super::JUMPS_RECORD).unwrap_or_default();
    let scene = attached_scene(&attachments, &meta)?;
    require_channels(&topics, &found)?;
    let has_links = topics.contains_key(Channel::Links.topic());
    let has_contacts = topics.contains_key(Channel::Contacts.topic())
        && topics.contains_key(Channel::Rollers.topic());
    let reader = Samples {
        topics: &topics,
        rollers: scene.chain.rollers,
        sprockets: scene.sprockets.len(),
        has_links,
        has_contacts,
    };
    let samples = reader.samples()?;
    let tensioners = reader.tensioners(scene.tensioners.len())?;
    Ok(Recording {
        name: name.to_owned(),
        scene,
        topics: found,
        metadata: meta,
        end_status,
        tooth_jumps,
        has_links,
        has_contacts,
        samples,
        tensioners,
    })
}

/// Metadata by name, and the attachments (name, media type, bytes).
type TopLevel = (
    BTreeMap<String, BTreeMap<String, String>>,
    Vec<(String, String, Vec<u8>)>,
);

/// The records outside chunks: metadata and attachments. A file cut short
/// (a killed run) still yields what precedes the damage.
fn top_level_records(name: &str, bytes: &[u8]) -> Result<TopLevel, ReadError> {
    let mut metadata = BTreeMap::new();
    let mut attachments = Vec::new();
    let reader = mcap::read::LinearReader::new(bytes).map_err(|e| ReadError::NotMcap {
        path: name.to_owned(),
        found: e.to_string(),
    })?;
    for record in reader {
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
    Ok((metadata, attachments))
}

/// Every message, by topic and log time (up to any damage).
fn messages_by_topic<'a>(
    name: &str,
    bytes: &'a [u8],
) -> Result<BTreeMap<String, Topic<'a>>, ReadError> {
    let mut topics: BTreeMap<String, Topic<'_>> = BTreeMap::new();
    let stream = mcap::MessageStream::new(bytes).map_err(|e| ReadError::NotMcap {
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
    Ok(topics)
}

/// The attached scene with the run's own settings, where the recording's
/// `chaindrive` metadata `meta` states them sensibly.
fn attached_scene(
    attachments: &[(String, String, Vec<u8>)],
    meta: &BTreeMap<String, String>,
) -> Result<Scene, ReadError> {
    let Some((scene_name, _, scene_bytes)) = attachments
        .iter()
        .find(|a| a.1 == "application/toml" || a.0.ends_with(".toml"))
    else {
        return Err(ReadError::NoScene {
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
    // The tables the scene read, as the run read them (not the files, which
    // are relative to a folder the recording does not know and may have
    // changed since).
    let tables = attachments
        .iter()
        .filter(|a| a.1 == super::TABLE_MEDIA_TYPE)
        .map(|a| (a.0.clone(), String::from_utf8_lossy(&a.2).into_owned()))
        .collect();
    // The run's own settings, where the recording states them sensibly.
    let number = |key: &str| meta.get(key).and_then(|v| v.parse::<f64>().ok());
    let overrides = Overrides {
        profile: meta.get("profile").and_then(|p| ProfileKind::parse(p)),
        dt_s: number("dt_s").filter(|dt| dt.is_finite() && *dt > 0.0),
        duration_s: number("duration_s").filter(|d| d.is_finite() && *d >= 0.0),
        stepping: meta.get("stepping").and_then(|s| Stepping::from_name(s)),
        integrator: meta
            .get("integrator")
            .and_then(|s| Integrator::from_name(s)),
        contact_law: meta
            .get("contact_law")
            .and_then(|s| ContactLaw::from_name(s)),
        ..Overrides::default()
    };
    Scene::from_toml_given(&text, tables, &overrides).map_err(|e| ReadError::Scene {
        name: scene_name.clone(),
        message: e.lines().join("; "),
    })
}

/// An error naming the channels the analysis cannot do without, if any
/// is missing (`found`: the topics there are).
fn require_channels(
    topics: &BTreeMap<String, Topic<'_>>,
    found: &[String],
) -> Result<(), ReadError> {
    let required = [Channel::Segments, Channel::Sprockets];
    let missing: Vec<Channel> = required
        .iter()
        .copied()
        .filter(|c| !topics.contains_key(c.topic()))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    Err(ReadError::MissingChannels {
        missing: missing
            .iter()
            .map(|c| c.topic())
            .collect::<Vec<_>>()
            .join(", "),
        needed_for: "segment forces, transverse displacements and sprocket speeds".to_owned(),
        found: if found.is_empty() {
            "no messages".to_owned()
        } else {
            found.join(", ")
        },
        channels: missing
            .iter()
            .map(|c| c.name())
            .collect::<Vec<_>>()
            .join(","),
    })
}

/// The messages read into samples, checked against the scene's shape.
struct Samples<'t, 'a> {
    topics: &'t BTreeMap<String, Topic<'a>>,
    /// Rollers (and links) of the attached scene.
    rollers: usize,
    /// Sprockets (and free strands: strand k runs from sprocket k to the next).
    sprockets: usize,
    has_links: bool,
    has_contacts: bool,
}

impl Samples<'_, '_> {
    /// The messages of `topic` (none if absent).
    fn get(&self, topic: &str) -> &Topic<'_> {
        static EMPTY: Topic<'static> = Topic::new();
        self.topics.get(topic).unwrap_or(&EMPTY)
    }

    /// The decoding error of `topic`'s message at `t_ns`.
    fn bad(topic: &str, t_ns: u64, message: String) -> ReadError {
        ReadError::Decode {
            topic: topic.to_owned(),
            message: format!("message at t = {} s: {message}", t_ns as f64 * 1e-9),
        }
    }

    /// A message whose count of `what` is `got` where the scene has `want`.
    fn shape(topic: &str, t_ns: u64, what: &str, got: usize, want: usize) -> ReadError {
        Self::bad(
            topic,
            t_ns,
            format!("{got} {what}, but the attached scene has {want}"),
        )
    }

    /// `topic`'s message at `t_ns` decoded by `decode` (the default when absent).
    fn decoded<T: Default>(
        &self,
        topic: &str,
        t_ns: u64,
        decode: impl Fn(&[u8]) -> Result<T, String>,
    ) -> Result<T, ReadError> {
        Ok(self
            .get(topic)
            .get(&t_ns)
            .map(|d| decode(d))
            .transpose()
            .map_err(|e| Self::bad(topic, t_ns, e))?
            .unwrap_or_default())
    }

    /// The samples present on every channel read, in time order.
    fn samples(&self) -> Result<Vec<RecordedSample>, ReadError> {
        let mut used = vec![Channel::Segments.topic(), Channel::Sprockets.topic()];
        if self.has_links {
            used.push(Channel::Links.topic());
        }
        if self.has_contacts {
            used.push(Channel::Contacts.topic());
            used.push(Channel::Rollers.topic());
        }
        let times: Vec<u64> = self
            .get(Channel::Segments.topic())
            .keys()
            .copied()
            .filter(|t| used.iter().all(|u| self.get(u).contains_key(t)))
            .collect();
        if times.len() < 2 {
            return Err(ReadError::TooFewSamples {
                samples: times.len(),
                topics: used.join(", "),
            });
        }
        times.iter().map(|&t_ns| self.sample(t_ns)).collect()
    }

    /// The sample at `t_ns`.
    fn sample(&self, t_ns: u64) -> Result<RecordedSample, ReadError> {
        let (rollers, n_spr) = (self.rollers, self.sprockets);
        let seg_topic = Channel::Segments.topic();
        let spr_topic = Channel::Sprockets.topic();
        let (t_s, force, transverse) = self.decoded(seg_topic, t_ns, decode_segments)?;
        if force.len() != n_spr {
            return Err(Self::shape(seg_topic, t_ns, "segments", force.len(), n_spr));
        }
        let (_, speed, torque) = self.decoded(spr_topic, t_ns, decode_sprockets)?;
        if speed.len() != n_spr || torque.len() != n_spr {
            return Err(Self::shape(
                spr_topic,
                t_ns,
                "sprocket values",
                speed.len(),
                n_spr,
            ));
        }
        let links = if self.has_links {
            let topic = Channel::Links.topic();
            let (_, l) = self.decoded(topic, t_ns, decode_forces)?;
            if l.len() != rollers {
                return Err(Self::shape(topic, t_ns, "link forces", l.len(), rollers));
            }
            Some(l)
        } else {
            None
        };
        let contacts = if self.has_contacts {
            let topic = Channel::Contacts.topic();
            let (_, c) = self.decoded(topic, t_ns, decode_forces)?;
            if c.len() != rollers {
                return Err(Self::shape(topic, t_ns, "contact forces", c.len(), rollers));
            }
            let topic = Channel::Rollers.topic();
            let xy = self.decoded(topic, t_ns, decode_cloud)?;
            if xy.len() != rollers {
                return Err(Self::shape(
                    topic,
                    t_ns,
                    "roller positions",
                    xy.len(),
                    rollers,
                ));
            }
            Some((c, xy))
        } else {
            None
        };
        let tf_topic = Channel::Transforms.topic();
        let sprocket_centers_m = self.decoded(tf_topic, t_ns, |d| decode_centers(d, n_spr))?;
        Ok(RecordedSample {
            sprocket_centers_m,
            t_s,
            segment_force_n: force,
            transverse_m: transverse,
            speed_rad_s: speed,
            chain_torque_n_m: torque,
            link_force_n: links,
            contacts,
        })
    }

    /// The tensioner arms' states, at whatever times they were written
    /// (`arms`: the scene's).
    fn tensioners(&self, arms: usize) -> Result<Vec<super::TensionerSignals>, ReadError> {
        let topic = Channel::Tensioners.topic();
        self.get(topic)
            .iter()
            .map(|(&t_ns, d)| {
                let m = decode_tensioners(d).map_err(|e| Self::bad(topic, t_ns, e))?;
                if m.tensioners.len() != arms {
                    return Err(Self::shape(
                        topic,
                        t_ns,
                        "tensioner arms",
                        m.tensioners.len(),
                        arms,
                    ));
                }
                Ok(m)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forces_decode_from_packed_and_unpacked_doubles() {
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
            // x, y, z only, as recordings made before the colour fields.
            point_stride: 12,
            fields: vec![field("x", 0), field("y", 4), field("z", 8)],
            data: foxglove::bytes::Bytes::from(data),
            ..PointCloud::default()
        };
        let mut buf = Vec::new();
        Encode::encode(&cloud, &mut buf).expect("encodes");
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
