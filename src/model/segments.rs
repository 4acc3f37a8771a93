//! Which links belong to which free strand ("segment"), and the strands'
//! transverse displacement — the definitions every output shares:
//!
//! - segment k's free strand is found **in chain order, from the contact
//!   state**: it is the run of consecutive rollers after the last roller
//!   engaged on sprocket k and before the first roller engaged on sprocket
//!   k + 1 (a roller is engaged when it touches a sprocket; it is engaged on
//!   the sprocket whose pitch circle it lies nearest). The run follows the
//!   rollers as they move, however far a long strand sags;
//! - a link is in segment k's free strand when both its rollers are in that
//!   run (so neither touches a sprocket);
//! - segment k's transverse displacement is the signed perpendicular distance,
//!   from the nominal line, of the roller of that run (or its two tangent
//!   rollers) nearest the line's middle; positive to the left of the
//!   direction from `from` to `to` (docs/model.md, “Segment
//!   link force and transverse displacement”).
//!
//! It does not decide what touches: that is the contact generator's
//! [`crate::forces::Forces::touching`].

use super::SprocketModel;
use crate::geometry::ChainPath;
use crate::scene::MAX_SPROCKETS;

/// The nominal strand lines, prepared for classification.
#[derive(Clone, Debug)]
pub(crate) struct Segments {
    lines: Vec<Line>,
}

#[derive(Clone, Copy, Debug)]
struct Line {
    dir: [f64; 2],
    mid: [f64; 2],
}

/// One segment's free run at one instant: `rollers` consecutive free rollers
/// from roller `first` on (chain order, modulo the roller count). Roller
/// `first − 1` is the last engaged on the segment's `from` sprocket, roller
/// `first + rollers` the first engaged on its `to` sprocket.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(crate) struct StrandRun {
    /// First free roller.
    pub first: usize,
    /// Number of free rollers (links in the free strand: one fewer).
    pub rollers: usize,
}

/// Every segment's free run at one instant ([`Segments::runs`]); held on the
/// stack, so finding them allocates nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct StrandRuns {
    n: usize,
    runs: [Option<StrandRun>; MAX_SPROCKETS],
}

/// As written (a checkpoint keeps a cache of runs): the roller count and the
/// runs up to the last segment that has one.
#[derive(serde::Serialize, serde::Deserialize)]
struct RunsAsWritten {
    n: usize,
    runs: Vec<Option<StrandRun>>,
}

impl serde::Serialize for StrandRuns {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let used = self
            .runs
            .iter()
            .rposition(Option::is_some)
            .map_or(0, |k| k + 1);
        RunsAsWritten {
            n: self.n,
            runs: self.runs[..used].to_vec(),
        }
        .serialize(s)
    }
}

impl<'de> serde::Deserialize<'de> for StrandRuns {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let written = RunsAsWritten::deserialize(d)?;
        if written.runs.len() > MAX_SPROCKETS {
            return Err(serde::de::Error::custom(format!(
                "{} strand runs, more than the {MAX_SPROCKETS} segments a drive may have",
                written.runs.len()
            )));
        }
        let mut runs = [None; MAX_SPROCKETS];
        runs[..written.runs.len()].copy_from_slice(&written.runs);
        Ok(Self { n: written.n, runs })
    }
}

impl StrandRuns {
    /// Segment `k`'s run; `None` when the contact state shows no passage from
    /// its `from` sprocket to its `to` sprocket (the chain off a sprocket).
    pub(crate) fn get(&self, k: usize) -> Option<StrandRun> {
        self.runs.get(k).copied().flatten()
    }

    /// The links of segment `k`'s free strand (link i joins rollers i and
    /// i + 1), in index order (a run across the last roller gives its links
    /// from 0 first), so that sums over them do not depend on where the
    /// chain's numbering starts.
    pub(crate) fn links(&self, k: usize) -> impl Iterator<Item = usize> {
        let [wrapped, rest] = self.link_ranges(k);
        wrapped.chain(rest)
    }

    /// Segment `k`'s links as two index ranges in the order of
    /// [`StrandRuns::links`]: those past the last roller (from 0), then the rest.
    fn link_ranges(&self, k: usize) -> [std::ops::Range<usize>; 2] {
        let (first, links) = self
            .get(k)
            .map_or((0, 0), |r| (r.first, r.rollers.saturating_sub(1)));
        let end = first + links;
        if end > self.n {
            [0..end - self.n, first..self.n]
        } else {
            [0..0, first..end]
        }
    }

