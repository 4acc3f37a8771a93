//! The seam through which a drive's roller loops run on two threads: a
//! [`Fork`] (the simulation's persistent worker, `sim::parallel`) and
//! [`Halves`], the view through which the two halves write disjoint parts of
//! one output.

/// Runs a job's two halves, on two threads or one after the other: the
/// halves write disjoint data, so the results do not depend on which.
pub(crate) trait Fork: Send + Sync + std::fmt::Debug {
    /// Whether a drive of `rollers` rollers is split.
    fn splits(&self, rollers: usize) -> bool;

    /// Runs `job(k)` once for every chunk `k` in `0..CHUNKS`, on whichever
    /// thread claims it, and returns when all are done.
    fn both(&self, job: &(dyn Fn(usize) + Sync));

    /// A copy with the same setting (and a worker of its own).
    fn clone_box(&self) -> Box<dyn Fork>;
}

/// Chunks a split loop's rollers are cut into; the two threads claim them
/// one at a time, so a thread the system stops for a while holds up one
/// chunk, not half the loop.
pub(crate) const CHUNKS: usize = 8;

/// Rollers `lo..hi` of chunk `k` of `n` (`n ≥ CHUNKS`: no chunk is empty).
#[inline]
pub(crate) fn chunk(n: usize, k: usize) -> (usize, usize) {
    (k * n / CHUNKS, (k + 1) * n / CHUNKS)
}

/// A raw view of a mutable slice that two halves of a job write in disjoint
/// ranges (one chunk each). Made from a `&mut [f64]` borrowed for the whole [`Fork::both`].
#[derive(Clone, Copy)]
pub(crate) struct Halves {
    ptr: *mut f64,
    len: usize,
}

// SAFETY: each half takes only its own range ([`Halves::range`] with
// disjoint bounds), so no element is reached from two threads.
unsafe impl Send for Halves {}
// SAFETY: as above.
unsafe impl Sync for Halves {}

impl Halves {
    pub(crate) fn new(s: &mut [f64]) -> Self {
        Self {
            ptr: s.as_mut_ptr(),
            len: s.len(),
        }
    }

    /// The elements `lo..hi` (clamped to the slice).
    ///
    /// # Safety
    /// The slice's borrow must outlive the use, and the two halves of a job
    /// must take disjoint ranges.
    pub(crate) unsafe fn range<'a>(self, lo: usize, hi: usize) -> &'a mut [f64] {
        let hi = hi.min(self.len);
        let lo = lo.min(hi);
        // SAFETY: in bounds (clamped); disjointness is the caller's promise.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(lo), hi - lo) }
    }
}
