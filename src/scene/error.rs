//! Scene errors: one line per problem, each naming the field's path.

use std::fmt;

/// One problem with one field.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldError {
    /// Path of the field in the scene file, e.g. `sprockets[2].teeth`.
    pub path: String,
    /// What is wrong and what is allowed.
    pub message: String,
    /// 1-based line and column of the field's value in the file, when known.
    pub location: Option<(usize, usize)>,
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some((line, column)) = self.location {
            write!(f, "{line}:{column}: ")?;
        }
        write!(f, "{}: {}", self.path, self.message)
    }
}

/// Finds where the value at `path` (`sprockets[2].teeth`, `chain`) sits in
/// the TOML `text`: 1-based (line, column). `None` if the text does not parse
/// or has no such field. A path that stops at an array element or table
/// points at that element or table.
pub fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    super::shape::line_column(text, value_span(text, path)?.start)
}

/// The byte range of the value at `path` (`sprockets[1].center_m`) in the
/// TOML `text`, as [`locate`] finds it (an empty path: the whole document);
/// `None` if the text does not parse or has no such field.
pub fn value_span(text: &str, path: &str) -> Option<std::ops::Range<usize>> {
    use toml::de::{DeTable, DeValue};
    let root = DeTable::parse(text).ok()?;
    let mut span = root.span();
    let mut table: Option<&DeTable<'_>> = Some(root.get_ref());
    let mut value: Option<&DeValue<'_>> = None;
    for part in path.split('.').filter(|p| !p.is_empty()) {
        let (key, indices) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        let t = match (table, value) {
            (Some(t), _) => t,
            (None, Some(v)) => v.as_table()?,
            (None, None) => return None,
        };
        let mut current = t.get(key)?;
        for index in indices.split(['[', ']']).filter(|s| !s.is_empty()) {
            let i: usize = index.parse().ok()?;
            current = current.get_ref().as_array()?.get(i)?;
        }
        span = current.span();
        table = None;
        value = Some(current.get_ref());
    }
    Some(span)
}

/// Why a scene was rejected.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SceneError {
    /// The text is not valid TOML (its first error).
    #[error("{}", .0)]
    Syntax(String),
    /// The file parsed, but fields are unknown, missing, mistyped or their
    /// values invalid. Every problem found is listed.
    #[error("{}", lines(.0))]
    Invalid(Vec<FieldError>),
}

fn lines(errors: &[FieldError]) -> String {
    errors
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}

impl SceneError {
    pub(crate) fn from_toml(e: toml::de::Error) -> Self {
        // toml's message already names the line, column and the field; keep it
        // on as few lines as possible for one-line-per-error output.
        let text = e.to_string();
        let text = text.trim_end().to_owned();
        Self::Syntax(text)
    }

    /// Builds an error about one field.
    pub fn field(path: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Invalid(vec![FieldError {
            path: path.into(),
            message: message.into(),
            location: None,
        }])
    }

    /// Fills in every field error's line and column from the scene's text,
    /// except for the fields at `overridden` paths (their value is not in it).
    pub fn located(self, text: &str, overridden: &[&str]) -> Self {
        match self {
            Self::Invalid(errors) => Self::Invalid(
                errors
                    .into_iter()
                    .map(|e| FieldError {
                        location: e.location.or_else(|| {
                            if overridden.contains(&e.path.as_str()) {
                                None
                            } else {
                                locate(text, &e.path)
                            }
                        }),
                        ..e
                    })
                    .collect(),
            ),
            other => other,
        }
    }

    /// Every problem as `path: message`, one per line.
    pub fn lines(&self) -> Vec<String> {
        match self {
            Self::Syntax(s) => vec![s.replace('\n', " ")],
            Self::Invalid(errors) => errors.iter().map(ToString::to_string).collect(),
        }
    }
}
