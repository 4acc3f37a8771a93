//! What every test module shares: the paper's drive shortened, its run
//! summary, the real `chaindrive` binary and its outputs, and a counter of
//! allocations.

#[cfg(feature = "cli")]
use std::path::Path;
#[cfg(feature = "cli")]
use std::process::{Command, Output};

use chaindrive::analysis::{RunSummary, Signals};
use chaindrive::forces::Forces;
use chaindrive::model::{DriveModel, DriveState};
use chaindrive::scene::{Integrator, Overrides, Scene};
use chaindrive::sim::{SampleRate, Simulation};

/// The paper's drive, shortened for tests, stepped by symplectic Euler (the
/// cheapest scheme, one force evaluation a step, with which the tests'
/// bounds were measured; the scene file's velocity Verlet closes its power
/// balance, which these tests do not count).
pub fn l60mc(duration_s: f64) -> Scene {
    Scene::l60mc()
        .with(&Overrides {
            duration_s: Some(duration_s),
            integrator: Some(Integrator::SymplecticEuler),
            ..Overrides::default()
        })
        .expect("a valid duration")
}

/// Runs the paper's drive for `duration_s`, sampled at `rate_hz`, and
/// returns its summary (statistics over the last second).
pub fn run_summary(duration_s: f64, rate_hz: f64) -> RunSummary {
    let scene = l60mc(duration_s);
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let sampling = SampleRate::new(rate_hz, scene.solver().dt_s).expect("a whole number of steps");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, duration_s - 1.0);
    let out = sim
        .run(duration_s, sampling.every, &mut signals, None)
        .expect("run");
    RunSummary::of_run(&sim, &out, &signals, 0.0)
}

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

/// Counts the allocations made by the current thread, so that a test can
/// check a loop allocates nothing while other tests run in parallel.
pub mod allocations {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    thread_local! {
        static COUNT: Cell<u64> = const { Cell::new(0) };
    }

    struct Counting;

    // SAFETY: every call is forwarded unchanged to the system allocator; the
    // counter is a const-initialised thread-local (no allocation to reach it).
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            COUNT.with(|c| c.set(c.get() + 1));
            // SAFETY: forwarded with the caller's layout.
            unsafe { System.alloc(layout) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            // SAFETY: forwarded with the caller's pointer and layout.
            unsafe { System.dealloc(ptr, layout) }
        }
        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            COUNT.with(|c| c.set(c.get() + 1));
            // SAFETY: forwarded with the caller's arguments.
            unsafe { System.realloc(ptr, layout, new_size) }
        }
    }

    #[global_allocator]
    static GLOBAL: Counting = Counting;

    /// Allocations made by this thread so far.
    pub fn count() -> u64 {
        COUNT.with(Cell::get)
    }
}

/// Mean link force of every segment's free strand, found by chain order in
/// `state` with `forces` evaluated at it (`None`: no free link).
pub fn strand_means(model: &DriveModel, state: &DriveState, forces: &Forces) -> Vec<Option<f64>> {
    let segments = &model.segments;
    let runs = segments.runs(&model.sprockets, &state.x, &state.y, &forces.touching);
    let mut mean = vec![None; segments.len()];
    segments.mean_forces(&runs, &forces.link_force, &mut mean);
    mean
}
