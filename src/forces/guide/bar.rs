//! The contact of a fixed straight guide without ramps (a guide bar, a wear
//! strip) on a run of consecutive candidate rollers, in two loops:
//!
//! 1. **Each roller**, branch-free, which the compiler vectorises: the
//!    guide's query ([`Straight::query_parts`]), the law, the friction, the
//!    roller's force (added where it touches) and its parts of the shoe's
//!    sums, into per-roller scratch.
//! 2. **The sums**, in roller order, over the rollers that touch.
//!
//! The same operations in the same order as the general kernel
//! ([`super::Guide::contact`]), so the same bits (the oracle test
//! `guide_culling_changes_nothing` compares them). Not for a carried shoe,
//! ramps or an arc.

use super::ShoeForces;
use crate::forces::ContactLawParams;
use crate::geometry::shoe::Straight;

/// Per-roller scratch of the bar's kernel, sized once (nothing is allocated
/// per evaluation).
#[derive(Clone, Debug, Default)]
pub(super) struct BarScratch {
    /// 1 where the roller touches the guide.
    pub(super) hit: Vec<u8>,
    fx: Vec<f64>,
    fy: Vec<f64>,
    /// The reaction's moment term r × f.
    moment: Vec<f64>,
    normal: Vec<f64>,
    /// |f_t|.
    friction: Vec<f64>,
    depth: Vec<f64>,
    energy: Vec<f64>,
    power: Vec<f64>,
}

impl BarScratch {
    pub(super) fn new(rollers: usize) -> Self {
        let zeros = || vec![0.0; rollers];
        Self {
            hit: vec![0; rollers],
            fx: zeros(),
            fy: zeros(),
            moment: zeros(),
            normal: zeros(),
            friction: zeros(),
            depth: zeros(),
            energy: zeros(),
            power: zeros(),
        }
    }
}

/// What the bar's kernel reads besides the rollers.
#[derive(Clone, Copy)]
pub(super) struct Bar {
    pub(super) face: Straight,
    pub(super) law: ContactLawParams,
    /// μ and the slip speed v_s, m/s.
    pub(super) friction: (f64, f64),
    pub(super) radius_m: f64,
    /// The face's bounds, [min x, min y, max x, max y], m.
    pub(super) bounds_m: [f64; 4],
    /// The weight of the force added to the rollers (the impulse's steps).
    pub(super) weight: f64,
}

/// The rollers' state and outputs over one run.
pub(super) struct Rollers<'a> {
    pub(super) x: &'a [f64],
    pub(super) y: &'a [f64],
    pub(super) vx: &'a [f64],
    pub(super) vy: &'a [f64],
    pub(super) onset: &'a [f64],
    pub(super) pending: &'a mut [f64],
    pub(super) fx: &'a mut [f64],
    pub(super) fy: &'a mut [f64],
}

/// The totals the sums loop adds to.
pub(super) struct Totals<'a> {
    pub(super) sums: &'a mut ShoeForces,
    pub(super) energy: &'a mut f64,
    pub(super) damping_power: &'a mut f64,
    /// The largest normal force on one roller.
    pub(super) largest_normal: &'a mut f64,
}

