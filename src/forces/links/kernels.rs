//! The links' kernels: the law of one link and the loops over the chain
//! (the open links, the kept geometry, the velocities, each roller's sums),
//! each compiled for the baseline target and for AVX2, chosen at run time.

use crate::model::DriveModel;
#[cfg(test)]
use crate::model::DriveState;

/// The link law for one link.
#[derive(Clone, Copy)]
pub(super) struct LinkLaw {
    pub(super) stiffness: f64,
    pub(super) damping: f64,
    pub(super) rest: f64,
}

impl LinkLaw {
    /// The chain's link law.
    pub(super) fn of(model: &DriveModel) -> Self {
        Self {
            stiffness: model.stiffness_n_m,
            damping: model.damping_n_s_m,
            rest: model.rest_length_m,
        }
    }

    /// From the link vector d = q_j − q_i and the velocity difference:
    /// (F_link, u_x, u_y, l − rest, 1/l).
    #[inline(always)]
    pub(super) fn eval(&self, dx: f64, dy: f64, dvx: f64, dvy: f64) -> (f64, f64, f64, f64, f64) {
        let (ux, uy, stretch, inv) = self.geometry(dx, dy);
        let f = self.stiffness * stretch + self.damping * (dvx * ux + dvy * uy);
        (f, ux, uy, stretch, inv)
    }

    /// What depends on the link vector d alone: (u_x, u_y, l − rest, 1/l).
    #[inline(always)]
    pub(super) fn geometry(&self, dx: f64, dy: f64) -> (f64, f64, f64, f64) {
        let l = (dx * dx + dy * dy).sqrt();
        // Coincident rollers have no direction: no force rather than NaN (the
        // blow-up detector stops the run, the stretch being a whole pitch).
        let inv = if l > 0.0 { 1.0 / l } else { 0.0 };
        (dx * inv, dy * inv, l - self.rest, inv)
    }
}

/// A link's angular velocity ω = (u × Δv)/ℓ and its normal over its length
/// n/ℓ = (−u_y, u_x)/ℓ, from its unit vector u, 1/ℓ and the velocity
/// difference Δv (all zero for coincident rollers, whose 1/ℓ is 0).
#[inline(always)]
pub(super) fn rates(ux: f64, uy: f64, inv: f64, dvx: f64, dvy: f64) -> (f64, f64, f64) {
    ((ux * dvy - uy * dvx) * inv, -uy * inv, ux * inv)
}

/// Each link's ω and n/ℓ (see [`rates`]) at state `s`, into slices of one
/// slot per link: what the links' pass writes into [`Forces::link_omega`]
/// and its normals when they were asked for (a test's slow reference).
#[cfg(test)]
pub(crate) fn link_rates(
    s: &DriveState,
    omega: &mut [f64],
    normal_x: &mut [f64],
    normal_y: &mut [f64],
) {
    let n = s.x.len();
    let law = LinkLaw {
        stiffness: 0.0,
        damping: 0.0,
        rest: 0.0,
    };
    for (j, ((w, gx), gy)) in omega
        .iter_mut()
        .zip(normal_x.iter_mut())
        .zip(normal_y.iter_mut())
        .enumerate()
        .take(n)
    {
        let k = if j + 1 == n { 0 } else { j + 1 };
        let (dvx, dvy) = (s.vx[k] - s.vx[j], s.vy[k] - s.vy[j]);
        let (_, ux, uy, _, inv) = law.eval(s.x[k] - s.x[j], s.y[k] - s.y[j], dvx, dvy);
        (*w, *gx, *gy) = rates(ux, uy, inv, dvx, dvy);
    }
}

/// The rollers' positions and speeds, as the links read them.
pub(super) struct Ends<'a> {
    pub(super) x: &'a [f64],
    pub(super) y: &'a [f64],
    pub(super) vx: &'a [f64],
    pub(super) vy: &'a [f64],
}

/// The links' outputs, one slot per link: force, its vector on the first
/// roller, and stretch.
pub(super) struct Slots<'a> {
    pub(super) force: &'a mut [f64],
    pub(super) fx: &'a mut [f64],
    pub(super) fy: &'a mut [f64],
    pub(super) stretch: &'a mut [f64],
}

