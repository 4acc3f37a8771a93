//! Scenes: what a user writes ([`SceneFile`], TOML) and what the rest of the
//! crate consumes ([`Scene`], valid by construction).
//!
//! [`Scene::from_toml`] parses and validates in one go and reports *every*
//! problem it finds, each with the field's path (`sprockets[2].teeth`) and
//! what is allowed. Units are converted here (rpm → rad/s) and nowhere else.
//! This module knows nothing of rapier or of stepping.

mod error;
mod file;
pub mod generate;
pub mod mutate;

pub use error::{FieldError, SceneError, locate};
pub use file::{ChainFile, ContactFile, EquilibriumFile, SceneFile, SolverFile, SprocketFile};

pub use crate::geometry::ProfileKind;
use crate::geometry::pitch_radius;

/// The most sprockets a drive may have (the contact generator keeps each
/// roller's set of sprockets within reach as a 64-bit mask).
pub const MAX_SPROCKETS: usize = 64;

/// The paper's drive (MAN B&W L60MC camshaft chain), embedded as the default scene.
pub const L60MC_TOML: &str = include_str!("../../assets/l60mc.toml");

/// Contact laws of the Hunt–Crossley family `K δⁿ (1 + χ δ̇/δ̇⁻)` (MODEL.md §3).
///
/// They differ only in the damping factor χ(e); the effective restitution of a
/// single Hertzian impact under each law is tabled in [`crate::forces`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactLaw {
    /// χ = 3(1 − e²)/4 (Lankarani & Nikravesh 1990), the paper's law.
    LankaraniNikravesh,
    /// χ = 3(1 − e)/2 (Hunt & Crossley 1975, with α = (1 − e)/δ̇⁻).
    HuntCrossley,
    /// χ = 8(1 − e)/(5e) (Flores et al. 2011); needs e > 0.
    Flores,
    /// χ = (1 − e²)/e (Gonthier et al. 2004); needs e > 0.
    Gonthier,
}

impl ContactLaw {
    /// Every law with its scene-file name.
    pub const ALL: [(&'static str, Self); 4] = [
        ("lankarani_nikravesh", Self::LankaraniNikravesh),
        ("hunt_crossley", Self::HuntCrossley),
        ("flores", Self::Flores),
        ("gonthier", Self::Gonthier),
    ];

    /// The name used in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            Self::LankaraniNikravesh => "lankarani_nikravesh",
            Self::HuntCrossley => "hunt_crossley",
            Self::Flores => "flores",
            Self::Gonthier => "gonthier",
        }
    }

    /// The damping factor χ of `K δⁿ (1 + χ δ̇/δ̇⁻)` for restitution `e`
    /// (infinite for Flores and Gonthier at e = 0, which the scene rejects).
    pub fn chi(self, e: f64) -> f64 {
        match self {
            Self::LankaraniNikravesh => 0.75 * (1.0 - e * e),
            Self::HuntCrossley => 1.5 * (1.0 - e),
            Self::Flores => 1.6 * (1.0 - e) / e,
            Self::Gonthier => (1.0 - e * e) / e,
        }
    }

    /// Whether χ(e) is finite only for e > 0.
    pub fn needs_positive_restitution(self) -> bool {
        matches!(self, Self::Flores | Self::Gonthier)
    }
}

/// How the chain reaches its pretension (MODEL.md §8).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PretensionRule {
    /// Keep every position and shorten the links' rest length.
    RestLength,
    /// Move the tensioner sprocket along its adjustment direction.
    Tensioner,
}

/// Which way the chain goes round a sprocket when followed in scene order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Counter-clockwise (the paper's "+").
    Ccw,
    /// Clockwise (the paper's "−").
    Cw,
}

impl Wrap {
    /// +1 for counter-clockwise, −1 for clockwise.
    pub fn sign(self) -> f64 {
        match self {
            Self::Ccw => 1.0,
            Self::Cw => -1.0,
        }
    }
}

