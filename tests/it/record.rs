//! MCAP recordings read back through the `mcap` crate's reader: in memory
//! through the library API, and from files written by the real binary,
//! including runs that blow up or are interrupted with SIGINT.

#[cfg(feature = "cli")]
use crate::common::{command, stderr};
use chaindrive::scene::L60MC_TOML;
use std::collections::BTreeMap;
#[cfg(feature = "cli")]
use std::path::Path;
#[cfg(feature = "cli")]
use std::time::{Duration, Instant};

/// A recording as read back: messages per topic, schema per topic, metadata
/// and attachments.
struct Recording {
    messages: BTreeMap<String, Vec<(u64, Vec<u8>)>>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
    attachments: BTreeMap<String, Vec<u8>>,
}

impl Recording {
    fn read(bytes: &[u8]) -> Self {
        let summary = mcap::Summary::read(bytes)
            .expect("summary readable")
            .expect("file has a summary section (it was finished)");
        for c in summary.channels.values() {
            assert!(c.schema.is_some(), "{} has no schema", c.topic);
            assert_eq!(c.message_encoding, "protobuf", "{}", c.topic);
        }
        let mut messages: BTreeMap<String, Vec<(u64, Vec<u8>)>> = BTreeMap::new();
        for m in mcap::MessageStream::new(bytes).expect("stream") {
            let m = m.expect("message readable");
            messages
                .entry(m.channel.topic.clone())
                .or_default()
                .push((m.log_time, m.data.to_vec()));
        }
        let metadata = summary
            .metadata_indexes
            .iter()
            .map(|i| {
                let m = mcap::read::metadata(bytes, i).expect("metadata");
                (m.name, m.metadata)
            })
            .collect();
        let attachments = summary
            .attachment_indexes
            .iter()
            .map(|i| {
                let a = mcap::read::attachment(bytes, i).expect("attachment");
                (a.name, a.data.to_vec())
            })
            .collect();
        Self {
            messages,
            metadata,
            attachments,
        }
    }

    fn count(&self, topic: &str) -> usize {
        self.messages.get(topic).map_or(0, Vec::len)
    }

    fn end_status(&self) -> &str {
        &self.metadata["chaindrive.end"]["status"]
    }
}

const PER_SAMPLE_TOPICS: [&str; 7] = [
    "/scene",
    "/tf",
    "/rollers",
    "/links",
    "/contacts",
    "/sprockets",
    "/segments",
];

#[cfg(feature = "cli")]
#[test]
fn binary_records_a_readable_file_at_the_series_rate() {
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("run.mcap");
    let out = command()
        .args([
            "run",
            "--duration",
            "0.3",
            "--rate",
            "200",
            "--quiet",
            "--record",
        ])
        .arg(&path)
        .output()
        .expect("binary runs");
    assert!(out.status.success(), "{}", stderr(&out));
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    for topic in PER_SAMPLE_TOPICS {
        assert_eq!(rec.count(topic), 61, "{topic}");
    }
    assert_eq!(rec.metadata["chaindrive"]["sample_rate_hz"], "200");
    assert_eq!(rec.attachments["l60mc.toml"], L60MC_TOML.as_bytes());
    assert_eq!(rec.end_status(), "completed");
}

#[cfg(feature = "cli")]
#[test]
fn unwritable_recording_path_fails_before_simulating() {
    let started = Instant::now();
    let out = command()
        .args(["run", "--record", "/nonexistent-dir/x.mcap"])
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("recording") && err.contains("/nonexistent-dir/x.mcap"),
        "{err}"
    );
    assert!(
        started.elapsed() < Duration::from_secs(5),
        "it simulated first"
    );
    let out = command()
        .args([
            "run",
            "--record",
            "x.mcap",
            "--record-channels",
            "scene,nope",
        ])
        .current_dir(tempfile::tempdir().expect("tmp").path())
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    assert!(stderr(&out).contains("nope"));
}

/// The paper's drive with a driver speed it cannot take: it blows up ~20 ms
/// into the run (penetration detector), after static equilibrium.
#[cfg(feature = "cli")]
fn blow_up_scene(dir: &Path) -> std::path::PathBuf {
    let text = L60MC_TOML.replace("speed_rpm = 120.0", "speed_rpm = 2000.0");
    assert_ne!(text, L60MC_TOML);
    let path = dir.join("too_fast.toml");
    std::fs::write(&path, text).expect("write scene");
    path
}

#[cfg(feature = "cli")]
#[test]
fn a_run_that_blows_up_leaves_a_readable_recording() {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = blow_up_scene(dir.path());
    let path = dir.path().join("blow-up.mcap");
    let out = command()
        .arg("run")
        .arg(&scene)
        .args(["--duration", "1", "--quiet", "--record"])
        .arg(&path)
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    assert!(stderr(&out).contains("blow-up"));
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    let frames = rec.count("/rollers");
    assert!(frames > 5 && frames < 1000, "{frames} frames");
    assert_eq!(rec.end_status(), "failed");
    assert!(rec.metadata["chaindrive.end"]["message"].contains("blow-up"));
    assert_eq!(
        rec.attachments["too_fast.toml"].len(),
        std::fs::read(&scene).expect("scene").len()
    );

    // A run that fails before t = 0 (the static equilibrium cannot meet a
    // tolerance below rounding: 1e-17 of the pretension is under half an
    // ulp, so only an exact hit would pass) still leaves a finished file:
    // metadata and channels, no messages.
    let unreachable = dir.path().join("unreachable.toml");
    std::fs::write(
        &unreachable,
        format!("{L60MC_TOML}\n[equilibrium]\ntension_tolerance = 1e-17\n"),
    )
    .expect("write scene");
    let path = dir.path().join("setup.mcap");
    let out = command()
        .arg("run")
        .arg(&unreachable)
        .args(["--quiet", "--record"])
        .arg(&path)
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    assert_eq!(rec.count("/rollers"), 0);
    assert!(rec.metadata.contains_key("chaindrive"));
}

#[cfg(feature = "cli")]
#[test]
fn a_run_interrupted_with_sigint_leaves_a_readable_recording() {
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("interrupted.mcap");
    let mut child = command()
        .args(["run", "--duration", "60", "--quiet", "--record"])
        .arg(&path)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("binary starts");
    // Wait until the stepping loop has written a few compressed chunks.
    let started = Instant::now();
    while std::fs::metadata(&path).map_or(0, |m| m.len()) < 400_000 {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no data recorded in 60 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let killed = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let status = child.wait().expect("binary ends");
    assert_eq!(status.code(), Some(130), "Ctrl-C exit code");
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    assert_eq!(rec.end_status(), "interrupted");
    let frames = rec.count("/rollers");
    assert!(frames > 10, "{frames} frames");
    for topic in PER_SAMPLE_TOPICS {
        assert!(rec.count(topic).abs_diff(frames) <= 1, "{topic}");
    }
    assert_eq!(rec.metadata["chaindrive.end"]["frames"], frames.to_string());
}
