//! The scene file as written by a user: plain serde structs, every field
//! named with its unit, unknown fields rejected. Nothing here is checked
//! beyond its TOML type; [`super::Scene`] is the validated form.
//!
//! The enumerated fields (`law`, `wrap`, `role`, …) are strings here, read
//! into their enumerations by the validator: an unknown name is then one
//! field error among all the others, with its path and the allowed names.

use serde::{Deserialize, Serialize};

use super::excitation::ExcitationFile;
use super::governor::GovernorFile;
use super::periodic::{LoadHarmonicFile, LoadTableFile, SpeedHarmonicFile};
use super::threads::ThreadsFile;

/// A whole scene file (TOML).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Free-form name, reported in every output.
    pub name: String,
    /// Gravity vector in m/s² (e.g. `[0.0, -9.81]`); `[0, 0]` turns it off.
    #[serde(default)]
    pub gravity_m_s2: [f64; 2],
    /// Default tooth profile of every sprocket: `"circular"` or `"real"`.
    #[serde(default = "default_profile")]
    pub profile: String,
    /// The chain.
    pub chain: ChainFile,
    /// The roller–tooth contact law.
    pub contact: ContactFile,
    /// The sprockets, in the order the chain visits them.
    pub sprockets: Vec<SprocketFile>,
    /// Integration settings.
    #[serde(default)]
    pub solver: SolverFile,
    /// Static-equilibrium settings (before t = 0).
    #[serde(default)]
    pub equilibrium: EquilibriumFile,
    /// The directory relative file names in the scene (a load table's) are
    /// read from: the scene file's ([`super::Scene::from_path_with`]); `None`:
    /// the working directory. Not part of the TOML.
    #[serde(skip)]
    pub base_dir: Option<std::path::PathBuf>,
    /// The texts of tables the scene names (`load_table.file`,
    /// `governor.drive_table.file`), by the name it writes: read instead of
    /// the files (a recording's copies, `Scene::from_toml_given`);
    /// a table not here is read from its file. Not part of the TOML.
    #[serde(skip)]
    pub(crate) given_tables: std::collections::BTreeMap<String, String>,
    /// Tensioner arms with their tensioners (`[[tensioners]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) tensioners: Vec<super::TensionerFile>,
    /// Fixed guides on the strands (`[[guides]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub guides: Vec<super::GuideFile>,
    /// Settings of the design checks (`[checks]`).
    #[serde(default, skip_serializing_if = "super::ChecksFile::is_empty")]
    pub checks: super::ChecksFile,
    /// A duty cycle's operating points (`[[duty]]`; `chaindrive life`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub duty: Vec<super::DutyPointFile>,
}

fn default_profile() -> String {
    "circular".to_owned()
}

/// The chain: rollers joined by spring-damper links.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ChainFile {
    /// Number of rollers (= number of links, the chain is closed).
    pub rollers: i64,
    /// A standard chain (`"ISO 606 16B-1"`, `"ANSI 80"`, `"520"`;
    /// `chaindrive chains` lists them): fills the pitch, roller radius, roller
    /// mass, stiffness, pin radius and tensile strength that the file does not
    /// give, where its row has them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub designation: Option<String>,
    /// Pitch P: roller-to-roller distance of the unloaded chain, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pitch_m: Option<f64>,
    /// Roller radius R_r, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roller_radius_m: Option<f64>,
    /// Lumped mass of one roller with its share of the plates and pins, kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roller_mass_kg: Option<f64>,
    /// Link stiffness K, N/m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_n_m: Option<f64>,
    /// Tensile strength of the whole chain (all strands), N: the maker's
    /// minimum for a chain the table has no strength for (the motorcycle
    /// chains) or none at all; overrides the designation's. The rating's
    /// safety factors and the fatigue check need it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tensile_strength_n: Option<f64>,
    /// Link damping D, N·s/m.
    pub damping_n_s_m: f64,
    /// Static pretension, N (mean link force of the free strands at static equilibrium).
    pub pretension_n: f64,
    /// How the pretension is reached: `"rest_length"` (shorten the links' rest
    /// length, positions stay) or `"tensioner"` (move the tensioner sprocket).
    #[serde(default = "default_pretension_by")]
    pub pretension_by: String,
    /// Pin radius r_pin of the pin–bushing joints, m (needed by the joint
    /// friction; docs/model.md, “Joint friction”).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pin_radius_m: Option<f64>,
    /// Coulomb friction coefficient μ between pin and bushing, in [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_friction: Option<f64>,
    /// Regularisation speed ω_s of the joint friction, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_friction_speed_rad_s: Option<f64>,
    /// Viscous joint damping c_θ, N·m·s/rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_damping_n_m_s_rad: Option<f64>,
    /// Length of the bushing the pin bears on, m (the wear check's bearing
    /// area is pin diameter × bushing length; docs/design-checks.md, "Wear").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bushing_length_m: Option<f64>,
    /// Wear elongation of every pitch, % (links and rollers lengthened, the
    /// sprockets as cut; docs/model.md, "A worn chain"). Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elongation_pct: Option<f64>,
}

fn default_pretension_by() -> String {
    "rest_length".to_owned()
}

