//! The work queue every batch of runs goes through: a list of independent
//! jobs run on a few threads, a stop flag that starts no more of them, a
//! progress callback as each one finishes, and the results handed back in
//! the jobs' order whatever order they finished in.
//!
//! A job is one run (a sweep's speed, a study's case, a convergence rung, a
//! stress cell); the closure that runs it is the caller's, and so is what a
//! running job does with the stop flag (a simulation hands it to
//! [`crate::sim::Simulation::run`], which stops within a step). The queue
//! only decides which job starts next and when to start none.
//!
//! What it does not do: split one run over threads (a run is a
//! deterministic function of its scene, see the crate docs), catch a job's
//! panic (a job that may panic catches it itself, as a study's case does),
//! or measure time.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;

/// A batch of jobs and how to run them; [`WorkQueue::run`] runs them
/// (its tests show its use).
pub(crate) struct WorkQueue<'a, J> {
    jobs: &'a [J],
    /// The order jobs are taken in (indices into `jobs`).
    order: Vec<usize>,
    threads: usize,
    stop: Option<&'a AtomicBool>,
}

impl<'a, J: Sync> WorkQueue<'a, J> {
    /// The jobs, taken in their order on one thread.
    pub(crate) fn new(jobs: &'a [J]) -> Self {
        Self {
            jobs,
            order: (0..jobs.len()).collect(),
            threads: 1,
            stop: None,
        }
    }

    /// Runs at most `threads` jobs at once (0 counts as 1; never more
    /// threads than jobs).
    pub(crate) fn threads(mut self, threads: usize) -> Self {
        self.threads = threads;
        self
    }

    /// Starts no job once `stop` is set (a running job sees the flag only if
    /// its closure looks at it).
    pub(crate) fn stop(mut self, stop: Option<&'a AtomicBool>) -> Self {
        self.stop = stop;
        self
    }

    /// Takes the jobs of the largest `cost` first (ties in the jobs' order),
    /// so that no long job starts last and leaves the other threads idle.
    /// The results still come back in the jobs' order.
    pub(crate) fn costliest_first(mut self, cost: impl Fn(&J) -> f64) -> Self {
        let jobs = self.jobs;
        self.order
            .sort_by(|&a, &b| cost(&jobs[b]).total_cmp(&cost(&jobs[a])));
        self
    }

    /// Runs every job with `work(index, job)`, which returns `None` for a job
    /// it did not finish (stopped). `progress(index, result)` is called on
    /// the calling thread as each job finishes, in the order they finish.
    /// Returns one slot per job, in the jobs' order: `None` for a job that
    /// was not started (stopped) or not finished.
    pub(crate) fn run<R: Send>(
        self,
        work: impl Fn(usize, &J) -> Option<R> + Sync,
        mut progress: impl FnMut(usize, &R),
    ) -> Vec<Option<R>> {
        let done = self.try_run(work, |k, r| {
            progress(k, r);
            Ok::<(), std::convert::Infallible>(())
        });
        match done {
            Ok(results) => results,
            Err(never) => match never {},
        }
    }

    /// [`WorkQueue::run`] with a progress callback that may fail: after its
    /// first error no job starts, the running ones finish, and the error is
    /// returned.
    ///
    /// # Errors
    ///
    /// The first error `progress` returned.
    pub(crate) fn try_run<R: Send, E>(
        self,
        work: impl Fn(usize, &J) -> Option<R> + Sync,
        mut progress: impl FnMut(usize, &R) -> Result<(), E>,
    ) -> Result<Vec<Option<R>>, E> {
        let mut results: Vec<Option<R>> = std::iter::repeat_with(|| None)
            .take(self.jobs.len())
            .collect();
        let next = AtomicUsize::new(0);
        // Set by the calling thread once `progress` failed.
        let halt = AtomicBool::new(false);
        let mut first_error = None;
        let mut finished = |k: usize, r: R| {
            if first_error.is_none()
                && let Err(e) = progress(k, &r)
            {
                first_error = Some(e);
                halt.store(true, Ordering::Relaxed);
            }
            results[k] = Some(r);
        };
        let threads = self.threads.clamp(1, self.jobs.len().max(1));
        if threads == 1 {
            // On the calling thread: nothing runs beside a job, and a flag
            // set by `progress` holds before the next job is taken.
            while let Some((k, job)) = self.take(&next, &halt) {
                if let Some(r) = work(k, job) {
                    finished(k, r);
                }
            }
        } else {
            let (tx, rx) = mpsc::channel::<(usize, R)>();
            let (queue, work, next, halt) = (&self, &work, &next, &halt);
            std::thread::scope(|scope| {
                for _ in 0..threads {
                    let tx = tx.clone();
                    scope.spawn(move || {
                        while let Some((k, job)) = queue.take(next, halt) {
                            if let Some(r) = work(k, job)
                                && tx.send((k, r)).is_err()
                            {
                                break;
                            }
                        }
                    });
                }
                drop(tx);
                for (k, r) in rx {
                    finished(k, r);
                }
            });
        }
        match first_error {
            Some(e) => Err(e),
            None => Ok(results),
        }
    }

