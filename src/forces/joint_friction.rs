//! Pin–bushing friction at every joint of the chain (docs/model.md, “Joint
//! friction”): a regularised Coulomb moment proportional to the pin load,
//! plus an optional viscous moment, applied as equal and opposite couples on
//! the two links that meet at the joint.
//!
//! It does not model stick (a regularised law has none: at rest the moment
//! is zero, so the static equilibrium is the frictionless one), the rollers'
//! own rotation, or friction between plates.

use super::links::link_rates;
use super::{ForceElement, Forces};
use crate::model::{DriveModel, DriveState};
use crate::scene::JointFriction as Params;

/// Joint friction: at roller i, where link a = (i−1, i) meets link
/// b = (i, i+1), the moment of link a on link b is
/// `M_i = −μ r_pin F_pin s(ω_rel / ω_s) − c_θ ω_rel`, s a cubic step
/// (docs/model.md, “Joint friction”), with
/// ω_rel = ω_b − ω_a (each link's ω = (d × ḋ) / |d|²) and F_pin the mean of
/// the two links' forces, zero in compression. On a link of length ℓ and
/// unit normal n a moment m is the couple −(m/ℓ) n at its first roller and
/// +(m/ℓ) n at its second: the forces sum to zero and their power is m ω.
#[derive(Clone, Debug)]
pub struct JointFriction {
    params: Params,
    /// Scratch: each joint's relative angular velocity ω_rel, rad/s.
    rel: Vec<f64>,
}

impl JointFriction {
    /// The element for a chain of `rollers` rollers (as many joints).
    pub fn new(params: Params, rollers: usize) -> Self {
        Self {
            params,
            rel: vec![0.0; rollers],
        }
    }

    /// The moment at one joint: relative speed `omega_rel`, rad/s, pin load
    /// `pin_n`, N (≥ 0). The evaluation inlines the same formula.
    #[cfg(test)]
    fn law(&self, omega_rel: f64, pin_n: f64) -> f64 {
        let p = &self.params;
        -p.friction * p.pin_radius_m * pin_n * cubic_step(omega_rel / p.speed_rad_s)
            - p.damping_n_m_s_rad * omega_rel
    }
}

/// The smooth sign of the law: a cubic step in x = ω_rel / ω_s,
/// s(x) = x − x³/6.75 for |x| ≤ 1.5 and ±1 beyond. It is odd, bounded by 1,
/// monotone, and C¹ (its slope 1 − x²/2.25 is 1 at rest, like tanh's, and 0
/// where it meets ±1), so the law near rest is the same viscous slope
/// μ r_pin F / ω_s as with tanh, and from 1.5 ω_s on it is Coulomb's exactly.
/// Written as y (3 − y²)/2 with y = x/1.5 clamped to [−1, 1]: five
/// arithmetic operations and two selects, no division; a NaN passes through.
#[inline(always)]
fn cubic_step(x: f64) -> f64 {
    let y = x * (1.0 / 1.5);
    // Plain comparisons (selects, which vectorise).
    let y = if y > 1.0 { 1.0 } else { y };
    let y = if y < -1.0 { -1.0 } else { y };
    y * (1.5 - 0.5 * (y * y))
}

/// Σ a_i b_i in four independent lanes (a plain running sum waits on each
/// addition and stays scalar), the lanes then summed in order.
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut lanes = [0.0f64; 4];
    for (ca, cb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for k in 0..4 {
            lanes[k] += ca[k] * cb[k];
        }
    }
    let tail = n - n % 4;
    let rest: f64 = a[tail..].iter().zip(&b[tail..]).map(|(x, y)| x * y).sum();
    lanes.into_iter().fold(rest, |s, l| s + l)
}

/// The law's constants, as the passes use them.
#[derive(Clone, Copy)]
struct Law {
    /// ½ μ r_pin (the pin load is the mean of two links' forces), m.
    half_coulomb: f64,
    /// 1 / ω_s, s/rad.
    per_speed: f64,
    /// c_θ, N·m·s/rad.
    damping: f64,
}

impl Law {
    /// The moment at a joint of relative speed `omega_rel` between links
    /// carrying `f_a` and `f_b`.
    #[inline(always)]
    fn moment(self, omega_rel: f64, f_a: f64, f_b: f64) -> f64 {
        let twice_pin = (f_a + f_b).max(0.0);
        -self.half_coulomb * twice_pin * cubic_step(omega_rel * self.per_speed)
            - self.damping * omega_rel
    }
}

