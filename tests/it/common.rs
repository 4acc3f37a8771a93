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
