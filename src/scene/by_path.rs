//! Setting one value of a scene file by its dotted path
//! (`chain.pretension_n`, `sprockets.2.speed_rpm`, `gravity_m_s2.1`): what a
//! study's factor or the command line's `--set path=value` changes.
//!
//! The value is written into the file's TOML form *before* validation, so
//! the result is validated exactly like a file. Array indices count from 0,
//! as in the TOML arrays and in the paths the validator prints
//! (`sprockets[2].teeth`); both `sprockets.2.teeth` and `sprockets[2].teeth`
//! are accepted, and errors print the second form.
//!
//! A path must name a field the scene file has (an optional field absent
//! from the base file may be set); the value must have the field's type. An
//! integer is accepted where a number is expected. Errors name the path and
//! what is allowed. This module checks only the path and the type; the
//! value's range is the validator's business.

use std::fmt;
use std::str::FromStr;

use super::{Scene, SceneError, SceneFile};

/// One step of a [`ScenePath`]: a table's key or an array's 0-based index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum PathPart {
    /// A key of a table (`chain`, `speed_rpm`).
    Key(String),
    /// A 0-based index into an array (`sprockets.2`).
    Index(usize),
}

/// A dotted path into a scene file, e.g. `sprockets.2.speed_rpm`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenePath {
    parts: Vec<PathPart>,
}

impl ScenePath {
    /// The steps of the path, root first.
    pub(crate) fn parts(&self) -> &[PathPart] {
        &self.parts
    }

    /// The path as the validator prints it, up to (excluding) step `n`.
    fn prefix(&self, n: usize) -> String {
        Self {
            parts: self.parts[..n].to_vec(),
        }
        .to_string()
    }
}

impl fmt::Display for ScenePath {
    /// `sprockets[2].speed_rpm`: keys joined by dots, indices in brackets.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, part) in self.parts.iter().enumerate() {
            match part {
                PathPart::Key(k) if i == 0 => write!(f, "{k}")?,
                PathPart::Key(k) => write!(f, ".{k}")?,
                PathPart::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

impl FromStr for ScenePath {
    type Err = SceneError;

    /// Parses `a.b.2.c` or `a.b[2].c`. Keys are letters, digits and `_`,
    /// and do not start with a digit; a step of digits alone is an index.
    fn from_str(text: &str) -> Result<Self, SceneError> {
        let bad = |why: &str| {
            SceneError::field(
                text,
                format!(
                    "not a scene path ({why}); allowed: keys joined by dots, array indices from 0 as `.2` or `[2]`, e.g. sprockets.2.speed_rpm"
                ),
            )
        };
        let mut parts = Vec::new();
        for step in text.split('.') {
            let (key, brackets) = match step.find('[') {
                Some(i) => (&step[..i], &step[i..]),
                None => (step, ""),
            };
            if key.is_empty() && brackets.is_empty() {
                return Err(bad("an empty step"));
            }
            if key.chars().all(|c| c.is_ascii_digit()) && !key.is_empty() {
                parts.push(PathPart::Index(
                    key.parse().map_err(|_| bad("index too large"))?,
                ));
            } else if !key.is_empty() {
                if !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    return Err(bad(&format!("`{key}` is not a key")));
                }
                parts.push(PathPart::Key(key.to_owned()));
            }
            let mut rest = brackets;
            while !rest.is_empty() {
                let inner = rest
                    .strip_prefix('[')
                    .and_then(|r| r.split_once(']'))
                    .ok_or_else(|| bad("unbalanced brackets"))?;
                let index = inner
                    .0
                    .parse()
                    .map_err(|_| bad(&format!("`[{}]` is not an index", inner.0)))?;
                parts.push(PathPart::Index(index));
                rest = inner.1;
            }
        }
        if !matches!(parts.first(), Some(PathPart::Key(_))) {
            return Err(bad("it must start with a key"));
        }
        Ok(Self { parts })
    }
}

/// A value for the field at a path: one study factor's level, or one
/// `--set path=value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    /// Where.
    pub path: ScenePath,
    /// What: any TOML value (number, string, array, …).
    pub value: toml::Value,
}