/// A driver's prescribed speed: a linear ramp from rest, then constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedLaw {
    /// Final speed, rad/s, counter-clockwise positive.
    pub speed_rad_s: f64,
    /// Ramp time from rest, s (0 = constant speed from t = 0).
    pub ramp_s: f64,
}

impl SpeedLaw {
    /// Angular speed at time `t_s` (rest before t = 0).
    pub fn speed_at(&self, t_s: f64) -> f64 {
        if t_s <= 0.0 && self.ramp_s > 0.0 {
            0.0
        } else if t_s < self.ramp_s {
            self.speed_rad_s * t_s / self.ramp_s
        } else {
            self.speed_rad_s
        }
    }
}

/// What a sprocket does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Role {
    /// Kinematically driven at a prescribed speed.
    Driver(SpeedLaw),
    /// Turns freely about a fixed centre, optionally against a load torque (N·m, CCW positive).
    Free {
        /// Constant external torque on the sprocket, N·m.
        load_torque_n_m: f64,
    },
    /// Turns freely; its centre is moved along `direction` to reach the pretension.
    Tensioner {
        /// Constant external torque on the sprocket, N·m.
        load_torque_n_m: f64,
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
}

impl Sprocket {
    /// The driver's speed law, if this is the driver.
    pub fn speed_law(&self) -> Option<SpeedLaw> {
        match self.role {
            Role::Driver(law) => Some(law),
            _ => None,
        }
    }

    /// External load torque (zero for the driver).
    pub fn load_torque_n_m(&self) -> f64 {
        match self.role {
            Role::Driver(_) => 0.0,
            Role::Free { load_torque_n_m }
            | Role::Tensioner {
                load_torque_n_m, ..
            } => load_torque_n_m,
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
}

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

/// How the chain is advanced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stepping {
    /// The plugin integrates the chain on its own arrays and writes poses back
    /// into rapier (the fast path).
    Substepped,
    /// rapier integrates every body; the plugin only supplies forces.
    Rapier,
}

impl Stepping {
    /// The name used in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            Self::Substepped => "substepped",
            Self::Rapier => "rapier",
        }
    }
}

/// Time integration scheme of the chain (see [`crate::sim::integrate`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// v ← v + dt a(x, v); x ← x + dt v (rapier's own scheme). Order 1, one
    /// force evaluation per step.
    SymplecticEuler,
    /// Velocity Verlet (kick–drift–kick). Order 2, two evaluations per step.
    VelocityVerlet,
    /// Classical Runge–Kutta. Order 4, four evaluations per step.
    Rk4,
    /// Dormand–Prince 5(4), adaptive, with contact onset and separation
    /// located; `solver.dt_s` is then the largest step and the sample step.
    DormandPrince45,
    /// Symplectic Euler with the contact damping taken implicitly: stable
    /// where the Lankarani–Nikravesh damping at small approach speeds limits
    /// the explicit schemes. Order 1.
    ImplicitDamping,
}

impl Integrator {
    /// Every scheme with its scene-file name.
    pub const ALL: [(&'static str, Self); 5] = [
        ("symplectic_euler", Self::SymplecticEuler),
        ("velocity_verlet", Self::VelocityVerlet),
        ("rk4", Self::Rk4),
        ("dormand_prince45", Self::DormandPrince45),
        ("implicit_damping", Self::ImplicitDamping),
    ];

    /// The name used in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            Self::SymplecticEuler => "symplectic_euler",
            Self::VelocityVerlet => "velocity_verlet",
            Self::Rk4 => "rk4",
            Self::DormandPrince45 => "dormand_prince45",
            Self::ImplicitDamping => "implicit_damping",
        }
    }

    /// From a scene-file name.
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.iter().find(|(n, _)| *n == s).map(|x| x.1)
    }

    /// Nominal order of convergence.
    pub fn order(self) -> u32 {
        match self {
            Self::SymplecticEuler | Self::ImplicitDamping => 1,
            Self::VelocityVerlet => 2,
            Self::Rk4 => 4,
            Self::DormandPrince45 => 5,
        }
    }

    /// Whether the step size is chosen by an error estimate.
    pub fn is_adaptive(self) -> bool {
        self == Self::DormandPrince45
    }
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
    /// Error tolerance of the adaptive scheme (see [`crate::sim::integrate`]).
    pub tolerance: f64,
    /// Simulated time, s.
    pub duration_s: f64,
}