/// Each link's ω and n/ℓ, one slot per link (for the joint friction).
pub(super) struct Rates<'a> {
    pub(super) omega: &'a mut [f64],
    pub(super) normal_x: &'a mut [f64],
    pub(super) normal_y: &'a mut [f64],
}

/// The open links 0..n−1 (the closing link is the caller's), with their
/// rates when asked. Compiled for the baseline target and, where the CPU
/// has it, for AVX2, chosen at run time as RustFFT chooses its kernels: four
/// lanes instead of two, the same operations in the same order, so the same
/// bits (test `avx2_and_baseline_links_agree_to_the_bit`).
pub(super) fn open_links(law: LinkLaw, ends: Ends, slots: Slots, rates: Option<Rates>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { open_links_avx2(law, ends, slots, rates) };
    }
    open_links_body(law, ends, slots, rates);
}

/// [`open_links_body`] compiled with AVX2 (no FMA: products and sums stay
/// separately rounded, as in the baseline build).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn open_links_avx2(law: LinkLaw, ends: Ends, slots: Slots, rates: Option<Rates>) {
    open_links_body(law, ends, slots, rates);
}

/// A branch-free loop over zipped slices, which the compiler vectorises
/// (square roots and divisions two or four at a time).
#[inline(always)]
pub(super) fn open_links_body(law: LinkLaw, ends: Ends, slots: Slots, with_rates: Option<Rates>) {
    let Ends { x, y, vx, vy } = ends;
    let n = x.len();
    let pairs = x[..n - 1]
        .iter()
        .zip(&x[1..])
        .zip(y[..n - 1].iter().zip(&y[1..]))
        .zip(vx[..n - 1].iter().zip(&vx[1..]))
        .zip(vy[..n - 1].iter().zip(&vy[1..]));
    let outs = slots.force[..n - 1]
        .iter_mut()
        .zip(slots.fx[..n - 1].iter_mut())
        .zip(slots.fy[..n - 1].iter_mut())
        .zip(slots.stretch[..n - 1].iter_mut());
    let Some(slots_rates) = with_rates else {
        for (((((x0, x1), (y0, y1)), (vx0, vx1)), (vy0, vy1)), (((f, fx), fy), st)) in
            pairs.zip(outs)
        {
            let (force_n, ux, uy, s, _) = law.eval(x1 - x0, y1 - y0, vx1 - vx0, vy1 - vy0);
            *f = force_n;
            *fx = force_n * ux;
            *fy = force_n * uy;
            *st = s;
        }
        return;
    };
    // The same loop, also writing each link's ω and n/ℓ from the u and 1/ℓ
    // it has at hand.
    let rate_outs = slots_rates.omega[..n - 1]
        .iter_mut()
        .zip(slots_rates.normal_x[..n - 1].iter_mut())
        .zip(slots_rates.normal_y[..n - 1].iter_mut());
    for (((((x0, x1), (y0, y1)), (vx0, vx1)), (vy0, vy1)), ((((f, fx), fy), st), ((w, gx), gy))) in
        pairs.zip(outs.zip(rate_outs))
    {
        let (dvx, dvy) = (vx1 - vx0, vy1 - vy0);
        let (force_n, ux, uy, s, inv) = law.eval(x1 - x0, y1 - y0, dvx, dvy);
        *f = force_n;
        *fx = force_n * ux;
        *fy = force_n * uy;
        *st = s;
        (*w, *gx, *gy) = rates(ux, uy, inv, dvx, dvy);
    }
}

/// The kept geometry's slots being written, with the stretches.
pub(super) struct Shape<'a> {
    pub(super) ux: &'a mut [f64],
    pub(super) uy: &'a mut [f64],
    pub(super) spring: &'a mut [f64],
    pub(super) inv: &'a mut [f64],
    pub(super) stretch: &'a mut [f64],
}

/// The kept geometry, as the velocities' pass reads it.
#[derive(Clone, Copy)]
pub(super) struct KeptShape<'a> {
    pub(super) ux: &'a [f64],
    pub(super) uy: &'a [f64],
    pub(super) spring: &'a [f64],
    pub(super) inv: &'a [f64],
}