/// What the links' pass wrote, one slot per link: ω, the force and n/ℓ.
struct LinkRates<'a> {
    omega: &'a [f64],
    force: &'a [f64],
    gx: &'a [f64],
    gy: &'a [f64],
}

/// The joints' outputs, one slot per joint: ω_rel and the moment.
struct Joints<'a> {
    rel: &'a mut [f64],
    moment: &'a mut [f64],
}

/// The element's two passes, compiled for the baseline target and, where
/// the CPU has it, for AVX2 (chosen at run time, as RustFFT chooses its
/// kernels): four lanes instead of two, the same operations in the same
/// order, so the same bits (test `avx2_and_baseline_passes_agree_to_the_bit`).
/// Returns the power Σ M ω_rel, W.
fn passes(law: Law, links: LinkRates, joints: Joints, fx: &mut [f64], fy: &mut [f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { passes_avx2(law, links, joints, fx, fy) };
    }
    passes_body(law, links, joints, fx, fy)
}

/// [`passes_body`] compiled with AVX2 (no FMA: products and sums stay
/// separately rounded, as in the baseline build).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn passes_avx2(law: Law, links: LinkRates, joints: Joints, fx: &mut [f64], fy: &mut [f64]) -> f64 {
    passes_body(law, links, joints, fx, fy)
}

/// Two passes over zipped slices, with no bounds checks and no branches,
/// which the compiler vectorises: each joint's moment (joint i ≥ 1 between
/// links i − 1 and i; joint 0 closes the loop), then each roller's two
/// couples. Needs at least two links.
#[inline(always)]
fn passes_body(law: Law, links: LinkRates, joints: Joints, fx: &mut [f64], fy: &mut [f64]) -> f64 {
    let LinkRates {
        omega,
        force: forces,
        gx,
        gy,
    } = links;
    let Joints { rel, moment } = joints;
    let n = omega.len();
    let pairs = omega[..n - 1]
        .iter()
        .zip(&omega[1..])
        .zip(forces[..n - 1].iter().zip(&forces[1..]));
    for (((w_a, w_b), (f_a, f_b)), (m, r)) in
        pairs.zip(moment[1..].iter_mut().zip(rel[1..].iter_mut()))
    {
        *r = w_b - w_a;
        *m = law.moment(*r, *f_a, *f_b);
    }
    rel[0] = omega[0] - omega[n - 1];
    moment[0] = law.moment(rel[0], forces[n - 1], forces[0]);
    let power = dot(moment, rel);
    // Link j carries +M_j (joint j, where it is link b) and −M_{j+1}
    // (joint j + 1, where it is link a): its couple is (m_j/ℓ) n with
    // m_j = M_j − M_{j+1}, −(m_j/ℓ) n on roller j, +(m_j/ℓ) n on roller
    // j + 1. Roller i gets couple(i − 1) − couple(i).
    let moment = &*moment;
    let roller = |h: usize, i: usize, k: usize| {
        let (before, after) = (moment[h] - moment[i], moment[i] - moment[k]);
        (
            before * gx[h] - after * gx[i],
            before * gy[h] - after * gy[i],
        )
    };
    let (first, last) = (roller(n - 1, 0, 1 % n), roller(n - 2, n - 1, 0));
    // Rollers 1..n−1: joints h = i − 1, i, k = i + 1; links i − 1 and i.
    let three = moment[..n - 2]
        .iter()
        .zip(&moment[1..n - 1])
        .zip(&moment[2..]);
    let normals = gx[..n - 2]
        .iter()
        .zip(&gx[1..n - 1])
        .zip(gy[..n - 2].iter().zip(&gy[1..n - 1]));
    let targets = fx[1..n - 1].iter_mut().zip(fy[1..n - 1].iter_mut());
    for ((((m_h, m_i), m_k), ((gx_h, gx_i), (gy_h, gy_i))), (f_x, f_y)) in
        three.zip(normals).zip(targets)
    {
        let (before, after) = (m_h - m_i, m_i - m_k);
        *f_x += before * gx_h - after * gx_i;
        *f_y += before * gy_h - after * gy_i;
    }
    fx[0] += first.0;
    fy[0] += first.1;
    fx[n - 1] += last.0;
    fy[n - 1] += last.1;
    power
}

