//! Every joint's pin–bushing sliding, counted every step from a chosen time:
//! the articulation ∫|ω_rel| dt and the pin load times it ∫F_pin |ω_rel| dt
//! (docs/design-checks.md, "Wear"). The wear check turns these into wear
//! depth ([`crate::analysis::design::wear`]); nothing here knows of wear
//! coefficients or bearing areas.
//!
//! Joint i sits at roller i, between link i − 1 and link i (joint 0 between
//! the closing link and link 0), as in the joint friction: ω_rel = ω_i −
//! ω_{i−1}, each link's ω = (u × Δv)/ℓ as the links' pass writes it, and the
//! pin load is the mean of the two links' forces, zero in compression. The
//! sliding distance is r_pin |Δφ|. Each step counts the values at its end
//! over its length (a right rectangle); the first step counted only marks
//! the start.

use serde::{Deserialize, Serialize};

use crate::forces::Forces;

/// The joints' sliding over a window (module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointSliding {
    /// Steps ending before this are not counted, s.
    from_s: f64,
    /// End time of the last step counted, s.
    last_s: Option<f64>,
    /// Time counted, s.
    duration_s: f64,
    /// ∫|ω_rel| dt of each joint, rad.
    angle_rad: Vec<f64>,
    /// ∫F_pin |ω_rel| dt of each joint, N·rad.
    load_angle_n_rad: Vec<f64>,
}

impl JointSliding {
    /// Counts the `joints` joints from `from_s` on.
    pub fn new(from_s: f64, joints: usize) -> Self {
        Self {
            from_s,
            last_s: None,
            duration_s: 0.0,
            angle_rad: vec![0.0; joints],
            load_angle_n_rad: vec![0.0; joints],
        }
    }

    /// Counts the step that ended at `t_s` with the forces `out` evaluated
    /// there. Needs the links' rates (`Forces::link_omega`, which
    /// [`crate::forces::ForceGenerator::want_link_rates`] asks for); without
    /// them it counts nothing.
    pub fn step(&mut self, t_s: f64, out: &Forces) {
        if t_s < self.from_s {
            return;
        }
        let Some(last) = self.last_s.replace(t_s) else {
            return;
        };
        let dt = t_s - last;
        let n = self.angle_rad.len();
        if out.link_omega.len() != n || out.link_force.len() != n || n < 2 || !(dt > 0.0) {
            return;
        }
        self.duration_s += dt;
        let (omega, force) = (&out.link_omega[..n], &out.link_force[..n]);
        let (angle, load) = (&mut self.angle_rad[..n], &mut self.load_angle_n_rad[..n]);
        // Joint 0 closes the loop; joints 1..n over zipped slices (no bounds
        // checks, vectorised).
        let count = |w_a: f64, w_b: f64, f_a: f64, f_b: f64, a: &mut f64, l: &mut f64| {
            let turned = (w_b - w_a).abs() * dt;
            *a += turned;
            // The pin load ½ (F_a + F_b), zero in compression.
            *l += (f_a + f_b).max(0.0) * (0.5 * turned);
        };
        count(
            omega[n - 1],
            omega[0],
            force[n - 1],
            force[0],
            &mut angle[0],
            &mut load[0],
        );
        let pairs = omega[..n - 1]
            .iter()
            .zip(&omega[1..])
            .zip(force[..n - 1].iter().zip(&force[1..]));
        for (((w_a, w_b), (f_a, f_b)), (a, l)) in
            pairs.zip(angle[1..].iter_mut().zip(load[1..].iter_mut()))
        {
            count(*w_a, *w_b, *f_a, *f_b, a, l);
        }
    }

    /// Time counted, s.
    pub fn duration_s(&self) -> f64 {
        self.duration_s
    }

    /// Each joint's ∫|ω_rel| dt over the counted time, rad.
    pub fn angle_rad(&self) -> &[f64] {
        &self.angle_rad
    }

    /// Each joint's ∫F_pin |ω_rel| dt over the counted time, N·rad.
    pub fn load_angle_n_rad(&self) -> &[f64] {
        &self.load_angle_n_rad
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_joint_turning_steadily_counts_angle_and_load_times_angle() {
        // Four links; link 1 turns at 2 rad/s, the others not: joint 1
        // (links 0 → 1) turns at +2, joint 2 (links 1 → 2) at −2 rad/s.
        // Links at 100 N but link 2 in compression (−50 N): joint 1 carries
        // 100 N, joint 2 ½(100 − 50) = 25 N, joint 3 ½(−50 + 100) = 25 N.
        // 11 steps of 1 ms from t = 0: the first marks the start, ten are
        // counted: 0.02 rad at joints 1 and 2; 2 N·rad and 0.5 N·rad.
        let mut out = Forces::new(4, 1, 0, 0);
        out.link_omega = vec![0.0, 2.0, 0.0, 0.0];
        out.link_force = vec![100.0, 100.0, -50.0, 100.0];
        let mut s = JointSliding::new(0.0, 4);
        for k in 0..=10 {
            s.step(k as f64 * 1e-3, &out);
        }
        approx::assert_relative_eq!(s.duration_s(), 0.01, max_relative = 1e-12);
        let expected_angle = [0.0, 0.02, 0.02, 0.0];
        let expected_load = [0.0, 2.0, 0.5, 0.0];
        for j in 0..4 {
            approx::assert_relative_eq!(s.angle_rad()[j], expected_angle[j], epsilon = 1e-15);
            approx::assert_relative_eq!(s.load_angle_n_rad()[j], expected_load[j], epsilon = 1e-12);
        }
    }

    #[test]
    fn steps_before_the_window_and_without_rates_count_nothing() {
        let mut out = Forces::new(4, 1, 0, 0);
        out.link_force = vec![100.0; 4];
        let mut s = JointSliding::new(1.0, 4);
        // No link rates sized: nothing, even inside the window.
        for k in 0..5 {
            s.step(1.0 + k as f64 * 1e-3, &out);
        }
        assert_eq!(s.duration_s(), 0.0);
        out.link_omega = vec![1.0, 0.0, 0.0, 0.0];
        let mut s = JointSliding::new(1.0, 4);
        s.step(0.5, &out);
        s.step(0.999, &out);
        assert_eq!(s.duration_s(), 0.0);
        assert!(s.angle_rad().iter().all(|a| *a == 0.0));
    }
}