/// Each link's geometry (all n links, the last closing the loop) from the
/// rollers' positions, as [`LinkLaw::eval`] computes it, and its n/ℓ where
/// `normals` asks (as [`rates`]). Compiled for AVX2 where the CPU has it
/// (element-wise: the same bits).
pub(super) fn link_geometry(
    law: LinkLaw,
    x: &[f64],
    y: &[f64],
    shape: Shape,
    normals: Option<(&mut [f64], &mut [f64])>,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { link_geometry_avx2(law, x, y, shape, normals) };
    }
    link_geometry_body(law, x, y, shape, normals);
}

/// [`link_geometry_body`] compiled with AVX2 (no FMA).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn link_geometry_avx2(
    law: LinkLaw,
    x: &[f64],
    y: &[f64],
    shape: Shape,
    normals: Option<(&mut [f64], &mut [f64])>,
) {
    link_geometry_body(law, x, y, shape, normals);
}

#[inline(always)]
fn link_geometry_body(
    law: LinkLaw,
    x: &[f64],
    y: &[f64],
    shape: Shape,
    normals: Option<(&mut [f64], &mut [f64])>,
) {
    let n = x.len();
    let Shape {
        ux,
        uy,
        spring,
        inv,
        stretch,
    } = shape;
    let (y, ux, uy) = (&y[..n], &mut ux[..n], &mut uy[..n]);
    let (spring, inv, stretch) = (&mut spring[..n], &mut inv[..n], &mut stretch[..n]);
    let mut link = |j: usize, dx: f64, dy: f64| {
        let (u_x, u_y, st, i) = law.geometry(dx, dy);
        (ux[j], uy[j], stretch[j], inv[j]) = (u_x, u_y, st, i);
        spring[j] = law.stiffness * st;
    };
    for j in 0..n - 1 {
        link(j, x[j + 1] - x[j], y[j + 1] - y[j]);
    }
    link(n - 1, x[0] - x[n - 1], y[0] - y[n - 1]);
    if let Some((gx, gy)) = normals {
        let (gx, gy) = (&mut gx[..n], &mut gy[..n]);
        for j in 0..n {
            (gx[j], gy[j]) = (-uy[j] * inv[j], ux[j] * inv[j]);
        }
    }
}

/// Each link's force from its kept geometry and the rollers' velocities
/// (all n links, the last closing the loop), as [`LinkLaw::eval`] computes
/// it, its vector, and its ω where `omega` asks (as [`rates`]). Compiled
/// for AVX2 where the CPU has it (element-wise: the same bits).
pub(super) fn link_velocities(
    damping: f64,
    v: [&[f64]; 2],
    shape: KeptShape,
    slots: Slots,
    omega: Option<&mut [f64]>,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { link_velocities_avx2(damping, v, shape, slots, omega) };
    }
    link_velocities_split(damping, v, shape, slots, omega);
}

/// [`link_velocities_split`] compiled with AVX2 (no FMA).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn link_velocities_avx2(
    damping: f64,
    v: [&[f64]; 2],
    shape: KeptShape,
    slots: Slots,
    omega: Option<&mut [f64]>,
) {
    link_velocities_split(damping, v, shape, slots, omega);
}

