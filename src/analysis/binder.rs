//! Binder's quasi-static force distribution over the rollers bedded on a
//! sprocket (the paper's (47)–(51); docs/model.md, “Binder's quasi-static contact
//! forces”), and the kinematic
//! polygonal-action reference.
//!
//! A sprocket has `nb` rollers bedded, numbered i = 1 … nb in the direction of
//! chain travel; link i joins roller i and i + 1, so link 0 is the last free
//! link of the entering strand (mean force q_a) and link nb the first free link
//! of the leaving strand (q_b). With the pressure angle α = 35° − 120°/nt (48),
//! the pitch angle φ = 2π/nt and β = sin α / sin(α + φ), a tension decays by β
//! per bedded roller from either side. The centrifugal part q_c = m_r V²/P (50)
//! of every link force reaches no tooth, so with q̃ = q − q_c the consistent
//! forms are
//!
//! ```text
//! (f_l)_i = q̃_a β^i + q̃_b β^(nb−i) + q_c                          i = 0 … nb   (47)
//! (f_c)_i = [q̃_a β^(i−1) + q̃_b β^(nb−i)] sin φ / sin(α + φ)       i = 1 … nb   (49)
//! ```
//!
//! The paper prints (47) with exponents i and nb − i + 1, adds q_c to the
//! full q_a, q_b terms, and adds 2 q_c sin(φ/2) to (49); [`printed_link_forces`]
//! and [`printed_contact_forces`] give those forms for comparison (with q_c in
//! SI: the printed q_c = m_r V²/(P g) is the imperial, weight-based form).
//! Nothing here looks at a simulation: the caller supplies q_a, q_b, q_c, nb.

use std::f64::consts::PI;

/// Pressure angle α = 35° − 120°/nt (48), rad.
pub(crate) fn pressure_angle_rad(teeth: u32) -> f64 {
    (35.0 - 120.0 / f64::from(teeth)).to_radians()
}

/// Pitch angle φ = 2π/nt, rad.
pub(crate) fn pitch_angle_rad(teeth: u32) -> f64 {
    2.0 * PI / f64::from(teeth)
}

/// Decay factor per bedded roller β = sin α / sin(α + φ).
pub(crate) fn beta(teeth: u32) -> f64 {
    let (a, p) = (pressure_angle_rad(teeth), pitch_angle_rad(teeth));
    a.sin() / (a + p).sin()
}

/// Centrifugal tension q_c = m_r V² / P (50), N.
pub(crate) fn centrifugal_tension_n(
    roller_mass_kg: f64,
    chain_speed_m_s: f64,
    pitch_m: f64,
) -> f64 {
    if pitch_m > 0.0 {
        roller_mass_kg * chain_speed_m_s * chain_speed_m_s / pitch_m
    } else {
        0.0
    }
}

/// What (47)–(49) need for one sprocket.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BinderInputs {
    /// Tooth count nt.
    pub teeth: u32,
    /// Rollers bedded, nb ≥ 1.
    pub bedded: usize,
    /// Mean link force of the entering strand q_a, N.
    pub q_a_n: f64,
    /// Mean link force of the leaving strand q_b, N.
    pub q_b_n: f64,
    /// Centrifugal tension q_c, N.
    pub q_c_n: f64,
}

impl BinderInputs {
    fn terms(&self) -> (f64, f64, f64, i32) {
        let nb = i32::try_from(self.bedded).unwrap_or(i32::MAX);
        let (a, p) = (pressure_angle_rad(self.teeth), pitch_angle_rad(self.teeth));
        (beta(self.teeth), p.sin() / (a + p).sin(), p, nb)
    }

    /// Link forces (47), consistent form: nb + 1 values for links i = 0 … nb, N.
    #[cfg(test)]
    pub(crate) fn link_forces(&self) -> Vec<f64> {
        let (b, _, _, nb) = self.terms();
        let (qa, qb) = (self.q_a_n - self.q_c_n, self.q_b_n - self.q_c_n);
        (0..=nb)
            .map(|i| qa * b.powi(i) + qb * b.powi(nb - i) + self.q_c_n)
            .collect()
    }

    /// Contact forces (49), consistent form: nb values for rollers i = 1 … nb, N.
    pub(crate) fn contact_forces(&self) -> Vec<f64> {
        let (b, s, _, nb) = self.terms();
        let (qa, qb) = (self.q_a_n - self.q_c_n, self.q_b_n - self.q_c_n);
        (1..=nb)
            .map(|i| (qa * b.powi(i - 1) + qb * b.powi(nb - i)) * s)
            .collect()
    }
}

/// Link forces as the paper prints (47): q_a β^i + q_b β^(nb−i+1) + q_c for
/// i = 1 … nb, N.
#[cfg(test)]
pub(crate) fn printed_link_forces(inputs: &BinderInputs) -> Vec<f64> {
    let (b, _, _, nb) = inputs.terms();
    (1..=nb)
        .map(|i| inputs.q_a_n * b.powi(i) + inputs.q_b_n * b.powi(nb - i + 1) + inputs.q_c_n)
        .collect()
}

/// Contact forces as the paper prints (49):
/// [q_a β^(i−1) + q_b β^(nb−i)] sin φ / sin(α+φ) + 2 q_c sin(φ/2), i = 1 … nb, N.
pub(crate) fn printed_contact_forces(inputs: &BinderInputs) -> Vec<f64> {
    let (b, s, p, nb) = inputs.terms();
    (1..=nb)
        .map(|i| {
            (inputs.q_a_n * b.powi(i - 1) + inputs.q_b_n * b.powi(nb - i)) * s
                + 2.0 * inputs.q_c_n * (0.5 * p).sin()
        })
        .collect()
}

/// The times (51) at which the nb analytical values are placed:
/// t_i = t_s + (i − 1)(t_e − t_s)/(nb − 1), i = 1 … nb (t_s alone for nb = 1).
pub(crate) fn placement_times_s(t_start_s: f64, t_end_s: f64, bedded: usize) -> Vec<f64> {
    if bedded <= 1 {
        return vec![t_start_s; bedded];
    }
    let step = (t_end_s - t_start_s) / (bedded - 1) as f64;
    (0..bedded).map(|i| t_start_s + i as f64 * step).collect()
}

/// Polygonal action (docs/model.md, “Polygonal action”): the strand speed
/// leaving a sprocket of nt teeth at constant ω varies by 1 − cos(π/nt) of its
/// maximum.
pub(crate) fn polygonal_speed_variation(teeth: u32) -> f64 {
    1.0 - (PI / f64::from(teeth)).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symmetric_loading_is_symmetric() {
        let b = BinderInputs {
            teeth: 30,
            bedded: 6,
            q_a_n: 20e3,
            q_b_n: 20e3,
            q_c_n: 3e3,
        };
        let f = b.contact_forces();
        for i in 0..f.len() {
            assert!((f[i] - f[f.len() - 1 - i]).abs() < 1e-9);
        }
        let l = b.link_forces();
        assert!((l[0] - l[6]).abs() < 1e-9);
    }

    #[test]
    fn placement_spans_contact() {
        let t = placement_times_s(1.0, 2.0, 5);
        assert_eq!(t, vec![1.0, 1.25, 1.5, 1.75, 2.0]);
        assert_eq!(placement_times_s(1.0, 2.0, 1), vec![1.0]);
    }
}