/// The contact of the rollers of one run with the bar; `scratch` is indexed
/// from the run's first roller.
pub(super) fn run(
    bar: &Bar,
    mut rollers: Rollers<'_>,
    scratch: &mut BarScratch,
    avx2: bool,
    totals: Totals<'_>,
) {
    let n = rollers.x.len();
    // One loop per law shape: a branch on the exponent inside the loop
    // would be turned into both sides computed and one chosen, `powf`
    // included.
    let law = bar.law;
    if law.hertz() {
        let k = law.stiffness;
        each_roller(bar, &mut rollers, scratch, avx2, |d| k * d * d.sqrt());
    } else {
        each_roller(bar, &mut rollers, scratch, avx2, |d| law.elastic(d));
    }
    let Totals {
        sums,
        energy,
        damping_power,
        largest_normal,
    } = totals;
    // Slices of one length and the totals in locals: no bounds checks and
    // no stores in the loop.
    let s = &*scratch;
    let m = n.min(s.hit.len());
    let (hit, fx, fy, moment) = (&s.hit[..m], &s.fx[..m], &s.fy[..m], &s.moment[..m]);
    let (normal, friction, depth) = (&s.normal[..m], &s.friction[..m], &s.depth[..m]);
    let (e, p) = (&s.energy[..m], &s.power[..m]);
    let mut t = *sums;
    let (mut energy_j, mut power_w) = (*energy, *damping_power);
    let mut largest = *largest_normal;
    for i in 0..m {
        if hit[i] == 0 {
            continue;
        }
        t.moment_n_m -= moment[i];
        t.force_n[0] -= fx[i];
        t.force_n[1] -= fy[i];
        t.normal_n += normal[i];
        if normal[i] > largest {
            largest = normal[i];
        }
        t.friction_n += friction[i];
        t.contacts += 1;
        // `f64::max` drops a NaN depth; the running maximum starts at 0 and
        // is never NaN, so a plain comparison gives the same bits.
        if depth[i] > t.max_penetration_m {
            t.max_penetration_m = depth[i];
        }
        energy_j += e[i];
        power_w += p[i];
    }
    *sums = t;
    (*energy, *damping_power) = (energy_j, power_w);
    *largest_normal = largest;
}

/// The per-roller loop for the CPU (AVX2 where it has it; the same bits).
#[inline(always)]
fn each_roller(
    bar: &Bar,
    r: &mut Rollers<'_>,
    s: &mut BarScratch,
    avx2: bool,
    elastic_of: impl Fn(f64) -> f64 + Copy,
) {
    let _ = avx2;
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is set only where the CPU has AVX2.
        unsafe {
            each_roller_avx2(
                bar,
                elastic_of,
                r.x,
                r.y,
                r.vx,
                r.vy,
                r.onset,
                r.pending,
                r.fx,
                r.fy,
                &mut s.hit,
                &mut s.fx,
                &mut s.fy,
                &mut s.moment,
                &mut s.normal,
                &mut s.friction,
                &mut s.depth,
                &mut s.energy,
                &mut s.power,
            );
        }
        return;
    }
    each_roller_body(
        bar,
        elastic_of,
        r.x,
        r.y,
        r.vx,
        r.vy,
        r.onset,
        r.pending,
        r.fx,
        r.fy,
        &mut s.hit,
        &mut s.fx,
        &mut s.fy,
        &mut s.moment,
        &mut s.normal,
        &mut s.friction,
        &mut s.depth,
        &mut s.energy,
        &mut s.power,
    );
}

/// [`each_roller_body`] compiled with AVX2 (no FMA: the same roundings).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
fn each_roller_avx2(
    bar: &Bar,
    elastic_of: impl Fn(f64) -> f64,
    xs: &[f64],
    ys: &[f64],
    vxs: &[f64],
    vys: &[f64],
    onset: &[f64],
    pending: &mut [f64],
    fx_out: &mut [f64],
    fy_out: &mut [f64],
    hit: &mut [u8],
    fxs: &mut [f64],
    fys: &mut [f64],
    moment: &mut [f64],
    normal: &mut [f64],
    friction: &mut [f64],
    depth_out: &mut [f64],
    energy: &mut [f64],
    power: &mut [f64],
) {
    each_roller_body(
        bar, elastic_of, xs, ys, vxs, vys, onset, pending, fx_out, fy_out, hit, fxs, fys, moment,
        normal, friction, depth_out, energy, power,
    );
}

