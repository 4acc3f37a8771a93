//! Every link's force, rainflow-counted as the steps come, with Miner's
//! damage added up on the fly (docs/design-checks.md, "Fatigue").
//!
//! Per link: the turning points of its force ([`Reversals`], with a gate
//! of [`super::sn_curve::GATE_FRACTION`] of the fatigue limit) and the
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

use super::rainflow::{Cycle, DEFAULT_CAPACITY, Rainflow, Reversals};
use super::sn_curve::{GATE_FRACTION, SnCurve};
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

    /// A count of the same links on the same curve, from nothing (a
    /// statistics window that starts anew).
    pub(crate) fn anew(&self) -> Self {
        Self::new(self.curve, self.links.len())
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
        let n = links.len().min(link_force_n.len()).min(places.len());
        let (links, forces, places) = (&mut links[..n], &link_force_n[..n], &places[..n]);
        for i in 0..n {
            let link = &mut links[i];
            if let Some(turn) = link.turns.push(forces[i].max(0.0), places[i]) {
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

    /// One link on a two-segment chain whose places never change.
    fn one_link(curve: SnCurve) -> (LinkCycles, StrandRuns) {
        (LinkCycles::new(curve, 1), StrandRuns::of(1, &[(0, 1)]))
    }

    /// Feeds `force(t)` at steps of `dt_s` for `steps` steps.
    fn feed(curve: SnCurve, dt_s: f64, steps: usize, force: impl Fn(f64) -> f64) -> CycleSums {
        let (mut count, runs) = one_link(curve);
        for k in 0..=steps {
            let t = k as f64 * dt_s;
            count.step(t, &[force(t)], Some((1, &runs)), 1);
        }
        count.sums()
    }

    /// A sinusoid F = F_m + F_a sin(2π f t) is one cycle of range 2 F_a
    /// about F_m per period: damage per hour f · 3600 · (F₀ / F_D)^m / N_D,
    /// with F₀ its pulsating equivalent, F_ar = F_a / (1 − F_m / F_u),
    /// F₀ = 2 F_ar / (1 + F_ar / F_u). 200 periods: the ends' half cycles
    /// move the count by under 1 %. (Sampled at 400 per period, so that a
    /// sample falls on every peak and valley.)
    #[test]
    fn a_sinusoid_does_the_closed_form_damage() {
        let c = SnCurve::for_tests();
        let (fm, fa, f_hz) = (4000.0, 1500.0, 2.0);
        let sums = feed(c, 1.0 / (400.0 * f_hz), 400 * 200, |t| {
            fm + fa * (std::f64::consts::TAU * f_hz * t).sin()
        });
        let reversed = fa / (1.0 - fm / c.tensile_strength_n);
        let f0 = 2.0 * reversed / (1.0 + reversed / c.tensile_strength_n);
        let closed_form = f_hz * 3600.0 * (f0 / c.fatigue_limit_n).powi(10) / c.knee_cycles;
        let counted = sums.damage / sums.counted_s * 3600.0;
        approx::assert_relative_eq!(counted, closed_form, max_relative = 0.01);
        approx::assert_relative_eq!(sums.largest_n, f0, max_relative = 1e-12);
    }

    /// Pulsating forces F = A (1 − cos 2π f t) of twice the A: 2^m times
    /// the damage.
    #[test]
    fn streamed_damage_scales_as_the_slope_says_when_the_amplitude_doubles() {
        let pulsating = |a: f64| {
            feed(SnCurve::for_tests(), 1e-3, 20_000, move |t| {
                a * (1.0 - (std::f64::consts::TAU * 5.0 * t).cos())
            })
            .damage
        };
        approx::assert_relative_eq!(
            pulsating(2400.0) / pulsating(1200.0),
            1024.0,
            max_relative = 1e-9
        );
    }

    #[test]
    fn forces_below_the_fatigue_limit_give_no_damage() {
        // Pulsating up to 1.9 kN against a 2 kN limit, and a negative
        // (slack) swing counted as zero: peak 1.9 kN still.
        let sums = feed(SnCurve::for_tests(), 1e-3, 20_000, |t| {
            -500.0 + 2400.0 * (std::f64::consts::TAU * 5.0 * t).sin().max(0.0)
        });
        assert_eq!(sums.damage, 0.0);
        assert!(sums.cycles > 90.0);
        approx::assert_relative_eq!(sums.largest_n, 1900.0, max_relative = 1e-9);
    }

    /// The ASTM E1049 history (−2, 1, −3, 5, −1, 3, −4, 4, −2, in kN and
    /// shifted by 4 kN to keep the link in tension) streamed one step per
    /// value: the damage is the standard's cycles' (range, mean, count:
    /// A–B 3 kN about −0.5, ½; B–C 4 about −1, ½; E–F 4 about 1, 1; C–D
    /// 8 about 1, ½; D–G 9 about 0.5, ½; G–H 8 about 0, ½; H–I 6 about 1,
    /// ½; means shifted by 4) on a curve whose limit lets every one count.
    #[test]
    fn the_astm_example_streamed_gives_the_standards_cycles_damage() {
        let c = SnCurve {
            slope: 10.0,
            fatigue_limit_n: 8.0,
            knee_cycles: 5e6,
            tensile_strength_n: 20_000.0,
        };
        let history = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];
        let sums = feed(c, 1.0, history.len() - 1, |t| {
            1000.0 * (history[t as usize] + 4.0)
        });
        let table = [
            (3.0, -0.5, 0.5),
            (4.0, -1.0, 0.5),
            (4.0, 1.0, 1.0),
            (8.0, 1.0, 0.5),
            (9.0, 0.5, 0.5),
            (8.0, 0.0, 0.5),
            (6.0, 1.0, 0.5),
        ];
        let expected: f64 = table
            .iter()
            .map(|&(range, mean, count)| count * c.damage(1000.0 * range, 1000.0 * (mean + 4.0)))
            .sum();
        assert_eq!(sums.cycles, 4.0);
        approx::assert_relative_eq!(sums.damage, expected, max_relative = 1e-12);
    }
}
