//! The collector of a scene's field errors: every check of every part of a
//! scene reports through one [`Checker`], which keeps each problem with its
//! field's path and the common range checks' wording. It knows no scene
//! part: the checks are their parts' own.

use super::error::FieldError;
use super::kinds::Named;

/// Collects field errors while a file is checked.
pub(super) struct Checker {
    pub(super) errors: Vec<FieldError>,
}

impl Checker {
    pub(super) fn new() -> Self {
        Self { errors: Vec::new() }
    }

    pub(super) fn fail(&mut self, path: impl Into<String>, message: impl Into<String>) {
        self.errors.push(FieldError {
            path: path.into(),
            message: message.into(),
            location: None,
        });
    }

    /// A finite, strictly positive quantity.
    pub(super) fn positive(&mut self, path: &str, value: f64) -> f64 {
        if !value.is_finite() {
            self.fail(path, format!("must be a finite number, got {value}"));
        } else if value <= 0.0 {
            self.fail(path, format!("must be > 0, got {value}"));
        }
        value
    }

    /// A finite quantity ≥ 0.
    pub(super) fn non_negative(&mut self, path: &str, value: f64) -> f64 {
        if !value.is_finite() {
            self.fail(path, format!("must be a finite number, got {value}"));
        } else if value < 0.0 {
            self.fail(path, format!("must be >= 0, got {value}"));
        }
        value
    }

    pub(super) fn finite(&mut self, path: &str, value: f64) -> f64 {
        if !value.is_finite() {
            self.fail(path, format!("must be a finite number, got {value}"));
        }
        value
    }

    /// A name of the enumeration `T`; an unknown one is an error listing the allowed names.
    pub(super) fn one_of<T: Named>(&mut self, path: &str, value: &str) -> Option<T> {
        let found = T::ALL.iter().copied().find(|v| v.name() == value);
        if found.is_none() {
            let names: Vec<String> = T::ALL.iter().map(|v| format!("\"{}\"", v.name())).collect();
            self.fail(
                path,
                format!("unknown value \"{value}\"; allowed: {}", names.join(", ")),
            );
        }
        found
    }
}
