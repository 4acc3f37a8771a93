//! Scenes: what a user writes ([`SceneFile`], TOML) and what the rest of the
//! crate consumes ([`Scene`], valid by construction).
//!
//! [`Scene::from_toml`] parses and validates in one go and reports *every*
//! problem it finds, each with the field's path (`sprockets[2].teeth`) and
//! what is allowed. Units are converted here (rpm → rad/s) and nowhere else.
//! A scene is also built in code ([`Scene::builder`]) or generated
//! ([`DriveSpec`]), through the same validation; a run's own settings
//! ([`Overrides`]) are applied to the file form and validated again, so a
//! [`Scene`] cannot change behind the validator's back.
//! This module knows nothing of rapier or of stepping.

#[cfg(all(test, feature = "cli"))]
mod auto_step_tests;
mod builder;
mod by_path;
mod checker;
mod checks;
pub(crate) mod designations;
#[cfg(test)]
mod designations_moto_tests;
#[cfg(test)]
mod designations_tests;
mod duty;
mod error;
mod excitation;
mod file;
pub(crate) mod generate;
mod governor;
mod guides;
mod kinds;
pub(crate) mod mutate;
mod overrides;
mod periodic;
mod resisting;
mod run_up;
#[cfg(test)]
mod scene_errors_tests;
mod shape;
pub(crate) mod stability;
mod tensioners;
mod threads;
mod types;
mod validate;

pub use crate::geometry::ProfileKind;
pub use builder::SceneBuilder;
pub use by_path::{Assignment, ScenePath};
pub(crate) use by_path::{PathPart, set_in_table};
pub use checks::ChecksFile;
pub(crate) use checks::{Checks, ELONGATION_LIMIT_CAP_PCT, JumpAction};
pub use duty::DutyPointFile;
pub(crate) use duty::{DutyFile, check_points};
pub(crate) use error::value_span;
pub use error::{FieldError, SceneError};
pub use file::{
    ChainFile, ContactFile, EquilibriumFile, LimitsFile, SceneFile, SolverFile, SprocketFile,
    StepFile,
};
pub use generate::{DriveSpec, GenerateError};
pub(crate) use governor::{DEFAULT_GOVERNOR_BANDWIDTH_HZ, GovernorGains, GovernorSpec};
pub(crate) use guides::Guide;
pub use guides::GuideFile;
pub(crate) use kinds::RoleKind;
pub use kinds::{ContactLaw, Integrator, PretensionRule, Stepping, Wrap};
pub use overrides::Overrides;
pub(crate) use periodic::{Harmonic, LoadTable};
pub(crate) use resisting::Resisting;
pub(crate) use run_up::RunUpFile;
pub(crate) use stability::StepLimits;
pub(crate) use stability::{AUTO_GRID_S, micro, step_note};
#[cfg(test)]
pub(crate) use stability::{AUTO_SAFETY, AUTO_STEPS_PER_IMPACT, impact_duration_s};
pub(crate) use tensioners::{HydraulicTensioner, Tensioner, TensionerFile, TensionerKind};
#[cfg(test)]
pub(crate) use tensioners::{STANDARD_ATMOSPHERE_PA, SpringTensioner};
pub(crate) use threads::AUTO_MIN_ROLLERS;
pub use threads::{Threads, ThreadsFile};
pub use types::{
    Chain, Contact, Equilibrium, JointFriction, Limits, Role, RunUp, Solver, SpeedLaw, Sprocket,
};

/// The most sprockets a drive may have: the contact generator keeps each
/// roller's set of sprockets within reach as a 64-bit mask (`u64`), one bit
/// per sprocket.
pub(crate) const MAX_SPROCKETS: usize = u64::BITS as usize;

/// The paper's drive (MAN B&W L60MC camshaft chain), embedded as the default scene.
pub const L60MC_TOML: &str = include_str!("../../assets/l60mc.toml");

/// A chain drive, valid by construction: built only by validating a
/// [`SceneFile`] (from TOML, a [`SceneBuilder`], or a file with
/// [`Overrides`]). Read it through its accessors; the crate reads the
/// fields directly and never writes them.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub(crate) name: String,
    pub(crate) gravity_m_s2: [f64; 2],
    pub(crate) chain: Chain,
    pub(crate) contact: Contact,
    pub(crate) sprockets: Vec<Sprocket>,
    pub(crate) solver: Solver,
    pub(crate) equilibrium: Equilibrium,
    /// Tensioner arms with their tensioners.
    pub(crate) tensioners: Vec<Tensioner>,
    pub(crate) guides: Vec<Guide>,
    /// Settings of the design checks.
    pub(crate) checks: Checks,
    /// The file form it was validated from (for [`Scene::with`]).
    pub(crate) file: SceneFile,
    pub(crate) source_toml: Option<String>,
}

/// Default floor on the remembered approach speed, m/s. At the paper's
/// K_g = 1 GN/m^1.5 and e = 0 a 20 kN contact has c = χ F / δ̇⁻ = 3·10⁵ N·s/m at
/// 0.05 m/s, right at the explicit limit 2 m_r/dt for dt = 20 µs; seating
/// impacts in the paper's drive run at 0.3–1 m/s, well above the floor.
pub(crate) const DEFAULT_MIN_APPROACH_SPEED_M_S: f64 = 0.05;

