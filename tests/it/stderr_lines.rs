//! Every line the `chaindrive` binary writes to stderr is whole: one write,
//! newline included, so that nothing else writing to the same pipe or file
//! (stdout through `2>&1`, another process, a progress bar) lands inside it.

use std::io::Read;
use std::process::Stdio;

use crate::common::command;

/// The chunks a reader of the binary's stderr pipe gets. A line written in
/// one write (< 4096 bytes, atomic on a pipe) reaches the reader whole, so
/// each chunk ends with a newline; a line written in pieces is, as often as
/// not, read before its last piece.
fn stderr_chunks(args: &[&str]) -> Vec<String> {
    let mut child = command()
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("binary runs");
    let mut stderr = child.stderr.take().expect("piped");
    let mut chunks = Vec::new();
    let mut buf = vec![0; 1 << 16];
    loop {
        let n = stderr.read(&mut buf).expect("read stderr");
        if n == 0 {
            break;
        }
        chunks.push(String::from_utf8_lossy(&buf[..n]).into_owned());
    }
    child.wait().expect("exits");
    chunks
}

/// `check` of a scene with a warning, a notice and a warning after the
/// static equilibrium; `check` of a scene with two field errors; a short
/// `run` with its step note and its summary's warnings: every chunk read
/// from stderr ends a line, and a line's `warning:` or `notice:` comes
/// only after the file name that starts it.
#[test]
fn every_stderr_line_is_written_whole() {
    let dir = tempfile::tempdir().expect("tmp");
    let bad = dir.path().join("bad.toml");
    let text = include_str!("../data/flat_20_40_1000rpm.toml")
        .replace("rollers = 90", "rollers = -90")
        .replace("pretension_n = 300.0", "pretension_n = -300.0");
    std::fs::write(&bad, text).expect("write");
    let sag = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/conveyor_sag_10m.toml"
    );
    let flat = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/flat_20_40_1000rpm.toml"
    );
    let bad = bad.to_str().expect("utf8");
    let runs: [&[&str]; 3] = [
        &["check", sag],
        &["check", bad],
        &["run", flat, "--duration", "0.02", "--window", "0.01"],
    ];
    for args in runs {
        let chunks = stderr_chunks(args);
        let text = chunks.concat();
        assert!(!text.is_empty(), "{args:?}: nothing on stderr");
        for chunk in &chunks {
            assert!(
                chunk.ends_with('\n'),
                "{args:?}: a line written in pieces: {chunk:?}\nin:\n{text}"
            );
        }
        for line in text.lines() {
            for tag in ["warning:", "notice:"] {
                if let Some(at) = line.find(tag) {
                    let head = &line[..at];
                    assert!(
                        head.is_empty() || args.iter().any(|a| head == format!("{a}: ")),
                        "{args:?}: {tag} inside a line: {line}"
                    );
                }
            }
        }
    }
}
