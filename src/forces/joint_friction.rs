//! Pin–bushing friction at every joint of the chain (docs/model.md, “Joint
//! friction”): a regularised Coulomb moment proportional to the pin load,
//! plus an optional viscous moment, applied as equal and opposite couples on
//! the two links that meet at the joint.
//!
//! It does not model stick (a regularised law has none: at rest the moment
//! is zero, so the static equilibrium is the frictionless one), the rollers'
//! own rotation, or friction between plates.

use super::links::link_rates;
use super::{ForceElement, Forces, History, HistoryError, HistoryReader};
use crate::model::{DriveModel, DriveState};
use crate::scene::JointFriction as Params;

/// Joint friction: at roller i, where link a = (i−1, i) meets link
/// b = (i, i+1), the moment of link a on link b is
/// `M_i = −μ r_pin F_pin tanh(ω_rel / ω_s) − c_θ ω_rel`, with
/// ω_rel = ω_b − ω_a (each link's ω = (d × ḋ) / |d|²) and F_pin the mean of
/// the two links' forces, zero in compression. On a link of length ℓ and
/// unit normal n a moment m is the couple −(m/ℓ) n at its first roller and
/// +(m/ℓ) n at its second: the forces sum to zero and their power is m ω.
#[derive(Clone, Debug)]
pub struct JointFriction {
    params: Params,
    /// Scratch: each joint's relative angular velocity ω_rel, rad/s.
    rel: Vec<f64>,
    /// Each joint's moment M_i at the last evaluation, N·m.
    moment: Vec<f64>,
}

impl JointFriction {
    /// The element for a chain of `rollers` rollers (as many joints).
    pub fn new(params: Params, rollers: usize) -> Self {
        Self {
            params,
            rel: vec![0.0; rollers],
            moment: vec![0.0; rollers],
        }
    }

    /// Each joint's moment at the last evaluation, N·m (joint i at roller i:
    /// the moment of link i−1 on link i, counter-clockwise positive).
    pub fn moments(&self) -> &[f64] {
        &self.moment
    }

    /// The moment at one joint: relative speed `omega_rel`, rad/s, pin load
    /// `pin_n`, N (≥ 0). The evaluation inlines the same formula.
    #[cfg(test)]
    fn law(&self, omega_rel: f64, pin_n: f64) -> f64 {
        let p = &self.params;
        -p.friction * p.pin_radius_m * pin_n * fast_tanh(omega_rel / p.speed_rad_s)
            - p.damping_n_m_s_rad * omega_rel
    }
}