/// Relative tolerance between a stated pitch radius and P / (2 sin(π/N)).
pub(crate) const PITCH_RADIUS_TOLERANCE: f64 = 1e-5;
/// Supported tooth counts.
pub(crate) const TEETH_RANGE: std::ops::RangeInclusive<i64> = 5..=300;
impl Scene {
    /// Parses and validates a TOML scene. All problems are reported at once.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        Self::from_toml_with(text, &Overrides::default())
    }

    /// The paper's drive (`assets/l60mc.toml`, embedded).
    pub fn l60mc() -> Self {
        match Self::from_toml(L60MC_TOML) {
            Ok(scene) => scene,
            // The embedded scene is checked by the test suite.
            Err(e) => unreachable!("embedded scene is invalid: {e}"),
        }
    }

    /// Name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Gravity, m/s².
    pub fn gravity_m_s2(&self) -> [f64; 2] {
        self.gravity_m_s2
    }

    /// The chain.
    pub fn chain(&self) -> &Chain {
        &self.chain
    }

    /// The contact law.
    pub fn contact(&self) -> &Contact {
        &self.contact
    }

    /// Tensioner arms with their tensioners (`[[tensioners]]`).
    pub(crate) fn tensioners(&self) -> &[Tensioner] {
        &self.tensioners
    }

    /// The sprockets, in the order the chain visits them.
    pub fn sprockets(&self) -> &[Sprocket] {
        &self.sprockets
    }

    /// Solver settings.
    pub fn solver(&self) -> &Solver {
        &self.solver
    }

    /// Fixed guides on the strands.
    pub(crate) fn guides(&self) -> &[Guide] {
        &self.guides
    }

    /// What is valid but likely unintended, one sentence each: a step above
    /// its integrator's estimated stability limit, guides and tensioner
    /// arms' shoes the chain's nominal path does not reach.
    pub fn warnings(&self) -> Vec<String> {
        let mut w: Vec<String> = stability::step_warning(&self.solver, &StepLimits::of(self))
            .into_iter()
            .collect();
        w.extend(guides::warnings(&self.guides));
        w.extend(resisting::warnings(&self.sprockets, self.solver.dt_s));
        w.extend(tensioners::warnings(
            &self.tensioners,
            &self.sprockets,
            &self.chain,
        ));
        if self.chain.elongation > 0.0
            && self
                .sprockets
                .iter()
                .any(|s| s.profile == ProfileKind::Circular)
        {
            w.push(format!(
                "chain.elongation_pct = {}: a worn chain's rollers ride up their teeth's flanks, which the circular profile does not have (its seats hold no roller above the pitch circle): use profile = \"real\" for a worn chain",
                100.0 * self.chain.elongation
            ));
        }
        w
    }

    /// Static-equilibrium settings.
    pub fn equilibrium(&self) -> &Equilibrium {
        &self.equilibrium
    }

    /// The file form this scene was validated from, overrides included.
    pub fn file(&self) -> &SceneFile {
        &self.file
    }

    /// The TOML text this scene was parsed from (without overrides), if it
    /// was parsed (for recordings and reports).
    pub fn source_toml(&self) -> Option<&str> {
        self.source_toml.as_deref()
    }

    /// The same drive with a new chain (no wear elongation), or `None`
    /// when its chain is new. Only the validated form changes: a worn
    /// chain's static equilibrium starts from the new chain's.
    pub(crate) fn as_new_chain(&self) -> Option<Self> {
        (self.chain.elongation != 0.0).then(|| {
            let mut new = self.clone();
            new.chain.elongation = 0.0;
            new
        })
    }

    /// The tables the scene read (load tables, governors' drive tables):
    /// each name as the scene writes it, once, with the text read.
    pub(crate) fn tables(&self) -> std::collections::BTreeMap<&str, &str> {
        self.sprockets
            .iter()
            .flat_map(|s| {
                let drive = s.excitation.governor.as_ref();
                [
                    s.excitation.load_table.as_ref(),
                    drive.and_then(|g| g.drive_table.as_ref()),
                ]
            })
            .flatten()
            .map(|t| (t.file.as_str(), t.text.as_str()))
            .collect()
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_scene_is_valid() {
        let scene = Scene::from_toml(L60MC_TOML).expect("valid");
        assert_eq!(scene.sprockets.len(), 4);
        assert_eq!(scene.chain.rollers, 122);
        // Pitch radii of the paper's drive (docs/model.md, “The paper's drive”;
        // tabled to 6 digits; agree within 5 µm).
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
        assert_eq!(error::locate(&text, "chain.pitch_m").map(|l| l.1), Some(11));
        assert_eq!(error::locate(&text, "sprockets[7].teeth"), None);
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
        let line = text
            .lines()
            .position(|l| l.starts_with("colour"))
            .expect("added")
            + 1;
        assert!(
            msg.starts_with(&format!("{line}:1: chain.colour: unknown field")),
            "{msg}"
        );
    }
}
