//! Checkpoints: a run stopped at a checkpoint and resumed from the file, in
//! a fresh simulation built from the scene, ends in the same bits as the run
//! that never stopped (state, summary, series); a checkpoint of another
//! scene, version or set of options is refused.
//!
//! The reference is the uninterrupted run itself: bit identity leaves no
//! tolerance to choose.

use chaindrive::analysis::{RunSummary, Signals};
use chaindrive::scene::{Integrator, Overrides, ProfileKind, Scene};
use chaindrive::sim::checkpoint::{
    Checkpoint, CheckpointError, read_checkpoint, scene_hash, write_checkpoint,
};
use chaindrive::sim::{RunOutcome, SampleRate, Simulation};
use serde::{Deserialize, Serialize};

/// What the test keeps of a run besides the simulation (as `run` does).
#[derive(Serialize, Deserialize)]
struct Kept {
    signals: Signals,
    steps: u64,
    max_penetration_m: f64,
}

const DURATION_S: f64 = 0.2;
/// The statistics window: shorter than the run, so `Signals` drops rows
/// and the checkpoint holds only the last ones.
const WINDOW_S: f64 = 0.05;
/// Where the first run stops: step 12 345 of 20 000 (between samples).
const STOP_S: f64 = 0.123_45;

fn scene(profile: ProfileKind, integrator: Integrator) -> Scene {
    Scene::l60mc()
        .with(&Overrides {
            profile: Some(profile),
            integrator: Some(integrator),
            duration_s: Some(DURATION_S),
            ..Overrides::default()
        })
        .expect("valid overrides")
}

/// A simulation and its signals as `chaindrive run` sets them up.
fn start(scene: &Scene) -> (Simulation, Signals, u64) {
    let mut sim = Simulation::new(scene).expect("equilibrium");
    sim.track_power(DURATION_S - WINDOW_S);
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("whole steps");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, DURATION_S - WINDOW_S);
    signals.keep_window(WINDOW_S);
    (sim, signals, sampling.every)
}

fn summary(sim: &Simulation, outcome: &RunOutcome, signals: &Signals) -> RunSummary {
    let mut s = RunSummary::of_run_over(sim, outcome, signals, 0.0, WINDOW_S);
    // Wall times differ from run to run.
    s.wall_s = 0.0;
    s.ns_per_step = 0.0;
    s
}

/// Runs `scene` at once, then stopped at [`STOP_S`], checkpointed to a file
/// and resumed in a new simulation; returns both ends' (state, summary) for
/// comparison, and the checkpoint's path.
fn at_once_and_resumed(
    scene: &Scene,
    dir: &std::path::Path,
    tamper: impl FnOnce(&mut Simulation),
) -> (Simulation, RunSummary, Simulation, RunSummary) {
    let (mut whole, mut signals, every) = start(scene);
    let out = whole
        .run(DURATION_S, every, &mut signals, None)
        .expect("run");
    let whole_summary = summary(&whole, &out, &signals);

    let path = dir.join("run.ckpt");
    {
        let (mut first, mut signals, every) = start(scene);
        let out = first.run(STOP_S, every, &mut signals, None).expect("run");
        assert_eq!(out.steps, (STOP_S / scene.solver().dt_s).round() as u64);
        let ck = Checkpoint {
            sim: first.snapshot().expect("substepped"),
            run: Kept {
                signals,
                steps: out.steps,
                max_penetration_m: out.max_penetration_m,
            },
        };
        write_checkpoint(&path, scene, &ck).expect("written");
    }
    let ck: Checkpoint<Kept> = read_checkpoint(&path, scene).expect("read back");
    let (mut resumed, _, every) = start(scene);
    resumed.restore(&ck.sim).expect("fits");
    tamper(&mut resumed);
    let mut signals = ck.run.signals;
    let mut out = resumed
        .run(DURATION_S, every, &mut signals, None)
        .expect("run");
    out.steps += ck.run.steps;
    out.max_penetration_m = out.max_penetration_m.max(ck.run.max_penetration_m);
    let resumed_summary = summary(&resumed, &out, &signals);
    (whole, whole_summary, resumed, resumed_summary)
}

fn check_bit_identical(profile: ProfileKind, integrator: Integrator) {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = scene(profile, integrator);
    let (whole, a, resumed, b) = at_once_and_resumed(&scene, dir.path(), |_| {});
    let label = format!("{} {}", profile.name(), integrator.name());
    assert_eq!(whole.state, resumed.state, "{label}: state");
    assert_eq!(
        whole.integration.stats, resumed.integration.stats,
        "{label}: integrator counters"
    );
    // Bit for bit: the summaries' JSON (floats printed shortest round-trip).
    let (ja, jb) = (
        serde_json::to_string(&a).expect("json"),
        serde_json::to_string(&b).expect("json"),
    );
    assert_eq!(ja, jb, "{label}: summary");
    assert_eq!(b.steps, 20_000, "{label}");
}