/// Each roller of the run against the bar, without branches; the
/// expressions of [`super::Guide::contact`] with the fixed pose (no
/// rotation, pivot at the origin, at rest). Slices as arguments tell the
/// compiler they do not overlap, so it vectorises the loop.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn each_roller_body(
    bar: &Bar,
    elastic_of: impl Fn(f64) -> f64,
    xs: &[f64],
    ys: &[f64],
    vxs: &[f64],
    vys: &[f64],
    onset: &[f64],
    pending: &mut [f64],
    fx_out: &mut [f64],
    fy_out: &mut [f64],
    hit: &mut [u8],
    fxs: &mut [f64],
    fys: &mut [f64],
    moment: &mut [f64],
    normal: &mut [f64],
    friction: &mut [f64],
    depth_out: &mut [f64],
    energy: &mut [f64],
    power: &mut [f64],
) {
    let n = xs.len();
    let (ys, vxs, vys, onset) = (&ys[..n], &vxs[..n], &vys[..n], &onset[..n]);
    let (pending, fx_out, fy_out) = (&mut pending[..n], &mut fx_out[..n], &mut fy_out[..n]);
    let (hit, fxs, fys, moment) = (
        &mut hit[..n],
        &mut fxs[..n],
        &mut fys[..n],
        &mut moment[..n],
    );
    let (normal, friction, depth_out) = (&mut normal[..n], &mut friction[..n], &mut depth_out[..n]);
    let (energy, power) = (&mut energy[..n], &mut power[..n]);
    // The fixed pose: R(−q) = identity, pivot at the origin, ω = 0.
    let (cos_q, sin_q, pivot, omega) = (1.0, 0.0, [0.0f64, 0.0f64], 0.0);
    let law = bar.law;
    let (mu, v_s) = bar.friction;
    let r = bar.radius_m;
    let weight = bar.weight;
    let [x0, y0, x1, y1] = bar.bounds_m;
    let (lo_x, lo_y, hi_x, hi_y) = (x0 - r, y0 - r, x1 + r, y1 + r);
    let exponent_plus_one = law.exponent + 1.0;
    for i in 0..n {
        // Into the shoe's frame: p_l = pivot + R(−q)(p − pivot).
        let (dx, dy) = (xs[i] - pivot[0], ys[i] - pivot[1]);
        let px = pivot[0] + cos_q * dx + sin_q * dy;
        let py = pivot[1] - sin_q * dx + cos_q * dy;
        let in_box = !(px < lo_x || px > hi_x || py < lo_y || py > hi_y);
        let (some, face) = bar.face.query_parts([px, py]);
        let depth = r - face.distance_m;
        let on = in_box & some & (depth > 0.0) & !(depth >= 2.0 * r);
        // The roller's velocity relative to the shoe, in the shoe's frame.
        let (vwx, vwy) = (vxs[i] + omega * dy, vys[i] - omega * dx);
        let vx = cos_q * vwx + sin_q * vwy;
        let vy = -sin_q * vwx + cos_q * vwy;
        let [nx, ny] = face.normal;
        let rate = -(vx * nx + vy * ny);
        let damping = if onset[i] >= 0.0 {
            onset[i]
        } else {
            law.damping_per_speed(rate)
        };
        pending[i] = if on { damping } else { -1.0 };
        let elastic = elastic_of(depth);
        let f_n = (elastic * (1.0 + damping * rate)).max(0.0);
        let v_t = -vx * ny + vy * nx;
        let f_t = -mu * f_n * v_t / (v_t * v_t + v_s * v_s).sqrt();
        // Force on the roller in the shoe's frame, then in the world.
        let (flx, fly) = (f_n * nx - f_t * ny, f_n * ny + f_t * nx);
        let fx = cos_q * flx - sin_q * fly;
        let fy = sin_q * flx + cos_q * fly;
        fx_out[i] = if on {
            fx_out[i] + weight * fx
        } else {
            fx_out[i]
        };
        fy_out[i] = if on {
            fy_out[i] + weight * fy
        } else {
            fy_out[i]
        };
        // Its reaction on the shoe at the contact point (world).
        let (cx, cy) = (face.point_m[0] - pivot[0], face.point_m[1] - pivot[1]);
        let (cwx, cwy) = (cos_q * cx - sin_q * cy, sin_q * cx + cos_q * cy);
        hit[i] = u8::from(on);
        fxs[i] = fx;
        fys[i] = fy;
        moment[i] = cwx * fy - cwy * fx;
        normal[i] = f_n;
        friction[i] = f_t.abs();
        depth_out[i] = depth;
        energy[i] = elastic * depth / exponent_plus_one;
        power[i] = (f_n - elastic) * -rate + f_t * v_t;
    }
}