    /// The sum of `link_force` over segment `k`'s free strand, in the order
    /// of [`StrandRuns::links`], and the number of links summed (links
    /// beyond `link_force` left out): two slices, no bounds check per link.
    pub(crate) fn force_sum(&self, k: usize, link_force: &[f64]) -> (f64, usize) {
        let mut sum = 0.0;
        let mut count = 0;
        for range in self.link_ranges(k) {
            let slice = link_force
                .get(range.start.min(link_force.len())..range.end.min(link_force.len()))
                .unwrap_or_default();
            for f in slice {
                sum += f;
            }
            count += slice.len();
        }
        (sum, count)
    }
}

#[cfg(test)]
impl StrandRuns {
    /// The runs `(first, rollers)` of segments 0, 1, … on a chain of `n`
    /// rollers, as given (tests of what reads runs).
    pub(crate) fn of(n: usize, runs: &[(usize, usize)]) -> Self {
        let mut out = Self {
            n,
            runs: [None; MAX_SPROCKETS],
        };
        for (slot, &(first, rollers)) in out.runs.iter_mut().zip(runs) {
            *slot = Some(StrandRun { first, rollers });
        }
        out
    }
}

/// `i` modulo `n` for `i < 2n`.
fn wrap(i: usize, n: usize) -> usize {
    if i >= n { i - n } else { i }
}

impl Segments {
    /// From the nominal path.
    pub(crate) fn new(path: &ChainPath) -> Self {
        Self {
            lines: path
                .strands
                .iter()
                .map(|s| Line {
                    dir: s.direction(),
                    mid: [
                        0.5 * (s.start_m[0] + s.end_m[0]),
                        0.5 * (s.start_m[1] + s.end_m[1]),
                    ],
                })
                .collect(),
        }
    }

    /// Number of segments.
    pub(crate) fn len(&self) -> usize {
        self.lines.len()
    }

    /// Every segment's free run, from the rollers' positions and which of
    /// them touch a sprocket: one pass over the chain, O(rollers), starting
    /// at a touching roller. A touching roller is engaged on the sprocket
    /// whose pitch circle is nearest to its centre; each change of that
    /// sprocket from k to k + 1 along the chain closes segment k's run.
    pub(crate) fn runs(
        &self,
        sprockets: &[SprocketModel],
        x: &[f64],
        y: &[f64],
        touching: &[bool],
    ) -> StrandRuns {
        let n = x.len().min(y.len()).min(touching.len());
        let count = self.lines.len().min(sprockets.len());
        self.runs_by(&touching[..n], count, |i| {
            nearest_pitch_circle(sprockets, x[i], y[i])
        })
    }

    /// [`Segments::runs`] with the sprocket each touching roller is engaged
    /// on given by `engaged_on` (`count` sprockets).
    fn runs_by(
        &self,
        touching: &[bool],
        count: usize,
        engaged_on: impl Fn(usize) -> usize,
    ) -> StrandRuns {
        let n = touching.len();
        let mut out = StrandRuns {
            n,
            runs: [None; MAX_SPROCKETS],
        };
        let count = count.min(self.lines.len()).min(MAX_SPROCKETS);
        let Some(start) = touching.iter().position(|&t| t) else {
            return out;
        };
        let mut last = (start, engaged_on(start));
        for step in 1..=n {
            let i = wrap(start + step, n);
            if !touching[i] {
                continue;
            }
            let on = engaged_on(i);
            if on != last.1 && last.1 < count && on == (last.1 + 1) % count {
                // Rollers strictly between the two engaged ones (i == start
                // on the last step: the whole loop back to it).
                let between = wrap(i + n - last.0, n);
                let rollers = if between == 0 { n - 1 } else { between - 1 };
                out.runs[last.1] = Some(StrandRun {
                    first: wrap(last.0 + 1, n),
                    rollers,
                });
            }
            last = (i, on);
        }
        out
    }

    /// Mean link force of each segment's free strand; NaN-free: a segment with
    /// no free link gets `None`.
    pub(crate) fn mean_forces(
        &self,
        runs: &StrandRuns,
        link_force: &[f64],
        out: &mut [Option<f64>],
    ) {
        for (k, o) in out.iter_mut().enumerate().take(self.lines.len()) {
            let (sum, count) = runs.force_sum(k, link_force);
            *o = (count > 0).then(|| sum / count as f64);
        }
    }

