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

/// Estimated largest stable steps of the explicit schemes (docs/model.md), s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepLimits {
    /// Links: 2 / ω_max with ω_max = 2 √(K / m_r) (symplectic Euler, velocity Verlet).
    pub links_s: f64,
    /// Contact damping at the approach-speed floor: 2 m_r / c with
    /// c = χ F / δ̇⁻_min, F taken as the pretension (a roller carrying the
    /// chain's tension, its contact begun slower than the floor).
    pub contact_damping_s: f64,
    /// Joint friction and damping (∞ without): 2 m_r ℓ² / (16 c_θ,eff) with
    /// c_θ,eff = μ r_pin F / ω_s + c_θ, the regularised law's slope in ω_rel
    /// at a pin load F taken as the pretension, and 16 / ℓ² the largest
    /// eigenvalue of the joints' damping matrix on the rollers' transverse
    /// speeds (the zig-zag mode, docs/model.md, “Joint friction”).
    pub joint_friction_s: f64,
}

impl StepLimits {
    /// The limits of a chain and its contact law.
    pub fn of_parts(chain: &Chain, contact: &Contact) -> Self {
        let m = chain.roller_mass_kg;
        let chi = contact.law.chi(contact.restitution);
        let c = chi * chain.pretension_n / contact.min_approach_speed_m_s;
        let joint_friction_s = chain.joint_friction.map_or(f64::INFINITY, |j| {
            let slope = j.friction * j.pin_radius_m * chain.pretension_n / j.speed_rad_s
                + j.damping_n_m_s_rad;
            if slope > 0.0 && slope.is_finite() {
                2.0 * m * chain.pitch_m * chain.pitch_m / (16.0 * slope)
            } else {
                f64::INFINITY
            }
        });
        Self {
            joint_friction_s,
            links_s: (m / chain.stiffness_n_m).sqrt(),
            contact_damping_s: if c > 0.0 && c.is_finite() {
                2.0 * m / c
            } else {
                f64::INFINITY
            },
        }
    }

    /// The smallest of them.
    pub fn min_s(&self) -> f64 {
        self.links_s
            .min(self.contact_damping_s)
            .min(self.joint_friction_s)
    }

    /// The estimated largest stable step of `scheme`, s (∞ for the adaptive
    /// scheme, which chooses its own). RK4's stability region reaches 2√2 on
    /// the imaginary axis (oscillating links) and 2.785 on the negative real
    /// axis (damping), against 2 and 2 for symplectic Euler.
    pub fn for_integrator(&self, scheme: Integrator) -> f64 {
        match scheme {
            Integrator::SymplecticEuler | Integrator::VelocityVerlet => self.min_s(),
            Integrator::Rk4 => (self.links_s * std::f64::consts::SQRT_2)
                .min(self.contact_damping_s * 1.3925)
                .min(self.joint_friction_s * 1.3925),
            Integrator::DormandPrince45 => f64::INFINITY,
            // The joint friction stays explicit there (its limit is far from
            // binding at the default ω_s, docs/model.md, “Joint friction”).
            Integrator::ImplicitDamping => self.links_s.min(self.joint_friction_s),
        }
    }

    /// The step `dt_s = "auto"` chooses for `scheme`: [`AUTO_SAFETY`] times
    /// its estimated limit. The adaptive scheme, which needs no limit, gets
    /// the symplectic schemes' step as its largest (and sample) step.
    pub fn auto_step_s(&self, scheme: Integrator) -> f64 {
        let limit = match scheme {
            Integrator::DormandPrince45 => self.min_s(),
            other => self.for_integrator(other),
        };
        AUTO_SAFETY * limit
    }
}

impl StepLimits {
    /// The limits of a validated scene's chain and contact law.
    pub fn of(scene: &super::Scene) -> Self {
        Self::of_parts(&scene.chain, &scene.contact)
    }
}
