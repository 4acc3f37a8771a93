//! Continuous contact laws of the Hunt–Crossley family (docs/model.md,
//! “Contact law”):
//!
//! ```text
//! f = K_g δⁿ (1 + χ δ̇ / δ̇⁻),   Lankarani–Nikravesh: χ = 3 (1 − e²) / 4
//! ```
//!
//! Guards every implementation needs, and which this one documents:
//! - the total is clamped to ≥ 0 (no adhesion while separating);
//! - the remembered approach speed δ̇⁻ is bounded below by
//!   `min_approach_speed_m_s`, so a gentle or resting contact does not get
//!   unbounded damping (c = χ K_g δⁿ / δ̇⁻) and the explicit step limit
//!   2 m_r / c does not collapse. A contact that starts slower than the floor
//!   is damped as if it had started at the floor speed: less dissipation than
//!   the law's literal reading, on impacts that carry almost no energy.
//!
//! Known limit: with e = 0 a Lankarani–Nikravesh impact still rebounds at about
//! 0.66 of its approach speed (the law was derived for e near 1).

use crate::scene::Contact;
#[cfg(test)]
use crate::scene::ContactLaw;

/// A contact law ready to evaluate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLawParams {
    /// K_g, N/m^n.
    pub stiffness: f64,
    /// n.
    pub exponent: f64,
    /// χ of `K δⁿ (1 + χ δ̇/δ̇⁻)`.
    pub chi: f64,
    /// Floor on δ̇⁻, m/s.
    pub min_approach_speed_m_s: f64,
    /// n == 1.5 exactly: δ^1.5 = δ √δ, much cheaper than `powf`.
    hertz: bool,
}

impl ContactLawParams {
    /// From the scene's contact settings.
    pub fn new(contact: &Contact) -> Self {
        let chi = contact.law.chi(contact.restitution);
        Self {
            stiffness: contact.stiffness,
            exponent: contact.exponent,
            chi,
            min_approach_speed_m_s: contact.min_approach_speed_m_s,
            hertz: contact.exponent == 1.5,
        }
    }

    /// The same law with another damping factor χ.
    pub fn with_chi(self, chi: f64) -> Self {
        Self { chi, ..self }
    }

    /// The approach speed to remember at contact onset.
    #[inline]
    pub fn onset_speed(&self, approach_speed_m_s: f64) -> f64 {
        approach_speed_m_s.max(self.min_approach_speed_m_s)
    }

    /// Whether n is 3/2 exactly, where [`Self::elastic`] is K δ √δ.
    #[inline]
    pub(crate) fn hertz(&self) -> bool {
        self.hertz
    }

    /// Elastic part K_g δⁿ, N.
    #[inline]
    pub fn elastic(&self, depth_m: f64) -> f64 {
        if self.hertz {
            self.stiffness * depth_m * depth_m.sqrt()
        } else {
            self.stiffness * depth_m.powf(self.exponent)
        }
    }

    /// The damping factor χ / δ̇⁻ to remember for a contact whose onset
    /// approach speed is `approach_speed_m_s` (floored), 1/(m/s).
    #[inline]
    pub fn damping_per_speed(&self, approach_speed_m_s: f64) -> f64 {
        self.chi / self.onset_speed(approach_speed_m_s)
    }

    /// Normal force from a remembered damping factor χ / δ̇⁻ (see
    /// [`Self::damping_per_speed`]): a multiplication where [`Self::force`] divides.
    #[inline]
    pub fn force_with(&self, depth_m: f64, depth_rate_m_s: f64, damping_per_speed: f64) -> f64 {
        (self.elastic(depth_m) * (1.0 + damping_per_speed * depth_rate_m_s)).max(0.0)
    }

