//! The links: linear spring-dampers between consecutive rollers
//! (docs/model.md, “Links”), and the rollers' weight.

use super::{ForceElement, Forces, Halves, History, HistoryError, HistoryReader};

mod step;
use crate::model::{DriveModel, DriveState};
pub(crate) use step::{Kick, kick_drift};

/// The link law for one link.
#[derive(Clone, Copy)]
struct LinkLaw {
    stiffness: f64,
    damping: f64,
    rest: f64,
}

impl LinkLaw {
    /// The chain's link law.
    fn of(model: &DriveModel) -> Self {
        Self {
            stiffness: model.stiffness_n_m,
            damping: model.damping_n_s_m,
            rest: model.rest_length_m,
        }
    }

    /// From the link vector d = q_j − q_i and the velocity difference:
    /// (F_link, u_x, u_y, l − rest, 1/l).
    #[inline(always)]
    fn eval(&self, dx: f64, dy: f64, dvx: f64, dvy: f64) -> (f64, f64, f64, f64, f64) {
        let (ux, uy, stretch, inv) = self.geometry(dx, dy);
        let f = self.stiffness * stretch + self.damping * (dvx * ux + dvy * uy);
        (f, ux, uy, stretch, inv)
    }

    /// What depends on the link vector d alone: (u_x, u_y, l − rest, 1/l).
    #[inline(always)]
    fn geometry(&self, dx: f64, dy: f64) -> (f64, f64, f64, f64) {
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
fn rates(ux: f64, uy: f64, inv: f64, dvx: f64, dvy: f64) -> (f64, f64, f64) {
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
struct Ends<'a> {
    x: &'a [f64],
    y: &'a [f64],
    vx: &'a [f64],
    vy: &'a [f64],
}

/// The links' outputs, one slot per link: force, its vector on the first
/// roller, and stretch.
struct Slots<'a> {
    force: &'a mut [f64],
    fx: &'a mut [f64],
    fy: &'a mut [f64],
    stretch: &'a mut [f64],
}

/// Each link's ω and n/ℓ, one slot per link (for the joint friction).
struct Rates<'a> {
    omega: &'a mut [f64],
    normal_x: &'a mut [f64],
    normal_y: &'a mut [f64],
}

