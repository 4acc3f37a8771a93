//! Overrides: settings that replace a scene file's own for one run (the
//! command line's `--duration`, `--dt`, …, the settings a recording was
//! made with, a study's step and scheme). They are written into the *file
//! form* and the result is validated like any file, so a [`Scene`] is never
//! edited behind the validator's back.

use super::{
    ContactLaw, Integrator, ProfileKind, Scene, SceneError, SceneFile, StepFile, Stepping,
};

/// Settings replacing a scene file's own; `None` keeps the file's value.
///
/// Each field names the scene-file field it replaces. Apply them with
/// [`Scene::with`] (to a validated scene), [`Scene::from_toml_with`] or
/// [`Scene::from_file_with`]; a bad value is a [`SceneError`] naming that
/// field's path, like a bad value in the file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Every sprocket's tooth profile (`sprockets[i].profile`).
    pub profile: Option<ProfileKind>,
    /// `solver.duration_s`: simulated time, s.
    pub duration_s: Option<f64>,
    /// `solver.dt_s`: the chain's integration step, s.
    pub dt_s: Option<f64>,
    /// `solver.dt_s = "auto"`: the step chosen from the scene (takes
    /// precedence over `dt_s`).
    pub dt_auto: bool,
    /// `solver.dt_s = "speed"`: the step chosen from the scene for speed
    /// (takes precedence over `dt_auto` and `dt_s`).
    pub dt_speed: bool,
    /// `solver.stepping`. Rapier's stepping without an `integrator`
    /// override also sets `solver.integrator` to symplectic Euler, the
    /// scheme rapier integrates with (whatever scheme the file names for
    /// the substepped chain).
    pub stepping: Option<Stepping>,
    /// `solver.integrator`.
    pub integrator: Option<Integrator>,
    /// `solver.tolerance`: error tolerance of the adaptive scheme.
    pub tolerance: Option<f64>,
    /// `contact.law`.
    pub contact_law: Option<ContactLaw>,
    /// `equilibrium.max_relax_s`: largest relaxation time per iteration, s.
    pub max_relax_s: Option<f64>,
    /// The rate the run samples at, Hz: an automatic step
    /// (`solver.dt_s = "auto"`) is a whole fraction of its period, so that
    /// every sample falls on a step (`None`: 1 kHz). Not a scene-file
    /// field, and nothing to a scene that gives its step in seconds; a rate
    /// that is not a finite number > 0 is left out here (the sampler
    /// refuses it).
    pub sample_rate_hz: Option<f64>,
}

impl Overrides {
    /// The scene-file paths of the fields these overrides replace (the
    /// per-sprocket profiles aside: a [`ProfileKind`] is always valid).
    pub fn paths(&self) -> Vec<&'static str> {
        [
            ("solver.duration_s", self.duration_s.is_some()),
            (
                "solver.dt_s",
                self.dt_s.is_some() || self.dt_auto || self.dt_speed,
            ),
            ("solver.stepping", self.stepping.is_some()),
            ("solver.integrator", self.integrator.is_some()),
            ("solver.tolerance", self.tolerance.is_some()),
            ("contact.law", self.contact_law.is_some()),
            ("equilibrium.max_relax_s", self.max_relax_s.is_some()),
        ]
        .into_iter()
        .filter_map(|(path, set)| set.then_some(path))
        .collect()
    }
}

impl SceneFile {
    /// Writes `overrides` into this file (nothing is checked here: the file
    /// is validated when it becomes a [`Scene`]).
    pub fn apply(&mut self, overrides: &Overrides) {
        let Overrides {
            profile,
            duration_s,
            dt_s,
            dt_auto,
            dt_speed,
            stepping,
            integrator,
            tolerance,
            contact_law,
            max_relax_s,
            sample_rate_hz,
        } = *overrides;
        if let Some(p) = profile {
            for s in &mut self.sprockets {
                s.profile = Some(p.name().to_owned());
            }
        }
        let solver = &mut self.solver;
        set(&mut solver.duration_s, duration_s);
        if dt_speed {
            solver.dt_s = StepFile::Word(super::file::SPEED.to_owned());
        } else if dt_auto {
            solver.dt_s = StepFile::Word(super::file::AUTO.to_owned());
        } else if let Some(dt) = dt_s {
            solver.dt_s = StepFile::Seconds(dt);
        }
        // Only an automatic step depends on the rate: a scene with its own
        // step stays the same scene at every rate.
        if let Some(rate) = sample_rate_hz.filter(|r| r.is_finite() && *r > 0.0)
            && matches!(solver.dt_s, StepFile::Word(_))
        {
            solver.sample_period_s = Some(1.0 / rate);
        }
        set(&mut solver.tolerance, tolerance);
        set_name(&mut solver.stepping, stepping.map(Stepping::name));
        let integrator = match (stepping, integrator) {
            (Some(Stepping::Rapier), None) => Some(Integrator::SymplecticEuler),
            _ => integrator,
        };
        set_name(&mut solver.integrator, integrator.map(Integrator::name));
        set_name(&mut self.contact.law, contact_law.map(ContactLaw::name));
        set(&mut self.equilibrium.max_relax_s, max_relax_s);
    }
}

fn set(field: &mut f64, value: Option<f64>) {
    if let Some(v) = value {
        *field = v;
    }
}

fn set_name(field: &mut String, name: Option<&str>) {
    if let Some(n) = name {
        *field = n.to_owned();
    }
}

