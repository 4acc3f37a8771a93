//! Scene errors: one line per problem, each naming the field's path.

use std::fmt;

/// One problem with one field.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldError {
    /// Path of the field in the scene file, e.g. `sprockets[2].teeth`.
    pub path: String,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

/// Why a scene was rejected.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SceneError {
    /// The text is not valid TOML, or does not have the scene's shape
    /// (unknown, missing or mistyped field).
    #[error("{}", .0)]
    Syntax(String),
    /// The file parsed, but values are invalid. Every problem found is listed.
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
        }])
    }

    /// Every problem as `path: message`, one per line.
    pub fn lines(&self) -> Vec<String> {
        match self {
            Self::Syntax(s) => vec![s.replace('\n', " ")],
            Self::Invalid(errors) => errors.iter().map(ToString::to_string).collect(),
        }
    }
}