/// The open links 0..n−1 (the closing link is the caller's), with their
/// rates when asked. Compiled for the baseline target and, where the CPU
/// has it, for AVX2, chosen at run time as RustFFT chooses its kernels: four
/// lanes instead of two, the same operations in the same order, so the same
/// bits (test `avx2_and_baseline_links_agree_to_the_bit`).
fn open_links(law: LinkLaw, ends: Ends, slots: Slots, rates: Option<Rates>) {
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
fn open_links_body(law: LinkLaw, ends: Ends, slots: Slots, with_rates: Option<Rates>) {
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

/// The chain's links and the rollers' weight: the first force element of
/// every drive. It *sets* each roller's force to its weight plus its two
/// links (every later element adds to it), the links' forces, the largest
/// stretch and the largest roller speed.
#[derive(Clone, Debug)]
pub(crate) struct Links {
    /// Scratch: force vector of link i on roller i, N.
    link_fx: Vec<f64>,
    /// Scratch: its y component, N.
    link_fy: Vec<f64>,
    /// l − rest length of link i at the last evaluation, m.
    stretch: Vec<f64>,
    /// Whether the pass writes each link's ω and n/ℓ into
    /// [`Forces::link_omega`] and its normals: set by
    /// [`Links::request_rates`], which an element asks for through
    /// [`super::ForceElement::wants_link_rates`].
    rates: bool,
    /// What each evaluation keeps for one at the same positions
    /// ([`Links::keep_positions`]); `None`: nothing kept.
    kept: Option<Kept>,
}

/// What depends on the rollers' positions alone, one slot per link, kept
/// from an evaluation for [`Links::evaluate_again`].
#[derive(Clone, Debug)]
struct Kept {
    /// Unit vector u, x and y.
    ux: Vec<f64>,
    uy: Vec<f64>,
    /// Spring force K (l − rest), N.
    spring: Vec<f64>,
    /// 1/l, 1/m.
    inv: Vec<f64>,
    /// Whether the last evaluation kept them at its positions.
    valid: bool,
}

impl Links {
    /// Buffers for a chain of `rollers` rollers (and as many links).
    pub(crate) fn new(rollers: usize) -> Self {
        Self {
            link_fx: vec![0.0; rollers],
            link_fy: vec![0.0; rollers],
            stretch: vec![0.0; rollers],
            rates: false,
            kept: None,
        }
    }

    /// From now on (`keep`) each evaluation on one thread keeps what depends
    /// on the positions alone, for [`Self::evaluate_again`]; `false` keeps
    /// nothing.
    pub(crate) fn keep_positions(&mut self, keep: bool) {
        let n = self.stretch.len();
        self.kept = keep.then(|| Kept {
            ux: vec![0.0; n],
            uy: vec![0.0; n],
            spring: vec![0.0; n],
            inv: vec![0.0; n],
            valid: false,
        });
    }

    /// From now on, write each link's ω and n/ℓ into `out`'s
    /// [`Forces::link_omega`] and normals, sized here (once, not per step).
    pub(crate) fn request_rates(&mut self, out: &mut Forces) {
        let n = self.stretch.len();
        self.rates = true;
        out.link_omega.resize(n, 0.0);
        out.link_normal_x.resize(n, 0.0);
        out.link_normal_y.resize(n, 0.0);
    }

    /// l − rest length of each link at the last evaluation, m.
    pub(crate) fn stretch(&self) -> &[f64] {
        &self.stretch
    }

    /// Whether a pass over `n` links writes their rates: asked for, and
    /// `out`'s rate buffers sized for them.
    fn rates_fit(&self, out: &Forces, n: usize) -> bool {
        self.rates
            && out.link_omega.len() == n
            && out.link_normal_x.len() == n
            && out.link_normal_y.len() == n
    }
}

impl Links {
    /// [`ForceElement::evaluate`] with the rollers split in two halves, run
    /// by `fork` (module `sim::parallel`) in chunks: each chunk evaluates its
    /// own links and sums its own rollers' forces. The link before a chunk's
    /// first roller belongs to the chunk before; the chunk evaluates it
    /// again, with the same operations, so each roller's sum is the same
    /// bits as on one thread without waiting for the other chunk.
    pub(crate) fn evaluate_split(
        &mut self,
        model: &DriveModel,
        s: &DriveState,
        out: &mut Forces,
        fork: &dyn super::Fork,
    ) {
        self.forget_positions();
        let n = s.x.len();
        let law = LinkLaw::of(model);
        let (x, y, vx, vy) = (&s.x[..n], &s.y[..n], &s.vx[..n], &s.vy[..n]);
        let with_rates = self.rates_fit(out, n);
        let force = Halves::new(&mut out.link_force[..n]);
        let (lfx, lfy) = (
            Halves::new(&mut self.link_fx[..n]),
            Halves::new(&mut self.link_fy[..n]),
        );
        let stretch = Halves::new(&mut self.stretch[..n]);
        let (fx, fy) = (Halves::new(&mut out.fx[..n]), Halves::new(&mut out.fy[..n]));
        let rate_views = with_rates.then(|| {
            (
                Halves::new(&mut out.link_omega[..n]),
                Halves::new(&mut out.link_normal_x[..n]),
                Halves::new(&mut out.link_normal_y[..n]),
            )
        });
        // Per chunk: NaN stretch seen, largest |stretch|, largest speed².
        let mut partial = [0.0f64; 3 * super::CHUNKS];
        let parts = Halves::new(&mut partial);
        let mass = model.roller_mass_kg;
        let (gx, gy) = (mass * model.gravity_m_s2[0], mass * model.gravity_m_s2[1]);
        let half = |h: usize| {
            // Rollers lo..hi; links lo..hi too, the last chunk's last being
            // the closing link n−1 → 0.
            let (lo, hi) = super::chunk(n, h);
            let last = hi == n;
            let open_hi = if last { n - 1 } else { hi };
            // SAFETY: the two halves take disjoint ranges lo..hi of every
            // output, and the borrows behind the views outlive `fork.both`.
            unsafe {
                let slots = Slots {
                    force: force.range(lo, open_hi),
                    fx: lfx.range(lo, open_hi),
                    fy: lfy.range(lo, open_hi),
                    stretch: stretch.range(lo, open_hi),
                };
                let rates_h = rate_views.map(|(w, gx, gy)| Rates {
                    omega: w.range(lo, open_hi),
                    normal_x: gx.range(lo, open_hi),
                    normal_y: gy.range(lo, open_hi),
                });
                let ends = Ends {
                    x: &x[lo..=open_hi],
                    y: &y[lo..=open_hi],
                    vx: &vx[lo..=open_hi],
                    vy: &vy[lo..=open_hi],
                };
                open_links(law, ends, slots, rates_h);
                // The link before roller lo: j → lo, with j = lo − 1 (or the
                // closing link n − 1 for roller 0). The last chunk writes
                // the closing link; the first only reads it.
                let j = if lo == 0 { n - 1 } else { lo - 1 };
                let (dvx, dvy) = (vx[lo] - vx[j], vy[lo] - vy[j]);
                let (f, ux, uy, _, _) = law.eval(x[lo] - x[j], y[lo] - y[j], dvx, dvy);
                let (prev_x, prev_y) = (f * ux, f * uy);
                if last {
                    let k = n - 1;
                    let (dvx, dvy) = (vx[0] - vx[k], vy[0] - vy[k]);
                    let (f, ux, uy, last, inv) = law.eval(x[0] - x[k], y[0] - y[k], dvx, dvy);
                    force.range(k, n)[0] = f;
                    lfx.range(k, n)[0] = f * ux;
                    lfy.range(k, n)[0] = f * uy;
                    stretch.range(k, n)[0] = last;
                    if let Some((w, nx, ny)) = rate_views {
                        (w.range(k, n)[0], nx.range(k, n)[0], ny.range(k, n)[0]) =
                            rates(ux, uy, inv, dvx, dvy);
                    }
                }
                let st_h = &*stretch.range(lo, hi);
                let nan = st_h.iter().fold(false, |b, s| b | s.is_nan());
                let max_stretch = largest(st_h, st_h, |s, _| s.abs());
                let max_speed_sq = largest(&vx[lo..hi], &vy[lo..hi], |a, b| a * a + b * b);
                let (lx, ly) = (&*lfx.range(lo, hi), &*lfy.range(lo, hi));
                let (fx_h, fy_h) = (fx.range(lo, hi), fy.range(lo, hi));
                fx_h[0] = gx + (lx[0] - prev_x);
                fy_h[0] = gy + (ly[0] - prev_y);
                for i in 1..hi - lo {
                    fx_h[i] = gx + (lx[i] - lx[i - 1]);
                    fy_h[i] = gy + (ly[i] - ly[i - 1]);
                }
                let p = parts.range(3 * h, 3 * h + 3);
                p[0] = if nan { 1.0 } else { 0.0 };
                p[1] = max_stretch;
                p[2] = max_speed_sq;
            }
        };
        fork.both(&half);
        // Maxima do not depend on the order in which they are taken.
        let larger = |a: f64, b: f64| if b > a { b } else { a };
        let mut nan = false;
        let (mut max_stretch, mut max_speed_sq) = (0.0f64, 0.0f64);
        for p in partial.chunks_exact(3) {
            nan |= p[0] != 0.0;
            max_stretch = larger(max_stretch, p[1]);
            max_speed_sq = larger(max_speed_sq, p[2]);
        }
        out.max_stretch_m = if nan { f64::NAN } else { max_stretch };
        out.max_roller_speed_m_s = max_speed_sq.sqrt();
    }
}

impl Links {
    /// The kept positions no longer hold: an evaluation that keeps none
    /// came after.
    fn forget_positions(&mut self) {
        if let Some(kept) = &mut self.kept {
            kept.valid = false;
        }
    }

    /// Each link's geometry at `s` into the kept slots (and its n/ℓ into
    /// `out` where the rates are asked for), and the stretches.
    fn keep_geometry(&mut self, model: &DriveModel, s: &DriveState, out: &mut Forces) {
        let n = s.x.len();
        let with_rates = self.rates_fit(out, n);
        let Some(kept) = &mut self.kept else {
            return;
        };
        let law = LinkLaw::of(model);
        let shape = Shape {
            ux: &mut kept.ux[..n],
            uy: &mut kept.uy[..n],
            spring: &mut kept.spring[..n],
            inv: &mut kept.inv[..n],
            stretch: &mut self.stretch[..n],
        };
        let normals =
            with_rates.then(|| (&mut out.link_normal_x[..n], &mut out.link_normal_y[..n]));
        link_geometry(law, &s.x[..n], &s.y[..n], shape, normals);
        kept.valid = true;
    }

    /// The links at `s`, whose roller positions are those of the last
    /// evaluation (kept, [`Self::keep_positions`]): only what depends on the
    /// velocities is computed again — the forces (the damping's part), each
    /// roller's sum, the rates' ω and the largest speed; the stretches and
    /// the normals stay. The same numbers as [`ForceElement::evaluate`].
    /// Without kept positions, the whole evaluation.
    pub(crate) fn evaluate_again(&mut self, model: &DriveModel, s: &DriveState, out: &mut Forces) {
        let n = s.x.len();
        let with_rates = self.rates_fit(out, n);
        let Some(kept) = self.kept.as_ref().filter(|k| k.valid) else {
            return self.evaluate(model, s, out);
        };
        let lfx = &mut self.link_fx[..n];
        let lfy = &mut self.link_fy[..n];
        let shape = KeptShape {
            ux: &kept.ux[..n],
            uy: &kept.uy[..n],
            spring: &kept.spring[..n],
            inv: &kept.inv[..n],
        };
        let slots = Slots {
            force: &mut out.link_force[..n],
            fx: &mut *lfx,
            fy: &mut *lfy,
            stretch: &mut [],
        };
        let omega = with_rates.then(|| &mut out.link_omega[..n]);
        link_velocities(
            model.damping_n_s_m,
            [&s.vx[..n], &s.vy[..n]],
            shape,
            slots,
            omega,
        );
        let m = model.roller_mass_kg;
        let weight = [m * model.gravity_m_s2[0], m * model.gravity_m_s2[1]];
        let (fx, fy) = (&mut out.fx[..n], &mut out.fy[..n]);
        let prev = [lfx[n - 1], lfy[n - 1]];
        let v = [&s.vx[..n], &s.vy[..n]];
        let (nan, max_stretch, max_speed_sq) = roller_sums(
            weight,
            [&*lfx, &*lfy],
            prev,
            [fx, fy],
            &self.stretch[..n],
            v,
        );
        out.max_stretch_m = if nan { f64::NAN } else { max_stretch };
        out.max_roller_speed_m_s = max_speed_sq.sqrt();
    }
}

/// The kept geometry's slots being written, with the stretches.
struct Shape<'a> {
    ux: &'a mut [f64],
    uy: &'a mut [f64],
    spring: &'a mut [f64],
    inv: &'a mut [f64],
    stretch: &'a mut [f64],
}

/// The kept geometry, as the velocities' pass reads it.
#[derive(Clone, Copy)]
struct KeptShape<'a> {
    ux: &'a [f64],
    uy: &'a [f64],
    spring: &'a [f64],
    inv: &'a [f64],
}

