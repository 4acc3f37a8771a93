//! Two threads per step for large drives: a persistent worker and the
//! roller split.
//!
//! A drive of many rollers spends its step in loops over the rollers (the
//! links, the rollers' update) whose iterations are independent. With
//! [`Split`] on, each such loop is cut into `CHUNKS` chunks of rollers,
//! which the stepping thread and a worker thread claim one at a time: one
//! fork and one join per loop, no allocation. Claiming (rather than a fixed
//! half each) keeps a thread the system stops for a while from holding up
//! the other: it finishes the chunks left.
//!
//! **Same bits.** Each roller's force is summed in the same order as on one
//! thread: the link before a chunk's first roller belongs to the chunk
//! before, and the chunk evaluates it again, locally, with the same
//! operations (IEEE square root and division, no fused multiply-add), so it
//! gets the same bits without waiting. The largest stretch and speed are
//! maxima, which do not depend on the order. Test:
//! `threads_1_and_2_agree_to_the_bit`.
//!
//! **The worker** is spawned at the first split step and lives as long as
//! its drive's [`crate::forces::ForceGenerator`]. Between jobs it spins
//! briefly (a step's next loop follows within microseconds), then parks (a
//! co-simulated drive waits a whole frame for the world's step). The caller
//! waits for the worker's last chunk the same way, spinning, then yielding
//! its core. Spawning a thread per step would cost more than the step.
//!
//! When the worker is busy with another caller (a generator shared between
//! threads) or cannot be spawned, every chunk runs on the caller: the
//! results never depend on the thread count.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::{self, JoinHandle, Thread};

use crate::forces::{CHUNKS, Fork};
use crate::scene::Threads;

/// Spins before the worker parks between jobs (≈ 20–50 µs).
const WORKER_SPINS: u32 = 20_000;

/// Spins before the caller starts yielding while it waits for the worker.
const CALLER_SPINS: u32 = 20_000;

/// A chunk's job: called with the chunk's index.
type Job = dyn Fn(usize) + Sync;

/// The posted job's address (only dereferenced under [`Shared`]'s protocol).
#[derive(Clone, Copy)]
struct JobPtr(*const Job);

// SAFETY: see `Shared`: the job is `Sync` and outlives every call made
// through this pointer.
unsafe impl Send for JobPtr {}

/// What the caller and the worker share.
struct Shared {
    /// Jobs posted so far.
    posted: AtomicU64,
    /// The posted job's ticket (bits 16 up), the end of its unclaimed
    /// chunks (bits 8–15) and their start (bits 0–7): a chunk is claimed by
    /// raising the start or lowering the end, for the ticket read.
    claim: AtomicU64,
    /// Chunks of the current job done.
    done: AtomicUsize,
    /// A chunk that panicked on the worker (the caller runs it again, to
    /// panic itself), or `usize::MAX`.
    panicked: AtomicUsize,
    /// The worker is parked or about to park.
    sleeping: AtomicBool,
    /// Stop and return (the generator is dropped).
    stop: AtomicBool,
    /// A caller holds the worker.
    busy: AtomicBool,
    /// The posted job.
    job: Mutex<Option<JobPtr>>,
}

// Protocol: the caller holding `busy` stores the job, then the claim word
// of the new ticket, then raises `posted`. A chunk is run only by the thread
// whose compare-exchange on `claim` for that ticket succeeded, and the caller
// returns only when `done` counts every chunk: so no chunk runs twice, and
// the job outlives every call. A worker late for a ticket finds its chunks
// claimed (the ticket in `claim` has moved on) and runs nothing.

impl Shared {
    /// Claims the next chunk of ticket `t`, if one is left: the caller
    /// (`front`) takes them from the first up, the worker from the last
    /// down, so each thread tends to get the same chunks step after step
    /// (its rollers still in its core's cache) while either still takes
    /// what the other has not reached.
    fn claim(&self, t: u64, front: bool) -> Option<usize> {
        let mut c = self.claim.load(Ordering::Acquire);
        loop {
            let (lo, hi) = ((c & 0xff) as usize, ((c >> 8) & 0xff) as usize);
            if c >> 16 != t || lo >= hi {
                return None;
            }
            let (k, next) = if front {
                (lo, c + 1)
            } else {
                (hi - 1, c - (1 << 8))
            };
            match self
                .claim
                .compare_exchange_weak(c, next, Ordering::AcqRel, Ordering::Acquire)
            {
                Ok(_) => return Some(k),
                Err(now) => c = now,
            }
        }
    }

