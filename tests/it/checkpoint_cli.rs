//! `chaindrive run --checkpoint` and `--resume` end to end, on a small,
//! fast drive: a finished run continued to a longer `--duration` is the
//! longer run done at once (series, summary and recording; wall times
//! aside), a run killed at any moment leaves a whole checkpoint that
//! resumes, and what cannot be continued is refused with what differs.
//!
//! The reference is always the run that never stopped: bit identity leaves
//! no tolerance to choose.

use std::path::Path;

use chaindrive::scene::{Overrides, Scene};
use chaindrive::sim::checkpoint::{Checkpoint, read_checkpoint_to_continue};

use crate::common::{chaindrive, command, read_json, stderr};

/// ANSI 40, 20T → 40T, the driver at 1000 rpm after a 0.1 s ramp, no load;
/// about 0.2 million steps per simulated second.
fn flat() -> String {
    format!(
        "{}/tests/data/flat_20_40_1000rpm.toml",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn without_wall_times(path: &Path) -> serde_json::Value {
    let mut v = read_json(path);
    for k in ["wall_s", "setup_wall_s", "ns_per_step"] {
        v.as_object_mut().expect("object").remove(k);
    }
    v
}

fn run_ok(args: &[String]) {
    let out = chaindrive(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
}

fn refused(args: &[String], expected: &str) {
    let out = chaindrive(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(!out.status.success(), "{args:?} was accepted");
    assert!(
        stderr(&out).contains(expected),
        "{args:?}: {}",
        stderr(&out)
    );
}

/// `run` on the flat drive to `duration_s` with `extra` arguments.
fn run_args(duration_s: &str, extra: &[&str]) -> Vec<String> {
    let scene = flat();
    ["run", "--quiet", &scene, "--duration", duration_s]
        .iter()
        .chain(extra)
        .map(|s| (*s).to_owned())
        .collect()
}

fn same_files(a: &str, b: &str) -> bool {
    std::fs::read(a).expect("a") == std::fs::read(b).expect("b")
}

/// The brief's soak, extended: 0.4 s with checkpoints, then continued to
/// 0.8 s, is the 0.8 s run; with the window over the whole run (it stays at
/// 0), the last 0.1 s (it starts after the checkpoint) and the last 0.4 s
/// (it starts at the checkpoint's last step, a sampled one). The series
/// the first run left holds a row past the checkpoint, as a killed run's
/// may: it is cut off, and no row is doubled or missing.
#[test]
fn a_finished_run_continued_to_a_longer_duration_is_the_longer_run() {
    let dir = tempfile::tempdir().expect("tmp");
    let p = |n: &str| dir.path().join(n).display().to_string();
    for window in [None, Some("0.1"), Some("0.4")] {
        let w: Vec<&str> = window.map_or_else(Vec::new, |w| vec!["--window", w]);
        fn with<'a>(w: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
            [w, extra].concat()
        }
        let (a_json, a_csv) = (p("a.json"), p("a.csv"));
        let (b_json, b_csv, ck) = (p("b.json"), p("b.csv"), p("b.ckpt"));
        run_ok(&run_args(
            "0.8",
            &with(&w, &["--summary", &a_json, "--series", &a_csv]),
        ));
        run_ok(&run_args(
            "0.4",
            &with(
                &w,
                &[
                    "--summary",
                    &b_json,
                    "--series",
                    &b_csv,
                    "--checkpoint",
                    &ck,
                    "--checkpoint-every",
                    "0.15",
                ],
            ),
        ));
        assert_eq!(read_json(Path::new(&b_json))["duration_s"], 0.4);
        let mut series = std::fs::read_to_string(&b_csv).expect("series");
        series.push_str("0.401,1,2,3,4,5,6\n");
        std::fs::write(&b_csv, series).expect("series");
        run_ok(&run_args(
            "0.8",
            &with(
                &w,
                &["--summary", &b_json, "--series", &b_csv, "--resume", &ck],
            ),
        ));
        assert_eq!(
            without_wall_times(Path::new(&a_json)),
            without_wall_times(Path::new(&b_json)),
            "window {window:?}: summary"
        );
        assert!(same_files(&a_csv, &b_csv), "window {window:?}: series");
    }
}

/// A chain with a designation has its links' fatigue counted over the
/// window: a run continued to a later end whose window starts after the
/// checkpoint counts it anew from there, as the longer run does.
#[test]
fn a_continued_run_counts_fatigue_over_its_new_window() {
    let dir = tempfile::tempdir().expect("tmp");
    let p = |n: &str| dir.path().join(n).display().to_string();
    let text = std::fs::read_to_string(flat()).expect("scene");
    let scene = p("flat_ansi40.toml");
    std::fs::write(
        &scene,
        text.replace("[chain]\n", "[chain]\ndesignation = \"ANSI 40\"\n"),
    )
    .expect("scene written");
    let args = |duration: &str, extra: &[&str]| -> Vec<String> {
        [
            "run",
            "--quiet",
            &scene,
            "--duration",
            duration,
            "--window",
            "0.1",
        ]
        .iter()
        .chain(extra)
        .map(|s| (*s).to_owned())
        .collect()
    };
    let (a_json, b_json, ck) = (p("a.json"), p("b.json"), p("b.ckpt"));
    run_ok(&args("0.8", &["--summary", &a_json]));
    run_ok(&args(
        "0.4",
        &["--checkpoint", &ck, "--checkpoint-every", "1"],
    ));
    run_ok(&args("0.8", &["--summary", &b_json, "--resume", &ck]));
    let (a, b) = (
        without_wall_times(Path::new(&a_json)),
        without_wall_times(Path::new(&b_json)),
    );
    assert!(
        a["fatigue"].is_object(),
        "a fatigue block: {}",
        a["fatigue"]
    );
    assert_eq!(a, b, "summary");
}

/// What cannot be continued is refused, naming what differs: an end before
/// the checkpoint, a window that would hold steps counted in another one,
/// other options, another scene.
#[test]
fn what_cannot_be_continued_is_refused_with_what_differs() {
    let dir = tempfile::tempdir().expect("tmp");
    let ck = dir.path().join("run.ckpt").display().to_string();
    run_ok(&run_args(
        "0.4",
        &[
            "--window",
            "0.2",
            "--checkpoint",
            &ck,
            "--checkpoint-every",
            "0.2",
        ],
    ));
    let resume =
        |duration: &str, extra: &[&str]| run_args(duration, &[extra, &["--resume", &ck]].concat());
    refused(
        &resume("0.3", &["--window", "0.2"]),
        "was taken at t = 0.4 s, after the end of this run (solver.duration_s = 0.3 s): continue it to a duration of at least 0.4 s",
    );
    // The window of a 0.5 s run, 0.3–0.5 s, holds 0.2–0.4 s sums it cannot
    // take apart.
    refused(
        &resume("0.5", &["--window", "0.2"]),
        "the statistics window (0.3 to 0.5 s) cannot be continued",
    );
    refused(
        &resume("0.5", &["--window", "0.2"]),
        "a --duration of at least 0.6 s puts it after the checkpoint",
    );
    refused(
        &resume("0.8", &["--window", "0.1"]),
        "started with --rate 1000 and --window 0.2, not --rate 1000 and --window 0.1",
    );
    refused(
        &resume("0.8", &[]),
        "--window 0.2, not --rate 1000 and without --window",
    );
    // The scene's automatic step divides the sample period: another rate
    // is another step, named as the option that sets it.
    refused(
        &resume("0.8", &["--window", "0.2", "--rate", "2000"]),
        "sample rate (--rate, which the automatic step divides): 1000 Hz there, 2000 Hz here",
    );
    refused(
        &resume("0.8", &["--window", "0.2", "--profile", "real"]),
        r#"written for another scene (sprockets[0].profile: not set there, "real" here; sprockets[1].profile: not set there, "real" here)"#,
    );
    // The options that fit: continued to 0.6 s (the window starts at the
    // checkpoint) and on from there with a checkpoint again.
    run_ok(&resume(
        "0.6",
        &[
            "--window",
            "0.2",
            "--checkpoint",
            &ck,
            "--checkpoint-every",
            "1",
        ],
    ));
    run_ok(&resume("1.0", &["--window", "0.2"]));
}

/// A run checkpointing at every step, killed outright (SIGKILL) at moments
/// spread over its writes: each time the checkpoint in place is whole (and
/// the file it was writing, when the kill came during a write, is left
/// beside it, often cut short), and resumes to the run that never stopped,
/// its series cut back to the checkpoint. Tried until a kill came during a
/// write (at most 60 times; on this machine 1 in 2 to 1 in 6 do).
#[test]
fn a_run_killed_at_any_moment_leaves_a_checkpoint_that_resumes() {
    let dir = tempfile::tempdir().expect("tmp");
    let p = |n: &str| dir.path().join(n).display().to_string();
    // Every tenth step is a row of the window, so that the checkpoint
    // (which holds the window's rows) grows to half a megabyte; each write
    // is synced, file and directory.
    let opts = ["--window", "0.1", "--rate", "21800"];
    let (ref_json, ref_csv) = (p("ref.json"), p("ref.csv"));
    run_ok(&run_args(
        "0.1",
        &[&opts[..], &["--summary", &ref_json, "--series", &ref_csv]].concat(),
    ));
    let scene = Scene::from_toml_with(
        &std::fs::read_to_string(flat()).expect("scene"),
        &Overrides {
            duration_s: Some(0.1),
            // The automatic step divides the run's sample period.
            sample_rate_hz: Some(21800.0),
            ..Overrides::default()
        },
    )
    .expect("valid");
    let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
    let (mut kills, mut during_writes, mut cut_short) = (0, 0, 0);
    for attempt in 0..60 {
        if kills >= 6 && during_writes >= 1 {
            break;
        }
        let name = format!("k{attempt}.ckpt");
        let (ck, csv, json) = (p(&name), p(&format!("k{attempt}.csv")), p("k.json"));
        let first = run_args(
            "0.1",
            &[
                &opts[..],
                &[
                    "--series",
                    &csv,
                    "--checkpoint",
                    &ck,
                    "--checkpoint-every",
                    "1e-9",
                ],
            ]
            .concat(),
        );
        let mut child = command()
            .args(&first)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("run starts");
        let started = std::time::Instant::now();
        while !Path::new(&ck).exists() {
            assert!(child.try_wait().expect("wait").is_none(), "ended early");
            assert!(started.elapsed().as_secs() < 120, "no checkpoint written");
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        // xorshift64*: delays of 0–150 ms, the same every time the test runs.
        seed ^= seed >> 12;
        seed ^= seed << 25;
        seed ^= seed >> 27;
        let delay_us = seed.wrapping_mul(0x2545_f491_4f6c_dd1d) % 150_000;
        std::thread::sleep(std::time::Duration::from_micros(delay_us));
        child.kill().expect("SIGKILL");
        child.wait().expect("reaped");
        kills += 1;
        let partial = std::fs::read_dir(dir.path())
            .expect("dir")
            .map(|e| e.expect("entry").path())
            .find(|f| {
                f.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with(&format!("{name}.partial.")))
            });
        if let Some(partial) = partial {
            during_writes += 1;
            cut_short += usize::from(
                read_checkpoint_to_continue::<serde::de::IgnoredAny>(&partial, &scene).is_err(),
            );
        }
        let whole: Checkpoint<serde::de::IgnoredAny> =
            read_checkpoint_to_continue(Path::new(&ck), &scene)
                .unwrap_or_else(|e| panic!("kill {attempt}: the checkpoint in place: {e}"));
        assert!(whole.sim.t_s() > 0.0 && whole.sim.t_s() < 0.1);
        run_ok(&run_args(
            "0.1",
            &[
                &opts[..],
                &["--resume", &ck, "--series", &csv, "--summary", &json],
            ]
            .concat(),
        ));
        assert_eq!(
            without_wall_times(Path::new(&ref_json)),
            without_wall_times(Path::new(&json)),
            "kill {attempt} at t = {} s",
            whole.sim.t_s()
        );
        assert!(same_files(&ref_csv, &csv), "kill {attempt}: series");
    }
    assert!(
        kills >= 6 && during_writes >= 1,
        "{kills} kills, {during_writes} during a write ({cut_short} of those files cut short)"
    );
}

/// A recorded run continued to a longer duration: the recording holds the
/// messages of the longer run's recording, bit for bit, and its metadata
/// (the planned duration is the longer one).
#[cfg(feature = "record")]
#[test]
fn a_recording_continued_to_a_longer_duration_is_the_longer_recording() {
    use crate::checkpoint::cli::messages;
    let dir = tempfile::tempdir().expect("tmp");
    let p = |n: &str| dir.path().join(n).display().to_string();
    let (a, b, ck) = (p("a.mcap"), p("b.mcap"), p("b.ckpt"));
    run_ok(&run_args("0.3", &["--record", &a]));
    run_ok(&run_args(
        "0.15",
        &[
            "--record",
            &b,
            "--checkpoint",
            &ck,
            "--checkpoint-every",
            "0.1",
        ],
    ));
    run_ok(&run_args("0.3", &["--record", &b, "--resume", &ck]));
    let (ma, mb) = (messages(Path::new(&a)), messages(Path::new(&b)));
    assert_eq!(ma.get("/sprockets").map(|m| m.len()), Some(301));
    assert!(ma == mb, "the messages differ");
    let read = |f: &str| chaindrive::record::read::read_recording(Path::new(f)).expect("readable");
    let (ra, rb) = (read(&a), read(&b));
    assert_eq!(ra.metadata, rb.metadata);
    assert_eq!(
        rb.metadata.get("duration_s").map(String::as_str),
        Some("0.3")
    );
    assert_eq!(rb.end_status, "completed");
}
