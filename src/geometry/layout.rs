//! Initial roller layout.
//!
//! The chain is walked once around the loop. On each wrap the rollers sit in
//! consecutive gaps, so wrap links are exactly one pitch. Each strand ends
//! where a circle of n strand links around the last seated roller meets the
//! next sprocket's seat circle, with n chosen so that the first roller lands
//! within a pitch after the tangent point; the free sprockets are thereby
//! turned to receive the chain. The strand link length λ (one value for every
//! strand) is found by a secant iteration so that the loop closes exactly on
//! the first roller. The chain's extra length over the path (or its lack)
//! thus sits evenly in the strands; the pretension rule takes it from there.
//!
//! The nearest roller count always lays out: a chain at most half a pitch
//! shorter or longer than the path is laid with its strand links lengthened
//! or shortened by the misfit shared among them ([`Layout::misfit_pitches`],
//! [`Layout::strand_stretch`]); whether the pretension can then be reached is
//! the equilibrium's question, not the layout's. A chain further off gets
//! [`LayoutError::ChainLength`], with what tensioner arms take up where the
//! drive has them ([`super::layout_with_arms`]). It names no count: which
//! counts the drive accepts is the equilibrium's question too
//! (`sim::count_verdicts`).
//!
//! Under gravity a chain longer than that hangs ([`layout_hanging`]): the
//! seated rollers and the strands' ends stay where the walk at λ = P puts
//! them, each strand takes a share of the excess links in proportion to the
//! length its sag holds (q⊥² L³ / 24 T² for a shallow cable, so in
//! proportion to q⊥² L³), and its rollers are laid one pitch apart along
//! the parabola of that arc length, sagging towards gravity. The static
//! equilibrium starts from there.

use super::laid::{Layout, LayoutError, length_error};
use super::path::{ChainPath, PathCircle};
use super::walk::{Walk, Walker};

/// Lays `rollers` rollers of pitch `pitch_m` on `path` around `circles`
/// (radius = the radius at which seated roller centres lie), circle k with
/// `teeth[k]` teeth.
pub(crate) fn layout_rollers(
    path: &ChainPath,
    circles: &[PathCircle],
    teeth: &[u32],
    rollers: usize,
    pitch_m: f64,
) -> Result<Layout, LayoutError> {
    let (walk, needed) = Walker::engaged(path, circles, teeth)?.close(rollers, pitch_m)?;
    Ok(walk.into_layout(pitch_m, needed - rollers as f64))
}

/// Pitches of chain the path through the seated rollers of `circles` needs
/// (the layout's count at strand links of one pitch): the quantity a chain of
/// N rollers must match within half a pitch.
pub(crate) fn needed_pitches(
    path: &ChainPath,
    circles: &[PathCircle],
    teeth: &[u32],
    pitch_m: f64,
) -> Result<f64, LayoutError> {
    let walker = Walker::engaged(path, circles, teeth)?;
    Ok(walker.walk(pitch_m, None)?.needed_links(pitch_m))
}

/// [`layout_rollers`], and where the chain is too long for it under
/// `gravity_m_s2`, the excess hung in the strands' sag (module docs). A
/// chain that is short, or long without gravity to sag it, or whose strands
/// all run along gravity, gets [`layout_rollers`]'s error.
pub(crate) fn layout_hanging(
    path: &ChainPath,
    circles: &[PathCircle],
    teeth: &[u32],
    rollers: usize,
    pitch_m: f64,
    gravity_m_s2: [f64; 2],
) -> Result<Layout, LayoutError> {
    match layout_rollers(path, circles, teeth, rollers, pitch_m) {
        Err(LayoutError::ChainLength { needed, .. }) => {
            hang_excess(path, circles, teeth, rollers, pitch_m, gravity_m_s2, needed)
        }
        laid => laid,
    }
}

