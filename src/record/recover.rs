//! Recovery: a complete, indexed MCAP file rebuilt from what a damaged one
//! holds (`chaindrive recover`).
//!
//! A recording cut short — the process killed outright (SIGKILL, an
//! out-of-memory kill, a power loss) before [`super::Recorder::finish`] —
//! has no summary section and no footer. Streaming readers (`chaindrive
//! analyze`) read it up to the damage; seeking readers (Foxglove, Rerun,
//! Python's `make_reader`) find no index and read nothing. [`recover`] reads
//! the file's records in order (chunks unpacked, each chunk's CRC checked)
//! up to the first one that is missing or broken, and writes every schema,
//! channel, message, attachment and metadata record before it into a new
//! file with the recorder's chunking and a full summary and index.
//!
//! What it does not do: repair a damaged record (everything from the first
//! broken record on is lost, including the unfinished chunk) or read a file
//! that does not start with the MCAP magic.

use std::collections::{BTreeMap, BTreeSet};
use std::io::{Seek, Write};

use mcap::records::Record;

use super::read::is_complete_mcap;

/// Why a recording cannot be recovered.
#[derive(Debug, thiserror::Error)]
pub(crate) enum RecoverError {
    /// The input does not start like an MCAP file.
    #[error("not an MCAP file: it does not start with the MCAP magic")]
    NotMcap,
    /// The input holds nothing before its first broken record.
    #[error("nothing is readable before the first damaged record ({0})")]
    Nothing(String),
    /// Writing the recovered file failed.
    #[error("writing the recovered file: {0}")]
    Write(#[from] mcap::McapError),
    /// Flushing the recovered file failed.
    #[error("writing the recovered file: {0}")]
    Io(#[from] std::io::Error),
}

/// What [`recover`] found and wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Recovered {
    /// Whether the input was already complete (it had its summary and footer).
    pub input_complete: bool,
    /// Where reading stopped, when it stopped at a broken or missing record.
    pub damage: Option<String>,
    /// Schemas written.
    pub schemas: usize,
    /// Channels written.
    pub channels: usize,
    /// Messages written.
    pub messages: u64,
    /// Attachments written.
    pub attachments: usize,
    /// Metadata records written.
    pub metadata: usize,
    /// Log time of the last message written, ns.
    pub last_log_time_ns: u64,
}

/// Reads the MCAP file held in `bytes` up to its first missing or broken
/// record and writes everything before it into `out` as a complete file
/// (see the module documentation). Schema and channel ids are kept.
pub(crate) fn recover<W: Write + Seek>(
    bytes: &[u8],
    out: W,
) -> Result<(W, Recovered), RecoverError> {
    if !bytes.starts_with(b"\x89MCAP0\r\n") {
        return Err(RecoverError::NotMcap);
    }
    let mut found = Recovered {
        input_complete: is_complete_mcap(bytes),
        ..Recovered::default()
    };
    let options = mcap::read::Options::ValidateChunkCrcs | mcap::read::Options::IgnoreEndMagic;
    let reader = mcap::read::ChunkFlattener::new_with_options(bytes, options)?;
    let mut writer: Option<mcap::Writer<W>> = None;
    let mut out = Some(out);
    let mut known_channels = BTreeSet::new();
    let mut known_schemas = BTreeSet::new();
    for record in reader {
        let record = match record {
            Ok(r) => r,
            Err(e) => {
                found.damage = Some(e.to_string());
                break;
            }
        };
        // The header comes first; anything else before it means a damaged file.
        let w = match (&record, writer.as_mut()) {
            (Record::Header(h), None) => {
                let Some(out) = out.take() else { break };
                writer = Some(
                    mcap::WriteOptions::new()
                        .compression(Some(mcap::Compression::Zstd))
                        .compression_level(3)
                        .compression_threads(0)
                        .chunk_size(Some(super::CHUNK_BYTES))
                        .profile(h.profile.clone())
                        .library(format!(
                            "{} (recovered by chaindrive {})",
                            h.library,
                            env!("CARGO_PKG_VERSION")
                        ))
                        .create(out)?,
                );
                continue;
            }
            (_, Some(w)) => w,
            (_, None) => {
                found.damage = Some("no header record".to_owned());
                break;
            }
        };
        match record {
            Record::Schema { header, data } => {
                w.add_schema_with_id(header.id, &header.name, &header.encoding, &data)?;
                if known_schemas.insert(header.id) {
                    found.schemas += 1;
                }
            }
            Record::Channel(c) => {
                w.add_channel_with_id(
                    c.id,
                    c.schema_id,
                    &c.topic,
                    &c.message_encoding,
                    &c.metadata,
                )?;
                if known_channels.insert(c.id) {
                    found.channels += 1;
                }
            }
            Record::Message { header, data } if known_channels.contains(&header.channel_id) => {
                w.write_to_known_channel(&header, &data)?;
                found.messages += 1;
                found.last_log_time_ns = found.last_log_time_ns.max(header.log_time);
            }
            Record::Attachment { header, data, .. } => {
                w.attach(&mcap::Attachment {
                    log_time: header.log_time,
                    create_time: header.create_time,
                    name: header.name,
                    media_type: header.media_type,
                    data,
                })?;
                found.attachments += 1;
            }
            Record::Metadata(m) => {
                w.write_metadata(&m)?;
                found.metadata += 1;
            }
            // The data section ends here: what follows is the old summary.
            Record::DataEnd(_) => break,
            _ => {}
        }
    }
    let Some(mut w) = writer else {
        return Err(RecoverError::Nothing(
            found.damage.unwrap_or_else(|| "the file ends".to_owned()),
        ));
    };
    if !found.input_complete {
        // Say in the file itself that it was recovered, and from how much.
        let metadata: BTreeMap<String, String> = [
            ("messages", found.messages.to_string()),
            (
                "last_log_time_s",
                format!("{}", found.last_log_time_ns as f64 * 1e-9),
            ),
            (
                "stopped_at",
                found
                    .damage
                    .clone()
                    .unwrap_or_else(|| "the end of the file".to_owned()),
            ),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_owned(), v))
        .collect();
        w.write_metadata(&mcap::records::Metadata {
            name: "chaindrive.recovered".to_owned(),
            metadata,
        })?;
    }
    w.finish()?;
    let mut inner = w.into_inner();
    inner.flush()?;
    Ok((inner, found))
}
