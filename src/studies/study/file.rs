//! A study plan's file as written: its TOML shapes (nothing checked beyond
//! them), and the list of problems the checks of `plan` and `design` collect.
//! It does not check a value or build a case.

use serde::Deserialize;

/// A plan file as written (nothing checked beyond its TOML shape).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PlanFile {
    /// The base scene, relative to the plan file.
    pub scene: String,
    /// Values set in every case, by path (nested tables or quoted dotted keys).
    #[serde(default)]
    pub set: toml::Table,
    /// The factors.
    #[serde(default)]
    pub factors: Vec<FactorFile>,
    /// The design.
    pub design: DesignFile,
    /// `"all"` or a list of summary fields (`segments.0.mean_link_force_n`).
    #[serde(default)]
    pub responses: Option<toml::Value>,
    /// Simulated seconds between a case's checkpoints (none if absent).
    #[serde(default)]
    pub checkpoint_every_s: Option<toml::Value>,
    /// Length of each case's statistics window, s (the default if absent).
    #[serde(default)]
    pub window_s: Option<toml::Value>,
    /// Each case's sample rate from its driver speed (else 1 kHz).
    #[serde(default)]
    pub sample_by_speed: bool,
}

/// One factor as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FactorFile {
    /// Dotted path into the scene file.
    pub path: String,
    /// Its levels.
    #[serde(default)]
    pub levels: Option<Vec<toml::Value>>,
    /// Or a range of numbers.
    #[serde(default)]
    pub range: Option<RangeFile>,
}

/// A range of a numeric factor.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RangeFile {
    /// First level.
    pub from: f64,
    /// Last level.
    pub to: f64,
    /// Number of evenly spaced levels (full factorial only).
    #[serde(default)]
    pub steps: Option<i64>,
}

/// The design as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct DesignFile {
    /// `full_factorial`, `latin_hypercube` or `explicit`.
    pub kind: String,
    /// Latin hypercube: seed of the draw.
    #[serde(default)]
    pub seed: Option<u64>,
    /// Latin hypercube: number of cases.
    #[serde(default)]
    pub count: Option<i64>,
    /// Explicit: one row of values per case, one value per factor.
    #[serde(default)]
    pub cases: Option<Vec<Vec<toml::Value>>>,
}

/// Collects `path: message` lines.
pub(super) struct Problems(pub(super) Vec<String>);

impl Problems {
    pub(super) fn add(&mut self, path: impl std::fmt::Display, message: impl std::fmt::Display) {
        self.0.push(format!("{path}: {message}"));
    }
}