impl Assignment {
    /// `path = value` from its parts; the value is read as TOML (`21000`,
    /// `1e-5`, `"ccw"`, `[0.5, 2.2]`), and as a plain string if it is not
    /// TOML (`ccw`).
    pub(crate) fn parse(path: &str, value: &str) -> Result<Self, SceneError> {
        let path: ScenePath = path.trim().parse()?;
        let text = value.trim();
        let value = format!("v = {text}")
            .parse::<toml::Table>()
            .ok()
            .and_then(|mut t| t.remove("v"))
            .unwrap_or_else(|| toml::Value::String(text.to_owned()));
        Ok(Self { path, value })
    }
}

impl FromStr for Assignment {
    type Err = SceneError;

    /// `path=value`, e.g. `chain.pretension_n=18000`.
    fn from_str(text: &str) -> Result<Self, SceneError> {
        let (path, value) = text.split_once('=').ok_or_else(|| {
            SceneError::field(
                text,
                "not an assignment; allowed: path=value, e.g. chain.pretension_n=18000",
            )
        })?;
        Self::parse(path, value)
    }
}

impl fmt::Display for Assignment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}", self.path, self.value)
    }
}

/// The TOML type's name, for messages.
fn kind(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::String(_) => "a string",
        toml::Value::Integer(_) => "an integer",
        toml::Value::Float(_) => "a number",
        toml::Value::Boolean(_) => "a boolean",
        toml::Value::Datetime(_) => "a date",
        toml::Value::Array(_) => "an array",
        toml::Value::Table(_) => "a table",
    }
}

/// Writes `a` into the TOML form of a scene file, checking that the path
/// exists (or names an optional field the file leaves out) and that the
/// value has the field's type. The table must hold a valid scene file's
/// shape; it is left unchanged on error.
pub(crate) fn set_in_table(table: &mut toml::Table, a: &Assignment) -> Result<(), SceneError> {
    let mut edited = table.clone();
    let previous = write(&mut edited, a)?;
    // The file's shape (known fields, their types) is serde's to check.
    let checked: Result<SceneFile, _> = toml::Value::Table(edited.clone()).try_into();
    if let Err(e) = checked {
        let why = e.message().trim().to_owned();
        let message = match &previous {
            Some(old) => format!(
                "{} does not fit this field ({why}); allowed: {} like the base scene's {old}",
                kind(&a.value),
                kind(old)
            ),
            None if why.starts_with("unknown field") => {
                format!("no such field in the scene file ({why})")
            }
            None => format!("{} does not fit this field ({why})", kind(&a.value)),
        };
        return Err(SceneError::field(a.path.to_string(), message));
    }
    *table = edited;
    Ok(())
}

/// Writes the value, returning the value it replaced (`None` for a field
/// the file left out). Checks the path's structure and, where there was a
/// value, the type.
fn write(table: &mut toml::Table, a: &Assignment) -> Result<Option<toml::Value>, SceneError> {
    let path = &a.path;
    let err = |n: usize, message: String| SceneError::field(path.prefix(n), message);
    let parts = path.parts();
    let last = parts.len() - 1;
    let mut here: &mut toml::Value = match &parts[0] {
        PathPart::Key(k) if last == 0 => return replace_key(table, k, a, path),
        PathPart::Key(k) => table
            .entry(k.clone())
            .or_insert_with(|| toml::Value::Table(toml::Table::new())),
        PathPart::Index(_) => return Err(err(0, "a path starts with a key".to_owned())),
    };
    for (n, part) in parts.iter().enumerate().skip(1) {
        here = match (part, here) {
            (PathPart::Key(k), toml::Value::Table(t)) => {
                if n == last {
                    return replace_key(t, k, a, path);
                }
                t.entry(k.clone())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            }
            (PathPart::Index(i), toml::Value::Array(items)) => {
                let len = items.len();
                let Some(item) = items.get_mut(*i) else {
                    let allowed = match len {
                        0 => "none: the array is empty".to_owned(),
                        _ => format!("0 to {}", len - 1),
                    };
                    return Err(err(
                        n + 1,
                        format!("index {i} is out of range; allowed indices: {allowed}"),
                    ));
                };
                if n == last {
                    return replace(item, a, path).map(Some);
                }
                item
            }
            (PathPart::Key(k), other) => {
                return Err(err(
                    n,
                    format!("is {}, not a table: it has no field `{k}`", kind(other)),
                ));
            }
            (PathPart::Index(i), other) => {
                return Err(err(
                    n,
                    format!("is {}, not an array: it has no index {i}", kind(other)),
                ));
            }
        };
    }
    unreachable!("the loop returns at the path's last step")
}

