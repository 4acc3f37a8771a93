//! What the crate's own tests share: the paper's drive shortened, its run
//! summary, a counter of allocations and the strands' mean forces.

use crate::analysis::{RunSummary, Signals};
use crate::forces::Forces;
use crate::model::{DriveModel, DriveState};
use crate::scene::{Integrator, Overrides, Scene};
use crate::sim::{SampleRate, Simulation};

/// The paper's drive, shortened for tests, stepped by symplectic Euler (the
/// cheapest scheme, one force evaluation a step, with which the tests'
/// bounds were measured; the scene file's velocity Verlet closes its power
/// balance, which these tests do not count).
pub(crate) fn l60mc(duration_s: f64) -> Scene {
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
pub(crate) fn run_summary(duration_s: f64, rate_hz: f64) -> RunSummary {
    let scene = l60mc(duration_s);
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let sampling = SampleRate::new(rate_hz, scene.solver().dt_s).expect("a whole number of steps");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, duration_s - 1.0);
    let out = sim
        .run(duration_s, sampling.every, &mut signals, None)
        .expect("run");
    RunSummary::of_run(&sim, &out, &signals, 0.0)
}

/// Counts the allocations made by the current thread, so that a test can
/// check a loop allocates nothing while other tests run in parallel.
pub(crate) mod allocations {
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
    pub(crate) fn count() -> u64 {
        COUNT.with(Cell::get)
    }
}

/// Mean link force of every segment's free strand, found by chain order in
/// `state` with `forces` evaluated at it (`None`: no free link).
pub(crate) fn strand_means(
    model: &DriveModel,
    state: &DriveState,
    forces: &Forces,
) -> Vec<Option<f64>> {
    let segments = &model.segments;
    let runs = segments.runs(&model.sprockets, &state.x, &state.y, &forces.touching);
    let mut mean = vec![None; segments.len()];
    segments.mean_forces(&runs, &forces.link_force, &mut mean);
    mean
}

/// The JSON file at `path`.
pub(crate) fn read_json(path: &std::path::Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).expect("JSON")
}
