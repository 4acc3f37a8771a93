//! The walk that lays rollers round a chain path: on each wrap the rollers
//! sit a gap apart (on a smooth circle, a link apart), and each strand of a
//! whole number of links lands on the next circle (module docs of
//! [`super::layout`]). It knows nothing of hanging strands or of arms: the
//! layouts built on it do.

use std::f64::consts::{PI, TAU};

use super::laid::{Layout, LayoutError, MAX_LENGTH_MISMATCH_PITCHES, length_error};
use super::path::{ChainPath, PathCircle};

/// Roller counts of a walk.
#[derive(Clone, Debug)]
pub(super) struct Counts {
    /// Seated rollers per circle.
    pub(super) seated: Vec<usize>,
    /// Links per strand.
    pub(super) strand_links: Vec<usize>,
}

/// One walk's result.
pub(super) struct Walk {
    /// Roller centres in chain order, m.
    pub(super) rollers_m: Vec<[f64; 2]>,
    /// For each roller on a sprocket's wrap: (circle, gap); `None` on a
    /// strand or a smooth circle.
    pub(super) seats: Vec<Option<(usize, u32)>>,
    /// Polar angle of the first roller on each circle, rad.
    pub(super) sprocket_angles_rad: Vec<f64>,
    /// Rollers on each circle's wrap.
    pub(super) seated: Vec<usize>,
    /// Links of each strand.
    pub(super) strand_links: Vec<usize>,
    /// Chord of the closing strand minus its links × λ, m.
    pub(super) residual_m: f64,
    /// Strand link length, m.
    pub(super) lambda_m: f64,
}

impl Walk {
    pub(super) fn counts(&self) -> Counts {
        Counts {
            seated: self.seated.clone(),
            strand_links: self.strand_links.clone(),
        }
    }

    /// Pitches of chain the path needs.
    pub(super) fn needed_links(&self, pitch_m: f64) -> f64 {
        let links: usize = self.strand_links.iter().sum::<usize>()
            + self.seated.iter().map(|m| m - 1).sum::<usize>();
        links as f64 + self.residual_m / pitch_m
    }

    /// Strand `k`'s ends: the last roller seated on sprocket k and the
    /// first on the next.
    pub(super) fn strand_ends(&self, k: usize) -> ([f64; 2], [f64; 2]) {
        let offset = |j: usize| -> usize {
            (0..j)
                .map(|i| self.seated[i] + self.strand_links[i] - 1)
                .sum()
        };
        let next = if k + 1 == self.seated.len() {
            0
        } else {
            offset(k + 1)
        };
        (
            self.rollers_m[offset(k) + self.seated[k] - 1],
            self.rollers_m[next],
        )
    }

    pub(super) fn into_layout(self, pitch_m: f64, misfit_pitches: f64) -> Layout {
        let wrap_links: usize = self.seated.iter().map(|m| m - 1).sum();
        let strand: usize = self.strand_links.iter().sum();
        Layout {
            polygon_length_m: wrap_links as f64 * pitch_m
                + strand as f64 * self.lambda_m
                + self.residual_m,
            rollers_m: self.rollers_m,
            sprocket_angles_rad: self.sprocket_angles_rad,
            seats: self.seats,
            strand_links: self.strand_links,
            strand_link_m: self.lambda_m,
            misfit_pitches,
            hanging: false,
            arms: Vec::new(),
        }
    }
}

/// Angle a − b folded into (−π, π].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    if d > PI { d - TAU } else { d }
}

/// Walks a path round its circles; a circle of 0 teeth is smooth (a
/// tensioner arm's shoe): its rollers lie a link apart and seat in no gap.
pub(super) struct Walker<'a> {
    path: &'a ChainPath,
    circles: &'a [PathCircle],
    teeth: &'a [u32],
}

