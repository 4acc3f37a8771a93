//! Integration tests: one binary, one module per topic. Every expected
//! number comes from outside the code under test (the paper's Table 4,
//! closed forms, the public contract), with its source in a comment.

mod analysis;
mod analyze;
mod cli;
mod cosim;
mod fuzz;
mod integrators;
mod paper;
mod profile;
mod record;
mod scene_errors;
mod stepping;
mod stress;

use chaindrive::scene::{Overrides, Scene};

/// The paper's drive, shortened for tests.
pub fn l60mc(duration_s: f64) -> Scene {
    Scene::l60mc()
        .with(&Overrides {
            duration_s: Some(duration_s),
            ..Overrides::default()
        })
        .expect("a valid duration")
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
