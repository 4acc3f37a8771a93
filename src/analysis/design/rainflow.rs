//! Rainflow counting of one load history, streamed: the turning points
//! ([`Reversals`]) and the cycles they close ([`Rainflow`]), as ASTM E1049-85
//! (reapproved 2017), "Standard Practices for Cycle Counting in Fatigue
//! Analysis", section 5.4.4 describes them (docs/design-checks.md,
//! "Fatigue").
//!
//! **Turning points.** A history's peaks and valleys, found as the values
//! arrive: the largest value since the last valley is a peak once the
//! history has fallen more than a gate below it (and the other way round).
//! With a gate of zero every change of direction is a turning point
//! (section 5.4.1); a gate drops reversal pairs smaller than itself, which
//! rainflow counting would have counted as cycles of those ranges and
//! nothing else: the larger cycles stay exactly as they were. The first
//! value is the history's first turning point; [`Reversals::last`] gives the
//! one still open at the end.
//!
//! **Cycles**, by the standard's rule for a history read from its start S:
//! with X the range of the last two turning points and Y the range before
//! it, while X ≥ Y: Y is one cycle (its two points are discarded) unless it
//! holds S, in which case Y is half a cycle and its first point is
//! discarded (S moves on). At the end each range left (the residue) is half
//! a cycle ([`Rainflow::finish`]). S is always the bottom of the stack of
//! turning points kept, which is all the memory a history needs; its ranges
//! shrink from the bottom up (a range that did not is counted at once).
//!
//! **Bounded memory.** The stack holds at most [`Rainflow::capacity`]
//! points. A history whose shrinking ranges would hold more (a long ring-down
//! between larger swings) has its oldest range counted as half a cycle and
//! its first point dropped, as the standard does with the range that holds
//! S; [`Rainflow::overflows`] counts how often, so that a report can say so.
//!
//! It knows nothing of forces, chains or damage: each cycle goes to a
//! caller's function with its range, mean, count (1 or ½) and the tags of
//! its two points (a caller's number, such as where a link was).

use serde::{Deserialize, Serialize};

/// Points a [`Rainflow`] stack holds unless told otherwise.
pub const DEFAULT_CAPACITY: usize = 64;

/// A turning point: its value and the caller's tag.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Turn {
    /// The value.
    pub value: f64,
    /// The caller's tag (e.g. where the value was reached).
    pub tag: u32,
}

/// One counted cycle or half cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cycle {
    /// Range |b − a|.
    pub range: f64,
    /// Mean (a + b) / 2.
    pub mean: f64,
    /// 1 for a cycle, ½ for a half cycle.
    pub count: f64,
    /// The point with the larger value.
    pub high: Turn,
    /// The point with the smaller value.
    pub low: Turn,
}

impl Cycle {
    fn of(a: Turn, b: Turn, count: f64) -> Self {
        let (high, low) = if a.value >= b.value { (a, b) } else { (b, a) };
        Self {
            range: high.value - low.value,
            mean: 0.5 * (high.value + low.value),
            count,
            high,
            low,
        }
    }
}

/// The turning points of a history, as its values arrive ([module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reversals {
    gate: f64,
    /// Which way the history goes: +1 rising (the candidate is the largest
    /// value since the last valley), −1 falling (the smallest since the
    /// last peak), 0 not yet known (no value, or none further than the gate
    /// from the first); one sign so that the common case is one test.
    going: f64,
    /// Whether a value came.
    started: bool,
    /// The extreme since the last turning point (the first value while
    /// the way is not known).
    candidate: Turn,
}

impl Reversals {
    /// Turning points at least `gate` apart (0: every change of direction).
    pub fn new(gate: f64) -> Self {
        Self {
            gate: gate.max(0.0),
            going: 0.0,
            started: false,
            candidate: Turn { value: 0.0, tag: 0 },
        }
    }

    /// Takes the next value (with its tag); returns the turning point it
    /// confirms, if any. The first value is confirmed as the history's
    /// first turning point once the history has left it by more than the gate.
    #[inline]
    pub fn push(&mut self, value: f64, tag: u32) -> Option<Turn> {
        // How far the value goes on the way the history goes.
        let further = (value - self.candidate.value) * self.going;
        if self.going != 0.0 {
            if further >= 0.0 {
                self.candidate = Turn { value, tag };
                None
            } else if -further > self.gate {
                self.going = -self.going;
                Some(std::mem::replace(&mut self.candidate, Turn { value, tag }))
            } else {
                None
            }
        } else {
            self.push_first(value, tag)
        }
    }