impl<'a> Walker<'a> {
    /// A walker over `path`, once every sprocket is wrapped: a sprocket the
    /// path only touches engages no roller.
    pub(super) fn engaged(
        path: &'a ChainPath,
        circles: &'a [PathCircle],
        teeth: &'a [u32],
    ) -> Result<Self, LayoutError> {
        for (k, w) in path.wraps.iter().enumerate() {
            if w.wrap_rad < 1e-9 {
                return Err(LayoutError::NoEngagement {
                    sprocket: k + 1,
                    wrap_deg: w.wrap_rad.to_degrees(),
                });
            }
        }
        Ok(Self {
            path,
            circles,
            teeth,
        })
    }
}

impl Walker<'_> {
    /// Lays `rollers` rollers of pitch `pitch_m`: the first walk, at λ = P,
    /// decides the roller counts and the path's need of chain (returned
    /// beside the walk, in pitches); the closing strand takes the links the
    /// chain has left, and λ closes the loop (secant). A chain more than
    /// [`MAX_LENGTH_MISMATCH_PITCHES`] off the need is refused.
    pub(super) fn close(&self, rollers: usize, pitch_m: f64) -> Result<(Walk, f64), LayoutError> {
        let first = self.walk(pitch_m, None)?;
        let used = first.rollers_m.len() - first.strand_links[first.strand_links.len() - 1] + 1;
        let needed = first.needed_links(pitch_m);
        if (needed - rollers as f64).abs() > MAX_LENGTH_MISMATCH_PITCHES || used > rollers {
            return Err(length_error(needed, rollers));
        }
        // Give the closing strand the links the chain has left, then close the loop by λ.
        let mut counts = first.counts();
        let last = counts.strand_links.len() - 1;
        counts.strand_links[last] = rollers + 1 - used;
        let total_strand: usize = counts.strand_links.iter().sum();
        let residual = |lambda: f64| self.walk(lambda, Some(&counts)).map(|w| w.residual_m);
        let (mut l0, mut r0) = (pitch_m, residual(pitch_m)?);
        let mut l1 = pitch_m + r0 / total_strand as f64;
        for _ in 0..50 {
            let r1 = residual(l1)?;
            if r1.abs() < 1e-13 || r1 == r0 {
                break;
            }
            let l2 = l1 - r1 * (l1 - l0) / (r1 - r0);
            (l0, r0, l1) = (l1, r1, l2);
        }
        let walk = self.walk(l1, Some(&counts))?;
        if walk.rollers_m.len() != rollers {
            return Err(length_error(needed, rollers));
        }
        Ok((walk, needed))
    }

    fn point(&self, k: usize, angle: f64) -> [f64; 2] {
        let c = &self.circles[k];
        [
            c.center_m[0] + c.radius_m * angle.cos(),
            c.center_m[1] + c.radius_m * angle.sin(),
        ]
    }

    /// The angle between neighbouring rollers on circle `k` with links of
    /// length `lambda`: a gap's on a sprocket, the chord's on a smooth circle.
    fn phi(&self, k: usize, lambda: f64) -> f64 {
        match self.teeth[k] {
            0 => 2.0 * (0.5 * lambda / self.circles[k].radius_m).min(1.0).asin(),
            teeth => TAU / f64::from(teeth),
        }
    }

    /// Where a strand of `links` links of length λ from `from` meets circle
    /// `k`: the polar angle nearest `near`.
    fn landing(
        &self,
        from: [f64; 2],
        links: usize,
        lambda: f64,
        k: usize,
        near: f64,
    ) -> Option<f64> {
        let c = &self.circles[k];
        let rho = links as f64 * lambda;
        let d = [c.center_m[0] - from[0], c.center_m[1] - from[1]];
        let dist = d[0].hypot(d[1]);
        if !(dist > 0.0) {
            return None;
        }
        let a = (rho * rho - c.radius_m * c.radius_m + dist * dist) / (2.0 * dist);
        let h2 = rho * rho - a * a;
        if !(h2 >= 0.0) {
            return None;
        }
        let h = h2.sqrt();
        let e = [d[0] / dist, d[1] / dist];
        [h, -h]
            .iter()
            .map(|s| {
                let p = [from[0] + a * e[0] - s * e[1], from[1] + a * e[1] + s * e[0]];
                (p[1] - c.center_m[1]).atan2(p[0] - c.center_m[0])
            })
            .min_by(|x, y| {
                angle_diff(*x, near)
                    .abs()
                    .total_cmp(&angle_diff(*y, near).abs())
            })
    }

    /// Walks the loop with strand links of length `lambda`; with `counts`, the
    /// roller counts are imposed, otherwise chosen.
    pub(super) fn walk(&self, lambda: f64, counts: Option<&Counts>) -> Result<Walk, LayoutError> {
        let n = self.circles.len();
        let mut out = Walk {
            rollers_m: Vec::new(),
            seats: Vec::new(),
            sprocket_angles_rad: Vec::with_capacity(n),
            seated: Vec::with_capacity(n),
            strand_links: Vec::with_capacity(n),
            residual_m: 0.0,
            lambda_m: lambda,
        };
        // The first roller of sprocket 0 sits half a pitch after the arrival point.
        let mut first =
            self.path.wraps[0].arrive_rad + self.circles[0].sense * 0.5 * self.phi(0, lambda);
        let start = self.point(0, first);
        for k in 0..n {
            let (s, phi) = (self.circles[k].sense, self.phi(k, lambda));
            let w = &self.path.wraps[k];
            let seated = match counts {
                Some(c) => c.seated[k],
                None => {
                    let into = s * angle_diff(first, w.arrive_rad);
                    // On a smooth circle the last roller stays short of the
                    // leaving point, so the strand from it clears the circle.
                    let round = if self.teeth[k] == 0 { 0.0 } else { 0.5 };
                    ((w.wrap_rad - into) / phi + round).floor().max(0.0) as usize + 1
                }
            };
            out.sprocket_angles_rad.push(first);
            for m in 0..seated {
                out.rollers_m
                    .push(self.point(k, first + s * m as f64 * phi));
                out.seats.push(match self.teeth[k] {
                    0 => None,
                    teeth => Some((k, (s * m as f64).rem_euclid(f64::from(teeth)) as u32)),
                });
            }
            out.seated.push(seated);
            let last = self.point(k, first + s * (seated - 1) as f64 * phi);
            let next = (k + 1) % n;
            let no_landing = LayoutError::NoLanding {
                from: k + 1,
                to: next + 1,
            };
            let (links, target) = if next == 0 {
                let chord = (start[0] - last[0]).hypot(start[1] - last[1]);
                let links = match counts {
                    Some(c) => c.strand_links[k],
                    None => ((chord / lambda).round() as usize).max(1),
                };
                out.residual_m = chord - links as f64 * lambda;
                (links, start)
            } else {
                // Half a pitch after the arrival point on a sprocket; half a
                // link before it on a smooth circle, so that the strand
                // reaches the circle without cutting into it.
                let half = 0.5 * self.phi(next, lambda);
                let aim = self.path.wraps[next].arrive_rad
                    + self.circles[next].sense * if self.teeth[next] == 0 { -half } else { half };
                let (links, angle) = match counts {
                    Some(c) => {
                        let l = c.strand_links[k];
                        (
                            l,
                            self.landing(last, l, lambda, next, aim).ok_or(no_landing)?,
                        )
                    }
                    None => {
                        let t = self.path.strands[k].end_m;
                        let guess =
                            ((t[0] - last[0]).hypot(t[1] - last[1]) / lambda).round() as usize;
                        (guess.saturating_sub(1).max(1)..=guess + 1)
                            .filter_map(|l| {
                                self.landing(last, l, lambda, next, aim).map(|a| (l, a))
                            })
                            .min_by(|x, y| {
                                angle_diff(x.1, aim)
                                    .abs()
                                    .total_cmp(&angle_diff(y.1, aim).abs())
                            })
                            .ok_or(no_landing)?
                    }
                };
                first = angle;
                (links, self.point(next, angle))
            };
            out.strand_links.push(links);
            for q in 1..links {
                let t = q as f64 / links as f64;
                out.rollers_m.push([
                    last[0] + t * (target[0] - last[0]),
                    last[1] + t * (target[1] - last[1]),
                ]);
                out.seats.push(None);
            }
        }
        Ok(out)
    }
}