    /// Signed transverse displacement of segment `k`: among the rollers of its
    /// run and its two tangent rollers, the one nearest the middle of the
    /// nominal line, its distance from the line (left positive). Without a
    /// run (the chain off a sprocket), the nearest roller of the whole chain.
    pub(crate) fn transverse(&self, k: usize, runs: &StrandRuns, x: &[f64], y: &[f64]) -> f64 {
        let Some(l) = self.lines.get(k) else {
            return 0.0;
        };
        let n = x.len().min(y.len());
        let mut best = (f64::INFINITY, 0.0);
        let mut consider = |i: usize| {
            let d = [x[i] - l.mid[0], y[i] - l.mid[1]];
            let dist_sq = d[0] * d[0] + d[1] * d[1];
            if dist_sq < best.0 {
                best = (dist_sq, -d[0] * l.dir[1] + d[1] * l.dir[0]);
            }
        };
        match runs.get(k) {
            Some(r) if n > 0 && runs.n == n => {
                // From the tangent roller on `from` to the one on `to`.
                let before = wrap(r.first + n - 1, n);
                for j in 0..(r.rollers + 2).min(n) {
                    consider(wrap(before + j, n));
                }
            }
            _ => (0..n).for_each(consider),
        }
        best.1
    }
}

/// The sprocket whose pitch circle lies nearest the point (x, y).
fn nearest_pitch_circle(sprockets: &[SprocketModel], x: f64, y: f64) -> usize {
    if sprockets.len() < 2 {
        return 0;
    }
    // The distances by √(dx² + dy²), within a few ulp of `hypot`'s: where
    // the nearest wins by far more than that, it is `hypot`'s nearest too.
    let mut best = (f64::INFINITY, 0);
    let mut second = f64::INFINITY;
    let mut scale = 0.0_f64;
    let mut plain = true;
    for (s, sp) in sprockets.iter().enumerate() {
        let (dx, dy) = (x - sp.center_m[0], y - sp.center_m[1]);
        let d2 = dx * dx + dy * dy;
        // Overflow, underflow and NaN leave it to `hypot`.
        plain &= (1e-280..1e280).contains(&d2);
        let d = d2.sqrt();
        let gap = (d - sp.pitch_radius_m).abs();
        scale = scale.max(d + sp.pitch_radius_m.abs());
        if gap < best.0 {
            second = best.0;
            best = (gap, s);
        } else if gap < second {
            second = gap;
        }
    }
    if plain && second - best.0 > NEAREST_MARGIN * scale {
        return best.1;
    }
    nearest_pitch_circle_by_hypot(sprockets, x, y)
}

/// Relative margin by which [`nearest_pitch_circle`]'s nearest must win for
/// √(dx² + dy²) to decide (its error and `hypot`'s are below 10⁻¹⁵).
const NEAREST_MARGIN: f64 = 1e-12;