/// Validated static-equilibrium settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equilibrium {
    /// Relative tolerance on the pretension.
    pub tension_tolerance: f64,
    /// Largest relaxation time per iteration, s.
    pub max_relax_s: f64,
}

/// A chain drive, valid by construction.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Name.
    pub name: String,
    /// Gravity, m/s².
    pub gravity_m_s2: [f64; 2],
    /// The chain.
    pub chain: Chain,
    /// The contact law.
    pub contact: Contact,
    /// Sprockets in the order the chain visits them.
    pub sprockets: Vec<Sprocket>,
    /// Solver settings.
    pub solver: Solver,
    /// Static-equilibrium settings.
    pub equilibrium: Equilibrium,
    /// The scene file this came from (for recordings and reports).
    pub source_toml: Option<String>,
}

/// Default floor on the remembered approach speed, m/s. At the paper's
/// K_g = 1 GN/m^1.5 and e = 0 a 20 kN contact has c = χ F / δ̇⁻ = 3·10⁵ N·s/m at
/// 0.05 m/s, right at the explicit limit 2 m_r/dt for dt = 20 µs; seating
/// impacts in the paper's drive run at 0.3–1 m/s, well above the floor.
pub const DEFAULT_MIN_APPROACH_SPEED_M_S: f64 = 0.05;

/// Relative tolerance between a stated pitch radius and P / (2 sin(π/N)).
pub const PITCH_RADIUS_TOLERANCE: f64 = 1e-5;
/// Supported tooth counts.
pub const TEETH_RANGE: std::ops::RangeInclusive<i64> = 5..=300;

impl Scene {
    /// Parses and validates a TOML scene. All problems are reported at once.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        let file: SceneFile = toml::from_str(text).map_err(SceneError::from_toml)?;
        let mut scene = Scene::try_from(file).map_err(|e| e.located(text))?;
        scene.source_toml = Some(text.to_owned());
        Ok(scene)
    }

    /// The paper's drive (`assets/l60mc.toml`, embedded).
    pub fn l60mc() -> Self {
        match Self::from_toml(L60MC_TOML) {
            Ok(scene) => scene,
            // The embedded scene is checked by the test suite.
            Err(e) => unreachable!("embedded scene is invalid: {e}"),
        }
    }

    /// Index of the driver.
    pub fn driver(&self) -> usize {
        self.sprockets
            .iter()
            .position(|s| matches!(s.role, Role::Driver(_)))
            .unwrap_or(0)
    }

    /// Index of the tensioner, if any.
    pub fn tensioner(&self) -> Option<usize> {
        self.sprockets
            .iter()
            .position(|s| matches!(s.role, Role::Tensioner { .. }))
    }

    /// The profile name for outputs: `circular`, `real` or `mixed`.
    pub fn profile_name(&self) -> &'static str {
        let first = self.sprockets[0].profile;
        if self.sprockets.iter().all(|s| s.profile == first) {
            first.name()
        } else {
            "mixed"
        }
    }

    /// Sets every sprocket's profile (the CLI's `--profile`).
    pub fn set_profile(&mut self, profile: ProfileKind) {
        for s in &mut self.sprockets {
            s.profile = profile;
        }
    }
}

/// Collects field errors while a file is checked.
struct Checker {
    errors: Vec<FieldError>,
}

impl Checker {
    fn fail(&mut self, path: impl Into<String>, message: impl Into<String>) {
        self.errors.push(FieldError {
            path: path.into(),
            message: message.into(),
            location: None,
        });
    }

    /// A finite, strictly positive quantity.
    fn positive(&mut self, path: &str, value: f64) -> f64 {
        if !value.is_finite() {
            self.fail(path, format!("must be a finite number, got {value}"));
        } else if value <= 0.0 {
            self.fail(path, format!("must be > 0, got {value}"));
        }
        value
    }

