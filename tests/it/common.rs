//! What every test module shares: the paper's drive shortened, its run
//! summary, the real `chaindrive` binary and its outputs.

#[cfg(feature = "cli")]
use std::path::Path;
#[cfg(feature = "cli")]
use std::process::{Command, Output};

/// The `chaindrive` binary, ready for arguments.
#[cfg(feature = "cli")]
pub fn command() -> Command {
    Command::new(env!("CARGO_BIN_EXE_chaindrive"))
}

/// Runs the binary with `args` and waits for it.
#[cfg(feature = "cli")]
pub fn chaindrive(args: &[&str]) -> Output {
    command().args(args).output().expect("binary runs")
}

/// Runs the binary with `args` in `dir` (relative paths are in `dir`).
#[cfg(feature = "cli")]
pub fn chaindrive_in(dir: &Path, args: &[&str]) -> Output {
    command()
        .args(args)
        .current_dir(dir)
        .output()
        .expect("binary runs")
}

/// Runs the binary with `args`, requires success, and returns its stdout.
#[cfg(feature = "cli")]
pub fn chaindrive_stdout(args: &[&str]) -> String {
    let out = chaindrive(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    String::from_utf8(out.stdout).expect("utf-8")
}

/// A finished process's stderr, as text.
#[cfg(feature = "cli")]
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The JSON file at `path`.
#[cfg(feature = "cli")]
pub fn read_json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).expect("JSON")
}

/// An MCAP file's records outside its chunks: metadata by name, and the
/// attachments (name, media type, bytes), read with the `mcap` crate.
#[cfg(feature = "record")]
pub fn mcap_top_level(path: &Path) -> McapTopLevel {
    let bytes = std::fs::read(path).expect("recording");
    let mut top = McapTopLevel::default();
    for record in mcap::read::LinearReader::new(&bytes).expect("an MCAP file") {
        match record.expect("a record") {
            mcap::records::Record::Metadata(m) => {
                top.metadata.insert(m.name, m.metadata);
            }
            mcap::records::Record::Attachment { header, data, .. } => {
                top.attachments
                    .push((header.name, header.media_type, data.into_owned()));
            }
            _ => {}
        }
    }
    top
}

/// What [`mcap_top_level`] reads.
#[cfg(feature = "record")]
#[derive(Default)]
pub struct McapTopLevel {
    /// Metadata records by name.
    pub metadata: std::collections::BTreeMap<String, std::collections::BTreeMap<String, String>>,
    /// Attachments: name, media type, bytes.
    pub attachments: Vec<(String, String, Vec<u8>)>,
}