/// One loop with the rates' ω, one without, over zipped slices (no bounds
/// checks, no branches: the compiler vectorises them), then the closing
/// link.
#[inline(always)]
fn link_velocities_split(
    damping: f64,
    v: [&[f64]; 2],
    shape: KeptShape,
    slots: Slots,
    omega: Option<&mut [f64]>,
) {
    let [vx, vy] = v;
    let n = vx.len();
    let m = n - 1;
    let KeptShape {
        ux,
        uy,
        spring,
        inv,
    } = shape;
    let (ux, uy, spring, inv) = (&ux[..n], &uy[..n], &spring[..n], &inv[..n]);
    let (force, fx, fy) = (
        &mut slots.force[..n],
        &mut slots.fx[..n],
        &mut slots.fy[..n],
    );
    // The force of a link as `LinkLaw::eval` computes it.
    let law = |spring: f64, ux: f64, uy: f64, dvx: f64, dvy: f64| {
        spring + damping * (dvx * ux + dvy * uy)
    };
    let pairs = vx[..m]
        .iter()
        .zip(&vx[1..])
        .zip(vy[..m].iter().zip(&vy[1..]));
    let shapes = ux[..m].iter().zip(&uy[..m]).zip(&spring[..m]);
    let (dvx, dvy) = (vx[0] - vx[m], vy[0] - vy[m]);
    let closing = law(spring[m], ux[m], uy[m], dvx, dvy);
    (force[m], fx[m], fy[m]) = (closing, closing * ux[m], closing * uy[m]);
    let outs = force[..m]
        .iter_mut()
        .zip(fx[..m].iter_mut())
        .zip(fy[..m].iter_mut());
    let Some(omega) = omega else {
        for ((((vx0, vx1), (vy0, vy1)), ((u_x, u_y), sp)), ((f, f_x), f_y)) in
            pairs.zip(shapes).zip(outs)
        {
            let force_n = law(*sp, *u_x, *u_y, vx1 - vx0, vy1 - vy0);
            (*f, *f_x, *f_y) = (force_n, force_n * u_x, force_n * u_y);
        }
        return;
    };
    let omega = &mut omega[..n];
    omega[m] = (ux[m] * dvy - uy[m] * dvx) * inv[m];
    let rates = omega[..m].iter_mut().zip(&inv[..m]);
    for ((((vx0, vx1), (vy0, vy1)), ((u_x, u_y), sp)), (((f, f_x), f_y), (w, i))) in
        pairs.zip(shapes).zip(outs.zip(rates))
    {
        let (dvx, dvy) = (vx1 - vx0, vy1 - vy0);
        let force_n = law(*sp, *u_x, *u_y, dvx, dvy);
        (*f, *f_x, *f_y) = (force_n, force_n * u_x, force_n * u_y);
        *w = (u_x * dvy - u_y * dvx) * i;
    }
}

/// Each roller's force, its weight plus its two links (`prev` the link
/// before the first roller: the last link, for a whole chain), and the links'
/// checks: whether a stretch is NaN, the largest |stretch| and the largest
/// squared roller speed. Compiled for AVX2 where the CPU has it, as
/// [`open_links`] is (element-wise sums and maxima: the same bits).
pub(super) fn roller_sums(
    weight: [f64; 2],
    link_f: [&[f64]; 2],
    prev: [f64; 2],
    roller_f: [&mut [f64]; 2],
    stretch: &[f64],
    v: [&[f64]; 2],
) -> (bool, f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { roller_sums_avx2(weight, link_f, prev, roller_f, stretch, v) };
    }
    roller_sums_body(weight, link_f, prev, roller_f, stretch, v)
}

/// [`roller_sums_body`] compiled with AVX2 (no FMA).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn roller_sums_avx2(
    weight: [f64; 2],
    link_f: [&[f64]; 2],
    prev: [f64; 2],
    roller_f: [&mut [f64]; 2],
    stretch: &[f64],
    v: [&[f64]; 2],
) -> (bool, f64, f64) {
    roller_sums_body(weight, link_f, prev, roller_f, stretch, v)
}

#[inline(always)]
fn roller_sums_body(
    weight: [f64; 2],
    link_f: [&[f64]; 2],
    prev: [f64; 2],
    roller_f: [&mut [f64]; 2],
    stretch: &[f64],
    v: [&[f64]; 2],
) -> (bool, f64, f64) {
    // `max` drops a NaN: keep it visible to the blow-up check.
    let (nan, max_stretch) = largest_abs(stretch);
    let max_speed_sq = largest(v[0], v[1], |a, b| a * a + b * b);
    for (((f, l), g), p) in roller_f.into_iter().zip(link_f).zip(weight).zip(prev) {
        let n = f.len().min(l.len());
        let (f, l) = (&mut f[..n], &l[..n]);
        f[0] = g + (l[0] - p);
        // Roller i between links i − 1 and i.
        for ((f, l1), l0) in f[1..].iter_mut().zip(&l[1..]).zip(&l[..n - 1]) {
            *f = g + (l1 - l0);
        }
    }
    (nan, max_stretch, max_speed_sq)
}

/// Whether `values` holds a NaN, and the largest |value| (at least 0, NaN
/// dropped, as [`largest`] takes it), in one pass of four lanes.
#[inline(always)]
fn largest_abs(values: &[f64]) -> (bool, f64) {
    let larger = |m: f64, v: f64| if v > m { v } else { m };
    let mut lanes = [0.0f64; 4];
    let mut nan = [false; 4];
    let chunks = values.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for k in 0..4 {
            nan[k] |= c[k].is_nan();
            lanes[k] = larger(lanes[k], c[k].abs());
        }
    }
    let tail_nan = rest.iter().any(|v| v.is_nan());
    let tail = rest.iter().fold(0.0f64, |m, v| larger(m, v.abs()));
    (
        tail_nan | nan.into_iter().any(|b| b),
        lanes.into_iter().fold(tail, larger),
    )
}