    fn job(&self) -> Option<JobPtr> {
        *self
            .job
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

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
            claim: AtomicU64::new(0),
            done: AtomicUsize::new(0),
            panicked: AtomicUsize::new(usize::MAX),
            sleeping: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            busy: AtomicBool::new(false),
            job: Mutex::new(None),
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

    /// Runs `job(k)` for every chunk, here and on the worker; returns when
    /// all are done. `false` (nothing run) when another caller holds the
    /// worker.
    fn run<'a>(&self, job: &'a (dyn Fn(usize) + Sync + 'a)) -> bool {
        let s = &*self.shared;
        if s.busy
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
        {
            return false;
        }
        // SAFETY: the lifetime is erased only while this call waits for
        // every chunk to be done (see `Shared`).
        let ptr: *const Job =
            unsafe { std::mem::transmute::<&'a (dyn Fn(usize) + Sync + 'a), &'static Job>(job) };
        *s.job
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(JobPtr(ptr));
        let ticket = s.posted.load(Ordering::Relaxed) + 1;
        s.done.store(0, Ordering::Relaxed);
        s.claim
            .store((ticket << 16) | ((CHUNKS as u64) << 8), Ordering::SeqCst);
        s.posted.store(ticket, Ordering::SeqCst);
        if s.sleeping.load(Ordering::SeqCst) {
            self.thread.unpark();
        }
        while let Some(k) = s.claim(ticket, true) {
            job(k);
            s.done.fetch_add(1, Ordering::AcqRel);
        }
        let mut spins = 0u32;
        while s.done.load(Ordering::Acquire) != CHUNKS {
            if spins < CALLER_SPINS {
                spins += 1;
                std::hint::spin_loop();
            } else {
                thread::yield_now();
            }
        }
        let panicked = s.panicked.swap(usize::MAX, Ordering::AcqRel);
        s.busy.store(false, Ordering::Release);
        if panicked != usize::MAX {
            // The worker's chunk panicked: run it here, to panic here.
            job(panicked);
        }
        true
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.thread.unpark();
        if let Some(h) = self.handle.take() {
            // A worker's panics are caught and handed to the caller.
            let _ = h.join();
        }
    }
}

/// The worker's loop: wait for a job, spinning then parking; claim and run
/// its chunks until none is left.
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
        let Some(JobPtr(job)) = s.job() else { continue };
        while let Some(k) = s.claim(ticket, false) {
            // SAFETY: a chunk of `ticket` was claimed, so its caller is
            // still waiting and `job` (the one posted before `ticket`, see
            // `Shared`) is alive.
            let job = unsafe { &*job };
            if catch_unwind(AssertUnwindSafe(|| job(k))).is_err() {
                s.panicked.store(k, Ordering::Release);
            }
            s.done.fetch_add(1, Ordering::AcqRel);
        }
    }
}

/// Whether and how a drive's roller loops are split over two threads, with
/// the worker that shares the chunks (spawned at first use).
pub(crate) struct Split {
    /// Rollers from which the loops are split (`usize::MAX`: never).
    min_rollers: usize,
    worker: OnceLock<Option<Worker>>,
}

impl Split {
    /// The split for `setting` (one thread, two, or two from
    /// [`AUTO_MIN_ROLLERS`] rollers on a machine with two cores or more).
    pub(crate) fn new(setting: Threads) -> Self {
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

    /// Whether a drive of `rollers` rollers is split (at least two rollers
    /// per chunk, whatever the setting).
    #[inline]
    pub(crate) fn splits(&self, rollers: usize) -> bool {
        rollers >= self.min_rollers.max(2 * CHUNKS)
    }

    /// Runs `job(k)` for every chunk, on two threads where the worker is
    /// available, else one after the other here. Each chunk must write only
    /// its own data: the results are the same either way.
    pub(crate) fn both(&self, job: &(dyn Fn(usize) + Sync)) {
        let worker = self.worker.get_or_init(Worker::spawn);
        if let Some(w) = worker
            && w.run(job)
        {
            return;
        }
        for k in 0..CHUNKS {
            job(k);
        }
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

pub(crate) use crate::scene::AUTO_MIN_ROLLERS;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_chunk_runs_once_and_the_worker_is_reused() {
        // 1000 jobs on one worker: every chunk runs once per call.
        let split = Split::new(Threads::Two);
        let count: Vec<AtomicU64> = (0..CHUNKS).map(|_| AtomicU64::new(0)).collect();
        for _ in 0..1000 {
            split.both(&|k| {
                count[k].fetch_add(1, Ordering::Relaxed);
            });
        }
        assert!(count.iter().all(|c| c.load(Ordering::Relaxed) == 1000));
    }

    #[test]
    fn a_panicking_chunk_panics_in_the_caller() {
        let split = Split::new(Threads::Two);
        let r = catch_unwind(AssertUnwindSafe(|| {
            split.both(&|k| assert!(k != 5, "chunk 5 fails"));
        }));
        assert!(r.is_err());
        // The worker still serves.
        let ran = AtomicU64::new(0);
        split.both(&|_| {
            ran.fetch_add(1, Ordering::Relaxed);
        });
        assert_eq!(ran.load(Ordering::Relaxed), CHUNKS as u64);
    }
}