    /// The next job to start, unless the stop flag or `halt` is set.
    fn take(&self, next: &AtomicUsize, halt: &AtomicBool) -> Option<(usize, &'a J)> {
        let stopped = self.stop.is_some_and(|f| f.load(Ordering::Relaxed));
        if stopped || halt.load(Ordering::Relaxed) {
            return None;
        }
        let k = *self.order.get(next.fetch_add(1, Ordering::Relaxed))?;
        Some((k, self.jobs.get(k)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;
    use std::time::Duration;

    /// A job that sleeps its milliseconds and returns 10 k (k its index).
    fn sleepy() -> impl Fn(usize, &u64) -> Option<usize> + Sync {
        |k, &ms| {
            std::thread::sleep(Duration::from_millis(ms));
            Some(10 * k)
        }
    }

    #[test]
    fn results_come_back_in_job_order_whatever_order_they_finish_in() {
        // Three threads, the first job the slowest: it finishes last.
        let ms = [60, 1, 1, 1, 1, 1];
        let mut finished = Vec::new();
        let results = WorkQueue::new(&ms)
            .threads(3)
            .run(sleepy(), |k, _| finished.push(k));
        assert_eq!(results, (0..6).map(|k| Some(10 * k)).collect::<Vec<_>>());
        assert_eq!(finished.len(), 6);
        assert_eq!(finished.last(), Some(&0), "finish order {finished:?}");
    }

    #[test]
    fn the_costliest_job_is_taken_first_and_its_result_stays_in_place() {
        let costs = [1.0, 5.0, 3.0, 5.0];
        let mut taken = Vec::new();
        let results = WorkQueue::new(&costs)
            .costliest_first(|&c| c)
            .run(|k, _| Some(k), |k, _| taken.push(k));
        // One thread: the order taken is the order finished; ties keep job order.
        assert_eq!(taken, [1, 3, 2, 0]);
        assert_eq!(results, [Some(0), Some(1), Some(2), Some(3)]);
    }

    #[test]
    fn the_stop_flag_starts_no_more_jobs() {
        let stop = AtomicBool::new(false);
        let started = AtomicUsize::new(0);
        let jobs = [(); 10];
        let results = WorkQueue::new(&jobs).stop(Some(&stop)).run(
            |k, _| {
                started.fetch_add(1, Ordering::Relaxed);
                Some(k)
            },
            |k, _| {
                if k == 2 {
                    stop.store(true, Ordering::Relaxed);
                }
            },
        );
        // One thread: jobs 0, 1, 2 ran; the flag was set before job 3 was taken.
        assert_eq!(started.load(Ordering::Relaxed), 3);
        assert_eq!(&results[..3], [Some(0), Some(1), Some(2)]);
        assert!(results[3..].iter().all(Option::is_none), "{results:?}");
    }

    #[test]
    fn on_several_threads_the_stop_flag_set_by_a_job_starts_no_more() {
        // Job 0 sets the flag at once; the others take 5 ms each, so at most
        // the job already taken by the other thread runs beside it.
        let stop = AtomicBool::new(false);
        let started = AtomicUsize::new(0);
        let jobs: Vec<usize> = (0..20).collect();
        let results = WorkQueue::new(&jobs).threads(2).stop(Some(&stop)).run(
            |k, _| {
                started.fetch_add(1, Ordering::Relaxed);
                if k == 0 {
                    stop.store(true, Ordering::Relaxed);
                } else {
                    std::thread::sleep(Duration::from_millis(5));
                }
                Some(k)
            },
            |_, _| {},
        );
        let started = started.load(Ordering::Relaxed);
        assert!(started < jobs.len(), "{started} jobs started");
        assert_eq!(results.iter().flatten().count(), started);
        assert_eq!(results[0], Some(0));
    }

    #[test]
    fn a_stop_flag_set_before_the_start_runs_nothing() {
        let stop = AtomicBool::new(true);
        let jobs = [1, 2, 3];
        let results = WorkQueue::new(&jobs)
            .threads(2)
            .stop(Some(&stop))
            .run(|_, &x| Some(x), |_, _| panic!("no job finished"));
        assert_eq!(results, [None, None, None]);
    }

    #[test]
    fn progress_is_called_once_per_finished_job_and_never_for_an_unfinished_one() {
        // Odd jobs are "stopped" mid-run: no result, no progress call.
        let jobs: Vec<usize> = (0..9).collect();
        let calls = Mutex::new(Vec::new());
        let results = WorkQueue::new(&jobs).threads(2).run(
            |_, &x| (x % 2 == 0).then_some(x),
            |k, &r| calls.lock().expect("not poisoned").push((k, r)),
        );
        let mut calls = calls.into_inner().expect("not poisoned");
        calls.sort_unstable();
        assert_eq!(calls, [(0, 0), (2, 2), (4, 4), (6, 6), (8, 8)]);
        let finished = results.iter().flatten().count();
        assert_eq!(finished, 5);
        assert_eq!(results[1], None);
    }

    #[test]
    fn a_failing_progress_callback_starts_no_more_jobs_and_returns_its_error() {
        let started = AtomicUsize::new(0);
        let jobs = [(); 6];
        let outcome = WorkQueue::new(&jobs).try_run(
            |k, _| {
                started.fetch_add(1, Ordering::Relaxed);
                Some(k)
            },
            |k, _| {
                if k == 1 {
                    Err(format!("job {k}"))
                } else {
                    Ok(())
                }
            },
        );
        assert_eq!(outcome, Err("job 1".to_owned()));
        assert_eq!(started.load(Ordering::Relaxed), 2);
    }

    #[test]
    fn no_jobs_and_more_threads_than_jobs_are_fine() {
        let none: [u8; 0] = [];
        assert!(
            WorkQueue::new(&none)
                .threads(4)
                .run(|_, &x| Some(x), |_, _| {})
                .is_empty()
        );
        let one = [7];
        let r = WorkQueue::new(&one)
            .threads(8)
            .run(|_, &x| Some(x), |_, _| {});
        assert_eq!(r, [Some(7)]);
    }

    #[test]
    fn results_come_in_the_jobs_order() {
        let squares = WorkQueue::new(&[1, 2, 3])
            .threads(2)
            .run(|_, &x| Some(x * x), |_, _| {});
        assert_eq!(squares, [Some(1), Some(4), Some(9)]);
    }
}
