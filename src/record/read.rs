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

use super::Channel;
use super::decode::{
    decode_centers, decode_cloud, decode_forces, decode_segments, decode_sprockets,
    decode_tensioners,
};
use crate::scene::{ContactLaw, Integrator, Overrides, ProfileKind, Scene, Stepping};
use crate::sim::{TipRide, ToothJump};

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
    /// The run's tooth jumps, in time order (the `chaindrive.tooth_jumps`
    /// metadata record; empty when it had none).
    pub tooth_jumps: Vec<ToothJump>,
    /// The tip rides of its rollers, in time order (the
    /// `chaindrive.tip_rides` metadata record; empty when it had none).
    pub tip_rides: Vec<TipRide>,
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

/// The `key=value` fields of one metadata entry, and its bare words.
fn entry_fields(entry: &str) -> (BTreeMap<&str, &str>, Vec<&str>) {
    let (mut fields, mut words) = (BTreeMap::new(), Vec::new());
    for part in entry.split_whitespace() {
        match part.split_once('=') {
            Some((k, v)) => {
                fields.insert(k, v);
            }
            None => words.push(part),
        }
    }
    (fields, words)
}

/// The tooth jumps a `chaindrive.tooth_jumps` record lists, in its order
/// (the inverse of how the recorder writes them); an entry that cannot be
/// read is left out.
fn jumps_of_record(record: &BTreeMap<String, String>) -> Vec<ToothJump> {
    record
        .iter()
        .filter(|(k, _)| k.starts_with("jump "))
        .filter_map(|(_, v)| {
            let (f, words) = entry_fields(v);
            Some(ToothJump {
                t_s: f.get("t_s")?.parse().ok()?,
                sprocket: f.get("sprocket")?.parse::<usize>().ok()?.checked_sub(1)?,
                roller: f.get("roller")?.parse().ok()?,
                gaps: f.get("gaps")?.parse().ok()?,
                ahead: match words.as_slice() {
                    ["ahead"] => true,
                    ["behind"] => false,
                    _ => return None,
                },
            })
        })
        .collect()
}

/// The tip rides a `chaindrive.tip_rides` record lists, in its order (the
/// inverse of how the recorder writes them); an entry that cannot be read is
/// left out.
fn rides_of_record(record: &BTreeMap<String, String>) -> Vec<TipRide> {
    record
        .iter()
        .filter(|(k, _)| k.starts_with("ride "))
        .filter_map(|(_, v)| {
            let (f, _) = entry_fields(v);
            Some(TipRide {
                t_s: f.get("t_s")?.parse().ok()?,
                sprocket: f.get("sprocket")?.parse::<usize>().ok()?.checked_sub(1)?,
                roller: f.get("roller")?.parse().ok()?,
            })
        })
        .collect()
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
    let tooth_jumps = metadata
        .remove(super::JUMPS_RECORD)
        .map(|r| jumps_of_record(&r))
        .unwrap_or_default();
    let tip_rides = metadata
        .remove(super::RIDES_RECORD)
        .map(|r| rides_of_record(&r))
        .unwrap_or_default();
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
        tip_rides,
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
    fn not_mcap_names_what_was_found() {
        let e = read_recording_bytes("x.mcap", b"name = \"a scene\"\n").err();
        let text = e.map(|e| e.to_string()).unwrap_or_default();
        assert!(text.contains("not a readable MCAP"), "{text}");
        assert!(text.contains("name = "), "{text}");
    }

    /// The records the recorder writes read back as the jumps and rides it
    /// was given, and an entry that is not one is left out.
    #[test]
    fn jump_and_ride_records_read_back_as_written() {
        let jumps = vec![
            ToothJump {
                t_s: 0.1625,
                sprocket: 1,
                roller: 57,
                gaps: -1,
                ahead: true,
            },
            ToothJump {
                t_s: 1.0 / 3.0,
                sprocket: 0,
                roller: 0,
                gaps: 2,
                ahead: false,
            },
        ];
        let rides = vec![TipRide {
            t_s: 0.121,
            sprocket: 2,
            roller: 119,
        }];
        let mut jump_record = super::super::jump_entries(&jumps);
        assert_eq!(jumps_of_record(&jump_record), jumps);
        assert_eq!(rides_of_record(&super::super::ride_entries(&rides)), rides);
        jump_record.insert("jump 0003".into(), "t_s=x sprocket=1".into());
        jump_record.insert(
            "jump 0004".into(),
            "t_s=0.2 sprocket=0 roller=1 gaps=1 ahead".into(),
        );
        assert_eq!(
            jumps_of_record(&jump_record),
            jumps,
            "unreadable entries left out"
        );
    }
}