/// tanh by Lambert's continued fraction cut after seven terms (a rational
/// function, no `exp`), clamped to [−1, 1]: within 1.1·10⁻⁴ of `f64::tanh`
/// everywhere (the clamp, near |x| = 5, is the largest error; below |x| = 3
/// it is under 10⁻⁶), odd, and ±1 beyond |x| ≈ 5. The library's tanh cost as
/// much as the rest of the element.
#[inline(always)]
fn fast_tanh(x: f64) -> f64 {
    // Beyond |x| = 10 the fraction would overflow to ∞/∞; its value there is 1.
    let x = if x > 10.0 { 10.0 } else { x };
    let x = if x < -10.0 { -10.0 } else { x };
    let x2 = x * x;
    let num = x * (135_135.0 + x2 * (17_325.0 + x2 * (378.0 + x2)));
    let den = 135_135.0 + x2 * (62_370.0 + x2 * (3_150.0 + 28.0 * x2));
    // Plain comparisons (selects, which vectorise); a NaN passes through.
    let r = num / den;
    let r = if r > 1.0 { 1.0 } else { r };
    if r < -1.0 { -1.0 } else { r }
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
        let omega = &out.link_omega[..n];
        let (gx, gy) = (&out.link_normal_x[..n], &out.link_normal_y[..n]);
        // Joint i (i ≥ 1) between links i − 1 and i; joint 0 closes the loop.
        let p = self.params;
        // The pin load is the mean of the two links' forces: its ½ goes into
        // the Coulomb factor (a product with ½ is exact: the same number).
        let half_coulomb = 0.5 * p.friction * p.pin_radius_m;
        let per_speed = 1.0 / p.speed_rad_s;
        let law = |omega_rel: f64, f_a: f64, f_b: f64| {
            let twice_pin = (f_a + f_b).max(0.0);
            -half_coulomb * twice_pin * fast_tanh(omega_rel * per_speed)
                - p.damping_n_m_s_rad * omega_rel
        };
        let forces = &out.link_force[..n];
        let moment = &mut self.moment[..n];
        let rel = &mut self.rel[..n];
        let joints = omega[..n - 1]
            .iter()
            .zip(&omega[1..])
            .zip(forces[..n - 1].iter().zip(&forces[1..]));
        for (((w_a, w_b), (f_a, f_b)), (m, r)) in
            joints.zip(moment[1..].iter_mut().zip(rel[1..].iter_mut()))
        {
            *r = w_b - w_a;
            *m = law(*r, *f_a, *f_b);
        }
        rel[0] = omega[0] - omega[n - 1];
        moment[0] = law(rel[0], forces[n - 1], forces[0]);
        let power = dot(moment, rel);
        // Link j carries +M_j (joint j, where it is link b) and −M_{j+1}
        // (joint j + 1, where it is link a): its couple is (m_j/ℓ) n with
        // m_j = M_j − M_{j+1}, −(m_j/ℓ) n on roller j, +(m_j/ℓ) n on roller
        // j + 1. Roller i gets couple(i − 1) − couple(i).
        let (fx, fy) = (&mut out.fx[..n], &mut out.fy[..n]);
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
        if out.joint_moment_n_m.len() != n {
            // Sized once, at the first evaluation.
            out.joint_moment_n_m.resize(n, 0.0);
        }
        out.joint_moment_n_m.copy_from_slice(moment);
        out.joint_friction_power_w = power;
    }

    /// No history; the last evaluation's moments ([`JointFriction::moments`]).
    fn save_history(&self, history: &mut History) {
        history.push_floats(self.moment.iter().copied());
    }

    fn restore_history(&mut self, history: &mut HistoryReader<'_>) -> Result<(), HistoryError> {
        let moment = history.floats(self.moment.len())?;
        self.moment.copy_from_slice(moment);
        Ok(())
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
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
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
                assert!(e.moment[i] * rel <= 0.0, "joint {i}");
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
    fn fast_tanh_matches_the_library_tanh() {
        // Oracle: f64::tanh on a fine grid over ±40 (and the clamp region);
        // tolerance 1.1e-4 overall, 1e-6 below |x| = 3; odd to the bit.
        for k in -40_000..=40_000 {
            let x = k as f64 * 1e-3;
            let (fast, exact) = (fast_tanh(x), x.tanh());
            let tol = if x.abs() < 3.0 { 1e-6 } else { 1.1e-4 };
            assert!(
                (fast - exact).abs() < tol,
                "x = {x}: {fast} against {exact}"
            );
            assert_eq!(fast_tanh(-x), -fast);
        }
        assert_eq!(fast_tanh(1e300), 1.0);
        assert!(fast_tanh(f64::NAN).is_nan());
    }

    #[test]
    fn joint_friction_moment_saturates_at_the_coulomb_value() {
        // M = −μ r F tanh(ω/ω_s): at ω = 10 ω_s, within 1e-8 of μ r F; at
        // ω = ω_s / 1000, the viscous slope μ r F / ω_s to 1e-6.
        let e = JointFriction::new(params(0.1, 0.0), 4);
        let coulomb = 0.1 * 0.017 * 30e3;
        assert!((e.law(10.0, 30e3) + coulomb).abs() < 1e-8 * coulomb);
        assert!((e.law(1e-3, 30e3) + coulomb * 1e-3).abs() < 1e-6 * coulomb * 1e-3);
        // Compression carries no pin load here: the caller clamps it.
        assert_eq!(e.law(0.0, 30e3), 0.0);
    }
}