    /// A finite quantity ≥ 0.
    fn non_negative(&mut self, path: &str, value: f64) -> f64 {
        if !value.is_finite() {
            self.fail(path, format!("must be a finite number, got {value}"));
        } else if value < 0.0 {
            self.fail(path, format!("must be >= 0, got {value}"));
        }
        value
    }

    fn finite(&mut self, path: &str, value: f64) -> f64 {
        if !value.is_finite() {
            self.fail(path, format!("must be a finite number, got {value}"));
        }
        value
    }

    fn one_of<T: Copy>(&mut self, path: &str, value: &str, allowed: &[(&str, T)]) -> Option<T> {
        let found = allowed.iter().find(|(name, _)| *name == value).map(|x| x.1);
        if found.is_none() {
            let names: Vec<String> = allowed.iter().map(|(n, _)| format!("\"{n}\"")).collect();
            self.fail(
                path,
                format!("unknown value \"{value}\"; allowed: {}", names.join(", ")),
            );
        }
        found
    }
}

impl TryFrom<SceneFile> for Scene {
    type Error = SceneError;

    fn try_from(file: SceneFile) -> Result<Self, SceneError> {
        let mut c = Checker { errors: Vec::new() };
        for (i, g) in file.gravity_m_s2.iter().enumerate() {
            c.finite(&format!("gravity_m_s2[{i}]"), *g);
        }
        let default_profile = c.one_of(
            "profile",
            &file.profile,
            &[
                ("circular", ProfileKind::Circular),
                ("real", ProfileKind::Real),
            ],
        );
        let chain = check_chain(&mut c, &file.chain);
        let contact = check_contact(&mut c, &file.contact);
        let sprockets = check_sprockets(
            &mut c,
            &file.sprockets,
            &chain,
            default_profile.unwrap_or(ProfileKind::Circular),
        );
        let solver = check_solver(&mut c, &file.solver);
        let equilibrium = Equilibrium {
            tension_tolerance: c.positive(
                "equilibrium.tension_tolerance",
                file.equilibrium.tension_tolerance,
            ),
            max_relax_s: c.positive("equilibrium.max_relax_s", file.equilibrium.max_relax_s),
        };
        if chain.pretension_by == PretensionRule::Tensioner
            && !sprockets
                .iter()
                .any(|s| matches!(s.role, Role::Tensioner { .. }))
        {
            c.fail(
                "chain.pretension_by",
                "is \"tensioner\" but no sprocket has role = \"tensioner\"",
            );
        }
        if !c.errors.is_empty() {
            return Err(SceneError::Invalid(c.errors));
        }
        Ok(Scene {
            name: file.name,
            gravity_m_s2: file.gravity_m_s2,
            chain,
            contact,
            sprockets,
            solver,
            equilibrium,
            source_toml: None,
        })
    }
}

fn check_chain(c: &mut Checker, f: &ChainFile) -> Chain {
    if f.rollers < 4 {
        c.fail(
            "chain.rollers",
            format!("must be at least 4, got {}", f.rollers),
        );
    }
    let pitch_m = c.positive("chain.pitch_m", f.pitch_m);
    let roller_radius_m = c.positive("chain.roller_radius_m", f.roller_radius_m);
    if pitch_m.is_finite() && roller_radius_m.is_finite() && 2.0 * roller_radius_m >= pitch_m {
        c.fail(
            "chain.roller_radius_m",
            format!(
                "rollers of diameter {} m overlap at pitch {pitch_m} m",
                2.0 * roller_radius_m
            ),
        );
    }
    Chain {
        rollers: f.rollers.max(0) as usize,
        pitch_m,
        roller_radius_m,
        roller_mass_kg: c.positive("chain.roller_mass_kg", f.roller_mass_kg),
        stiffness_n_m: c.positive("chain.stiffness_n_m", f.stiffness_n_m),
        damping_n_s_m: c.non_negative("chain.damping_n_s_m", f.damping_n_s_m),
        pretension_n: c.positive("chain.pretension_n", f.pretension_n),
        pretension_by: c
            .one_of(
                "chain.pretension_by",
                &f.pretension_by,
                &[
                    ("rest_length", PretensionRule::RestLength),
                    ("tensioner", PretensionRule::Tensioner),
                ],
            )
            .unwrap_or(PretensionRule::RestLength),
    }
}

