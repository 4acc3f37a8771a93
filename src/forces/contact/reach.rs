//! The reach pass of the roller–tooth contact: each roller's set of
//! sprockets within reach, kept between measurements ([`Culling`]), and the
//! [`Run`]s of consecutive rollers with one set.

use super::super::buffer::Buffer;
use crate::model::{DriveModel, DriveState};
use crate::scene::MAX_SPROCKETS;

/// Reach caching ("culling"): a roller's set of sprockets within reach is
/// measured, then kept for
/// τ = min(c / (speed_factor · v_max + speed_floor), max_skip_s),
/// c the distance from the roller's centre to the nearest reach circle's
/// edge, v_max the chain's fastest roller at that moment. Within τ a roller
/// could only cross that edge by more than doubling its speed plus the floor
/// (5 m/s) within ≤ 5 ms — a speed gain of v_max + 5 m/s held for at most
/// 5 ms, an acceleration beyond 1000 m/s² all along, which only a blow-up
/// gives a roller that far from a sprocket (a roller near one has a short
/// τ: c is small). The longest skip sets how often a roller in a free
/// strand is measured again: every 100 steps at dt = 50 µs, every 500 at
/// 10 µs. A roller within no reach circle costs nothing more until then; one within
/// reach goes straight to its sprockets' contact loops. The oracle test
/// `culling_changes_nothing` checks the bitwise equality of runs with and
/// without it (without: every roller measured against every sprocket at
/// every evaluation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Culling {
    /// Factor on the fastest roller speed.
    pub speed_factor: f64,
    /// Speed added to the bound, m/s (covers rollers starting from rest).
    pub speed_floor_m_s: f64,
    /// Longest skip, s.
    pub max_skip_s: f64,
}

impl Default for Culling {
    fn default() -> Self {
        Self {
            speed_factor: 2.0,
            speed_floor_m_s: 5.0,
            max_skip_s: 5e-3,
        }
    }
}

/// Consecutive rollers within reach of one sprocket.
#[derive(Clone, Copy, Debug)]
pub(super) struct Run {
    pub(super) sprocket: usize,
    pub(super) start: usize,
    pub(super) end: usize,
    /// Its rollers are within reach of other sprockets too.
    pub(super) shared: bool,
}

/// The stretches of rollers within reach of several sprockets, each once:
/// a stretch's runs (one per sprocket) follow each other and share its range.
pub(super) fn shared_stretches(runs: &[Run]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    runs.iter()
        .enumerate()
        .filter(|&(k, run)| run.shared && (k == 0 || runs[k - 1].start != run.start))
        .map(|(_, run)| run.start..run.end)
}

/// Each roller's set of sprockets within reach, with the runs they form.
#[derive(Clone, Debug)]
pub(super) struct Reach {
    /// Time before which roller i's set of sprockets within reach is kept (see [`Culling`]).
    until_s: Vec<f64>,
    /// That set, bit j for sprocket j. It is also the set in effect at the
    /// last committed evaluation, so the contact memory of roller i is
    /// current only where it is not empty.
    pub(super) mask: Vec<u64>,
    /// Rollers whose set the last evaluation measured again, with the new
    /// set and time in `pending_*` (adopted on commit).
    remeasured: Buffer<u32>,
    /// See `remeasured`.
    pending_until_s: Vec<f64>,
    /// See `remeasured`.
    pending_mask: Vec<u64>,
    /// The earliest of `until_s`: before it no kept set expires, and the
    /// pass skips the rollers' loop.
    earliest_s: f64,
    /// The earliest time in effect after the last pass (adopted on commit).
    pending_earliest_s: f64,
    /// The earliest of `until_s` in each block of [`BLOCK`] rollers: a pass
    /// skips a block whose time has not come without looking at its rollers.
    block_until_s: Vec<f64>,
    /// See `block_until_s`: the last pass's (adopted on commit).
    pending_block_until_s: Vec<f64>,
    /// Whether the last pass looked at the blocks (else it reused the
    /// committed sets, and a commit keeps `block_until_s`).
    scanned: bool,
    /// The last evaluation's stretches of rollers within reach.
    pub(super) runs: Buffer<Run>,
    /// The runs of the committed sets (`mask`).
    committed_runs: Buffer<Run>,
}