/// The largest `f(a_i, b_i)`, at least 0, in four independent lanes of plain
/// comparisons, which the compiler turns into packed `max` instructions. A
/// NaN is dropped, as by `f64::max` (the links report NaN stretches apart; a
/// NaN speed comes with a NaN position, which the blow-up check stops on).
#[inline(always)]
pub(super) fn largest(a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) -> f64 {
    let larger = |m: f64, v: f64| if v > m { v } else { m };
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut lanes = [0.0f64; 4];
    for (ca, cb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for k in 0..4 {
            lanes[k] = larger(lanes[k], f(ca[k], cb[k]));
        }
    }
    let tail = n - n % 4;
    let rest = a[tail..]
        .iter()
        .zip(&b[tail..])
        .fold(0.0f64, |m, (&x, &y)| larger(m, f(x, y)));
    lanes.into_iter().fold(rest, larger)
}

#[cfg(test)]
mod tests {
    use super::{Ends, LinkLaw, Rates, Slots, largest, open_links_body};
    use crate::model::DriveModel;

    #[test]
    fn avx2_and_baseline_links_agree_to_the_bit() {
        // The run-time choice of kernel changes no result: both builds of
        // the open links' loop, with and without rates, on the paper's drive
        // with a disturbed velocity field, give the same bits.
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let scene = crate::scene::Scene::l60mc();
            let (model, mut s, _) = DriveModel::build(&scene).expect("paper's drive lays out");
            let n = s.rollers();
            for i in 0..n {
                s.x[i] += ((i * 3 % 7) as f64 - 3.0) * 1e-4;
                s.vx[i] += ((i * 7 % 11) as f64 - 5.0) * 0.3;
                s.vy[i] += ((i * 5 % 13) as f64 - 6.0) * 0.2;
            }
            let law = LinkLaw::of(&model);
            let run = |avx2: bool, with_rates: bool| {
                let mut v = vec![vec![0.0; n]; 7];
                let [force, fx, fy, stretch, omega, gx, gy] = &mut v[..] else {
                    unreachable!("seven buffers")
                };
                let ends = Ends {
                    x: &s.x,
                    y: &s.y,
                    vx: &s.vx,
                    vy: &s.vy,
                };
                let slots = Slots {
                    force,
                    fx,
                    fy,
                    stretch,
                };
                let rates = with_rates.then_some(Rates {
                    omega,
                    normal_x: gx,
                    normal_y: gy,
                });
                if avx2 {
                    // SAFETY: the CPU has AVX2, checked above.
                    unsafe { super::open_links_avx2(law, ends, slots, rates) }
                } else {
                    open_links_body(law, ends, slots, rates)
                }
                v.concat().iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            };
            for with_rates in [false, true] {
                let wide = run(true, with_rates);
                assert!(wide.iter().any(|b| *b != 0));
                assert_eq!(wide, run(false, with_rates), "rates: {with_rates}");
            }
        }
    }

    #[test]
    fn largest_matches_the_plain_fold() {
        // Oracle: `f64::max` over the items (NaNs dropped), at least 0; every
        // length 0..12 (so every tail of the four lanes), mixed signs.
        let a: Vec<f64> = (0..12).map(|k| ((k * 7 % 5) as f64 - 2.0) * 0.3).collect();
        let b: Vec<f64> = (0..12).map(|k| ((k * 3 % 7) as f64 - 3.0) * 0.2).collect();
        for n in 0..=12 {
            let f = |x: f64, y: f64| x * y + x;
            let plain = a[..n]
                .iter()
                .zip(&b[..n])
                .fold(0.0f64, |m, (&x, &y)| m.max(f(x, y)));
            assert_eq!(largest(&a[..n], &b[..n], f), plain, "n = {n}");
        }
        let with_nan = [1.0, f64::NAN, 3.0, -4.0, 2.0];
        assert_eq!(largest(&with_nan, &with_nan, |x, _| x.abs()), 4.0);
    }
}