/// [`nearest_pitch_circle`] with every distance by `hypot` (the definition).
fn nearest_pitch_circle_by_hypot(sprockets: &[SprocketModel], x: f64, y: f64) -> usize {
    let mut best = (f64::INFINITY, 0);
    for (s, sp) in sprockets.iter().enumerate() {
        let gap = ((x - sp.center_m[0]).hypot(y - sp.center_m[1]) - sp.pitch_radius_m).abs();
        if gap < best.0 {
            best = (gap, s);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn three_segments() -> Segments {
        let line = Line {
            dir: [1.0, 0.0],
            mid: [0.0, 0.0],
        };
        Segments {
            lines: vec![line; 3],
        }
    }

    /// The nearest pitch circle by √(dx² + dy²) with its margin is the one
    /// by `hypot` everywhere, near ties included: points on the bisector of
    /// the paper's two equal-toothed sprockets and 10⁻¹⁸ to 10⁻¹⁴ of their
    /// distance either side of it, where the two distances round differently.
    #[test]
    fn nearest_pitch_circle_is_the_one_by_hypot() {
        let scene = crate::scene::Scene::l60mc();
        let (model, _, _) = crate::model::DriveModel::build(&scene).expect("the paper's drive");
        let sp = &model.sprockets;
        let (a, b) = (0..sp.len())
            .flat_map(|a| (0..sp.len()).map(move |b| (a, b)))
            .find(|&(a, b)| a < b && sp[a].pitch_radius_m == sp[b].pitch_radius_m)
            .expect("two sprockets of one size");
        let (ca, cb) = (sp[a].center_m, sp[b].center_m);
        let mid = [0.5 * (ca[0] + cb[0]), 0.5 * (ca[1] + cb[1])];
        let along = [cb[0] - ca[0], cb[1] - ca[1]];
        let across = [-along[1], along[0]];
        let mut rng = crate::rng::SeededRng::new(7);
        let mut ties = 0;
        for _ in 0..200_000 {
            let t = rng.range(-2.0, 2.0);
            let off = rng.range(-1.0, 1.0) * 10f64.powf(-rng.range(14.0, 18.0));
            let (x, y) = (
                mid[0] + t * across[0] + off * along[0],
                mid[1] + t * across[1] + off * along[1],
            );
            let exact = nearest_pitch_circle_by_hypot(sp, x, y);
            assert_eq!(nearest_pitch_circle(sp, x, y), exact, "at ({x}, {y})");
            let d = |c: [f64; 2]| ((x - c[0]).hypot(y - c[1]) - sp[a].pitch_radius_m).abs();
            ties += usize::from((d(ca) - d(cb)).abs() < 1e-9);
        }
        assert!(ties > 100_000, "{ties} near ties");
        for (x, y) in [(f64::NAN, 0.0), (1e300, 1e300), (0.0, f64::INFINITY)] {
            assert_eq!(
                nearest_pitch_circle(sp, x, y),
                nearest_pitch_circle_by_hypot(sp, x, y)
            );
        }
    }

    /// Runs of a hand-labelled chain of 20 rollers on 3 sprockets, the loop
    /// starting inside strand 3 (so it wraps past roller 0): label s means
    /// engaged on sprocket s, `.` free.
    #[test]
    fn runs_follow_chain_order_between_engaged_rollers() {
        //             01234567890123456789
        let labels = b"..000.0..1111...222.";
        let touching: Vec<bool> = labels.iter().map(|c| *c != b'.').collect();
        let runs = three_segments().runs_by(&touching, 3, |i| (labels[i] - b'0') as usize);
        // Sprocket 0 -> 1: after roller 6 (the last on 0; 5 lifted inside the
        // wrap), before 9.
        assert_eq!(
            runs.get(0),
            Some(StrandRun {
                first: 7,
                rollers: 2
            })
        );
        assert_eq!(runs.links(0).collect::<Vec<_>>(), vec![7]);
        // 1 -> 2: rollers 13, 14, 15.
        assert_eq!(
            runs.get(1),
            Some(StrandRun {
                first: 13,
                rollers: 3
            })
        );
        assert_eq!(runs.links(1).collect::<Vec<_>>(), vec![13, 14]);
        // 2 -> 0 across the seam: rollers 19, 0, 1; links 19 and 0, given
        // in index order.
        assert_eq!(
            runs.get(2),
            Some(StrandRun {
                first: 19,
                rollers: 3
            })
        );
        assert_eq!(runs.links(2).collect::<Vec<_>>(), vec![0, 19]);
    }

    #[test]
    fn a_sprocket_the_chain_has_left_gives_its_neighbours_no_run() {
        let labels = b"..000....222....";
        let touching: Vec<bool> = labels.iter().map(|c| *c != b'.').collect();
        let runs = three_segments().runs_by(&touching, 3, |i| (labels[i] - b'0') as usize);
        assert_eq!(runs.get(0), None);
        assert_eq!(runs.get(1), None);
        assert_eq!(
            runs.get(2),
            Some(StrandRun {
                first: 12,
                rollers: 6
            })
        );
        let none = three_segments().runs_by(&[false; 8], 3, |_| 0);
        assert!((0..3).all(|k| none.get(k).is_none() && none.links(k).count() == 0));
    }

    /// The mean is over the run's links only, and the transverse value is the
    /// run's own roller nearest the middle, even when another strand's
    /// roller lies nearer (a strand sagging past another's line).
    #[test]
    fn means_and_transverse_use_only_the_segments_own_rollers() {
        let labels = b"0....1....";
        let touching: Vec<bool> = labels.iter().map(|c| *c != b'.').collect();
        let segs = Segments {
            lines: vec![
                Line {
                    dir: [1.0, 0.0],
                    mid: [0.0, 0.0],
                },
                Line {
                    dir: [-1.0, 0.0],
                    mid: [0.0, 1.0],
                },
            ],
        };
        let runs = segs.runs_by(&touching, 2, |i| (labels[i] - b'0') as usize);
        let force: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let mut mean = [None; 2];
        segs.mean_forces(&runs, &force, &mut mean);
        // Segment 0: links 1, 2, 3 (rollers 1–4); segment 1: links 6, 7, 8.
        assert_eq!(mean, [Some(2.0), Some(7.0)]);
        // Segment 1 (line y = 1) sags past segment 0's line (y = 0): its
        // roller 7 at the middle lies 1.2 below its line, segment 0's roller
        // 2 only 0.99.
        let x = [-2.0, -1.0, 0.0, 1.0, 2.0, 2.0, 1.0, 0.0, -1.0, -2.0];
        let y = [0.0, 0.0, 0.01, 0.0, 0.0, 1.0, 0.0, -0.2, 0.0, 1.0];
        // Left of −x is −y: a sag of 1.2 is +1.2.
        assert!((segs.transverse(1, &runs, &x, &y) - 1.2).abs() < 1e-12);
        assert!((segs.transverse(0, &runs, &x, &y) - 0.01).abs() < 1e-12);
    }
}