fn check_contact(c: &mut Checker, f: &ContactFile) -> Contact {
    let law = c
        .one_of("contact.law", &f.law, &ContactLaw::ALL)
        .unwrap_or(ContactLaw::LankaraniNikravesh);
    let restitution = c.finite("contact.restitution", f.restitution);
    if !(0.0..=1.0).contains(&restitution) {
        c.fail(
            "contact.restitution",
            format!("must lie in [0, 1], got {restitution}"),
        );
    } else if restitution == 0.0 && law.needs_positive_restitution() {
        c.fail(
            "contact.restitution",
            format!(
                "must be > 0 with law \"{}\" (its damping factor is infinite at e = 0)",
                law.name()
            ),
        );
    }
    let exponent = c.positive("contact.exponent", f.exponent);
    if exponent.is_finite() && exponent < 1.0 {
        c.fail(
            "contact.exponent",
            format!("must be >= 1 (a stiffening contact), got {exponent}"),
        );
    }
    Contact {
        law,
        stiffness: c.positive("contact.stiffness", f.stiffness),
        exponent,
        restitution,
        min_approach_speed_m_s: c
            .positive("contact.min_approach_speed_m_s", f.min_approach_speed_m_s),
    }
}

fn check_sprockets(
    c: &mut Checker,
    files: &[SprocketFile],
    chain: &Chain,
    default_profile: ProfileKind,
) -> Vec<Sprocket> {
    if files.len() < 2 {
        c.fail(
            "sprockets",
            format!("a drive needs at least 2 sprockets, got {}", files.len()),
        );
    }
    if files.len() > MAX_SPROCKETS {
        c.fail(
            "sprockets",
            format!(
                "a drive has at most {MAX_SPROCKETS} sprockets, got {}",
                files.len()
            ),
        );
    }
    let mut out = Vec::with_capacity(files.len());
    let mut drivers = 0;
    for (i, f) in files.iter().enumerate() {
        let p = |field: &str| format!("sprockets[{i}].{field}");
        let center_m = [
            c.finite(&p("center_m[0]"), f.center_m[0]),
            c.finite(&p("center_m[1]"), f.center_m[1]),
        ];
        let teeth_ok = TEETH_RANGE.contains(&f.teeth);
        if !teeth_ok {
            c.fail(
                p("teeth"),
                format!(
                    "must lie in {}..={}, got {}",
                    TEETH_RANGE.start(),
                    TEETH_RANGE.end(),
                    f.teeth
                ),
            );
        }
        let teeth = f.teeth.clamp(*TEETH_RANGE.start(), *TEETH_RANGE.end()) as u32;
        let radius = pitch_radius(chain.pitch_m, teeth);
        if let Some(stated) = f.pitch_radius_m {
            let stated = c.positive(&p("pitch_radius_m"), stated);
            if teeth_ok
                && radius.is_finite()
                && stated.is_finite()
                && ((stated - radius) / radius).abs() > PITCH_RADIUS_TOLERANCE
            {
                c.fail(
                    p("pitch_radius_m"),
                    format!(
                        "{stated} m disagrees with P / (2 sin(pi/N)) = {radius:.6} m for P = {} m, N = {teeth} (tolerance {PITCH_RADIUS_TOLERANCE:e} relative); omit it to use the computed value",
                        chain.pitch_m
                    ),
                );
            }
        }
        let wrap = c
            .one_of(&p("wrap"), &f.wrap, &[("ccw", Wrap::Ccw), ("cw", Wrap::Cw)])
            .unwrap_or(Wrap::Ccw);
        let profile = match &f.profile {
            Some(name) => c
                .one_of(
                    &p("profile"),
                    name,
                    &[
                        ("circular", ProfileKind::Circular),
                        ("real", ProfileKind::Real),
                    ],
                )
                .unwrap_or(default_profile),
            None => default_profile,
        };
        let role = check_role(c, f, i);
        if matches!(role, Role::Driver(_)) {
            drivers += 1;
        }
        out.push(Sprocket {
            name: f.name.clone(),
            center_m,
            teeth,
            pitch_radius_m: radius,
            mass_kg: c.positive(&p("mass_kg"), f.mass_kg),
            inertia_kg_m2: c.positive(&p("inertia_kg_m2"), f.inertia_kg_m2),
            wrap,
            role,
            profile,
        });
    }
    // No driver is allowed: a drive turned by torques on mounted bodies (crate::cosim).
    if drivers > 1 {
        c.fail(
            "sprockets",
            format!("at most one sprocket may have role = \"driver\", found {drivers}"),
        );
    }
    check_overlaps(c, &out, chain);
    out
}