/// Guides and tensioner arms keep histories of their own (the shoes'
/// remembered onsets, the ratchet's reach, the chamber's reference): a
/// drive with both, resumed, ends bit for bit where the run at once ends.
#[test]
fn resumed_runs_with_guides_and_a_hydraulic_tensioner_are_bit_identical() {
    for (file, dt_s) in [("l60mc-guides.toml", 1e-5), ("timing-drive.toml", 5e-6)] {
        let path = format!("{}/assets/{file}", env!("CARGO_MANIFEST_DIR"));
        let scene = Scene::from_toml_with(
            &std::fs::read_to_string(&path).expect("example scene"),
            &Overrides {
                duration_s: Some(DURATION_S),
                dt_s: Some(dt_s),
                ..Overrides::default()
            },
        )
        .expect("valid scene");
        let dir = tempfile::tempdir().expect("tmp");
        let (whole, a, resumed, b) = at_once_and_resumed(&scene, dir.path(), |_| {});
        assert_eq!(whole.state, resumed.state, "{file}: state");
        let (ja, jb) = (
            serde_json::to_string(&a).expect("json"),
            serde_json::to_string(&b).expect("json"),
        );
        assert_eq!(ja, jb, "{file}: summary");
    }
}

#[test]
fn resumed_runs_are_bit_identical_circular_symplectic_euler() {
    check_bit_identical(ProfileKind::Circular, Integrator::SymplecticEuler);
}

#[test]
fn resumed_runs_are_bit_identical_real_symplectic_euler() {
    check_bit_identical(ProfileKind::Real, Integrator::SymplecticEuler);
}

#[test]
fn resumed_runs_are_bit_identical_circular_dormand_prince45() {
    check_bit_identical(ProfileKind::Circular, Integrator::DormandPrince45);
}

#[test]
fn resumed_runs_are_bit_identical_real_dormand_prince45() {
    check_bit_identical(ProfileKind::Real, Integrator::DormandPrince45);
}

#[test]
fn resumed_runs_are_bit_identical_implicit_damping() {
    // The damping rows of the last evaluation are part of the contact's history.
    check_bit_identical(ProfileKind::Circular, Integrator::ImplicitDamping);
}

/// The check above can fail: a resume that drops the contact memory (the
/// remembered onset speeds) ends elsewhere.
#[test]
fn the_contact_memory_is_needed() {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = scene(ProfileKind::Circular, Integrator::SymplecticEuler);
    let (whole, _, resumed, _) = at_once_and_resumed(&scene, dir.path(), |sim| {
        sim.forces.reset_memory();
    });
    assert_ne!(whole.state, resumed.state);
}

#[test]
fn a_checkpoint_of_another_scene_is_refused() {
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("run.ckpt");
    let scene = scene(ProfileKind::Circular, Integrator::SymplecticEuler);
    let sim = Simulation::new(&scene).expect("equilibrium");
    let ck = Checkpoint {
        sim: sim.snapshot().expect("substepped"),
        run: (),
    };
    write_checkpoint(&path, &scene, &ck).expect("written");
    read_checkpoint::<()>(&path, &scene).expect("the same scene takes it");
    // Another duration (or any other field) is another scene.
    let other = scene
        .with(&Overrides {
            duration_s: Some(2.0 * DURATION_S),
            ..Overrides::default()
        })
        .expect("valid");
    assert_ne!(scene_hash(&other), scene_hash(&scene));
    let err = read_checkpoint::<()>(&path, &other).expect_err("another scene");
    assert!(matches!(err, CheckpointError::OtherScene { .. }), "{err}");
    assert!(err.to_string().contains("another scene"), "{err}");
    // Not a checkpoint at all.
    std::fs::write(&path, "t_s,omega_1\n").expect("write");
    let err = read_checkpoint::<()>(&path, &scene).expect_err("garbage");
    assert!(
        err.to_string().contains("is not a chaindrive checkpoint"),
        "{err}"
    );
}

#[test]
fn rapier_stepping_is_not_checkpointed() {
    let scene = Scene::l60mc()
        .with(&Overrides {
            duration_s: Some(DURATION_S),
            stepping: Some(chaindrive::scene::Stepping::Rapier),
            ..Overrides::default()
        })
        .expect("valid");
    let sim = Simulation::new(&scene).expect("equilibrium");
    let err = sim.snapshot().expect_err("rapier");
    assert!(err.to_string().contains("solver.stepping"), "{err}");
}

#[cfg(feature = "cli")]
mod cli {
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
            &p("run.ckpt"),
            "--checkpoint-every",
            "0.07",
            "--summary",
            &p("a.json"),
            "--series",
            &p("a.csv"),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        // The last checkpoint is at 0.14 s: a run killed after it resumes there.
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
    type Topics = std::collections::BTreeMap<String, std::collections::BTreeMap<u64, Vec<u8>>>;

    #[cfg(feature = "record")]
    fn messages(path: &std::path::Path) -> Topics {
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
                assert!(chaindrive::record::read::is_complete_mcap_file(path).expect("read"));
                let rec = chaindrive::record::read::read_recording(path).expect("readable");
                assert_eq!(rec.end_status, "interrupted");
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
            assert!(
                chaindrive::record::read::is_complete_mcap_file(std::path::Path::new(&mcap))
                    .expect("read")
            );
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