    /// [`Reversals::push`] while the way is not known.
    #[cold]
    fn push_first(&mut self, value: f64, tag: u32) -> Option<Turn> {
        if !self.started {
            self.started = true;
            self.candidate = Turn { value, tag };
            return None;
        }
        let c = self.candidate.value;
        if (value - c).abs() > self.gate {
            self.going = if value > c { 1.0 } else { -1.0 };
            Some(std::mem::replace(&mut self.candidate, Turn { value, tag }))
        } else {
            None
        }
    }

    /// The turning point still open: the extreme since the last confirmed
    /// one (the history's end point of a rainflow count), `None` before
    /// any value.
    pub fn last(&self) -> Option<Turn> {
        self.started.then_some(self.candidate)
    }
}

/// Rainflow counting of a stream of turning points ([module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rainflow {
    stack: Vec<Turn>,
    capacity: usize,
    overflows: u64,
}

impl Default for Rainflow {
    fn default() -> Self {
        Self::new(DEFAULT_CAPACITY)
    }
}

impl Rainflow {
    /// An empty count keeping at most `capacity` (≥ 3) turning points.
    pub fn new(capacity: usize) -> Self {
        Self {
            stack: Vec::new(),
            capacity: capacity.max(3),
            overflows: 0,
        }
    }

    /// Most turning points kept.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Times the stack was full and its oldest range was counted as half a
    /// cycle early.
    pub fn overflows(&self) -> u64 {
        self.overflows
    }

    /// The turning points kept (the residue so far), oldest first.
    pub fn residue(&self) -> &[Turn] {
        &self.stack
    }

    /// Takes the next turning point and hands every cycle it closes to
    /// `counted`. Consecutive points must alternate (peaks and valleys, as
    /// [`Reversals`] gives them); a point equal to the last is skipped.
    pub fn push(&mut self, point: Turn, counted: &mut impl FnMut(Cycle)) {
        if self.stack.last().is_some_and(|l| l.value == point.value) {
            return;
        }
        if self.stack.len() == self.capacity {
            // The oldest range as the standard counts the range holding S.
            let first = self.stack.remove(0);
            counted(Cycle::of(first, self.stack[0], 0.5));
            self.overflows += 1;
        }
        self.stack.push(point);
        while self.stack.len() >= 3 {
            let n = self.stack.len();
            let (a, b, c) = (self.stack[n - 3], self.stack[n - 2], self.stack[n - 1]);
            let x = (c.value - b.value).abs();
            let y = (b.value - a.value).abs();
            if x < y {
                break;
            }
            if n == 3 {
                // Y holds the starting point: half a cycle, S moves on.
                counted(Cycle::of(a, b, 0.5));
                self.stack.remove(0);
            } else {
                counted(Cycle::of(a, b, 1.0));
                self.stack.truncate(n - 3);
                self.stack.push(c);
            }
        }
    }

    /// Counts the residue, each range as half a cycle (the standard's last
    /// step), and empties the stack.
    pub fn finish(&mut self, counted: &mut impl FnMut(Cycle)) {
        for w in self.stack.windows(2) {
            counted(Cycle::of(w[0], w[1], 0.5));
        }
        self.stack.clear();
    }
}