impl ForceElement for JointFriction {
    fn name(&self) -> &'static str {
        "joint friction"
    }

    /// Each link's ω and n/ℓ come from the links' pass (sized here at the
    /// first evaluation, which computes them itself). Then two passes over
    /// zipped slices, with no bounds checks and no branches, which the
    /// compiler vectorises: each joint's moment, each roller's two couples.
    fn evaluate(&mut self, _model: &DriveModel, s: &DriveState, out: &mut Forces) {
        let n = s.x.len();
        if n < 2 {
            return;
        }
        if out.link_omega.len() != n || out.link_normal_x.len() != n || out.link_normal_y.len() != n
        {
            // Sized once: from now on the links write them.
            out.link_omega.resize(n, 0.0);
            out.link_normal_x.resize(n, 0.0);
            out.link_normal_y.resize(n, 0.0);
            link_rates(
                s,
                &mut out.link_omega,
                &mut out.link_normal_x,
                &mut out.link_normal_y,
            );
        }
        let p = self.params;
        // The pin load is the mean of the two links' forces: its ½ goes into
        // the Coulomb factor (a product with ½ is exact: the same number).
        let law = Law {
            half_coulomb: 0.5 * p.friction * p.pin_radius_m,
            per_speed: 1.0 / p.speed_rad_s,
            damping: p.damping_n_m_s_rad,
        };
        let links = LinkRates {
            omega: &out.link_omega[..n],
            force: &out.link_force[..n],
            gx: &out.link_normal_x[..n],
            gy: &out.link_normal_y[..n],
        };
        if out.joint_moment_n_m.len() != n {
            // Sized once, at the first evaluation.
            out.joint_moment_n_m.resize(n, 0.0);
        }
        // The moments are written where observers read them.
        let joints = Joints {
            rel: &mut self.rel[..n],
            moment: &mut out.joint_moment_n_m[..n],
        };
        out.joint_friction_power_w = passes(law, links, joints, &mut out.fx[..n], &mut out.fy[..n]);
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::Links;

    fn params(mu: f64, damping: f64) -> Params {
        Params {
            pin_radius_m: 0.017,
            friction: mu,
            speed_rad_s: 1.0,
            damping_n_m_s_rad: damping,
        }
    }

    /// The paper's drive as laid out, its rollers given a deterministic
    /// pseudo-random velocity field and its links tensions of 5–35 kN (one
    /// in compression), and the links' forces at that state.
    fn disturbed() -> (DriveModel, DriveState, Forces) {
        let scene = crate::scene::Scene::l60mc();
        let (model, mut state, _) = DriveModel::build(&scene).expect("paper's drive lays out");
        let mut rng = crate::rng::SeededRng::new(12345);
        let mut next = || rng.unit() - 0.5;
        for i in 0..state.rollers() {
            state.vx[i] += 2.0 * next();
            state.vy[i] += 2.0 * next();
        }
        let n = state.rollers();
        let mut out = Forces::new(n, model.sprockets.len(), 0, 0);
        Links::new(n).evaluate(&model, &state, &mut out);
        for (i, f) in out.link_force.iter_mut().enumerate() {
            *f = 20e3 + 15e3 * next() * 2.0;
            if i == 7 {
                *f = -5e3;
            }
        }
        (model, state, out)
    }

    #[test]
    fn joint_friction_forces_sum_to_zero_and_only_dissipate() {
        // The couples are internal: their forces sum to zero (to rounding,
        // 1e-9 of their largest), and their power Σ F·v equals Σ M ω_rel,
        // which the law makes ≤ 0 at every joint.
        let (model, state, base) = disturbed();
        for (mu, c) in [(0.1, 0.0), (0.0, 5.0), (0.15, 2.0)] {
            let mut e = JointFriction::new(params(mu, c), state.rollers());
            let mut out = base.clone();
            e.evaluate(&model, &state, &mut out);
            let (mut sx, mut sy, mut largest, mut power) = (0.0, 0.0, 0.0f64, 0.0);
            for i in 0..state.rollers() {
                let (fx, fy) = (out.fx[i] - base.fx[i], out.fy[i] - base.fy[i]);
                sx += fx;
                sy += fy;
                largest = largest.max(fx.hypot(fy));
                power += fx * state.vx[i] + fy * state.vy[i];
            }
            assert!(largest > 0.0, "μ = {mu}, c = {c}: no force at all");
            assert!(sx.abs() < 1e-9 * largest && sy.abs() < 1e-9 * largest);
            // Every joint dissipates: M ω_rel ≤ 0 (checked per joint through
            // the law's sign, and in total through the forces' power).
            let n = state.rollers();
            let omega = |j: usize| {
                let k = (j + 1) % n;
                let (dx, dy) = (state.x[k] - state.x[j], state.y[k] - state.y[j]);
                let (dvx, dvy) = (state.vx[k] - state.vx[j], state.vy[k] - state.vy[j]);
                (dx * dvy - dy * dvx) / (dx * dx + dy * dy)
            };
            for i in 0..n {
                let rel = omega(i) - omega((i + n - 1) % n);
                assert!(out.joint_moment_n_m[i] * rel <= 0.0, "joint {i}");
            }
            assert!(out.joint_friction_power_w < 0.0);
            let rel = (power - out.joint_friction_power_w).abs() / power.abs();
            assert!(
                rel < 1e-9,
                "Σ F·v = {power} W against Σ M ω = {} W",
                out.joint_friction_power_w
            );
        }
    }

    #[test]
    fn cubic_step_is_an_odd_bounded_c1_sign() {
        // Closed form s(x) = x − x³/6.75 on |x| ≤ 1.5, sign(x) beyond:
        // at 0.75 it is 0.75 − 0.421875/6.75 = 0.6875 exactly; its slope
        // 1 − x²/2.25 is 1 at 0 and 0 at ±1.5 (one-sided difference
        // quotients over 1e-7 within 1e-6), and it is monotone, odd to the
        // bit and within [−1, 1] on a fine grid.
        assert_eq!(cubic_step(0.75), 0.6875);
        assert_eq!(cubic_step(0.0), 0.0);
        assert_eq!(cubic_step(1.5), 1.0);
        assert_eq!(cubic_step(7.0), 1.0);
        assert_eq!(cubic_step(1e300), 1.0);
        assert!(cubic_step(f64::NAN).is_nan());
        let h = 1e-7;
        assert!((cubic_step(h) / h - 1.0).abs() < 1e-6);
        assert!(((1.0 - cubic_step(1.5 - h)) / h).abs() < 1e-6);
        let mut last = -1.0;
        for k in -40_000..=40_000 {
            let x = k as f64 * 1e-4;
            let s = cubic_step(x);
            assert_eq!(cubic_step(-x), -s);
            assert!(s >= last && s.abs() <= 1.0, "x = {x}");
            last = s;
        }
    }

    #[test]
    fn avx2_and_baseline_passes_agree_to_the_bit() {
        // The run-time choice of kernel changes no result: both builds of
        // the passes, on the disturbed paper's drive, give the same bits.
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let (model, state, mut base) = disturbed();
            let n = state.rollers();
            let _ = model;
            let (mut omega, mut gx, mut gy) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            link_rates(&state, &mut omega, &mut gx, &mut gy);
            base.link_omega = omega;
            let law = Law {
                half_coulomb: 0.5 * 0.12 * 0.017,
                per_speed: 1.0,
                damping: 3.0,
            };
            let run = |avx2: bool| {
                let (mut rel, mut moment) = (vec![0.0; n], vec![0.0; n]);
                let (mut fx, mut fy) = (base.fx.clone(), base.fy.clone());
                let links = LinkRates {
                    omega: &base.link_omega,
                    force: &base.link_force,
                    gx: &gx,
                    gy: &gy,
                };
                let joints = Joints {
                    rel: &mut rel,
                    moment: &mut moment,
                };
                let power = if avx2 {
                    // SAFETY: the CPU has AVX2, checked above.
                    unsafe { passes_avx2(law, links, joints, &mut fx, &mut fy) }
                } else {
                    passes_body(law, links, joints, &mut fx, &mut fy)
                };
                (power.to_bits(), moment, fx, fy)
            };
            let (wide, base_run) = (run(true), run(false));
            assert!(wide.1.iter().any(|m| *m != 0.0));
            assert_eq!(wide.0, base_run.0);
            for (a, b) in [
                (&wide.1, &base_run.1),
                (&wide.2, &base_run.2),
                (&wide.3, &base_run.3),
            ] {
                assert!(a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()));
            }
        }
    }

    #[test]
    fn joint_friction_moment_saturates_at_the_coulomb_value() {
        // M = −μ r F s(ω/ω_s): at ω = 10 ω_s, within 1e-8 of μ r F; at
        // ω = ω_s / 1000, the viscous slope μ r F / ω_s to 1e-6.
        let e = JointFriction::new(params(0.1, 0.0), 4);
        let coulomb = 0.1 * 0.017 * 30e3;
        assert!((e.law(10.0, 30e3) + coulomb).abs() < 1e-8 * coulomb);
        assert!((e.law(1e-3, 30e3) + coulomb * 1e-3).abs() < 1e-6 * coulomb * 1e-3);
        // Compression carries no pin load here: the caller clamps it.
        assert_eq!(e.law(0.0, 30e3), 0.0);
    }
}