fn check_role(c: &mut Checker, f: &SprocketFile, i: usize) -> Role {
    let p = |field: &str| format!("sprockets[{i}].{field}");
    let forbid = |c: &mut Checker, field: &str, present: bool, role: &str| {
        if present {
            c.fail(p(field), format!("is not allowed for role = \"{role}\""));
        }
    };
    match f.role.as_str() {
        "driver" => {
            forbid(c, "load_torque_n_m", f.load_torque_n_m.is_some(), "driver");
            forbid(
                c,
                "adjust_direction",
                f.adjust_direction.is_some(),
                "driver",
            );
            let speed_rpm = match f.speed_rpm {
                Some(v) => c.finite(&p("speed_rpm"), v),
                None => {
                    c.fail(p("speed_rpm"), "is required for role = \"driver\"");
                    0.0
                }
            };
            let ramp_s = c.non_negative(&p("ramp_s"), f.ramp_s.unwrap_or(0.0));
            Role::Driver(SpeedLaw {
                speed_rad_s: speed_rpm * std::f64::consts::TAU / 60.0,
                ramp_s,
            })
        }
        "free" | "tensioner" => {
            forbid(c, "speed_rpm", f.speed_rpm.is_some(), &f.role);
            forbid(c, "ramp_s", f.ramp_s.is_some(), &f.role);
            let load_torque_n_m = c.finite(&p("load_torque_n_m"), f.load_torque_n_m.unwrap_or(0.0));
            if f.role == "free" {
                forbid(c, "adjust_direction", f.adjust_direction.is_some(), "free");
                return Role::Free { load_torque_n_m };
            }
            let direction = match f.adjust_direction {
                Some([x, y]) => {
                    let n = x.hypot(y);
                    if !n.is_finite() || n <= 0.0 {
                        c.fail(p("adjust_direction"), "must be a finite, non-zero vector");
                        [0.0, 1.0]
                    } else {
                        [x / n, y / n]
                    }
                }
                None => {
                    c.fail(
                        p("adjust_direction"),
                        "is required for role = \"tensioner\"",
                    );
                    [0.0, 1.0]
                }
            };
            Role::Tensioner {
                load_torque_n_m,
                direction,
            }
        }
        other => {
            c.fail(
                p("role"),
                format!("unknown value \"{other}\"; allowed: \"driver\", \"free\", \"tensioner\""),
            );
            Role::Free {
                load_torque_n_m: 0.0,
            }
        }
    }
}

/// Two sprockets whose tip circles (pitch radius + roller radius) intersect cannot both turn.
fn check_overlaps(c: &mut Checker, sprockets: &[Sprocket], chain: &Chain) {
    for i in 0..sprockets.len() {
        for j in i + 1..sprockets.len() {
            let (a, b) = (&sprockets[i], &sprockets[j]);
            let d = (a.center_m[0] - b.center_m[0]).hypot(a.center_m[1] - b.center_m[1]);
            let reach = a.pitch_radius_m + b.pitch_radius_m + 2.0 * chain.roller_radius_m;
            if d.is_finite() && reach.is_finite() && d < reach {
                c.fail(
                    format!("sprockets[{j}].center_m"),
                    format!(
                        "sprocket \"{}\" overlaps sprocket {i} (\"{}\"): centres {d:.4} m apart, need at least {reach:.4} m",
                        b.name, a.name
                    ),
                );
            }
        }
    }
}

