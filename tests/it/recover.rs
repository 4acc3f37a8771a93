//! A recording killed outright (SIGKILL) loses at most the recorder's flush
//! interval, and `chaindrive recover` makes it a complete, indexed file that
//! seeking readers open.

use crate::common::{chaindrive, command, stderr};
use std::process::Stdio;
use std::time::{Duration, Instant};

/// Messages a streaming reader finds in `bytes` before the first damage.
fn streamed(bytes: &[u8]) -> (u64, u64) {
    let Ok(stream) = mcap::MessageStream::new(bytes) else {
        return (0, 0);
    };
    let mut count = 0;
    let mut last_ns = 0;
    for m in stream {
        let Ok(m) = m else { break };
        count += 1;
        last_ns = last_ns.max(m.log_time);
    }
    (count, last_ns)
}

/// Messages a seeking reader finds through the summary's chunk indexes
/// (as Foxglove, Rerun and Python's `make_reader` do); `None` without a summary.
fn seeked(bytes: &[u8]) -> Option<(mcap::Summary, u64)> {
    let summary = mcap::Summary::read(bytes).ok().flatten()?;
    let mut count = 0;
    for index in &summary.chunk_indexes {
        count += summary
            .stream_chunk(bytes, index)
            .expect("indexed chunk")
            .filter(Result::is_ok)
            .count() as u64;
    }
    Some((summary, count))
}

#[test]
fn a_recording_killed_with_sigkill_is_recovered_whole() {
    let dir = tempfile::tempdir().expect("tmp");
    let killed = dir.path().join("killed.mcap");
    let recovered = dir.path().join("recovered.mcap");
    let mut child = command()
        .args(["run", "--quiet", "--duration", "60", "--record"])
        .arg(&killed)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("binary runs");
    // Let it write a few chunks (~1.2 s of the run with every channel), then
    // kill it outright: no handler runs, nothing is finished.
    let deadline = Instant::now() + Duration::from_secs(180);
    loop {
        let size = std::fs::metadata(&killed).map_or(0, |m| m.len());
        if size > 6 << 20 {
            break;
        }
        let exited = child.try_wait().expect("wait");
        if exited.is_some() || Instant::now() > deadline {
            let _ = child.kill();
            panic!("the recording reached only {size} bytes (exit: {exited:?})");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.kill().expect("SIGKILL");
    child.wait().expect("reaped");

    let bytes = std::fs::read(&killed).expect("killed recording");
    // What the viewers met: no summary, so a seeking reader finds nothing.
    assert!(seeked(&bytes).is_none(), "a killed recording has a summary");
    let (streamed_count, streamed_last_ns) = streamed(&bytes);
    assert!(streamed_count > 0);

    let out = chaindrive(&[
        "recover",
        killed.to_str().expect("utf8"),
        recovered.to_str().expect("utf8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let fixed = std::fs::read(&recovered).expect("recovered recording");
    let (summary, count) = seeked(&fixed).expect("the recovered file has a summary");
    // Every message a streaming reader found in the killed file, no more.
    let stats = summary.stats.as_ref().expect("statistics");
    assert_eq!(stats.message_count, streamed_count);
    assert_eq!(count, streamed_count);
    assert_eq!(stats.message_end_time, streamed_last_ns);
    // Channels, the scene file and the metadata came along.
    // Eight topics, and the paper's four sprockets' outlines.
    assert_eq!(summary.channels.len(), 12, "{:?}", summary.channels.keys());
    let attached: Vec<&str> = summary
        .attachment_indexes
        .iter()
        .map(|a| a.name.as_str())
        .collect();
    assert_eq!(attached, ["l60mc.toml"]);
    let metadata: Vec<&str> = summary
        .metadata_indexes
        .iter()
        .map(|m| m.name.as_str())
        .collect();
    assert_eq!(metadata, ["chaindrive", "chaindrive.recovered"]);

    // The analysis reads the recovered file, and on the killed one says
    // how to make it whole.
    let analysis = dir.path().join("analysis");
    let out = chaindrive(&[
        "analyze",
        recovered.to_str().expect("utf8"),
        "--out",
        analysis.to_str().expect("utf8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        !stderr(&out).contains("chaindrive recover"),
        "{}",
        stderr(&out)
    );
    let empty = dir.path().join("empty.mcap");
    std::fs::write(&empty, &bytes[..bytes.len().min(4096)]).expect("write");
    let out = chaindrive(&["analyze", empty.to_str().expect("utf8")]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("`chaindrive recover "),
        "{}",
        stderr(&out)
    );
}

#[test]
fn recover_refuses_to_write_over_its_input() {
    let dir = tempfile::tempdir().expect("tmp");
    let f = dir.path().join("a.mcap");
    std::fs::write(&f, b"\x89MCAP0\r\n").expect("write");
    let path = f.to_str().expect("utf8");
    let out = chaindrive(&["recover", path, path]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("is the input recording"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read(&f).expect("kept"), b"\x89MCAP0\r\n");
}
