//! What a recording opens with, before its first sample: the `chaindrive`
//! metadata record, the scene file and the tables it read as attachments,
//! a schema and channel per recorded topic, and (resuming from a
//! checkpoint) the earlier file's messages up to the checkpoint. The
//! per-sample messages are the writer's (`super::writer`).

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

use foxglove::Encode;
use foxglove::schemas::{FrameTransforms, PointCloud, SceneUpdate};

use super::channels::{Channel, Channels, STATIC_SCENE_TOPIC};
use super::messages::{
    ChainContactForces, ChainLinkForces, GuideSignals, SegmentSignals, SprocketSignals,
    TensionerSignals,
};
use super::writer::ChannelIds;
use super::{RecordError, RecordMark, RecordOptions, TABLE_MEDIA_TYPE, visual};
use crate::scene::Scene;

/// The `chaindrive` metadata record: the run's settings as text. A
/// co-simulated run (`frame_dt_s`) writes its duration when it ends.
pub(super) fn header_metadata(
    scene: &Scene,
    options: &RecordOptions,
    frame_dt_s: Option<f64>,
) -> BTreeMap<String, String> {
    let mut metadata: BTreeMap<String, String> = [
        ("scene", scene.name.clone()),
        ("profile", scene.profile_name().to_owned()),
        ("contact_law", scene.contact.law.name().to_owned()),
        ("integrator", scene.solver.integrator.name().to_owned()),
        ("stepping", scene.solver.stepping.name().to_owned()),
        ("dt_s", format!("{:e}", scene.solver.dt_s)),
        ("duration_s", format!("{}", scene.solver.duration_s)),
        ("sample_rate_hz", format!("{}", options.rate_hz)),
        ("rollers", scene.chain.rollers.to_string()),
        ("sprockets", scene.sprockets.len().to_string()),
        ("version", env!("CARGO_PKG_VERSION").to_owned()),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_owned(), v))
    .collect();
    if let Some(frame_dt_s) = frame_dt_s {
        // Not known until the run ends: written then.
        metadata.remove("duration_s");
        metadata.insert("frame_dt_s".to_owned(), format!("{frame_dt_s:e}"));
        metadata.insert("run".to_owned(), "co-simulation".to_owned());
    }
    metadata
}

/// The scene file, and the tables it read under the names it writes, as
/// attachments: the scene is rebuilt from the recording alone (`super::read`).
pub(super) fn attach_scene<W: Write + Seek>(
    w: &mut mcap::Writer<W>,
    scene: &Scene,
    options: &RecordOptions,
) -> Result<(), RecordError> {
    if let Some((name, data)) = &options.scene_file {
        w.attach(&mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: name.clone(),
            media_type: "application/toml".to_owned(),
            data: Cow::Borrowed(data),
        })?;
        // The tables it read, under the names it writes: the scene is
        // rebuilt from the recording alone ([`read`]).
        for (name, text) in scene.tables() {
            w.attach(&mcap::Attachment {
                log_time: 0,
                create_time: 0,
                name: name.to_owned(),
                media_type: TABLE_MEDIA_TYPE.to_owned(),
                data: Cow::Borrowed(text.as_bytes()),
            })?;
        }
    }
    Ok(())
}

