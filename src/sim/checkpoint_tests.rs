//! Checkpoints: a run stopped at a checkpoint and resumed from the file, in
//! a fresh simulation built from the scene, ends in the same bits as the run
//! that never stopped (state, summary, series); continued to a later end,
//! it ends in the bits of the longer run done at once; a checkpoint of
//! another scene, version or set of options is refused.
//!
//! The reference is the uninterrupted run itself: bit identity leaves no
//! tolerance to choose.

use crate::analysis::{RunSummary, Signals};
use crate::model::DriveState;
use crate::scene::{Integrator, Overrides, ProfileKind, Scene};
use crate::sim::checkpoint::{
    Checkpoint, CheckpointError, read_checkpoint, read_checkpoint_to_continue, scene_hash,
    write_checkpoint,
};
use crate::sim::{RunOutcome, SampleRate, Simulation};
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

#[test]
fn resumed_runs_are_bit_identical_verlet_implicit_damping() {
    // The step's start forces are the evaluated ones with the solved
    // contact damping: the snapshot's forces carry them.
    check_bit_identical(ProfileKind::Real, Integrator::VerletImplicitDamping);
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

/// A run of `scene` to `end_s` with a statistics window of `window_s`, as
/// `chaindrive run` sets it up: the simulation, its signals and sampling.
fn start_to(scene: &Scene, end_s: f64, window_s: f64) -> (Scene, Simulation, Signals, u64) {
    let scene = scene
        .with(&Overrides {
            duration_s: Some(end_s),
            ..Overrides::default()
        })
        .expect("valid duration");
    let from_s = (end_s - window_s).max(0.0);
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    sim.track_power(from_s);
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("whole steps");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, from_s);
    signals.keep_window(window_s);
    (scene, sim, signals, sampling.every)
}

fn summary_json(sim: &Simulation, out: &RunOutcome, signals: &Signals, window_s: f64) -> String {
    let mut s = RunSummary::of_run_over(sim, out, signals, 0.0, window_s);
    s.wall_s = 0.0;
    s.ns_per_step = 0.0;
    serde_json::to_string(&s).expect("json")
}

/// Runs `scene` to `end_s` at once, and to `stop_s`, checkpointed, then
/// continued from the file to `end_s`, the statistics window the last
/// `window_s` of each run (it moves with the end). Returns (state, summary)
/// of both; `replay = false` starts the window anew without taking up the
/// last step again (its extremes, its powers).
fn at_once_and_continued(
    scene: &Scene,
    stop_s: f64,
    end_s: f64,
    window_s: f64,
    replay: bool,
) -> (Ran, Ran) {
    let (_, mut whole, mut signals, every) = start_to(scene, end_s, window_s);
    let out = whole.run(end_s, every, &mut signals, None).expect("run");
    let at_once = (
        whole.state.clone(),
        summary_json(&whole, &out, &signals, window_s),
        in_window(&signals, end_s - window_s),
    );

    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("run.ckpt");
    let (short, mut first, mut signals, every) = start_to(scene, stop_s, window_s);
    let out = first.run(stop_s, every, &mut signals, None).expect("run");
    let ck = Checkpoint {
        sim: first.snapshot().expect("substepped"),
        run: Kept {
            signals,
            steps: out.steps,
            max_penetration_m: out.max_penetration_m,
        },
    };
    write_checkpoint(&path, &short, &ck).expect("written");

    let (long, mut sim, _, every) = start_to(scene, end_s, window_s);
    let ck: Checkpoint<Kept> = read_checkpoint_to_continue(&path, &long).expect("read back");
    sim.restore(&ck.sim).expect("fits");
    let (was_from_s, from_s) = ((stop_s - window_s).max(0.0), (end_s - window_s).max(0.0));
    let restarts = ck
        .sim
        .window_restarts(was_from_s, from_s)
        .expect("continued");
    let mut signals = ck.run.signals;
    let sampled = sim.last_step_sampled(every).filter(|_| replay);
    let last = sampled.map(|sampled| (sim.sample(), sampled));
    let last = last.as_ref().map(|(s, sampled)| (s, *sampled));
    signals.continue_window(&sim.model, from_s, window_s, last);
    if restarts && replay {
        sim.restart_power(&ck.sim, from_s);
    } else if restarts {
        sim.track_power(from_s);
    }
    let mut out = sim.run(end_s, every, &mut signals, None).expect("run");
    out.steps += ck.run.steps;
    out.max_penetration_m = out.max_penetration_m.max(ck.run.max_penetration_m);
    let continued = (
        sim.state.clone(),
        summary_json(&sim, &out, &signals, window_s),
        in_window(&signals, end_s - window_s),
    );
    (at_once, continued)
}

/// A run's end state, summary and signals ([`in_window`]).
type Ran = (DriveState, String, String);

/// The debug form of `signals` (every accumulator and spectrum, numbers
/// bit for bit) with the rows from `from_s` on, the window's (its first
/// included, where the step integrals start): the rows before it hold the
/// extremes of the steps the run followed, which a run whose window starts
/// later did not follow (no summary reads them).
fn in_window(signals: &Signals, from_s: f64) -> String {
    let mut s = signals.clone();
    s.rows.retain(|r| r.t_s >= from_s - 1e-9);
    format!("{s:?}")
}