fn replace_key(
    table: &mut toml::Table,
    key: &str,
    a: &Assignment,
    path: &ScenePath,
) -> Result<Option<toml::Value>, SceneError> {
    match table.get_mut(key) {
        Some(old) => replace(old, a, path).map(Some),
        None => {
            table.insert(key.to_owned(), a.value.clone());
            Ok(None)
        }
    }
}

/// Replaces `old` by the assignment's value: an integer becomes a float
/// where the field holds a float; other differences in type are left to
/// the file's shape check (a step may be `1e-5` or `"auto"`).
fn replace(
    old: &mut toml::Value,
    a: &Assignment,
    path: &ScenePath,
) -> Result<toml::Value, SceneError> {
    let new = match (&*old, &a.value) {
        (toml::Value::Float(_), toml::Value::Integer(i)) => toml::Value::Float(*i as f64),
        (toml::Value::Table(_), v) | (_, v @ toml::Value::Table(_)) => {
            return Err(SceneError::field(
                path.to_string(),
                format!(
                    "is {}; a path must name one field, not a table (set {} got {})",
                    kind(old),
                    path,
                    kind(v)
                ),
            ));
        }
        (_, v) => v.clone(),
    };
    Ok(std::mem::replace(old, new))
}

impl SceneFile {
    /// Writes `a` into this file (path and type checked; the value is
    /// validated when the file becomes a [`Scene`]).
    pub(crate) fn set(&mut self, a: &Assignment) -> Result<(), SceneError> {
        let mut table = match toml::Value::try_from(&*self) {
            Ok(toml::Value::Table(t)) => t,
            Ok(_) | Err(_) => {
                return Err(SceneError::Syntax(
                    "the scene file cannot be written as TOML".to_owned(),
                ));
            }
        };
        set_in_table(&mut table, a)?;
        *self = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| SceneError::field(a.path.to_string(), e.message()))?;
        Ok(())
    }
}

impl Scene {
    /// Parses a TOML scene, writes `assignments` into it in order and
    /// validates the result. Errors in the file carry their line and
    /// column; errors in an assigned field name its path without one.
    pub(crate) fn from_toml_set(
        text: &str,
        assignments: &[Assignment],
    ) -> Result<Self, SceneError> {
        // The base must be a scene file before anything is written into it.
        let read = super::shape::read::<SceneFile>(text, super::file::required)?;
        if !read.errors.is_empty() {
            return Err(SceneError::Invalid(read.errors));
        }
        let mut table: toml::Table = text.parse().map_err(SceneError::from_toml)?;
        for a in assignments {
            set_in_table(&mut table, a)?;
        }
        let file: SceneFile = toml::Value::Table(table)
            .try_into()
            .map_err(SceneError::from_toml)?;
        let paths: Vec<String> = assignments.iter().map(|a| a.path.to_string()).collect();
        let paths: Vec<&str> = paths.iter().map(String::as_str).collect();
        let mut scene = Self::try_from(file).map_err(|e| e.located(text, &paths))?;
        scene.source_toml = Some(text.to_owned());
        Ok(scene)
    }