/// Contact law parameters (docs/model.md, “Contact law”).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    /// `"lankarani_nikravesh"` (the paper's), `"hunt_crossley"`, `"flores"` or `"gonthier"`.
    #[serde(default = "default_law")]
    pub law: String,
    /// Generalized stiffness K_g, N/m^exponent.
    pub stiffness: f64,
    /// Exponent n of the penetration (1.5 for Hertz).
    #[serde(default = "default_exponent")]
    pub exponent: f64,
    /// Coefficient of restitution e in [0, 1].
    pub restitution: f64,
    /// Floor on the remembered approach speed δ̇⁻, m/s.
    #[serde(default = "default_min_approach")]
    pub min_approach_speed_m_s: f64,
}

/// What a required field that a file leaves out needs, by its path, where
/// "it is required here" says too little.
pub(super) fn required(path: &str) -> Option<&'static str> {
    Some(match path {
        "contact" => {
            "the roller–tooth contact has no defaults: give [contact] with stiffness (K_g, N/m^exponent; the paper's 56B chain: 1e9) and restitution (e, from 0 to 1; the paper: 0.0); law, exponent and min_approach_speed_m_s default to \"lankarani_nikravesh\", 1.5 and 0.05 m/s"
        }
        "contact.stiffness" => {
            "K_g, N/m^exponent, has no default (the paper's 56B chain: 1e9 with exponent 1.5)"
        }
        "contact.restitution" => "e, from 0 to 1, has no default (the paper's drive: 0.0)",
        "chain" => {
            "give [chain] with rollers, damping_n_s_m, pretension_n and a designation or its dimensions"
        }
        "sprockets" => {
            "give the sprockets as [[sprockets]] tables, in the order the chain visits them"
        }
        _ => return None,
    })
}

fn default_law() -> String {
    "lankarani_nikravesh".to_owned()
}
fn default_exponent() -> f64 {
    1.5
}
fn default_min_approach() -> f64 {
    super::DEFAULT_MIN_APPROACH_SPEED_M_S
}

/// One sprocket.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SprocketFile {
    /// Name, for humans.
    pub name: String,
    /// Centre in the world, m.
    pub center_m: [f64; 2],
    /// Number of teeth.
    pub teeth: i64,
    /// Pitch radius, m. Optional: computed as P / (2 sin(π/N)); if given it must agree within 1e-5.
    #[serde(default)]
    pub pitch_radius_m: Option<f64>,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Polar moment of inertia about the centre, kg·m².
    pub inertia_kg_m2: f64,
    /// Wrap sense: `"ccw"` if the chain, followed in scene order, goes
    /// counter-clockwise around this sprocket (the paper's "+"), `"cw"` otherwise.
    pub wrap: String,
    /// `"driver"`, `"free"` or `"tensioner"`.
    pub role: String,
    /// Driver only: target speed, rpm, counter-clockwise positive.
    #[serde(default)]
    pub speed_rpm: Option<f64>,
    /// Driver only: time of the linear ramp from rest to the target speed, s (0 = constant speed).
    #[serde(default)]
    pub ramp_s: Option<f64>,
    /// Driver only: a slow linear change of its speed after the ramp
    /// (`sprockets.run_up`; a governed driver's target follows it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) run_up: Option<super::RunUpFile>,
    /// Free or tensioner: constant load torque on the sprocket, N·m (counter-clockwise positive).
    #[serde(default)]
    pub load_torque_n_m: Option<f64>,
    /// Free or tensioner with a load torque: time of the load's linear rise
    /// from zero to its full value, s (0 or absent: the load acts from rest on,
    /// and the static equilibrium carries it).
    #[serde(default)]
    pub load_ramp_s: Option<f64>,
    /// Free or tensioner: a torque of this size, N·m (≥ 0), that opposes the
    /// sprocket's rotation whichever way it turns (a conveyor's friction, a
    /// brake), where `load_torque_n_m` acts in one direction whatever the
    /// motion (a lifted load, a pump). It is −T ω / ω_s below the creep speed
    /// ω_s and −T sign(ω) above (docs/model.md, “A resisting load”).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resisting_torque_n_m: Option<f64>,
    /// With a `resisting_torque_n_m`: the creep speed ω_s below which the
    /// resisting torque falls linearly to zero, rad/s (> 0; default: the
    /// smallest that the step integrates stably, at least 0.01 rad/s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resisting_speed_rad_s: Option<f64>,
    /// Tensioner only: direction along which the centre is moved to reach the pretension.
    #[serde(default)]
    pub adjust_direction: Option<[f64; 2]>,
    /// Tooth profile of this sprocket, overriding the scene's default.
    #[serde(default)]
    pub profile: Option<String>,
    /// Driver only: harmonics of the speed in the driver's angle
    /// (`[[sprockets.speed_harmonics]]`, docs/model.md, “Excitation”).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) speed_harmonics: Vec<SpeedHarmonicFile>,
    /// Free or tensioner: a load torque in the sprocket's angle, as a
    /// harmonic series (`[[sprockets.load_harmonics]]`), added to the
    /// constant load.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) load_harmonics: Vec<LoadHarmonicFile>,
    /// Free or tensioner: a load torque in the sprocket's angle, tabled over
    /// one revolution in a CSV file (`sprockets.load_table`), added to the
    /// constant load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) load_table: Option<LoadTableFile>,
    /// Driver only: turn the driver by a drive torque under a PI speed
    /// governor to its `speed_rpm` (`[sprockets.governor]`, docs/model.md,
    /// “A torque-driven driver”) instead of prescribing its speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) governor: Option<GovernorFile>,
}

