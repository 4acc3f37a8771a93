//! Two threads per step for large drives: a persistent worker and the
//! roller split.
//!
//! A drive of many rollers spends its step in loops over the rollers (the
//! links, the rollers' update) whose iterations are independent. With
//! [`Split`] on, the caller takes the first half of the rollers and a worker
//! thread the second, for each such loop: one fork and one join per loop,
//! no allocation.
//!
//! **Same bits.** Each roller's force is summed in the same order as on one
//! thread: the two links at the halves' boundary are evaluated by the thread
//! that owns them, and the neighbouring thread evaluates the one it reads
//! again, locally, with the same operations (IEEE square root and division,
//! no fused multiply-add), so it gets the same bits without waiting. The
//! largest stretch and speed are maxima, which do not depend on the order.
//! Test: `threads_1_and_2_agree_to_the_bit`.
//!
//! **The worker** is spawned at the first split step and lives as long as
//! its drive's [`crate::forces::ForceGenerator`]. Between jobs it spins
//! briefly (a step's next loop follows within microseconds), then parks (a
//! co-simulated drive waits a whole frame for the world's step). The caller
//! waits for the worker's half the same way, spinning, then yielding its
//! core. Spawning a thread per step would cost more than the step.
//!
//! When the worker is busy with another caller (a generator shared between
//! threads) or cannot be spawned, both halves run on the caller, in the
//! same order: the results never depend on the thread count.

use std::cell::UnsafeCell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::{self, JoinHandle, Thread};

use crate::forces::Fork;
use crate::scene::Threads;

/// Spins before the worker parks between jobs (≈ 20–50 µs).
const WORKER_SPINS: u32 = 20_000;

/// Spins before the caller starts yielding while it waits for the worker.
const CALLER_SPINS: u32 = 20_000;

/// One half's job: called with the half's index (1 on the worker).
type Job = dyn Fn(usize) + Sync;

/// What the caller and the worker share.
struct Shared {
    /// Jobs posted so far.
    posted: AtomicU64,
    /// Jobs the worker has finished.
    finished: AtomicU64,
    /// The worker is parked or about to park.
    sleeping: AtomicBool,
    /// The worker's job panicked (the caller runs it again, to panic itself).
    panicked: AtomicBool,
    /// Stop and return (the generator is dropped).
    stop: AtomicBool,
    /// A caller holds the worker.
    busy: AtomicBool,
    /// The posted job: written by the caller before `posted` is raised, read
    /// by the worker after it sees the raise, and not touched again until
    /// `finished` catches up.
    job: UnsafeCell<Option<*const Job>>,
}

// SAFETY: `job` is written only by the caller holding `busy`, before the
// Release increment of `posted`, and read by the worker only after its
// Acquire load of `posted` sees that increment, while the caller waits for
// `finished` (Release by the worker, Acquire by the caller) before it
// returns and the borrowed job ends. The job itself is `Sync`.
unsafe impl Sync for Shared {}
// SAFETY: as above; the raw pointer is only dereferenced under that protocol.
unsafe impl Send for Shared {}

/// The persistent worker thread.
struct Worker {
    shared: Arc<Shared>,
    thread: Thread,
    handle: Option<JoinHandle<()>>,
}

impl Worker {
    fn spawn() -> Option<Self> {
        let shared = Arc::new(Shared {
            posted: AtomicU64::new(0),
            finished: AtomicU64::new(0),
            sleeping: AtomicBool::new(false),
            panicked: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            busy: AtomicBool::new(false),
            job: UnsafeCell::new(None),
        });
        let theirs = Arc::clone(&shared);
        let handle = thread::Builder::new()
            .name("chaindrive-worker".to_owned())
            .spawn(move || work(&theirs))
            .ok()?;
        Some(Self {
            shared,
            thread: handle.thread().clone(),
            handle: Some(handle),
        })
    }

    /// Runs `job(0)` here and `job(1)` on the worker; returns when both are
    /// done. `false` (nothing run) when another caller holds the worker.
    fn run<'a>(&self, job: &'a (dyn Fn(usize) + Sync + 'a)) -> bool {
        let s = &*self.shared;
        if s.busy
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
        {
            return false;
        }
        // SAFETY: the lifetime is erased only while this call waits for the
        // worker to finish with the job (see `Shared`).
        let ptr: *const Job =
            unsafe { std::mem::transmute::<&'a (dyn Fn(usize) + Sync + 'a), &'static Job>(job) };
        // SAFETY: we hold `busy` and the worker is idle (finished == posted).
        unsafe { *s.job.get() = Some(ptr) };
        let ticket = s.posted.fetch_add(1, Ordering::SeqCst) + 1;
        if s.sleeping.load(Ordering::SeqCst) {
            self.thread.unpark();
        }
        job(0);
        let mut spins = 0u32;
        while s.finished.load(Ordering::Acquire) != ticket {
            if spins < CALLER_SPINS {
                spins += 1;
                std::hint::spin_loop();
            } else {
                thread::yield_now();
            }
        }
        let panicked = s.panicked.swap(false, Ordering::Relaxed);
        s.busy.store(false, Ordering::Release);
        if panicked {
            // The worker's half panicked: run it here, to panic here.
            job(1);
        }
        true
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.thread.unpark();
        if let Some(h) = self.handle.take() {
            // A worker that panicked has already reported it.
            let _ = h.join();
        }
    }
}

