//! Pin–bushing friction at every joint of the chain (docs/model.md, “Joint
//! friction”): a regularised Coulomb moment proportional to the pin load,
//! plus an optional viscous moment, applied as equal and opposite couples on
//! the two links that meet at the joint.
//!
//! It does not model stick (a regularised law has none: at rest the moment
//! is zero, so the static equilibrium is the frictionless one), the rollers'
//! own rotation, or friction between plates.

use super::{ForceElement, Forces};
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
    /// Scratch: each link's angular velocity, rad/s.
    omega: Vec<f64>,
    /// Scratch: each link's normal over its length, n / ℓ, 1/m.
    nx: Vec<f64>,
    /// Scratch: its y component, 1/m.
    ny: Vec<f64>,
    /// Each joint's moment M_i at the last evaluation, N·m.
    moment: Vec<f64>,
}

impl JointFriction {
    /// The element for a chain of `rollers` rollers (as many joints).
    pub fn new(params: Params, rollers: usize) -> Self {
        Self {
            params,
            omega: vec![0.0; rollers],
            nx: vec![0.0; rollers],
            ny: vec![0.0; rollers],
            moment: vec![0.0; rollers],
        }
    }

    /// Each joint's moment at the last evaluation, N·m (joint i at roller i:
    /// the moment of link i−1 on link i, counter-clockwise positive).
    pub fn moments(&self) -> &[f64] {
        &self.moment
    }

    /// The moment at one joint: relative speed `omega_rel`, rad/s, pin load
    /// `pin_n`, N (≥ 0).
    #[inline(always)]
    fn law(&self, omega_rel: f64, pin_n: f64) -> f64 {
        let p = &self.params;
        -p.friction * p.pin_radius_m * pin_n * (omega_rel / p.speed_rad_s).tanh()
            - p.damping_n_m_s_rad * omega_rel
    }
}

impl ForceElement for JointFriction {
    fn name(&self) -> &'static str {
        "joint friction"
    }

    fn evaluate(&mut self, _model: &DriveModel, s: &DriveState, out: &mut Forces) {
        let n = s.x.len();
        if n == 0 {
            return;
        }
        // Link j joins roller j to roller j + 1 (the last one closes the loop).
        for j in 0..n {
            let k = if j + 1 == n { 0 } else { j + 1 };
            let (dx, dy) = (s.x[k] - s.x[j], s.y[k] - s.y[j]);
            let (dvx, dvy) = (s.vx[k] - s.vx[j], s.vy[k] - s.vy[j]);
            let l2 = dx * dx + dy * dy;
            // Coincident rollers have no direction: no moment rather than NaN
            // (the blow-up detector stops such a run).
            let inv = if l2 > 0.0 { 1.0 / l2 } else { 0.0 };
            self.omega[j] = (dx * dvy - dy * dvx) * inv;
            self.nx[j] = -dy * inv;
            self.ny[j] = dx * inv;
        }
        let forces = &out.link_force[..n];
        let mut power = 0.0;
        for i in 0..n {
            let a = if i == 0 { n - 1 } else { i - 1 };
            let omega_rel = self.omega[i] - self.omega[a];
            let pin = (0.5 * (forces[a] + forces[i])).max(0.0);
            let m = self.law(omega_rel, pin);
            self.moment[i] = m;
            power += m * omega_rel;
        }
        // Link j carries +M_j (joint j, where it is link b) and −M_{j+1}
        // (joint j + 1, where it is link a).
        for j in 0..n {
            let k = if j + 1 == n { 0 } else { j + 1 };
            let m = self.moment[j] - self.moment[k];
            let (fx, fy) = (m * self.nx[j], m * self.ny[j]);
            out.fx[k] += fx;
            out.fy[k] += fy;
            out.fx[j] -= fx;
            out.fy[j] -= fy;
        }
        if out.joint_moment_n_m.len() != n {
            // Sized once, at the first evaluation.
            out.joint_moment_n_m.resize(n, 0.0);
        }
        out.joint_moment_n_m.copy_from_slice(&self.moment);
        out.joint_friction_power_w = power;
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
    use crate::sim::Simulation;

    fn params(mu: f64, damping: f64) -> Params {
        Params {
            pin_radius_m: 0.017,
            friction: mu,
            speed_rad_s: 1.0,
            damping_n_m_s_rad: damping,
        }
    }

    /// A settled paper's drive with its state disturbed by a deterministic
    /// pseudo-random velocity field, and its forces at that state.
    fn disturbed() -> (DriveModel, DriveState, Forces) {
        let scene = crate::scene::Scene::l60mc();
        let mut sim = Simulation::new(&scene).expect("paper's drive settles");
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for i in 0..sim.state.rollers() {
            sim.state.vx[i] += 2.0 * next();
            sim.state.vy[i] += 2.0 * next();
        }
        sim.forces.evaluate(&sim.model, &sim.state);
        (sim.model, sim.state, sim.forces.output().clone())
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
            for i in 0..state.rollers() {
                let a = (i + state.rollers() - 1) % state.rollers();
                assert!(e.moment[i] * (e.omega[i] - e.omega[a]) <= 0.0, "joint {i}");
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