impl Reach {
    pub(super) fn new(rollers: usize, sprockets: usize) -> Self {
        Self {
            until_s: vec![f64::NEG_INFINITY; rollers],
            mask: vec![0; rollers],
            remeasured: Buffer::with_capacity(rollers),
            pending_until_s: vec![f64::NEG_INFINITY; rollers],
            pending_mask: vec![0; rollers],
            earliest_s: f64::NEG_INFINITY,
            pending_earliest_s: f64::NEG_INFINITY,
            block_until_s: vec![f64::NEG_INFINITY; rollers.div_ceil(BLOCK)],
            pending_block_until_s: vec![f64::NEG_INFINITY; rollers.div_ceil(BLOCK)],
            scanned: false,
            // Room for a run per roller and sprocket pair in reach twice over:
            // the step loop does not allocate.
            runs: Buffer::with_capacity(2 * rollers + sprockets),
            committed_runs: Buffer::with_capacity(2 * rollers + sprockets),
        }
    }

    /// Forgets every kept set and the committed runs.
    pub(super) fn reset(&mut self) {
        self.until_s.fill(f64::NEG_INFINITY);
        self.earliest_s = f64::NEG_INFINITY;
        self.block_until_s.fill(f64::NEG_INFINITY);
        self.scanned = false;
        self.mask.fill(0);
        self.remeasured.clear();
        self.committed_runs.clear();
    }

    /// Each roller's kept set and the time it expires (for a checkpoint).
    pub(super) fn kept(&self) -> (&[u64], &[f64]) {
        (&self.mask, &self.until_s)
    }

    /// Takes back the kept sets and their expiry at a committed evaluation
    /// ([`Self::kept`]). The runs, a function of the sets alone, are rebuilt:
    /// after a commit the last evaluation's runs are the committed ones, and
    /// those are the sets' runs (every pass builds them from the sets in
    /// effect, which the commit makes the kept ones).
    pub(super) fn restore(&mut self, mask: &[u64], until_s: &[f64]) {
        self.mask.copy_from_slice(mask);
        self.until_s.copy_from_slice(until_s);
        self.earliest_s = self
            .until_s
            .iter()
            .fold(f64::INFINITY, |m, &t| earlier(m, t));
        for (b, block) in self.until_s.chunks(BLOCK).enumerate() {
            self.block_until_s[b] = block.iter().fold(f64::INFINITY, |m, &t| earlier(m, t));
        }
        self.scanned = false;
        self.remeasured.clear();
        self.runs.clear();
        let n = self.mask.len();
        let mut stretch = Stretch::default();
        for (i, &m) in self.mask.iter().enumerate() {
            if m != stretch.mask {
                stretch.close(i, &mut self.runs);
                stretch = Stretch { mask: m, start: i };
            }
        }
        stretch.close(n, &mut self.runs);
        self.committed_runs.clone_from(&self.runs);
    }

    /// Expires every kept set: the next pass measures every roller again.
    pub(super) fn expire(&mut self) {
        self.until_s.fill(f64::NEG_INFINITY);
        self.earliest_s = f64::NEG_INFINITY;
        self.block_until_s.fill(f64::NEG_INFINITY);
        self.scanned = false;
    }

    /// Adopts the last pass's measurements.
    pub(super) fn commit(&mut self) {
        for &i in self.remeasured.iter() {
            let i = i as usize;
            self.until_s[i] = self.pending_until_s[i];
            self.mask[i] = self.pending_mask[i];
        }
        self.earliest_s = self.pending_earliest_s;
        if self.scanned {
            self.block_until_s
                .copy_from_slice(&self.pending_block_until_s);
        }
        self.remeasured.clear();
        self.committed_runs.clone_from(&self.runs);
    }

