//! The explicit schemes' stability estimates (docs/model.md, “Time scales and stability”),
//! from the validated chain and contact law alone; they also choose the step
//! of a scene whose `solver.dt_s` is `"auto"`.

use super::{Chain, Contact, Integrator};

/// Safety factor of `dt_s = "auto"`: the step is this fraction of the
/// scheme's estimated largest stable step. The estimates are
/// linearisations (a link between two fixed neighbours, a contact carrying the
/// pretension at the approach-speed floor); on the paper's drive the largest
/// stable step measured 0.94 times the links' estimate and 2.4 times the
/// contact damping's (docs/model.md, “Time scales and stability”), so one
/// half keeps a margin below the worst case.
pub const AUTO_SAFETY: f64 = 0.5;

/// `dt_s = "auto"` chooses a whole fraction of this interval, s (1 ms: the
/// default sample period).
pub const AUTO_GRID_S: f64 = 1e-3;

/// Estimated largest stable steps of the explicit schemes (docs/model.md), s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepLimits {
    /// Links: 2 / ω_max with ω_max = 2 √(K / m_r) (symplectic Euler, velocity Verlet).
    pub links_s: f64,
    /// Contact damping at the approach-speed floor: 2 m_r / c with
    /// c = χ F / δ̇⁻_min, F taken as the pretension (a roller carrying the
    /// chain's tension, its contact begun slower than the floor).
    pub contact_damping_s: f64,
}

impl StepLimits {
    /// The limits of a chain and its contact law.
    pub fn of_parts(chain: &Chain, contact: &Contact) -> Self {
        let m = chain.roller_mass_kg;
        let chi = contact.law.chi(contact.restitution);
        let c = chi * chain.pretension_n / contact.min_approach_speed_m_s;
        Self {
            links_s: (m / chain.stiffness_n_m).sqrt(),
            contact_damping_s: if c > 0.0 && c.is_finite() {
                2.0 * m / c
            } else {
                f64::INFINITY
            },
        }
    }

    /// The smaller of the two.
    pub fn min_s(&self) -> f64 {
        self.links_s.min(self.contact_damping_s)
    }

    /// The estimated largest stable step of `scheme`, s (∞ for the adaptive
    /// scheme, which chooses its own). RK4's stability region reaches 2√2 on
    /// the imaginary axis (oscillating links) and 2.785 on the negative real
    /// axis (damping), against 2 and 2 for symplectic Euler.
    pub fn for_integrator(&self, scheme: Integrator) -> f64 {
        match scheme {
            Integrator::SymplecticEuler | Integrator::VelocityVerlet => self.min_s(),
            Integrator::Rk4 => {
                (self.links_s * std::f64::consts::SQRT_2).min(self.contact_damping_s * 1.3925)
            }
            Integrator::DormandPrince45 => f64::INFINITY,
            Integrator::ImplicitDamping => self.links_s,
        }
    }

    /// The step `dt_s = "auto"` chooses for `scheme`: [`AUTO_SAFETY`] times
    /// its estimated limit, rounded down to a whole fraction of
    /// [`AUTO_GRID_S`] (so that the default 1 kHz sampling, and every rate
    /// dividing it, is a whole number of steps). The adaptive scheme, which
    /// needs no limit, gets the symplectic schemes' step as its largest (and
    /// sample) step.
    pub fn auto_step_s(&self, scheme: Integrator) -> f64 {
        let limit = match scheme {
            Integrator::DormandPrince45 => self.min_s(),
            other => self.for_integrator(other),
        };
        let raw = AUTO_SAFETY * limit;
        if !(raw.is_finite() && raw > 0.0) {
            return raw;
        }
        // The largest AUTO_GRID_S / n not above `raw`; the small tolerance
        // keeps a step that is already a whole fraction from losing one.
        let n = (AUTO_GRID_S / raw * (1.0 - 1e-12)).ceil().max(1.0);
        AUTO_GRID_S / n
    }
}

impl StepLimits {
    /// The limits of a validated scene's chain and contact law.
    pub fn of(scene: &super::Scene) -> Self {
        Self::of_parts(&scene.chain, &scene.contact)
    }
}
