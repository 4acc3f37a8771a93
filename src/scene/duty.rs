//! A duty cycle's operating points as written (`[[duty]]`, in a scene or a
//! file of their own; docs/design-checks.md, "Duty cycle"):
//!
//! ```toml
//! [[duty]]
//! name = "cruise"                        # optional
//! hours = 800.0                          # or fraction = 0.8
//! set = { "sprockets.0.speed_rpm" = 3000.0, "sprockets.1.load_torque_n_m" = -200.0 }
//! ```
//!
//! Each point is the scene with `set`'s values (dotted scene paths, as a
//! study's factors) for `hours` of operation, or a `fraction` of the time.
//! This module checks the points' own fields (weights, names); the values
//! in `set` are checked against the scene where the points are run
//! ([`crate::studies::duty`]).

use serde::{Deserialize, Serialize};

use super::checker::Checker;

/// How far fractions may sum from 1.
pub const FRACTION_SUM_TOLERANCE: f64 = 1e-6;

/// One operating point as written.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DutyPointFile {
    /// Name, for the tables (default `point N`, 1-based).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Hours of operation at this point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hours: Option<f64>,
    /// Or its fraction of the time (the points' fractions sum to 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fraction: Option<f64>,
    /// The scene's values at this point, by dotted path.
    #[serde(default)]
    pub set: toml::Table,
}

/// A file holding a duty cycle only (`[[duty]]` tables).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DutyFile {
    /// The points.
    pub duty: Vec<DutyPointFile>,
}

/// Checks a duty cycle's points on their own (a file of their own):
/// every problem, each with its path (`duty[1].hours`).
///
/// # Errors
/// The problems found.
pub fn check_points(points: &[DutyPointFile]) -> Result<(), super::SceneError> {
    let mut c = Checker::new();
    if points.is_empty() {
        c.fail("duty", "is empty; allowed: at least one [[duty]] point");
    }
    check_duty(&mut c, points);
    if c.errors.is_empty() {
        Ok(())
    } else {
        Err(super::SceneError::Invalid(c.errors))
    }
}

/// Checks the points' weights: each gives `hours` (> 0) or `fraction`
/// (in (0, 1]), all the same one; fractions sum to 1. Names are unique.
pub(super) fn check_duty(c: &mut Checker, points: &[DutyPointFile]) {
    let hours = points.iter().filter(|p| p.hours.is_some()).count();
    let fractions = points.iter().filter(|p| p.fraction.is_some()).count();
    for (i, p) in points.iter().enumerate() {
        let at = format!("duty[{i}]");
        match (p.hours, p.fraction) {
            (Some(h), None) => {
                c.positive(&format!("{at}.hours"), h);
            }
            (None, Some(f)) => {
                if !(f > 0.0 && f <= 1.0) {
                    c.fail(
                        format!("{at}.fraction"),
                        format!("must be in (0, 1], got {f}"),
                    );
                }
            }
            (Some(_), Some(_)) => c.fail(
                &at,
                "gives both hours and fraction; allowed: one (hours of operation, or a fraction of the time)",
            ),
            (None, None) => c.fail(
                &at,
                "gives neither hours nor fraction; allowed: hours = 800.0 (hours of operation) or fraction = 0.8 (of the time)",
            ),
        }
        if let Some(name) = &p.name
            && points[..i].iter().any(|q| q.name.as_ref() == Some(name))
        {
            c.fail(
                format!("{at}.name"),
                format!("\"{name}\" names an earlier point too"),
            );
        }
    }
    if hours > 0 && fractions > 0 {
        c.fail(
            "duty",
            format!("{hours} points give hours and {fractions} a fraction; allowed: all hours, or all fractions"),
        );
    } else if fractions > 0 && fractions == points.len() {
        let sum: f64 = points.iter().filter_map(|p| p.fraction).sum();
        if (sum - 1.0).abs() > FRACTION_SUM_TOLERANCE {
            c.fail(
                "duty",
                format!("the fractions sum to {sum}; allowed: 1 (or give hours instead)"),
            );
        }
    }
}