impl Scene {
    /// This scene with `overrides` written into its file form, validated
    /// again. Errors name the overridden field's path.
    pub fn with(&self, overrides: &Overrides) -> Result<Self, SceneError> {
        let mut file = self.file.clone();
        file.apply(overrides);
        let mut scene = Self::try_from(file)?;
        scene.source_toml.clone_from(&self.source_toml);
        Ok(scene)
    }

    /// Validates `file` with `overrides` applied.
    pub fn from_file_with(mut file: SceneFile, overrides: &Overrides) -> Result<Self, SceneError> {
        file.apply(overrides);
        Self::try_from(file)
    }

    /// Reads the scene file at `path`, applies `overrides` and validates the
    /// result, reading the files it names (a load table) relative to the
    /// scene file's directory. Errors as [`Self::from_toml_with`]'s; a file
    /// that cannot be read is an I/O error.
    pub fn from_path_with(
        path: &std::path::Path,
        overrides: &Overrides,
    ) -> Result<Result<Self, SceneError>, std::io::Error> {
        let text = std::fs::read_to_string(path)?;
        Ok(Self::from_toml_in(&text, path.parent(), overrides))
    }

    /// Parses a TOML scene whose relative file names are read from `base_dir`
    /// (`None`: the working directory), applies `overrides` and validates it.
    pub fn from_toml_in(
        text: &str,
        base_dir: Option<&std::path::Path>,
        overrides: &Overrides,
    ) -> Result<Self, SceneError> {
        Self::parse(text, base_dir, std::collections::BTreeMap::new(), overrides)
    }

    /// Parses a TOML scene whose tables are given with it, by the name the
    /// scene writes (`load_table.file`): a recording's copies
    /// (`crate::record`), so that the scene is the one that was run
    /// wherever it is read and whatever became of the files. A table not
    /// given is read from its file, relative to the working directory.
    /// Applies `overrides` and validates, as [`Self::from_toml_with`].
    pub(crate) fn from_toml_given(
        text: &str,
        tables: std::collections::BTreeMap<String, String>,
        overrides: &Overrides,
    ) -> Result<Self, SceneError> {
        Self::parse(text, None, tables, overrides)
    }

    fn parse(
        text: &str,
        base_dir: Option<&std::path::Path>,
        tables: std::collections::BTreeMap<String, String>,
        overrides: &Overrides,
    ) -> Result<Self, SceneError> {
        // Every problem at once: the shape's (unknown, mistyped, missing
        // fields), and the values' when only unknown fields were wrong.
        let read = super::shape::read::<SceneFile>(text, super::file::required)?;
        let Some(mut file) = read.value else {
            return Err(SceneError::Invalid(read.errors));
        };
        file.base_dir = base_dir.map(std::path::Path::to_path_buf);
        file.given_tables = tables;
        file.apply(overrides);
        let mut errors = read.errors;
        match Self::try_from(file).map_err(|e| e.located(text, &overrides.paths())) {
            Ok(mut scene) if errors.is_empty() => {
                scene.source_toml = Some(text.to_owned());
                Ok(scene)
            }
            Ok(_) => Err(SceneError::Invalid(errors)),
            Err(SceneError::Invalid(more)) => {
                errors.extend(more);
                Err(SceneError::Invalid(errors))
            }
            Err(other) => Err(other),
        }
    }

    /// Parses a TOML scene, applies `overrides` and validates the result.
    /// Errors in the file carry their line and column; errors in an
    /// overridden field do not (their value is not in the text).
    pub fn from_toml_with(text: &str, overrides: &Overrides) -> Result<Self, SceneError> {
        Self::from_toml_in(text, None, overrides)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::L60MC_TOML;

    #[test]
    fn an_override_replaces_the_file_value() {
        let scene = Scene::l60mc()
            .with(&Overrides {
                dt_s: Some(5e-6),
                integrator: Some(Integrator::Rk4),
                profile: Some(ProfileKind::Real),
                ..Overrides::default()
            })
            .expect("valid");
        assert_eq!(scene.solver().dt_s, 5e-6);
        assert_eq!(scene.solver().integrator, Integrator::Rk4);
        assert_eq!(scene.profile_name(), "real");
    }

    #[test]
    fn no_override_changes_nothing() {
        let scene = Scene::l60mc();
        assert_eq!(scene.with(&Overrides::default()).expect("valid"), scene);
    }

    #[test]
    fn a_bad_override_names_its_field_without_a_location() {
        let overrides = Overrides {
            dt_s: Some(-1.0),
            ..Overrides::default()
        };
        let err = Scene::from_toml_with(L60MC_TOML, &overrides).expect_err("invalid");
        assert_eq!(err.lines(), ["solver.dt_s: must be > 0, got -1"]);
    }

    #[test]
    fn rapier_stepping_brings_its_own_scheme() {
        // The paper's drive names velocity Verlet for its substepped chain;
        // `--stepping rapier` alone runs it with rapier's symplectic Euler.
        let overrides = Overrides {
            stepping: Some(Stepping::Rapier),
            ..Overrides::default()
        };
        let scene = Scene::l60mc().with(&overrides).expect("valid");
        assert_eq!(scene.solver().integrator, Integrator::SymplecticEuler);
    }

    #[test]
    fn an_override_is_checked_against_the_rest_of_the_file() {
        let overrides = Overrides {
            stepping: Some(Stepping::Rapier),
            integrator: Some(Integrator::Rk4),
            ..Overrides::default()
        };
        let err = Scene::l60mc().with(&overrides).expect_err("invalid");
        assert!(err.to_string().contains("solver.integrator"), "{err}");
    }
}