    /// Measures the rollers whose kept set has expired and gathers the runs.
    /// `cull` is (speed bound, longest skip) with culling on; `None`
    /// measures every roller.
    pub(super) fn measure(&mut self, model: &DriveModel, s: &DriveState, cull: Option<(f64, f64)>) {
        self.remeasured.clear();
        // No kept set has expired (two evaluations in three): the runs are
        // the committed ones.
        if s.t_s < self.earliest_s {
            self.scanned = false;
            self.pending_earliest_s = self.earliest_s;
            self.runs.clone_from(&self.committed_runs);
            return;
        }
        // Slices of one length: the compiler drops the bounds checks on `[i]`.
        let n = s.x.len();
        let (xs, ys) = (&s.x[..n], &s.y[..n]);
        let (until, kept) = (&self.until_s[..n], &self.mask[..n]);
        let pending_until = &mut self.pending_until_s[..n];
        let pending_mask = &mut self.pending_mask[..n];
        // Measure the rollers whose kept set has expired (a few per step),
        // four at a time: a chunk whose four sets are all kept (the common
        // case) costs four comparisons, in packed form.
        let t = s.t_s;
        let mut changed = false;
        let mut earliest = f64::INFINITY;
        let mut measure = |i: usize, earliest: &mut f64| {
            if t < until[i] {
                *earliest = earlier(*earliest, until[i]);
                return;
            }
            let mut mask = 0u64;
            let mut clearance = f64::INFINITY;
            // One bit per sprocket: a scene holds at most MAX_SPROCKETS (64).
            for (j, sp) in model.sprockets.iter().enumerate().take(MAX_SPROCKETS) {
                let rx = xs[i] - sp.center_m[0];
                let ry = ys[i] - sp.center_m[1];
                let d_sq = rx * rx + ry * ry;
                if d_sq <= sp.reach_sq_m2 {
                    mask |= 1 << j;
                }
                if cull.is_some() {
                    clearance = clearance.min((d_sq.sqrt() - sp.reach_m).abs());
                }
            }
            pending_mask[i] = mask;
            pending_until[i] = match cull {
                Some((speed_bound, max_skip)) => t + (clearance / speed_bound).min(max_skip),
                None => f64::NEG_INFINITY,
            };
            *earliest = earlier(*earliest, pending_until[i]);
            self.remeasured.push(i as u32);
            changed |= mask != kept[i];
        };
        // Block by block: a block whose earliest time has not come keeps
        // every set (most of a long chain's free strands), else its rollers
        // four at a time, as above.
        let block_until = &self.block_until_s[..];
        let pending_block = &mut self.pending_block_until_s[..];
        pending_block.copy_from_slice(block_until);
        for (b, (&kept_until, pending)) in
            block_until.iter().zip(pending_block.iter_mut()).enumerate()
        {
            if t < kept_until {
                earliest = earliest.min(kept_until);
                continue;
            }
            let (lo, hi) = (b * BLOCK, ((b + 1) * BLOCK).min(n));
            let mut block_earliest = f64::INFINITY;
            let chunks = until[lo..hi].chunks_exact(4);
            let tail = hi - chunks.remainder().len();
            for (c, u) in chunks.enumerate() {
                let kept_all = (t < u[0]) & (t < u[1]) & (t < u[2]) & (t < u[3]);
                if kept_all {
                    // All four are after t, none NaN: plain comparisons.
                    let first = |a: f64, b: f64| if b < a { b } else { a };
                    block_earliest =
                        first(block_earliest, first(first(u[0], u[1]), first(u[2], u[3])));
                } else {
                    for i in lo + 4 * c..lo + 4 * c + 4 {
                        measure(i, &mut block_earliest);
                    }
                }
            }
            for i in tail..hi {
                measure(i, &mut block_earliest);
            }
            *pending = block_earliest;
            earliest = earlier(earliest, block_earliest);
        }
        self.scanned = true;
        self.pending_earliest_s = earliest;
        // Runs are a function of the sets alone: with no set changed they
        // are the committed ones.
        if !changed {
            self.runs.clone_from(&self.committed_runs);
            return;
        }
        self.runs.clear();
        let mut stretch = Stretch::default();
        for i in 0..n {
            let mask = if s.t_s < until[i] {
                kept[i]
            } else {
                pending_mask[i]
            };
            if mask != stretch.mask {
                stretch.close(i, &mut self.runs);
                stretch = Stretch { mask, start: i };
            }
        }
        stretch.close(n, &mut self.runs);
    }
}

/// Rollers per block of the reach pass's skip ([`Reach`]'s `block_until_s`).
const BLOCK: usize = 64;

/// The earlier of a running earliest time and `t`; a NaN `t` (a roller
/// measured at a non-finite position) makes it −∞, so that every roller is
/// measured again at the next pass, as that roller would be.
#[inline(always)]
fn earlier(earliest: f64, t: f64) -> f64 {
    if t >= earliest {
        earliest
    } else if t.is_nan() {
        f64::NEG_INFINITY
    } else {
        t
    }
}

/// Consecutive rollers with one set of sprockets within reach, while the reach pass grows it.
#[derive(Default)]
struct Stretch {
    mask: u64,
    start: usize,
}

impl Stretch {
    /// Ends the stretch before roller `end`: one run per sprocket of its set.
    fn close(&self, end: usize, runs: &mut Buffer<Run>) {
        if self.mask == 0 || end == self.start {
            return;
        }
        let several = !self.mask.is_power_of_two();
        let mut mask = self.mask;
        while mask != 0 {
            runs.push(Run {
                sprocket: mask.trailing_zeros() as usize,
                start: self.start,
                end,
                shared: several,
            });
            mask &= mask - 1;
        }
    }
}