/// Continued to a later end, a run is the longer run at once, whether its
/// window stays where it started (the whole run), starts at the
/// checkpoint's last step (its extremes and the power ledger count that
/// step again) or after it: with guides (their shoes' extremes) and a
/// hydraulic tensioner, under each integrator family.
#[test]
fn runs_continued_to_a_later_end_are_the_longer_runs() {
    let file = |name: &str| {
        let path = format!("{}/assets/{name}", env!("CARGO_MANIFEST_DIR"));
        Scene::from_toml(&std::fs::read_to_string(path).expect("example scene")).expect("valid")
    };
    let guides = file("l60mc-guides.toml");
    let timing = file("timing-drive.toml")
        .with(&Overrides {
            dt_s: Some(5e-6),
            ..Overrides::default()
        })
        .expect("valid");
    let paper = |integrator| scene(ProfileKind::Real, integrator);
    let cases = [
        ("guides, the window from the start", &guides, 0.1, 0.2, 0.2),
        (
            "guides, the window from the last step",
            &guides,
            0.1,
            0.2,
            0.1,
        ),
        (
            "tensioner, the window from the last step",
            &timing,
            0.05,
            0.1,
            0.05,
        ),
        (
            "dormand_prince45, the window after the checkpoint",
            &paper(Integrator::DormandPrince45),
            0.08,
            0.2,
            0.05,
        ),
        (
            "implicit_damping, the window from the last step",
            &paper(Integrator::ImplicitDamping),
            0.1,
            0.2,
            0.1,
        ),
    ];
    for (label, scene, stop_s, end_s, window_s) in cases {
        let (at_once, continued) = at_once_and_continued(scene, stop_s, end_s, window_s, true);
        assert_eq!(at_once.0, continued.0, "{label}: state");
        assert_eq!(at_once.1, continued.1, "{label}: summary");
        // The signals too (the window's rows with their step integrals,
        // spectra, accumulators), so that a checkpoint written by the
        // continued run holds what the run at once would.
        assert!(at_once.2 == continued.2, "{label}: signals");
    }
}

/// The check above can fail: a window starting at the checkpoint's last
/// step that does not count that step again ends elsewhere.
#[test]
fn the_last_step_is_counted_again() {
    let scene = scene(ProfileKind::Circular, Integrator::SymplecticEuler);
    let (at_once, continued) = at_once_and_continued(&scene, 0.1, 0.2, 0.1, false);
    assert_eq!(at_once.0, continued.0, "the same state");
    assert_ne!(at_once.1, continued.1, "another summary");
}

/// A window starts anew only after the step before the checkpoint's last:
/// a run with that window from the start has counted at most the last step.
#[test]
fn a_window_starts_anew_only_after_the_step_before_the_last() {
    let scene = scene(ProfileKind::Circular, Integrator::SymplecticEuler);
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let dt = scene.solver().dt_s;
    let mut signals = Signals::new(&sim.model, 1000.0, 0.0);
    sim.run(10.0 * dt, 1, &mut signals, None).expect("run");
    let snapshot = sim.snapshot().expect("substepped");
    // The times as the run computes them: steps × dt.
    let (before_last, last) = (9.0 * dt, 10.0 * dt);
    assert_eq!(snapshot.t_s(), last);
    let restarts = |from_s: f64| snapshot.window_restarts(0.0, from_s);
    assert!(!restarts(0.0).expect("the same start goes on"));
    assert!(restarts(last).expect("the last step"));
    assert!(restarts(f64::from_bits(before_last.to_bits() + 1)).expect("just after"));
    assert!(restarts(1.0).expect("after the checkpoint"));
    let err = restarts(before_last).expect_err("holds a step counted from 0");
    assert!(matches!(err, CheckpointError::WindowMoved { .. }), "{err}");
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
    // Another duration is the same scene ending elsewhere: refused where
    // the end must be the same, taken up to continue the run.
    let other = scene
        .with(&Overrides {
            duration_s: Some(2.0 * DURATION_S),
            ..Overrides::default()
        })
        .expect("valid");
    assert_eq!(scene_hash(&other), scene_hash(&scene));
    let err = read_checkpoint::<()>(&path, &other).expect_err("another end");
    assert!(matches!(err, CheckpointError::OtherScene { .. }), "{err}");
    assert!(
        err.to_string()
            .contains("another scene (solver.duration_s: 0.2 there, 0.4 here)"),
        "{err}"
    );
    read_checkpoint_to_continue::<()>(&path, &other).expect("continued to a later end");
    // Any other field is another scene, named.
    let other = scene
        .with(&Overrides {
            integrator: Some(Integrator::Rk4),
            ..Overrides::default()
        })
        .expect("valid");
    assert_ne!(scene_hash(&other), scene_hash(&scene));
    let err = read_checkpoint_to_continue::<()>(&path, &other).expect_err("another scene");
    assert!(
        err.to_string()
            .contains(r#"solver.integrator: "symplectic_euler" there, "rk4" here"#),
        "{err}"
    );
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
            stepping: Some(crate::scene::Stepping::Rapier),
            ..Overrides::default()
        })
        .expect("valid");
    let sim = Simulation::new(&scene).expect("equilibrium");
    let err = sim.snapshot().expect_err("rapier");
    assert!(err.to_string().contains("solver.stepping"), "{err}");
}

/// A scene with a load table is the same scene however its file is named:
/// by a relative or an absolute path, its checkpoints are its own (the
/// table's text counts, not the folder it was read from).
#[test]
fn a_scene_with_a_load_table_is_the_same_by_any_path() {
    let rel = std::path::Path::new("assets/timing-excited.toml");
    let abs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    let read = |p: &std::path::Path| {
        Scene::from_path_with(p, &Overrides::default())
            .expect("readable")
            .expect("valid")
    };
    let (by_rel, by_abs) = (read(rel), read(&abs));
    assert!(
        by_rel.sprockets()[1].excitation.load_table.is_some(),
        "the scene has a table"
    );
    assert_eq!(scene_hash(&by_rel), scene_hash(&by_abs));
}
