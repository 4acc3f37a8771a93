//! Checkpoints: a run stopped at a checkpoint and resumed from the file, in
//! a fresh simulation built from the scene, ends in the same bits as the run
//! that never stopped (state, summary, series); a checkpoint of another
//! scene, version or set of options is refused.
//!
//! The reference is the uninterrupted run itself: bit identity leaves no
//! tolerance to choose.

use crate::analysis::{RunSummary, Signals};
use crate::scene::{Integrator, Overrides, ProfileKind, Scene};
use crate::sim::checkpoint::{
    Checkpoint, CheckpointError, read_checkpoint, scene_hash, write_checkpoint,
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
            stepping: Some(crate::scene::Stepping::Rapier),
            ..Overrides::default()
        })
        .expect("valid");
    let sim = Simulation::new(&scene).expect("equilibrium");
    let err = sim.snapshot().expect_err("rapier");
    assert!(err.to_string().contains("solver.stepping"), "{err}");
}
