//! The validated parts of a scene: chain, contact, sprockets, solver and
//! static-equilibrium settings, in SI units. Built only by the validator
//! ([`super::Scene`]); read, never written, by the rest of the crate.

use super::excitation::Excitation;
use super::resisting::Resisting;
use super::{ContactLaw, Integrator, PretensionRule, ProfileKind, Stepping, Wrap};

/// A driver's prescribed speed: a linear ramp from rest, then constant,
/// then optionally a slow linear run-up to another speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedLaw {
    /// Speed after the ramp, rad/s, counter-clockwise positive.
    pub speed_rad_s: f64,
    /// Ramp time from rest, s (0 = constant speed from t = 0).
    pub ramp_s: f64,
    /// A linear change of speed after the ramp (`sprockets.run_up`).
    pub run_up: Option<RunUp>,
}

/// A driver's run-up: from `start_s` on its speed goes linearly from the
/// law's `speed_rad_s` to `to_rad_s` over `duration_s`, and stays there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunUp {
    /// Start, s (not before the ramp's end).
    pub start_s: f64,
    /// Length, s (> 0).
    pub duration_s: f64,
    /// Speed at its end, rad/s, the sense of the law's speed.
    pub to_rad_s: f64,
}

impl SpeedLaw {
    /// A ramp from rest to `speed_rad_s` over `ramp_s`, then constant.
    pub fn ramped(speed_rad_s: f64, ramp_s: f64) -> Self {
        Self {
            speed_rad_s,
            ramp_s,
            run_up: None,
        }
    }

    /// Angular speed at time `t_s` (rest before t = 0).
    pub fn speed_at(&self, t_s: f64) -> f64 {
        let base = if t_s <= 0.0 && self.ramp_s > 0.0 {
            0.0
        } else if t_s < self.ramp_s {
            self.speed_rad_s * t_s / self.ramp_s
        } else {
            self.speed_rad_s
        };
        match self.run_up {
            Some(r) if t_s > r.start_s => {
                let s = ((t_s - r.start_s) / r.duration_s).min(1.0);
                base + (r.to_rad_s - self.speed_rad_s) * s
            }
            _ => base,
        }
    }

    /// The largest speed magnitude the law reaches, rad/s.
    pub fn top_speed_rad_s(&self) -> f64 {
        let end = self.run_up.map_or(0.0, |r| r.to_rad_s.abs());
        self.speed_rad_s.abs().max(end)
    }
}

/// What a sprocket does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Role {
    /// Kinematically driven at a prescribed speed.
    Driver(SpeedLaw),
    /// Turns freely about a fixed centre, optionally against a load torque (N·m, CCW positive).
    Free {
        /// External torque on the sprocket at full value, N·m.
        load_torque_n_m: f64,
        /// Time of the load's linear rise from zero, s (0: applied at rest).
        load_ramp_s: f64,
    },
    /// Turns freely; its centre is moved along `direction` to reach the pretension.
    Tensioner {
        /// External torque on the sprocket at full value, N·m.
        load_torque_n_m: f64,
        /// Time of the load's linear rise from zero, s (0: applied at rest).
        load_ramp_s: f64,
        /// Unit adjustment direction (world frame).
        direction: [f64; 2],
    },
}

/// A validated sprocket.
#[derive(Clone, Debug, PartialEq)]
pub struct Sprocket {
    /// Name, for humans.
    pub name: String,
    /// Centre, m.
    pub center_m: [f64; 2],
    /// Tooth count.
    pub teeth: u32,
    /// Pitch radius P / (2 sin(π/N)), m.
    pub pitch_radius_m: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Polar moment of inertia, kg·m².
    pub inertia_kg_m2: f64,
    /// Wrap sense.
    pub wrap: Wrap,
    /// Driver, free or tensioner.
    pub role: Role,
    /// Tooth profile.
    pub profile: ProfileKind,
    /// Speed harmonics (a driver) or a load in the sprocket's angle.
    pub(crate) excitation: Excitation,
    /// A torque opposing the sprocket's rotation; `None`: none.
    pub(crate) resisting: Option<Resisting>,
}

impl Sprocket {
    /// The driver's speed law, if this is the driver.
    pub fn speed_law(&self) -> Option<SpeedLaw> {
        match self.role {
            Role::Driver(law) => Some(law),
            _ => None,
        }
    }

    /// The size of the torque opposing its rotation, N·m (zero without one;
    /// see `resisting_torque_n_m` in the scene file).
    pub fn resisting_torque_n_m(&self) -> f64 {
        self.resisting.map_or(0.0, |r| r.torque_n_m)
    }

    /// External load torque (zero for the driver).
    pub fn load_torque_n_m(&self) -> f64 {
        match self.role {
            Role::Driver(_) => 0.0,
            Role::Free {
                load_torque_n_m, ..
            }
            | Role::Tensioner {
                load_torque_n_m, ..
            } => load_torque_n_m,
        }
    }

    /// Time over which the load torque rises linearly from zero, s (0: the
    /// load acts from rest on; always 0 for the driver).
    pub fn load_ramp_s(&self) -> f64 {
        match self.role {
            Role::Driver(_) => 0.0,
            Role::Free { load_ramp_s, .. } | Role::Tensioner { load_ramp_s, .. } => load_ramp_s,
        }
    }
}