/// The worker's loop: wait for a job, spinning then parking; run it.
fn work(s: &Shared) {
    let mut seen = 0u64;
    loop {
        let mut spins = 0u32;
        let ticket = loop {
            let p = s.posted.load(Ordering::Acquire);
            if p != seen {
                break p;
            }
            if s.stop.load(Ordering::Acquire) {
                return;
            }
            if spins < WORKER_SPINS {
                spins += 1;
                std::hint::spin_loop();
            } else {
                s.sleeping.store(true, Ordering::SeqCst);
                if s.posted.load(Ordering::SeqCst) == seen && !s.stop.load(Ordering::SeqCst) {
                    thread::park();
                }
                s.sleeping.store(false, Ordering::SeqCst);
            }
        };
        seen = ticket;
        // SAFETY: see `Shared`: the caller wrote the job before posting it
        // and keeps it alive until `finished` reaches `ticket`.
        if let Some(job) = unsafe { *s.job.get() } {
            // SAFETY: as above.
            let job = unsafe { &*job };
            if catch_unwind(AssertUnwindSafe(|| job(1))).is_err() {
                s.panicked.store(true, Ordering::Relaxed);
            }
        }
        s.finished.store(ticket, Ordering::Release);
    }
}

/// Whether and how a drive's roller loops are split over two threads, with
/// the worker that takes the second half (spawned at first use).
pub struct Split {
    /// Rollers from which the loops are split (`usize::MAX`: never).
    min_rollers: usize,
    worker: OnceLock<Option<Worker>>,
}

impl Split {
    /// The split for `setting` (one thread, two, or two from
    /// [`AUTO_MIN_ROLLERS`] rollers on a machine with two cores or more).
    pub fn new(setting: Threads) -> Self {
        let min_rollers = match setting {
            Threads::One => usize::MAX,
            Threads::Two => 0,
            Threads::Auto => {
                let cores = thread::available_parallelism().map_or(1, |n| n.get());
                if cores >= 2 {
                    AUTO_MIN_ROLLERS
                } else {
                    usize::MAX
                }
            }
        };
        Self {
            min_rollers,
            worker: OnceLock::new(),
        }
    }

    /// Whether a drive of `rollers` rollers is split (at least 4 rollers,
    /// two per half, whatever the setting).
    #[inline]
    pub(crate) fn splits(&self, rollers: usize) -> bool {
        rollers >= self.min_rollers.max(4)
    }

    /// Runs `job(0)` and `job(1)`, on two threads where the worker is
    /// available, else one after the other here. Each half must write only
    /// its own data: the results are the same either way.
    pub(crate) fn both(&self, job: &(dyn Fn(usize) + Sync)) {
        let worker = self.worker.get_or_init(Worker::spawn);
        if let Some(w) = worker
            && w.run(job)
        {
            return;
        }
        job(0);
        job(1);
    }
}

impl Fork for Split {
    fn splits(&self, rollers: usize) -> bool {
        Split::splits(self, rollers)
    }

    fn both(&self, job: &(dyn Fn(usize) + Sync)) {
        Split::both(self, job);
    }

    /// The same setting, with a worker of its own (spawned at first use).
    fn clone_box(&self) -> Box<dyn Fork> {
        Box::new(Self {
            min_rollers: self.min_rollers,
            worker: OnceLock::new(),
        })
    }
}

impl std::fmt::Debug for Split {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Split")
            .field("min_rollers", &self.min_rollers)
            .field("worker", &matches!(self.worker.get(), Some(Some(_))))
            .finish()
    }
}

/// Drive size from which `threads = "auto"` splits the rollers over two
/// threads (benches/README.md, "Two threads": below it the fork and join
/// cost more than the half step saves).
pub const AUTO_MIN_ROLLERS: usize = 2000;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_halves_run_and_the_worker_is_reused() {
        // 1000 jobs on one worker: every half runs once per call.
        let split = Split::new(Threads::Two);
        let count = [AtomicU64::new(0), AtomicU64::new(0)];
        for _ in 0..1000 {
            split.both(&|h| {
                count[h].fetch_add(1, Ordering::Relaxed);
            });
        }
        assert_eq!(count[0].load(Ordering::Relaxed), 1000);
        assert_eq!(count[1].load(Ordering::Relaxed), 1000);
    }

    #[test]
    fn a_panicking_half_panics_in_the_caller() {
        let split = Split::new(Threads::Two);
        let r = catch_unwind(AssertUnwindSafe(|| {
            split.both(&|h| assert!(h == 0, "second half fails"));
        }));
        assert!(r.is_err());
        // The worker still serves.
        let ran = AtomicU64::new(0);
        split.both(&|_| {
            ran.fetch_add(1, Ordering::Relaxed);
        });
        assert_eq!(ran.load(Ordering::Relaxed), 2);
    }
}