/// A channel for each recorded topic (no guide or tensioner channel where
/// the scene has none), its id by topic in `topics`.
pub(super) fn open_channels<W: Write + Seek>(
    w: &mut mcap::Writer<W>,
    topics: &mut BTreeMap<String, u16>,
    scene: &Scene,
    channels: Channels,
) -> Result<ChannelIds, RecordError> {
    let mut ids = ChannelIds::default();
    for (slot, &c) in ids.per_sample.iter_mut().zip(&Channel::ALL) {
        // No guides (arms), no guide (tensioner) channel: a recording is
        // as it was without.
        if !channels.contains(c.into())
            || (c == Channel::Guides && scene.guides.is_empty())
            || (c == Channel::Tensioners && scene.tensioners.is_empty())
        {
            continue;
        }
        let topic = c.topic();
        *slot = Some(match c {
            Channel::Scene => {
                ids.static_scene = Some(add_channel::<_, SceneUpdate>(
                    w,
                    topics,
                    STATIC_SCENE_TOPIC,
                )?);
                add_channel::<_, SceneUpdate>(w, topics, topic)?
            }
            Channel::Transforms => add_channel::<_, FrameTransforms>(w, topics, topic)?,
            Channel::Rollers => add_channel::<_, PointCloud>(w, topics, topic)?,
            Channel::Outlines => {
                for i in 0..scene.sprockets.len() {
                    let id = add_channel::<_, PointCloud>(w, topics, &visual::outline_topic(i))?;
                    ids.outlines.push(id);
                }
                // Nothing at every sample: the per-sprocket channels above.
                continue;
            }
            Channel::Links => add_channel::<_, ChainLinkForces>(w, topics, topic)?,
            Channel::Contacts => add_channel::<_, ChainContactForces>(w, topics, topic)?,
            Channel::Sprockets => add_channel::<_, SprocketSignals>(w, topics, topic)?,
            Channel::Segments => add_channel::<_, SegmentSignals>(w, topics, topic)?,
            Channel::Guides => add_channel::<_, GuideSignals>(w, topics, topic)?,
            Channel::Tensioners => add_channel::<_, TensionerSignals>(w, topics, topic)?,
        });
    }
    Ok(ids)
}

pub(super) fn add_channel<W: Write + Seek, T: Encode>(
    w: &mut mcap::Writer<W>,
    topics: &mut BTreeMap<String, u16>,
    topic: &str,
) -> Result<u16, RecordError> {
    let (name, encoding, data) = match T::get_schema() {
        Some(s) => (s.name, s.encoding, s.data),
        None => (String::new(), String::new(), Cow::Borrowed(&[][..])),
    };
    let schema = if name.is_empty() {
        0
    } else {
        w.add_schema(&name, &encoding, &data)?
    };
    let id = w.add_channel(schema, topic, &T::get_message_encoding(), &BTreeMap::new())?;
    topics.insert(topic.to_owned(), id);
    Ok(id)
}

/// Copies the messages of the MCAP file `earlier` up to `mark` into `w`,
/// each on the channel of the same topic, with its times and sequence
/// number. A file cut short is read up to its damage.
pub(super) fn copy_messages<W: Write + Seek>(
    w: &mut mcap::Writer<W>,
    topics: &BTreeMap<String, u16>,
    earlier: &[u8],
    mark: &RecordMark,
) -> Result<(), RecordError> {
    use mcap::records::Record;
    let options = mcap::read::Options::IgnoreEndMagic | mcap::read::Options::ValidateChunkCrcs;
    let reader = mcap::read::ChunkFlattener::new_with_options(earlier, options)?;
    let mut ids = BTreeMap::new();
    let mut copied: u32 = 0;
    for record in reader {
        // A file cut short: what precedes the damage.
        let Ok(record) = record else { break };
        match record {
            Record::Channel(c) => {
                let Some(&id) = topics.get(&c.topic) else {
                    return Err(RecordError::Continue(format!(
                        "the earlier recording has channel {}, this run does not record it: resume with the same --record-channels",
                        c.topic
                    )));
                };
                ids.insert(c.id, id);
            }
            Record::Message { header, data }
                if header.log_time <= mark.last_t_ns && copied < mark.messages =>
            {
                let Some(&channel_id) = ids.get(&header.channel_id) else {
                    continue;
                };
                w.write_to_known_channel(
                    &mcap::records::MessageHeader {
                        channel_id,
                        ..header
                    },
                    &data,
                )?;
                copied += 1;
            }
            Record::DataEnd(_) => break,
            _ => {}
        }
    }
    if copied != mark.messages {
        return Err(RecordError::Continue(format!(
            "the earlier recording holds {copied} messages up to t = {} s, the checkpoint counted {}: give the recording the run was writing",
            mark.last_t_ns as f64 * 1e-9,
            mark.messages
        )));
    }
    Ok(())
}