/// A validated chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// Number of rollers (and of links).
    pub rollers: usize,
    /// Pitch, m.
    pub pitch_m: f64,
    /// Roller radius, m.
    pub roller_radius_m: f64,
    /// Roller mass, kg.
    pub roller_mass_kg: f64,
    /// Link stiffness K, N/m.
    pub stiffness_n_m: f64,
    /// Link damping D, N·s/m.
    pub damping_n_s_m: f64,
    /// Static pretension, N.
    pub pretension_n: f64,
    /// How the pretension is reached.
    pub pretension_by: PretensionRule,
    /// Pin–bushing friction at every joint; `None`: off.
    pub joint_friction: Option<JointFriction>,
    /// The standard chain the scene named (`chain.designation`), if any.
    pub designation: Option<&'static str>,
    /// Strands side by side (`"ANSI 80-2"`: 2; 1 without a designation);
    /// the designation's mass, stiffness and strength are already of all
    /// strands.
    pub strands: u32,
    /// Pin radius, m, where the scene or its designation gives it.
    pub pin_radius_m: Option<f64>,
    /// Tensile strength of the whole chain (all strands), N, where the scene
    /// (`chain.tensile_strength_n`) or its designation gives it.
    pub tensile_strength_n: Option<f64>,
    /// Length of the bushing the pin bears on, m, where known.
    pub bushing_length_m: Option<f64>,
    /// Wear elongation of every pitch, as a fraction (`chain.elongation_pct`
    /// / 100; 0 for a new chain).
    pub elongation: f64,
}

impl Chain {
    /// The worn chain's pitch P (1 + e), m: the length of every link and the
    /// distance of consecutive rollers at rest (the nominal pitch for a new
    /// chain).
    pub fn worn_pitch_m(&self) -> f64 {
        if self.elongation == 0.0 {
            self.pitch_m
        } else {
            self.pitch_m * (1.0 + self.elongation)
        }
    }

    /// The chain's mass per length, kg/m: a roller's mass over the worn
    /// pitch (a worn chain is the same mass spread over a longer length).
    pub(crate) fn mass_per_length_kg_m(&self) -> f64 {
        self.roller_mass_kg / self.worn_pitch_m()
    }

    /// The length the worn chain gained over the new one, N P e, m.
    pub(crate) fn wear_gain_m(&self) -> f64 {
        self.rollers as f64 * self.pitch_m * self.elongation
    }
}

/// Pin–bushing friction and damping at the chain's joints (docs/model.md,
/// “Joint friction”): M = −μ r_pin F_pin s(ω_rel / ω_s) − c_θ ω_rel, s a cubic step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointFriction {
    /// Pin radius r_pin, m.
    pub pin_radius_m: f64,
    /// Coulomb coefficient μ.
    pub friction: f64,
    /// Regularisation speed ω_s, rad/s.
    pub speed_rad_s: f64,
    /// Viscous joint damping c_θ, N·m·s/rad.
    pub damping_n_m_s_rad: f64,
}

/// Regularisation speed ω_s of the joint friction when the scene gives none,
/// rad/s: far below the articulation speed at a sprocket (its angular speed,
/// 12.6 rad/s on the paper's drive's crankshaft), and large enough that the
/// law's slope μ r_pin F / ω_s keeps the paper's drive's explicit limit above
/// 10 µs (docs/model.md, “Joint friction”).
pub(crate) const DEFAULT_JOINT_FRICTION_SPEED_RAD_S: f64 = 1.0;

/// Validated contact-law parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The law.
    pub law: ContactLaw,
    /// K_g, N/m^n.
    pub stiffness: f64,
    /// n.
    pub exponent: f64,
    /// e.
    pub restitution: f64,
    /// Floor on δ̇⁻, m/s.
    pub min_approach_speed_m_s: f64,
}

/// Validated solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solver {
    /// How the chain is advanced.
    pub stepping: Stepping,
    /// Integration scheme.
    pub integrator: Integrator,
    /// Step, s (the adaptive scheme's largest step and sample step).
    pub dt_s: f64,
    /// Whether `dt_s` was chosen automatically (`dt_s = "auto"` or
    /// `"speed"`, or left out).
    pub dt_auto: bool,
    /// Whether the automatic step was chosen for speed (`dt_s = "speed"`).
    pub dt_speed: bool,
    /// The sample period an automatic step is a whole fraction of, s (the
    /// run's, [`super::Overrides::sample_rate_hz`]; 1 ms where none is given).
    pub sample_period_s: f64,
    /// The blow-up detectors' limits.
    pub limits: Limits,
    /// Error tolerance of the adaptive scheme (see `crate::sim::integrate`).
    pub tolerance: f64,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Threads stepping the drive (`solver.threads`).
    pub threads: super::Threads,
}

/// Validated blow-up limits (`[solver.limits]`, docs/model.md "Blow-up
/// detectors"), defaults filled in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Deepest penetration of a roller into a tooth, m.
    pub max_penetration_m: f64,
    /// Largest |link length − rest length|, m.
    pub max_stretch_m: f64,
    /// Growth of the largest link stretch within `growth_steps` steps that
    /// counts as numerical blow-up.
    pub growth_factor: f64,
    /// The growth detector's window, steps.
    pub growth_steps: u32,
}

/// Validated static-equilibrium settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equilibrium {
    /// Relative tolerance on the pretension.
    pub tension_tolerance: f64,
    /// Largest relaxation time per iteration, s.
    pub max_relax_s: f64,
}
