//! Checkpoints from the command line: a recorded run stopped after a
//! checkpoint and resumed, a run resumed from a later checkpoint, and the
//! refusals of what cannot be resumed. The library's side (runs stopped,
//! written, read and resumed in a fresh simulation, continued to a later
//! end) is tested next to the code (`src/sim/checkpoint_tests.rs`).
//!
//! The reference is the uninterrupted run itself: bit identity leaves no
//! tolerance to choose.

#[cfg(feature = "cli")]
pub(crate) mod cli {
    use crate::common::{chaindrive, stderr};

    fn without_wall_times(path: &std::path::Path) -> serde_json::Value {
        let mut v = crate::common::read_json(path);
        for k in ["wall_s", "setup_wall_s", "ns_per_step"] {
            v.as_object_mut().expect("object").remove(k);
        }
        v
    }

    /// `run --checkpoint` then `run --resume` from the last checkpoint:
    /// summary and series as the run at once.
    #[test]
    fn run_resume_continues_summary_and_series() {
        let dir = tempfile::tempdir().expect("tmp");
        let p = |n: &str| dir.path().join(n).display().to_string();
        let out = chaindrive(&[
            "run",
            "--quiet",
            "--duration",
            "0.2",
            "--window",
            "0.05",
            "--checkpoint",
            &p("end.ckpt"),
            "--checkpoint-every",
            "0.07",
            "--summary",
            &p("a.json"),
            "--series",
            &p("a.csv"),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        // A run that ends at 0.14 s, its checkpoint there; its series went on
        // to 0.2 s (as a run killed after its checkpoint leaves it).
        let out = chaindrive(&[
            "run",
            "--quiet",
            "--duration",
            "0.14",
            "--window",
            "0.05",
            "--checkpoint",
            &p("run.ckpt"),
            "--checkpoint-every",
            "0.07",
            "--series",
            &p("b.csv"),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        std::fs::copy(p("a.csv"), p("b.csv")).expect("copy");
        let out = chaindrive(&[
            "run",
            "--quiet",
            "--duration",
            "0.2",
            "--window",
            "0.05",
            "--resume",
            &p("run.ckpt"),
            "--summary",
            &p("b.json"),
            "--series",
            &p("b.csv"),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        assert_eq!(
            without_wall_times(&dir.path().join("a.json")),
            without_wall_times(&dir.path().join("b.json"))
        );
        let (a, b) = (
            std::fs::read(p("a.csv")).expect("a"),
            std::fs::read(p("b.csv")).expect("b"),
        );
        assert!(a == b, "series differ: {} vs {} bytes", a.len(), b.len());
        // And a run in pieces is the run at once.
        let out = chaindrive(&[
            "run",
            "--quiet",
            "--duration",
            "0.2",
            "--window",
            "0.05",
            "--summary",
            &p("c.json"),
            "--series",
            &p("c.csv"),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        assert_eq!(
            without_wall_times(&dir.path().join("a.json")),
            without_wall_times(&dir.path().join("c.json"))
        );
        assert!(
            a == std::fs::read(p("c.csv")).expect("c"),
            "series in pieces"
        );

        // Refusals: another scene (profile), other options, another file.
        let refused = |args: &[&str], expected: &str| {
            let out = chaindrive(args);
            assert!(!out.status.success(), "{args:?} was accepted");
            assert!(
                stderr(&out).contains(expected),
                "{args:?}: {}",
                stderr(&out)
            );
        };
        let ck = p("run.ckpt");
        refused(
            &[
                "run",
                "--quiet",
                "--duration",
                "0.2",
                "--window",
                "0.05",
                "--profile",
                "real",
                "--resume",
                &ck,
            ],
            "another scene",
        );
        refused(
            &[
                "run",
                "--quiet",
                "--duration",
                "0.2",
                "--window",
                "0.05",
                "--rate",
                "500",
                "--resume",
                &ck,
            ],
            "resume with the same options",
        );
        refused(
            &[
                "run",
                "--quiet",
                "--duration",
                "0.2",
                "--resume",
                &p("a.csv"),
            ],
            "is not a chaindrive checkpoint",
        );
        refused(
            &[
                "run",
                "--quiet",
                "--duration",
                "0.2",
                "--checkpoint",
                &ck,
                "--checkpoint-every",
                "0",
            ],
            "--checkpoint-every 0",
        );
    }

    /// Every message of an MCAP file by topic: log time → payload (a file
    /// cut short read up to its damage).
    #[cfg(feature = "record")]
    pub(crate) type Topics =
        std::collections::BTreeMap<String, std::collections::BTreeMap<u64, Vec<u8>>>;

    /// The end status a complete recording's `chaindrive.end` metadata holds
    /// (`None`: the file has no summary section, so it was cut short, or no
    /// such record), read with the `mcap` crate alone.
    fn end_status(path: &std::path::Path) -> Option<String> {
        let bytes = std::fs::read(path).expect("recording");
        let summary = mcap::Summary::read(&bytes).expect("an MCAP file")?;
        summary.metadata_indexes.iter().find_map(|index| {
            let m = mcap::read::metadata(&bytes, index).expect("a metadata record");
            (m.name == "chaindrive.end").then(|| m.metadata.get("status").cloned())?
        })
    }

    #[cfg(feature = "record")]
    pub(crate) fn messages(path: &std::path::Path) -> Topics {
        let bytes = std::fs::read(path).expect("recording");
        let mut topics: std::collections::BTreeMap<_, std::collections::BTreeMap<_, _>> =
            std::collections::BTreeMap::new();
        for m in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
            let m = m.expect("a message");
            let old = topics
                .entry(m.channel.topic.clone())
                .or_default()
                .insert(m.log_time, m.data.into_owned());
            assert!(
                old.is_none(),
                "{} twice at {} ns",
                m.channel.topic,
                m.log_time
            );
        }
        topics
    }

    /// A recorded run stopped after a checkpoint, outright (SIGKILL: no
    /// handler runs, the checkpoint is the last periodic one) or cleanly
    /// (SIGTERM: the run writes a checkpoint where it stopped and finishes
    /// its outputs), then resumed with the same `--record` and `--series`:
    /// the recording holds the same messages, per channel and bit for bit,
    /// as the run that never stopped; the series and summary too.
    #[cfg(feature = "record")]
    #[test]
    fn a_stopped_recorded_run_resumes_its_recording() {
        fn args(v: &[String]) -> Vec<&str> {
            v.iter().map(String::as_str).collect()
        }
        let dir = tempfile::tempdir().expect("tmp");
        let p = |n: &str| dir.path().join(n).display().to_string();
        let base = ["run", "--quiet", "--duration", "0.5", "--window", "0.05"];
        let with = |extra: &[&str]| -> Vec<String> {
            base.iter().chain(extra).map(|s| (*s).to_owned()).collect()
        };
        let whole = with(&[
            "--record",
            &p("a.mcap"),
            "--series",
            &p("a.csv"),
            "--summary",
            &p("a.json"),
        ]);
        let out = chaindrive(&args(&whole));
        assert!(out.status.success(), "{}", stderr(&out));
        let a = messages(&dir.path().join("a.mcap"));
        // 501 samples (t = 0 … 0.5 s at 1 kHz) on a per-sample channel.
        assert_eq!(a.get("/sprockets").map(|m| m.len()), Some(501));
        let counts = |m: &Topics| {
            m.iter()
                .map(|(t, v)| (t.clone(), v.len()))
                .collect::<Vec<_>>()
        };

        for signal in ["-KILL", "-TERM"] {
            let n = |name: &str| p(&format!("{}{name}", &signal[1..]));
            let ck = n(".ckpt");
            let (mcap, csv, json) = (n(".mcap"), n(".csv"), n(".json"));
            let first = with(&[
                "--record",
                &mcap,
                "--series",
                &csv,
                "--summary",
                &json,
                "--checkpoint",
                &ck,
                "--checkpoint-every",
                "0.05",
            ]);
            let mut child = crate::common::command()
                .args(args(&first))
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .spawn()
                .expect("run starts");
            let started = std::time::Instant::now();
            while !std::path::Path::new(&ck).exists() {
                assert!(
                    child.try_wait().expect("wait").is_none(),
                    "{signal}: the run ended before its first checkpoint"
                );
                assert!(started.elapsed().as_secs() < 300, "no checkpoint written");
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
            let kill = std::process::Command::new("kill")
                .args([signal, &child.id().to_string()])
                .status()
                .expect("kill");
            assert!(kill.success());
            let status = child.wait().expect("reaped");
            if signal == "-TERM" {
                // Stopped cleanly: its outputs are whole and readable.
                assert_eq!(status.code(), Some(130));
                let summary = crate::common::read_json(std::path::Path::new(&json));
                assert_eq!(summary["interrupted"], true);
                let path = std::path::Path::new(&mcap);
                assert_eq!(end_status(path).as_deref(), Some("interrupted"));
            }

            let resumed = with(&[
                "--record",
                &mcap,
                "--series",
                &csv,
                "--summary",
                &json,
                "--resume",
                &ck,
            ]);
            let out = chaindrive(&args(&resumed));
            assert!(out.status.success(), "{signal}: {}", stderr(&out));
            assert!(
                !std::path::Path::new(&format!("{mcap}.before-resume")).exists(),
                "the earlier file set aside is removed"
            );
            assert_eq!(
                without_wall_times(&dir.path().join("a.json")),
                without_wall_times(std::path::Path::new(&json)),
                "{signal}"
            );
            let b = messages(std::path::Path::new(&mcap));
            assert_eq!(counts(&a), counts(&b), "{signal}");
            assert!(a == b, "{signal}: the messages differ");
            assert!(end_status(std::path::Path::new(&mcap)).is_some());
            assert!(
                std::fs::read(p("a.csv")).expect("a") == std::fs::read(&csv).expect("b"),
                "{signal}: the series differ"
            );
        }

        // Resumed with other channels: refused, the recording left alone.
        let ck = p("KILL.ckpt");
        let out = chaindrive(&args(&with(&[
            "--record",
            &p("other.mcap"),
            "--record-channels",
            "sprockets",
            "--resume",
            &ck,
        ])));
        assert!(!out.status.success());
        assert!(
            stderr(&out).contains("--record-channels"),
            "{}",
            stderr(&out)
        );
    }
}