    /// This scene with `assignments` written into its file form, validated
    /// again.
    pub fn with_set(&self, assignments: &[Assignment]) -> Result<Self, SceneError> {
        let mut file = self.file.clone();
        for a in assignments {
            file.set(a)?;
        }
        let mut scene = Self::try_from(file)?;
        scene.source_toml.clone_from(&self.source_toml);
        Ok(scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::L60MC_TOML;

    fn set(text: &str) -> Result<Scene, SceneError> {
        let a: Assignment = text.parse()?;
        Scene::from_toml_set(L60MC_TOML, &[a])
    }

    fn message(text: &str) -> String {
        set(text).expect_err("rejected").to_string()
    }

    #[test]
    fn paths_print_like_the_validator() {
        for (given, printed) in [
            ("sprockets.2.speed_rpm", "sprockets[2].speed_rpm"),
            ("sprockets[2].speed_rpm", "sprockets[2].speed_rpm"),
            ("sprockets.1.center_m.0", "sprockets[1].center_m[0]"),
            ("sprockets[1].center_m[0]", "sprockets[1].center_m[0]"),
            ("chain.pretension_n", "chain.pretension_n"),
        ] {
            let p: ScenePath = given.parse().expect("a path");
            assert_eq!(p.to_string(), printed);
        }
        for bad in ["", "2.teeth", "chain..x", "chain.pitch-m", "sprockets[x]"] {
            assert!(bad.parse::<ScenePath>().is_err(), "{bad}");
        }
    }

    #[test]
    fn a_set_value_replaces_the_file_value() {
        let s = set("chain.pretension_n=18000").expect("valid");
        assert_eq!(s.chain().pretension_n, 18000.0);
        // Index 2 is the third [[sprockets]] table (the tightener).
        let s = set("sprockets.2.mass_kg=200.5").expect("valid");
        assert_eq!(s.sprockets()[2].mass_kg, 200.5);
        assert_eq!(s.file().sprockets[2].name, "tightener");
        let s = set("sprockets[1].center_m[0]=0.6").expect("valid");
        assert_eq!(s.file().sprockets[1].center_m, [0.6, 2.2020]);
        let s = set("solver.dt_s=auto").expect("valid");
        assert_eq!(
            s.file().solver.dt_s,
            crate::scene::StepFile::Word("auto".into())
        );
    }

    #[test]
    fn an_optional_field_absent_from_the_file_can_be_set() {
        let a = ["chain.joint_friction=0.1", "chain.pin_radius_m=0.016"]
            .map(|t| t.parse::<Assignment>().expect("assignment"));
        let s = Scene::from_toml_set(L60MC_TOML, &a).expect("valid");
        assert_eq!(s.file().chain.joint_friction, Some(0.1));
        assert_eq!(s.file().chain.pin_radius_m, Some(0.016));
        let s = set("sprockets.1.load_torque_n_m=-500").expect("valid");
        assert_eq!(s.file().sprockets[1].load_torque_n_m, Some(-500.0));
    }

    #[test]
    fn the_result_is_validated_like_a_file() {
        assert_eq!(
            set("sprockets.2.teeth=2")
                .expect_err("invalid")
                .lines()
                .iter()
                .filter(|l| l.starts_with("sprockets[2].teeth:"))
                .count(),
            1
        );
    }

    #[test]
    fn an_unknown_path_names_the_path_and_the_fields() {
        let m = message("chain.colour=3");
        assert!(m.starts_with("chain.colour: no such field"), "{m}");
        assert!(m.contains("pretension_n"), "{m}");
        let m = message("sprockets.7.teeth=20");
        assert!(
            m.starts_with("sprockets[7]: index 7 is out of range; allowed indices: 0 to 3"),
            "{m}"
        );
        let m = message("chain.pitch_m.x=1");
        assert!(
            m.starts_with("chain.pitch_m: is a number, not a table"),
            "{m}"
        );
        let m = message("chain=1");
        assert!(m.starts_with("chain: is a table"), "{m}");
    }

    #[test]
    fn a_value_of_the_wrong_type_names_the_path_and_the_type() {
        let m = message("chain.pretension_n=high");
        assert!(
            m.starts_with("chain.pretension_n: a string does not fit"),
            "{m}"
        );
        assert!(m.contains("allowed: a number"), "{m}");
        let m = message("sprockets.0.teeth=60.5");
        assert!(
            m.starts_with("sprockets[0].teeth: a number does not fit"),
            "{m}"
        );
        assert!(m.contains("allowed: an integer"), "{m}");
    }

    #[test]
    fn the_typed_file_form_takes_the_same_paths() {
        let mut file = Scene::l60mc().file().clone();
        file.set(&"sprockets.0.speed_rpm=90".parse().expect("assignment"))
            .expect("set");
        assert_eq!(file.sprockets[0].speed_rpm, Some(90.0));
        let scene = Scene::l60mc()
            .with_set(&["chain.pretension_n=15000".parse().expect("assignment")])
            .expect("valid");
        assert_eq!(scene.chain().pretension_n, 15000.0);
        assert!(file.set(&"chain.nope=1".parse().expect("a")).is_err());
    }
}