/// Every cycle of a whole history `values` (gate 0, tags the indices):
/// turning points, counting, residue.
pub fn count(values: &[f64]) -> Vec<Cycle> {
    let mut cycles = Vec::new();
    let mut turns = Reversals::new(0.0);
    let mut flow = Rainflow::new(usize::MAX);
    let mut counted = |c: Cycle| cycles.push(c);
    for (i, &v) in values.iter().enumerate() {
        if let Some(t) = turns.push(v, i as u32) {
            flow.push(t, &mut counted);
        }
    }
    if let Some(t) = turns.last() {
        flow.push(t, &mut counted);
    }
    flow.finish(&mut counted);
    cycles
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (range, count) pairs summed by range, sorted by range.
    fn histogram(cycles: &[Cycle]) -> Vec<(f64, f64)> {
        let mut out: Vec<(f64, f64)> = Vec::new();
        for c in cycles {
            match out.iter_mut().find(|(r, _)| *r == c.range) {
                Some((_, n)) => *n += c.count,
                None => out.push((c.range, c.count)),
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }

    /// ASTM E1049-85, Fig. 6 and its table (section 5.4.4): the history
    /// −2, 1, −3, 5, −1, 3, −4, 4, −2 has ranges 3 (½ cycle, A–B), 4 (1½:
    /// B–C, E–F), 6 (½: H–I), 8 (1: C–D, G–H), 9 (½: D–G).
    #[test]
    fn the_astm_e1049_worked_example_is_counted_exactly() {
        let cycles = count(&[-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0]);
        assert_eq!(
            histogram(&cycles),
            vec![(3.0, 0.5), (4.0, 1.5), (6.0, 0.5), (8.0, 1.0), (9.0, 0.5)]
        );
        // E–F is the one whole cycle: points 4 and 5 (values −1 and 3).
        let whole: Vec<&Cycle> = cycles.iter().filter(|c| c.count == 1.0).collect();
        assert_eq!(whole.len(), 1);
        assert_eq!((whole[0].low.tag, whole[0].high.tag), (4, 5));
        assert_eq!(whole[0].mean, 1.0);
    }

    /// By hand: 0, 4, 1, 3, 0 (points between turning points dropped:
    /// 2 between 0 and 4). From S = 0: 0–4 (Y = 4) against 4–1 (X = 3)
    /// stays; 1–3 (X = 2) < 3 stays; 3–0 (X = 3) ≥ 1–3 (Y = 2): 1–3 is a
    /// whole cycle; then 0–4 against 4–0: the half cycle 0–4 (it holds S);
    /// the residue 4–0 is another half. So: one cycle of 2 at mean 2, one
    /// of 4 (two halves) at mean 2.
    #[test]
    fn a_hand_counted_history_with_one_inner_cycle() {
        let cycles = count(&[0.0, 2.0, 4.0, 1.0, 3.0, 0.0]);
        assert_eq!(histogram(&cycles), vec![(2.0, 1.0), (4.0, 1.0)]);
        assert!(cycles.iter().all(|c| c.mean == 2.0));
    }

    /// By hand: a repeated block 0, 10, 5, 10, 0, 10, 5, 10, 0 (every value
    /// a turning point). S = 0; 10–5–10: X = 5 ≥ Y = 5 closes the cycle
    /// 10–5 (range 5), leaving 0, 10; the next 0: X = 10 ≥ Y = 10 and Y
    /// holds S: half a cycle 0–10, S moves to 10; the next 10: half a cycle
    /// 10–0 the same way; the second dip closes another cycle of 5; the
    /// last 0 another half of 10; the residue 10–0 the last half. So: two
    /// cycles of 5 and two (four halves) of 10.
    #[test]
    fn a_hand_counted_repeated_block() {
        let cycles = count(&[0.0, 10.0, 5.0, 10.0, 0.0, 10.0, 5.0, 10.0, 0.0]);
        assert_eq!(histogram(&cycles), vec![(5.0, 2.0), (10.0, 2.0)]);
    }

    #[test]
    fn a_gate_drops_small_reversals_and_keeps_the_large_cycle() {
        // 0 → 10 with a 0.5 dip on the way, then back to 0.
        let values = [0.0, 5.0, 4.5, 10.0, 0.0];
        let mut turns = Reversals::new(1.0);
        let mut got: Vec<f64> = values
            .iter()
            .filter_map(|&v| turns.push(v, 0))
            .map(|t| t.value)
            .collect();
        got.extend(turns.last().map(|t| t.value));
        assert_eq!(got, vec![0.0, 10.0, 0.0]);
        // Without the gate the dip is one more (small) cycle, the rest the same.
        let h = histogram(&count(&values));
        assert_eq!(h, vec![(0.5, 1.0), (10.0, 1.0)]);
    }

    #[test]
    fn a_full_stack_counts_its_oldest_range_as_half_a_cycle() {
        // A ring-down: ranges shrink, so nothing closes; capacity 4.
        let mut flow = Rainflow::new(4);
        let mut cycles = Vec::new();
        for (i, v) in [10.0, -10.0, 9.0, -8.0, 7.0, -6.0].into_iter().enumerate() {
            flow.push(
                Turn {
                    value: v,
                    tag: i as u32,
                },
                &mut |c| cycles.push(c),
            );
        }
        assert_eq!(flow.overflows(), 2);
        assert_eq!(flow.residue().len(), 4);
        assert_eq!(histogram(&cycles), vec![(19.0, 0.5), (20.0, 0.5)]);
    }

    #[test]
    fn a_constant_history_has_no_cycle() {
        assert!(count(&[3.0; 10]).is_empty());
        assert!(count(&[]).is_empty());
    }
}