/// Each link's geometry (all n links, the last closing the loop) from the
/// rollers' positions, as [`LinkLaw::eval`] computes it, and its n/ℓ where
/// `normals` asks (as [`rates`]). Compiled for AVX2 where the CPU has it
/// (element-wise: the same bits).
fn link_geometry(
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
fn link_velocities(
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

impl ForceElement for Links {
    fn name(&self) -> &'static str {
        "links"
    }

    /// Two passes: the links' force vectors first (independent iterations,
    /// which the compiler pipelines and vectorises), then each roller's sum
    /// of its two links, so no iteration waits on the previous one's store.
    ///
    /// Keeping what depends on the positions alone
    /// ([`Links::keep_positions`]), the same numbers in two other passes:
    /// each link's geometry, then what depends on the velocities
    /// ([`Links::evaluate_again`]).
    fn evaluate(&mut self, model: &DriveModel, s: &DriveState, out: &mut Forces) {
        if self.kept.is_some() {
            self.keep_geometry(model, s, out);
            return self.evaluate_again(model, s, out);
        }
        let n = s.x.len();
        let law = LinkLaw::of(model);
        let with_rates = self.rates_fit(out, n);
        let (x, y, vx, vy) = (&s.x[..n], &s.y[..n], &s.vx[..n], &s.vy[..n]);
        let force = &mut out.link_force[..n];
        let (lfx, lfy) = (&mut self.link_fx[..n], &mut self.link_fy[..n]);
        let stretch = &mut self.stretch[..n];
        // Links 0..n−1 join consecutive rollers; the closing link n−1 → 0
        // after them.
        let link_rates = with_rates.then(|| Rates {
            omega: &mut out.link_omega[..n],
            normal_x: &mut out.link_normal_x[..n],
            normal_y: &mut out.link_normal_y[..n],
        });
        let slots = Slots {
            force: &mut *force,
            fx: &mut *lfx,
            fy: &mut *lfy,
            stretch: &mut *stretch,
        };
        open_links(law, Ends { x, y, vx, vy }, slots, link_rates);
        let (dvx, dvy) = (vx[0] - vx[n - 1], vy[0] - vy[n - 1]);
        let (f, ux, uy, last, inv) = law.eval(x[0] - x[n - 1], y[0] - y[n - 1], dvx, dvy);
        force[n - 1] = f;
        lfx[n - 1] = f * ux;
        lfy[n - 1] = f * uy;
        stretch[n - 1] = last;
        if with_rates {
            (
                out.link_omega[n - 1],
                out.link_normal_x[n - 1],
                out.link_normal_y[n - 1],
            ) = rates(ux, uy, inv, dvx, dvy);
        }
        let m = model.roller_mass_kg;
        let weight = [m * model.gravity_m_s2[0], m * model.gravity_m_s2[1]];
        let (fx, fy) = (&mut out.fx[..n], &mut out.fy[..n]);
        let prev = [lfx[n - 1], lfy[n - 1]];
        let (nan, max_stretch, max_speed_sq) =
            roller_sums(weight, [&*lfx, &*lfy], prev, [fx, fy], &*stretch, [vx, vy]);
        out.max_stretch_m = if nan { f64::NAN } else { max_stretch };
        out.max_roller_speed_m_s = max_speed_sq.sqrt();
    }

    /// No history; the last evaluation's stretches ([`Links::stretch`]).
    fn save_history(&self, history: &mut History) {
        history.push_floats(self.stretch.iter().copied());
    }

    fn restore_history(&mut self, history: &mut HistoryReader<'_>) -> Result<(), HistoryError> {
        let stretch = history.floats(self.stretch.len())?;
        self.stretch.copy_from_slice(stretch);
        Ok(())
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// Each roller's force, its weight plus its two links (`prev` the link
/// before the first roller: the last link, for a whole chain), and the links'
/// checks: whether a stretch is NaN, the largest |stretch| and the largest
/// squared roller speed. Compiled for AVX2 where the CPU has it, as
/// [`open_links`] is (element-wise sums and maxima: the same bits).
fn roller_sums(
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
fn largest(a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) -> f64 {
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
    use crate::forces::{ForceElement, Forces, Links};
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
    fn links_pass_writes_each_links_angular_velocity_and_normal() {
        // Oracle: for link j from roller j to k = j + 1 (mod n), with d its
        // vector and ḋ its velocity difference, ω = (d × ḋ)/|d|² and
        // n/ℓ = (−d_y, d_x)/|d|²; relative tolerance 1e-12 of the largest.
        // The paper's drive as laid out, every roller given its own velocity.
        let scene = crate::scene::Scene::l60mc();
        let (model, mut s, _) = DriveModel::build(&scene).expect("paper's drive lays out");
        let n = s.rollers();
        for i in 0..n {
            s.vx[i] += ((i * 7 % 11) as f64 - 5.0) * 0.3;
            s.vy[i] += ((i * 5 % 13) as f64 - 6.0) * 0.2;
        }
        let mut out = Forces::new(n, model.sprockets.len(), 0, 0);
        // Not asked for: nothing written.
        let mut links = Links::new(n);
        links.evaluate(&model, &s, &mut out);
        assert!(out.link_omega.is_empty());
        links.request_rates(&mut out);
        out.link_omega.fill(f64::NAN);
        out.link_normal_x.fill(f64::NAN);
        out.link_normal_y.fill(f64::NAN);
        links.evaluate(&model, &s, &mut out);
        let mut worst = [0.0f64; 3];
        let mut largest_seen = [0.0f64; 3];
        for j in 0..n {
            let k = (j + 1) % n;
            let (dx, dy) = (s.x[k] - s.x[j], s.y[k] - s.y[j]);
            let (dvx, dvy) = (s.vx[k] - s.vx[j], s.vy[k] - s.vy[j]);
            let l2 = dx * dx + dy * dy;
            let expected = [(dx * dvy - dy * dvx) / l2, -dy / l2, dx / l2];
            let got = [
                out.link_omega[j],
                out.link_normal_x[j],
                out.link_normal_y[j],
            ];
            assert!(got.iter().all(|v| v.is_finite()), "link {j} not written");
            for c in 0..3 {
                worst[c] = worst[c].max((got[c] - expected[c]).abs());
                largest_seen[c] = largest_seen[c].max(expected[c].abs());
            }
        }
        for c in 0..3 {
            assert!(largest_seen[c] > 0.0);
            assert!(
                worst[c] <= 1e-12 * largest_seen[c],
                "component {c}: {worst:?}"
            );
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
