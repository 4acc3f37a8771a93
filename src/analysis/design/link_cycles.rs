//! Every link's force, rainflow-counted as the steps come, with Miner's
//! damage added up on the fly (docs/design-checks.md, "Fatigue").
//!
//! Per link: the turning points of its force ([`Reversals`], with a gate
//! of [`super::fatigue::GATE_FRACTION`] of the fatigue limit) and the
//! stack of those not yet closed ([`Rainflow`], at most
//! [`super::rainflow::DEFAULT_CAPACITY`] points); per counted cycle, its
//! damage on the S–N curve, added to the chain's total and to the place
//! where the cycle's peak was reached. Nothing is kept per step: memory is
//! bounded by the links and the places, whatever the window's length.
//!
//! A link carries tension only: a negative model force (a link pushed
//! shorter than its rest length, a slack chain) is counted as zero.
//!
//! Places: each link's place at each step (a free strand or a sprocket's
//! wrap, and its pitches into it) is known from the segments' free runs,
//! found again only when the contact state changes
//! ([`crate::model::StrandRuns`]); a turning point carries the place of the
//! step at which its extreme was reached.
//!
//! Per step it costs a comparison or two per link; a cycle's damage is one
//! power. It does not compute lives (that is [`super::fatigue`]'s, from
//! [`CycleSums`]).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::fatigue::{GATE_FRACTION, SnCurve};
use super::rainflow::{Cycle, DEFAULT_CAPACITY, Rainflow, Reversals};
use crate::model::StrandRuns;

/// A place no run shows (the chain off its sprockets).
pub const UNKNOWN_PLACE: u32 = u32::MAX;

/// A place packed in a `u32`: place index (2k: segment k's free strand,
/// 2k + 1: the wrap of the sprocket it reaches) in the high 16 bits,
/// pitches into it in the low 16.
fn pack(place: usize, pitches: usize) -> u32 {
    ((place.min(0x7fff) as u32) << 16) | pitches.min(0xffff) as u32
}

/// The place index and the pitches of a packed place (`None`: unknown).
pub fn unpack(packed: u32) -> Option<(usize, usize)> {
    (packed != UNKNOWN_PLACE).then_some(((packed >> 16) as usize, (packed & 0xffff) as usize))
}

/// Each link's place from the segments' free runs (`n` links, link i
/// joining rollers i and i + 1): free links by their pitches from the
/// strand's start, then the links after each strand, up to the next
/// strand's, by their pitches into the wrap of the sprocket it reaches.
pub fn places(runs: &StrandRuns, segments: usize, out: &mut [u32]) {
    let n = out.len();
    out.fill(UNKNOWN_PLACE);
    if n == 0 {
        return;
    }
    for k in 0..segments {
        if let Some(r) = runs.get(k) {
            for j in 0..r.rollers.saturating_sub(1) {
                out[(r.first + j) % n] = pack(2 * k, j);
            }
        }
    }
    for k in 0..segments {
        if let Some(r) = runs.get(k) {
            let start = r.first + r.rollers.saturating_sub(1);
            for j in 0..n {
                let i = (start + j) % n;
                if out[i] != UNKNOWN_PLACE {
                    break;
                }
                out[i] = pack(2 * k + 1, j);
            }
        }
    }
}

/// One link's turning points and open cycles.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct LinkHistory {
    turns: Reversals,
    flow: Rainflow,
}

/// What the counted cycles add up to.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CycleSums {
    /// Miner's damage summed over every link.
    pub damage: f64,
    /// Cycles counted over every link (halves as ½).
    pub cycles: f64,
    /// The largest cycle's pulsating equivalent, N, and its peak's place.
    pub largest_n: f64,
    /// Where the largest cycle's peak was (packed).
    pub largest_at: u32,
    /// Damage by the place of each cycle's peak (packed places).
    pub by_place: BTreeMap<u32, f64>,
    /// Times a link's stack was full ([`Rainflow::overflows`]).
    pub overflows: u64,
    /// Time counted, s.
    pub counted_s: f64,
    /// Links counted.
    pub links: usize,
}

impl CycleSums {
    fn add(&mut self, curve: &SnCurve, c: Cycle) {
        let equivalent = curve.pulsating_equivalent_n(c.range, c.mean);
        let damage = c.count * curve.damage_of_pulsating(equivalent);
        self.cycles += c.count;
        if equivalent > self.largest_n {
            self.largest_n = equivalent;
            self.largest_at = c.high.tag;
        }
        if damage > 0.0 {
            self.damage += damage;
            *self.by_place.entry(c.high.tag).or_insert(0.0) += damage;
        }
    }
}