/// The hanging half of [`layout_hanging`], for a chain that
/// [`layout_rollers`] refused because the path needs `needed` pitches: the
/// excess hung, or that refusal where it cannot hang (a short chain, no
/// gravity across any strand).
pub(crate) fn hang_excess(
    path: &ChainPath,
    circles: &[PathCircle],
    teeth: &[u32],
    rollers: usize,
    pitch_m: f64,
    gravity_m_s2: [f64; 2],
    needed: f64,
) -> Result<Layout, LayoutError> {
    let straight = Err(length_error(needed, rollers));
    if !(needed < rollers as f64) {
        return straight;
    }
    // The excess links each strand takes, from the walk on the straight
    // path; then the path with each strand's ends moved round their
    // sprockets by its sag's end slope (less wrap where the strand sags
    // away from the sprocket, more where it sags towards it, so that it
    // leaves each wrap along the parabola's tangent), walked again.
    let walker = Walker::engaged(path, circles, teeth)?;
    let straight_walk = walker.walk(pitch_m, None)?;
    let Some((_, slopes)) = sag_shares(&straight_walk, rollers, pitch_m, gravity_m_s2) else {
        return straight;
    };
    let tilted = tilted_path(path, circles, &slopes, gravity_m_s2);
    let first = match Walker::engaged(&tilted, circles, teeth).and_then(|w| w.walk(pitch_m, None)) {
        Ok(walk) if walk.rollers_m.len() <= rollers => walk,
        _ => straight_walk,
    };
    let strands = first.strand_links.len();
    let Some((shares, _)) = sag_shares(&first, rollers, pitch_m, gravity_m_s2) else {
        return straight;
    };
    let chords: Vec<([f64; 2], [f64; 2])> = (0..strands).map(|k| first.strand_ends(k)).collect();
    let mut rollers_m = Vec::with_capacity(rollers);
    let mut seats = Vec::with_capacity(rollers);
    let mut strand_links = Vec::with_capacity(strands);
    let mut at = 0;
    for k in 0..strands {
        let seated = first.seated[k];
        rollers_m.extend_from_slice(&first.rollers_m[at..at + seated]);
        seats.extend_from_slice(&first.seats[at..at + seated]);
        at += seated + first.strand_links[k] - 1;
        let links = first.strand_links[k] + shares[k];
        let (a, b) = chords[k];
        for p in hang(a, b, links, pitch_m, gravity_m_s2) {
            rollers_m.push(p);
            seats.push(None);
        }
        strand_links.push(links);
    }
    if rollers_m.len() != rollers {
        return straight;
    }
    Ok(Layout {
        rollers_m,
        sprocket_angles_rad: first.sprocket_angles_rad,
        seats,
        strand_links,
        strand_link_m: pitch_m,
        polygon_length_m: needed * pitch_m,
        misfit_pitches: needed - rollers as f64,
        hanging: true,
        arms: Vec::new(),
    })
}