fn check_solver(c: &mut Checker, f: &SolverFile) -> Solver {
    let stepping = c
        .one_of(
            "solver.stepping",
            &f.stepping,
            &[
                ("substepped", Stepping::Substepped),
                ("rapier", Stepping::Rapier),
            ],
        )
        .unwrap_or(Stepping::Substepped);
    let integrator = c
        .one_of("solver.integrator", &f.integrator, &Integrator::ALL)
        .unwrap_or(Integrator::SymplecticEuler);
    if stepping == Stepping::Rapier && integrator != Integrator::SymplecticEuler {
        c.fail(
            "solver.integrator",
            format!(
                "\"{}\" needs stepping = \"substepped\": rapier integrates with symplectic Euler",
                integrator.name()
            ),
        );
    }
    let tolerance = c.positive("solver.tolerance", f.tolerance);
    if tolerance.is_finite() && tolerance >= 1.0 {
        c.fail(
            "solver.tolerance",
            format!("must be below 1 (a relative error), got {tolerance}"),
        );
    }
    Solver {
        stepping,
        integrator,
        dt_s: c.positive("solver.dt_s", f.dt_s),
        tolerance,
        duration_s: c.non_negative("solver.duration_s", f.duration_s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_scene_is_valid() {
        let scene = Scene::from_toml(L60MC_TOML).expect("valid");
        assert_eq!(scene.sprockets.len(), 4);
        assert_eq!(scene.chain.rollers, 122);
        // Pitch radii of MODEL.md §8 (tabled to 6 digits; agree within 5 µm).
        for (s, r) in scene
            .sprockets
            .iter()
            .zip([0.849325, 0.425245, 0.397000, 0.425245])
        {
            assert!(
                (s.pitch_radius_m - r).abs() < 5e-6,
                "{} vs {r}",
                s.pitch_radius_m
            );
        }
    }

    #[test]
    fn errors_name_every_bad_field() {
        let text = L60MC_TOML
            .replace("roller_mass_kg = 3.01", "roller_mass_kg = -3.01")
            .replace("teeth = 28", "teeth = 2");
        let err = Scene::from_toml(&text).expect_err("invalid");
        let msg = err.to_string();
        assert!(msg.contains("chain.roller_mass_kg"), "{msg}");
        assert!(msg.contains("sprockets[2].teeth"), "{msg}");
    }

    #[test]
    fn errors_carry_line_and_column() {
        let text = L60MC_TOML.replace("teeth = 28", "teeth = 2");
        let line = text
            .lines()
            .position(|l| l == "teeth = 2")
            .expect("edited line")
            + 1;
        let msg = Scene::from_toml(&text).expect_err("invalid").to_string();
        // "teeth = 2": the value starts at column 9.
        assert!(
            msg.contains(&format!("{line}:9: sprockets[2].teeth")),
            "{msg}"
        );
        assert_eq!(locate(&text, "chain.pitch_m").map(|l| l.1), Some(11));
        assert_eq!(locate(&text, "sprockets[7].teeth"), None);
    }

    #[test]
    fn stated_pitch_radius_must_agree() {
        let text = L60MC_TOML.replace("pitch_radius_m = 0.397000", "pitch_radius_m = 0.3975");
        let msg = Scene::from_toml(&text).expect_err("invalid").to_string();
        assert!(msg.contains("sprockets[2].pitch_radius_m"), "{msg}");
    }

    #[test]
    fn unknown_field_is_rejected_with_position() {
        let text = L60MC_TOML.replace("[chain]", "[chain]\ncolour = \"red\"");
        let msg = Scene::from_toml(&text).expect_err("invalid").to_string();
        assert!(msg.contains("colour"), "{msg}");
        assert!(msg.contains("line"), "{msg}");
    }
}
