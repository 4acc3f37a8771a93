//! Which rollers a fixed guide's contact looks at: each roller's side of the
//! guide's bounding box (grown by the roller radius, the contact's own
//! test) and a margin is kept between measurements, as the tooth contact
//! keeps its reach sets ([`crate::forces::Culling`], the same bound and
//! defaults): a roller outside the box grown by the margin, at clearance c
//! from it, cannot reach the contact's box within (c + margin) /
//! (2 v_max + 5 m/s), v_max the chain's fastest roller, nor within 1 ms.
//! Only the rollers inside (the candidates, in runs of consecutive rollers)
//! go through the contact test; the others cost nothing until their time
//! runs out. The margin keeps the rollers lying on a guide (whose centres
//! are on the contact box's edge) from being measured at every step. Every
//! candidate is taken in roller order, so the sums are those of a pass over
//! all rollers (the oracle test `guide_culling_changes_nothing`).
//!
//! Not for a carried shoe (its box turns with its arm): that scans every
//! roller.

use crate::forces::Culling;

/// The kept sides, the candidates they give, and the measurements of the
/// last evaluation (adopted at commit).
#[derive(Clone, Debug)]
pub(super) struct Near {
    /// Time before which roller i's side is kept.
    until_s: Vec<f64>,
    /// Whether roller i is inside the grown box (as last measured).
    inside: Vec<bool>,
    /// The earliest of `until_s`: before it no roller is measured.
    earliest_s: f64,
    /// Rollers measured by the last evaluation, with their new side and time.
    remeasured: Vec<u32>,
    pending_until_s: Vec<f64>,
    pending_inside: Vec<bool>,
    pending_earliest_s: f64,
    /// The runs of consecutive rollers inside, [start, end), ascending:
    /// those of the last evaluation, and of the committed sides.
    candidates: Vec<[usize; 2]>,
    committed: Vec<[usize; 2]>,
}

/// The margin added to the contact's box, in roller radii.
const MARGIN_RADII: f64 = 4.0;

impl Near {
    pub(super) fn new(rollers: usize) -> Self {
        Self {
            until_s: vec![f64::NEG_INFINITY; rollers],
            inside: vec![false; rollers],
            earliest_s: f64::NEG_INFINITY,
            remeasured: Vec::with_capacity(rollers),
            pending_until_s: vec![f64::NEG_INFINITY; rollers],
            pending_inside: vec![false; rollers],
            pending_earliest_s: f64::NEG_INFINITY,
            // At most one run per two rollers: no allocation in a run.
            candidates: Vec::with_capacity(rollers / 2 + 1),
            committed: Vec::with_capacity(rollers / 2 + 1),
        }
    }

    /// Forgets every kept side: the next evaluation measures every roller.
    pub(super) fn expire(&mut self) {
        self.until_s.fill(f64::NEG_INFINITY);
        self.earliest_s = f64::NEG_INFINITY;
        self.remeasured.clear();
    }

    /// Adopts the last evaluation's measurements.
    pub(super) fn commit(&mut self) {
        for &i in &self.remeasured {
            let i = i as usize;
            self.until_s[i] = self.pending_until_s[i];
            self.inside[i] = self.pending_inside[i];
        }
        self.remeasured.clear();
        self.earliest_s = self.pending_earliest_s;
        self.committed.clone_from(&self.candidates);
    }

    /// The candidates' runs at time `t_s` for rollers at `xs`, `ys`; `bounds`
    /// = [min x, min y, max x, max y] is the contact's box (already grown by
    /// the roller radius `radius_m`), `v_max` the fastest roller's speed.
    /// Each roller measured outside has its `pending` onset cleared (−1, no
    /// contact), as the full pass would clear it.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn candidates(
        &mut self,
        t_s: f64,
        xs: &[f64],
        ys: &[f64],
        bounds: [f64; 4],
        radius_m: f64,
        v_max: f64,
        pending: &mut [f64],
    ) -> &[[usize; 2]] {
        self.remeasured.clear();
        if t_s < self.earliest_s {
            self.pending_earliest_s = self.earliest_s;
            self.candidates.clone_from(&self.committed);
            return &self.candidates;
        }
        let c = Culling::default();
        let speed_bound = c.speed_factor * v_max + c.speed_floor_m_s;
        let margin = MARGIN_RADII * radius_m;
        let [bx0, by0, bx1, by1] = [
            bounds[0] - margin,
            bounds[1] - margin,
            bounds[2] + margin,
            bounds[3] + margin,
        ];
        let n = xs
            .len()
            .min(ys.len())
            .min(self.until_s.len())
            .min(pending.len());
        let mut earliest = f64::INFINITY;
        let mut changed = false;
        for i in 0..n {
            if t_s < self.until_s[i] {
                earliest = earliest.min(self.until_s[i]);
                continue;
            }
            let (px, py) = (xs[i], ys[i]);
            // The contact's own test on the grown box (a NaN is inside).
            let outside = px < bx0 || px > bx1 || py < by0 || py > by1;
            // Outside: the largest gap along an axis (no more than the
            // distance) and the margin to the contact's box; inside, the
            // nearest edge (when it may leave: only the work depends on it).
            let clearance = if outside {
                (bx0 - px).max(px - bx1).max(by0 - py).max(py - by1) + margin
            } else {
                (px - bx0).min(bx1 - px).min(py - by0).min(by1 - py)
            };
            let until = t_s + (clearance / speed_bound).min(c.max_skip_s);
            // A NaN position is a candidate, measured again at every evaluation.
            let until = if until.is_nan() {
                f64::NEG_INFINITY
            } else {
                until
            };
            self.pending_until_s[i] = until;
            self.pending_inside[i] = !outside;
            earliest = earliest.min(until);
            self.remeasured.push(i as u32);
            changed |= outside == self.inside[i];
            if outside {
                pending[i] = -1.0;
            }
        }
        self.pending_earliest_s = earliest;
        if !changed && self.until_s.len() == n {
            self.candidates.clone_from(&self.committed);
            return &self.candidates;
        }
        self.candidates.clear();
        let mut open: Option<usize> = None;
        for i in 0..n {
            let inside = if t_s < self.until_s[i] {
                self.inside[i]
            } else {
                self.pending_inside[i]
            };
            match (inside, open) {
                (true, None) => open = Some(i),
                (false, Some(start)) => {
                    self.candidates.push([start, i]);
                    open = None;
                }
                _ => {}
            }
        }
        if let Some(start) = open {
            self.candidates.push([start, n]);
        }
        &self.candidates
    }
}