impl SprocketFile {
    /// Its excitation fields, as [`super::excitation`] checks them.
    pub(super) fn excitation(&self) -> ExcitationFile<'_> {
        ExcitationFile {
            speed_harmonics: &self.speed_harmonics,
            load_harmonics: &self.load_harmonics,
            load_table: self.load_table.as_ref(),
            governor: self.governor.as_ref(),
        }
    }
}

/// Integration settings.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolverFile {
    /// `"substepped"` (the fast path) or `"rapier"` (rapier integrates every body).
    #[serde(default = "default_stepping")]
    pub stepping: String,
    /// `"symplectic_euler"`, `"velocity_verlet"`, `"rk4"`, `"dormand_prince45"`
    /// (adaptive) or `"implicit_damping"`.
    #[serde(default = "default_integrator")]
    pub integrator: String,
    /// The chain's integration step: seconds, `"auto"` (the default: the
    /// largest step within the integrator's stability estimates times a safety
    /// factor, capped for a roller's impact; see docs/model.md) or `"speed"`
    /// (the largest step within nine tenths of the estimates, no cap). The
    /// adaptive scheme's largest step.
    #[serde(default)]
    pub dt_s: StepFile,
    /// Error tolerance of the adaptive scheme (relative to the static link stretch).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// Simulated time after t = 0, s.
    #[serde(default = "default_duration")]
    pub duration_s: f64,
    /// The blow-up detectors' limits (`[solver.limits]`); each left out takes
    /// its default, derived from the chain.
    #[serde(default)]
    pub limits: LimitsFile,
    /// Threads stepping the drive: 1, 2 or `"auto"` (the default: two from
    /// `super::AUTO_MIN_ROLLERS` rollers on a machine with two cores).
    #[serde(default, skip_serializing_if = "ThreadsFile::is_auto")]
    pub threads: ThreadsFile,
    /// The sample period an automatic step is a whole fraction of, s
    /// (`None`: `super::AUTO_GRID_S`). Not part of the TOML: the run's
    /// sample rate sets it ([`super::Overrides::sample_rate_hz`]).
    #[serde(skip)]
    pub sample_period_s: Option<f64>,
}

/// `solver.dt_s` as written: a number of seconds or the word `"auto"`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum StepFile {
    /// A fixed step, s.
    Seconds(f64),
    /// A word; only `"auto"` and `"speed"` are valid.
    Word(String),
}

impl Default for StepFile {
    fn default() -> Self {
        Self::Word(AUTO.to_owned())
    }
}

/// The word that asks for an automatic step.
pub(crate) const AUTO: &str = "auto";

/// The word that asks for an automatic step chosen for speed.
pub(crate) const SPEED: &str = "speed";

/// The blow-up detectors' limits (`[solver.limits]`), each optional.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsFile {
    /// Deepest roller penetration into a tooth, m (default: the roller
    /// radius, the roller's centre on the tooth's surface).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_penetration_m: Option<f64>,
    /// Largest |link length − rest length|, m (default: 10 % of the pitch).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_stretch_m: Option<f64>,
    /// Growth of the largest link stretch within `growth_steps` steps taken
    /// as numerical blow-up (default: 100).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub growth_factor: Option<f64>,
    /// The window of the growth detector, steps (default: 20).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub growth_steps: Option<i64>,
}

impl Default for SolverFile {
    fn default() -> Self {
        Self {
            stepping: default_stepping(),
            integrator: default_integrator(),
            dt_s: StepFile::default(),
            tolerance: default_tolerance(),
            duration_s: default_duration(),
            limits: LimitsFile::default(),
            threads: ThreadsFile::default(),
            sample_period_s: None,
        }
    }
}

fn default_stepping() -> String {
    "substepped".to_owned()
}
fn default_integrator() -> String {
    "symplectic_euler".to_owned()
}
fn default_tolerance() -> f64 {
    1e-3
}
fn default_duration() -> f64 {
    10.0
}

/// Static equilibrium before t = 0: damped relaxation with the driver held.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EquilibriumFile {
    /// Relative tolerance on the pretension (rest-length or tensioner iteration).
    #[serde(default = "default_eq_tol")]
    pub tension_tolerance: f64,
    /// Largest relaxation time per iteration, s.
    #[serde(default = "default_eq_time")]
    pub max_relax_s: f64,
}

impl Default for EquilibriumFile {
    fn default() -> Self {
        Self {
            tension_tolerance: default_eq_tol(),
            max_relax_s: default_eq_time(),
        }
    }
}

fn default_eq_tol() -> f64 {
    1e-3
}
fn default_eq_time() -> f64 {
    2.0
}