/// The streaming count of every link's force ([module docs](self)); kept in
/// a checkpoint with the signals.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinkCycles {
    curve: SnCurve,
    links: Vec<LinkHistory>,
    /// Each link's place now.
    places: Vec<u32>,
    /// The number of the runs the places were found from.
    runs_found: Option<u64>,
    /// The first and the last step counted, s.
    first_s: Option<f64>,
    last_s: f64,
    sums: CycleSums,
}

impl LinkCycles {
    /// A count of `links` links' forces on `curve`.
    pub fn new(curve: SnCurve, links: usize) -> Self {
        let gate = GATE_FRACTION * curve.fatigue_limit_n;
        Self {
            curve,
            links: vec![
                LinkHistory {
                    turns: Reversals::new(gate),
                    flow: Rainflow::new(DEFAULT_CAPACITY),
                };
                links
            ],
            places: vec![UNKNOWN_PLACE; links],
            runs_found: None,
            first_s: None,
            last_s: 0.0,
            sums: CycleSums {
                links,
                largest_at: UNKNOWN_PLACE,
                ..CycleSums::default()
            },
        }
    }

    /// The curve counted on.
    pub fn curve(&self) -> &SnCurve {
        &self.curve
    }

    /// Counts the step that ended at `t_s` with the links' forces
    /// `link_force_n`; `runs` are the segments' free runs now (`segments`
    /// of them) with a number that changes when they may have, `None`
    /// where unknown (the step is then not counted).
    pub fn step(
        &mut self,
        t_s: f64,
        link_force_n: &[f64],
        runs: Option<(u64, &StrandRuns)>,
        segments: usize,
    ) {
        let Some((found, runs)) = runs else {
            return;
        };
        if self.runs_found != Some(found) {
            places(runs, segments, &mut self.places);
            self.runs_found = Some(found);
        }
        self.first_s.get_or_insert(t_s);
        self.last_s = t_s;
        let Self {
            curve,
            links,
            places,
            sums,
            ..
        } = self;
        let each = links.iter_mut().zip(link_force_n).zip(places.iter());
        for ((link, &f), &place) in each {
            if let Some(turn) = link.turns.push(f.max(0.0), place) {
                link.flow.push(turn, &mut |c| sums.add(curve, c));
            }
        }
    }

    /// The sums with every link's history closed as the standard closes a
    /// history's end: its open extreme as the last turning point, the
    /// residue as half cycles. The count itself goes on unchanged.
    pub fn sums(&self) -> CycleSums {
        let mut sums = self.sums.clone();
        let curve = self.curve;
        for link in &self.links {
            let mut flow = link.flow.clone();
            let mut add = |c: Cycle| sums.add(&curve, c);
            if let Some(turn) = link.turns.last() {
                flow.push(turn, &mut add);
            }
            flow.finish(&mut add);
            sums.overflows += link.flow.overflows();
        }
        sums.counted_s = self.first_s.map_or(0.0, |first| self.last_s - first);
        sums
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve() -> SnCurve {
        SnCurve {
            slope: 10.0,
            fatigue_limit_n: 2000.0,
            knee_cycles: 5e6,
            tensile_strength_n: 20_000.0,
        }
    }

    #[test]
    fn places_follow_the_runs_round_the_chain() {
        // 10 rollers; segment 0 free from roller 2 (4 rollers: links 2, 3,
        // 4), segment 1 free from roller 7 (2 rollers: link 7).
        let runs = StrandRuns::of(10, &[(2, 4), (7, 2)]);
        let mut out = vec![0; 10];
        places(&runs, 2, &mut out);
        let got: Vec<Option<(usize, usize)>> = out.iter().map(|&p| unpack(p)).collect();
        assert_eq!(
            got,
            vec![
                Some((3, 2)), // after segment 1, into sprocket 0's wrap
                Some((3, 3)),
                Some((0, 0)),
                Some((0, 1)),
                Some((0, 2)),
                Some((1, 0)), // roller 5, the last free one, to roller 6
                Some((1, 1)),
                Some((2, 0)),
                Some((3, 0)),
                Some((3, 1)),
            ]
        );
    }
}