    /// Normal force magnitude, N (≥ 0).
    ///
    /// `depth_rate_m_s` is δ̇ (positive while approaching), `onset_m_s` the
    /// remembered approach speed δ̇⁻ (already floored).
    #[inline]
    pub fn force(&self, depth_m: f64, depth_rate_m_s: f64, onset_m_s: f64) -> f64 {
        let f = self.elastic(depth_m) * (1.0 + self.chi * depth_rate_m_s / onset_m_s);
        f.max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ln(e: f64) -> ContactLawParams {
        ContactLawParams::new(&Contact {
            law: ContactLaw::LankaraniNikravesh,
            stiffness: 1e9,
            exponent: 1.5,
            restitution: e,
            min_approach_speed_m_s: 0.05,
        })
    }

    #[test]
    fn closed_form_values() {
        // f = 1e9 · (1e-4)^1.5 · (1 + 0.75 · 0.3/0.6) = 1e3 · 1.375
        let law = ln(0.0);
        assert!((law.force(1e-4, 0.3, 0.6) - 1375.0).abs() < 1e-9);
        // e = 1: purely elastic.
        assert!((ln(1.0).force(1e-4, 0.3, 0.6) - 1000.0).abs() < 1e-9);
        // e = 0.5: χ = 0.5625.
        assert!((ln(0.5).force(4e-4, -0.2, 0.4) - 8000.0 * (1.0 - 0.5625 * 0.5)).abs() < 1e-9);
    }

    #[test]
    fn remembered_factor_form_agrees() {
        let law = ln(0.2);
        let k = law.damping_per_speed(0.6);
        let (a, b) = (law.force(2e-4, 0.3, 0.6), law.force_with(2e-4, 0.3, k));
        assert!((a - b).abs() <= 1e-12 * a);
    }

    #[test]
    fn never_adhesive() {
        // Separating fast: 1 + 0.75·(−3)/0.1 < 0 → clamped.
        assert_eq!(ln(0.0).force(1e-4, -3.0, 0.1), 0.0);
    }

    #[test]
    fn general_exponent_matches_hertz_fast_path() {
        let mut general = ln(0.3);
        general.hertz = false;
        let fast = ln(0.3);
        for d in [1e-7, 3e-5, 2e-4] {
            let (a, b) = (general.force(d, 0.1, 0.2), fast.force(d, 0.1, 0.2));
            assert!((a - b).abs() <= 1e-12 * a.abs());
        }
    }

    /// Rebound ratio of one impact of a unit mass at 1 m/s on K = 1e9 N/m^1.5
    /// under `law` with restitution `e` (RK4, 1e-8 s steps through a ~0.1 ms impact).
    fn rebound(law: ContactLaw, e: f64) -> f64 {
        let p = ContactLawParams::new(&Contact {
            law,
            stiffness: 1e9,
            exponent: 1.5,
            restitution: e,
            min_approach_speed_m_s: 1e-3,
        });
        let v0 = 1.0;
        let k = p.damping_per_speed(v0);
        // State (δ, δ̇): δ̈ = −f(δ, δ̇) / m.
        let acc = |d: f64, v: f64| {
            if d > 0.0 { -p.force_with(d, v, k) } else { 0.0 }
        };
        let (mut d, mut v, h) = (0.0f64, v0, 1e-8);
        for _ in 0..10_000_000 {
            let (k1d, k1v) = (v, acc(d, v));
            let (k2d, k2v) = (v + 0.5 * h * k1v, acc(d + 0.5 * h * k1d, v + 0.5 * h * k1v));
            let (k3d, k3v) = (v + 0.5 * h * k2v, acc(d + 0.5 * h * k2d, v + 0.5 * h * k2v));
            let (k4d, k4v) = (v + h * k3v, acc(d + h * k3d, v + h * k3v));
            d += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            if d < 0.0 {
                return -v / v0;
            }
        }
        f64::NAN
    }

    #[test]
    fn effective_restitution_table() {
        use ContactLaw::*;
        // docs/model.md, “Limits of the contact law”: Lankarani–Nikravesh with e = 0 rebounds at
        // about 0.66.
        let ln0 = rebound(LankaraniNikravesh, 0.0);
        assert!((0.65..0.68).contains(&ln0), "{ln0}");
        // Near e = 1 every law was built to give e (within 3 %).
        for law in [LankaraniNikravesh, HuntCrossley, Flores, Gonthier] {
            let r = rebound(law, 0.9);
            assert!((r - 0.9).abs() < 0.03, "{law:?}: {r}");
        }
        // Gonthier et al.'s χ gives e over the whole range (within 0.02);
        // Lankarani–Nikravesh and Hunt–Crossley stay far above it at small e.
        for e in [0.1, 0.3, 0.5, 0.7] {
            let r = rebound(Gonthier, e);
            assert!((r - e).abs() < 0.035, "Gonthier e = {e}: {r}");
        }
        assert!(rebound(HuntCrossley, 0.0) > 0.45);
        // The rebound grows with e under every law.
        for law in [LankaraniNikravesh, HuntCrossley, Flores, Gonthier] {
            let r: Vec<f64> = [0.2, 0.5, 0.8].iter().map(|&e| rebound(law, e)).collect();
            assert!(r[0] < r[1] && r[1] < r[2], "{law:?}: {r:?}");
        }
    }

    #[test]
    fn onset_speed_is_floored() {
        assert_eq!(ln(0.0).onset_speed(1e-6), 0.05);
        assert_eq!(ln(0.0).onset_speed(0.7), 0.7);
    }
}