/// The extra links each strand of `walk` takes when the chain has `rollers`
/// (largest remainders of shares in proportion to q⊥² L³ ∝ (|t × g|)² L³),
/// and the end slope 4 s / c of each strand's sag with them; `None` when
/// the chain is not longer than the walk or nothing sags.
fn sag_shares(
    walk: &Walk,
    rollers: usize,
    pitch_m: f64,
    gravity_m_s2: [f64; 2],
) -> Option<(Vec<usize>, Vec<f64>)> {
    let extra = rollers.checked_sub(walk.rollers_m.len())?;
    let strands = walk.strand_links.len();
    let g = gravity_m_s2[0].hypot(gravity_m_s2[1]);
    let chords: Vec<f64> = (0..strands)
        .map(|k| {
            let (a, b) = walk.strand_ends(k);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .collect();
    let weights: Vec<f64> = (0..strands)
        .map(|k| {
            let (a, b) = walk.strand_ends(k);
            let d = [b[0] - a[0], b[1] - a[1]];
            let l = chords[k];
            if !(l > 0.0 && g > 0.0) {
                return 0.0;
            }
            let across = (d[0] * gravity_m_s2[1] - d[1] * gravity_m_s2[0]).abs() / (l * g);
            across * across * l.powi(3)
        })
        .collect();
    let total: f64 = weights.iter().sum();
    if !(total > 0.0) {
        return None;
    }
    let exact: Vec<f64> = weights.iter().map(|w| extra as f64 * w / total).collect();
    let mut shares: Vec<usize> = exact.iter().map(|e| e.floor() as usize).collect();
    let mut order: Vec<usize> = (0..strands).collect();
    order.sort_by(|&i, &j| (exact[j] - exact[j].floor()).total_cmp(&(exact[i] - exact[i].floor())));
    let given: usize = shares.iter().sum();
    for &k in order.iter().take(extra.saturating_sub(given)) {
        shares[k] += 1;
    }
    let slopes = (0..strands)
        .map(|k| {
            let links = walk.strand_links[k] + shares[k];
            4.0 * sag_of(chords[k], links as f64 * pitch_m) / chords[k].max(f64::MIN_POSITIVE)
        })
        .collect();
    Some((shares, slopes))
}

/// The sag s of the parabola over a chord `c` whose arc length is `arc`
/// (see [`hang`]); 0 when the arc is no longer than the chord.
fn sag_of(c: f64, arc: f64) -> f64 {
    if !(c > 0.0 && arc > c) {
        return 0.0;
    }
    let length = |k: f64| c * parabola_f(k, 1.0);
    let (mut lo, mut hi) = (0.0, 1.0);
    while length(hi) < arc && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if length(mid) < arc {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) * c / 4.0
}

/// F(v) = (v √(1 + k²v²) + asinh(k v) / k) / 2: the parabola's arc-length
/// integral (see [`hang`]).
fn parabola_f(k: f64, v: f64) -> f64 {
    let asinh_over = if k > 1e-9 { (k * v).asinh() / k } else { v };
    0.5 * (v * (1.0 + k * k * v * v).sqrt() + asinh_over)
}

/// `path` with each strand's ends moved round their sprockets by its sag's
/// end angle atan(`slopes[k]`): a strand that sags away from a sprocket
/// leaves it (or reaches it) that much earlier (or later) along the wrap,
/// one that sags towards it that much later (or earlier). Strand k from
/// circle a to b with normal ν = (−t_y, t_x): a's centre lies on the side
/// σ_a ν, so it sags towards a when σ_a (g · ν) > 0; the start's polar
/// angle moves by +δ sgn(g · ν) and the end's by −δ sgn(g · ν) either way.
fn tilted_path(
    path: &ChainPath,
    circles: &[PathCircle],
    slopes: &[f64],
    gravity_m_s2: [f64; 2],
) -> ChainPath {
    let mut out = path.clone();
    let n = circles.len();
    let point = |k: usize, angle: f64| {
        let c = &circles[k];
        [
            c.center_m[0] + c.radius_m * angle.cos(),
            c.center_m[1] + c.radius_m * angle.sin(),
        ]
    };
    for (k, strand) in path.strands.iter().enumerate() {
        let [tx, ty] = strand.direction();
        let gn = -ty * gravity_m_s2[0] + tx * gravity_m_s2[1];
        let delta = slopes[k].atan() * gn.signum();
        if !(delta.abs() > 0.0) {
            continue;
        }
        let (a, b) = (k, (k + 1) % n);
        let leave = out.wraps[a].leave_rad + delta;
        out.wraps[a].leave_rad = leave;
        out.wraps[a].wrap_rad += circles[a].sense * delta;
        let arrive = out.wraps[b].arrive_rad - delta;
        out.wraps[b].arrive_rad = arrive;
        out.wraps[b].wrap_rad += circles[b].sense * delta;
        let (start_m, end_m) = (point(a, leave), point(b, arrive));
        let s = &mut out.strands[k];
        s.start_m = start_m;
        s.end_m = end_m;
        s.length_m = (end_m[0] - start_m[0]).hypot(end_m[1] - start_m[1]);
    }
    out
}

/// The `links − 1` inner rollers of a strand of `links` links of one pitch
/// from `a` to `b` (chord c ≤ the links' length), a pitch apart along the
/// parabola y = 4 s u (1 − u) over the chord whose arc length is the links'
/// length, sagging on the side gravity pulls to. The arc length of that
/// parabola with a = 4 s / c is (c / 2) (√(1 + a²) + asinh(a) / a), and
/// from u = 0 to u it is (c / 2) (F(1) − F(1 − 2u)), F(v) = (v √(1 + a²v²)
/// + asinh(a v) / a) / 2.
fn hang(
    a: [f64; 2],
    b: [f64; 2],
    links: usize,
    pitch_m: f64,
    gravity_m_s2: [f64; 2],
) -> Vec<[f64; 2]> {
    let d = [b[0] - a[0], b[1] - a[1]];
    let c = d[0].hypot(d[1]);
    let inner = links.saturating_sub(1);
    let straight = |u: f64| [a[0] + u * d[0], a[1] + u * d[1]];
    if !(c > 0.0) || links == 0 {
        return (1..=inner)
            .map(|q| straight(q as f64 / links as f64))
            .collect();
    }
    let t = [d[0] / c, d[1] / c];
    // The chord's normal on gravity's side.
    let mut n = [-t[1], t[0]];
    if n[0] * gravity_m_s2[0] + n[1] * gravity_m_s2[1] < 0.0 {
        n = [-n[0], -n[1]];
    }
    // The links' length as the arc; a chord longer than the links (the
    // closing strand's residual) stays straight, its links a little long.
    let sag = sag_of(c, links as f64 * pitch_m);
    let k = 4.0 * sag / c;
    let f = parabola_f;
    let total = c * f(k, 1.0);
    (1..=inner)
        .map(|q| {
            // u where the arc from u = 0 is q / links of the whole.
            let goal = total * q as f64 / links as f64;
            let (mut u0, mut u1) = (0.0, 1.0);
            for _ in 0..60 {
                let u = 0.5 * (u0 + u1);
                if 0.5 * c * (f(k, 1.0) - f(k, 1.0 - 2.0 * u)) < goal {
                    u0 = u;
                } else {
                    u1 = u;
                }
            }
            let u = 0.5 * (u0 + u1);
            let p = straight(u);
            let y = 4.0 * sag * u * (1.0 - u);
            [p[0] + y * n[0], p[1] + y * n[1]]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::chain_path;

    /// Two equal circles of 20 teeth, P = 25.4 mm, 3 m apart, both
    /// counter-clockwise (a conveyor: strand 0 below, strand 1 above).
    fn conveyor() -> (Vec<PathCircle>, Vec<u32>, f64) {
        let pitch = 0.0254;
        let r = pitch / (2.0 * (std::f64::consts::PI / 20.0).sin());
        let circle = |x: f64| PathCircle {
            center_m: [x, 0.0],
            radius_m: r,
            sense: 1.0,
        };
        (vec![circle(0.0), circle(3.0)], vec![20, 20], pitch)
    }

    #[test]
    fn a_chain_longer_than_its_path_hangs_in_its_strands_with_links_of_one_pitch() {
        let (circles, teeth, pitch) = conveyor();
        let path = chain_path(&circles).expect("a path");
        let needed = needed_pitches(&path, &circles, &teeth, pitch).expect("walks");
        let rollers = needed.round() as usize + 6;
        let gravity = [0.0, -9.81];
        // Too long for the straight layout, laid hanging under gravity.
        assert!(layout_rollers(&path, &circles, &teeth, rollers, pitch).is_err());
        let layout =
            layout_hanging(&path, &circles, &teeth, rollers, pitch, gravity).expect("hangs");
        assert!(layout.hanging);
        assert_eq!(layout.rollers_m.len(), rollers);
        // Every link one pitch long (the closing strand's residual aside:
        // within half a pitch over its links, well under 1e-4 of P here).
        let n = rollers;
        for i in 0..n {
            let (a, b) = (layout.rollers_m[i], layout.rollers_m[(i + 1) % n]);
            let l = (b[0] - a[0]).hypot(b[1] - a[1]);
            assert!((l / pitch - 1.0).abs() < 1e-4, "link {i}: {l} m");
        }
        // Each strand sags below the chord between its end rollers on
        // gravity's side, as deep as the shallow parabola whose arc exceeds
        // the chord c by e = links · P − c: 8 s² / (3 c) = e, s = √(3 c e / 8)
        // (within 3 %: the arc's next term, −(32/5) s⁴/c³, is 2.4 (s/c)² of
        // e, about 2.5 % here at s ≈ 0.1 c, 1.2 % of s).
        let (mut k, mut seen) = (0, 0);
        while k < n {
            if layout.seats[k].is_some() || layout.seats[(k + n - 1) % n].is_none() {
                k += 1;
                continue;
            }
            // A strand starts after seated roller k − 1.
            let start = layout.rollers_m[(k + n - 1) % n];
            let mut end = k;
            while layout.seats[end % n].is_none() {
                end += 1;
            }
            let finish = layout.rollers_m[end % n];
            let links = end - k + 1;
            let d = [finish[0] - start[0], finish[1] - start[1]];
            let c = d[0].hypot(d[1]);
            let below = |p: [f64; 2]| {
                // Distance below the chord (its normal pointing down).
                let nrm = if d[0] > 0.0 {
                    [d[1] / c, -d[0] / c]
                } else {
                    [-d[1] / c, d[0] / c]
                };
                (p[0] - start[0]) * nrm[0] + (p[1] - start[1]) * nrm[1]
            };
            let sag = (k..end)
                .map(|i| below(layout.rollers_m[i % n]))
                .fold(0.0, f64::max);
            let e = links as f64 * pitch - c;
            let expected = (3.0 * c * e / 8.0).sqrt();
            assert!(e > 2.0 * pitch, "strand from roller {k}: {e} m of excess");
            assert!(
                (sag / expected - 1.0).abs() < 0.03,
                "strand from roller {k}: sag {sag} m, shallow parabola {expected} m"
            );
            seen += 1;
            k = end;
        }
        assert_eq!(seen, 2, "two strands");
    }

    #[test]
    fn without_gravity_a_long_chain_is_refused_as_before() {
        let (circles, teeth, pitch) = conveyor();
        let path = chain_path(&circles).expect("a path");
        let needed = needed_pitches(&path, &circles, &teeth, pitch).expect("walks");
        let rollers = needed.round() as usize + 6;
        let err = layout_hanging(&path, &circles, &teeth, rollers, pitch, [0.0, 0.0])
            .expect_err("nothing sags");
        assert!(matches!(err, LayoutError::ChainLength { .. }), "{err}");
        // A short chain is refused under gravity too.
        let err = layout_hanging(&path, &circles, &teeth, rollers - 12, pitch, [0.0, -9.81])
            .expect_err("too short");
        assert!(matches!(err, LayoutError::ChainLength { .. }), "{err}");
    }
}
