//! A scene's `[checks]` section: settings of the design checks
//! (docs/design-checks.md, "Settings"), all optional. Today: the fatigue
//! check's own S–N curve where a user has one (`fatigue_limit_n`, the peak
//! of the pulsating cycle the chain endures for ever; `sn_slope`, the
//! exponent m of N = N_D (F_D / F)^m).
//!
//! It checks the values; what they mean is [`crate::analysis::design`]'s.

use serde::{Deserialize, Serialize};

use super::validate::Checker;

/// Slopes allowed for an S–N curve: steels' lie within (welded joints near
/// 3, plain and notched plates 5 to 15).
pub const SN_SLOPE_RANGE: std::ops::RangeInclusive<f64> = 2.0..=30.0;

/// `[checks]` as written.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ChecksFile {
    /// The chain's fatigue limit: the peak force of a pulsating (0 → F)
    /// cycle it endures for ever, N (default: derived from the rating).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fatigue_limit_n: Option<f64>,
    /// The S–N curve's slope m (default 10, from the rating).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sn_slope: Option<f64>,
}

impl ChecksFile {
    /// Whether nothing is set (the section is then not written).
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// Validated `[checks]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Checks {
    /// The fatigue limit given, N.
    pub fatigue_limit_n: Option<f64>,
    /// The S–N slope given.
    pub sn_slope: Option<f64>,
}

pub(super) fn check_checks(c: &mut Checker, f: &ChecksFile) -> Checks {
    let fatigue_limit_n = f
        .fatigue_limit_n
        .map(|v| c.positive("checks.fatigue_limit_n", v));
    let sn_slope = f.sn_slope.inspect(|&m| {
        if !SN_SLOPE_RANGE.contains(&m) {
            c.fail(
                "checks.sn_slope",
                format!(
                    "must be from {} to {} (steels: 3 for welded joints, about 10 for chain plates), got {m}",
                    SN_SLOPE_RANGE.start(),
                    SN_SLOPE_RANGE.end()
                ),
            );
        }
    });
    Checks {
        fatigue_limit_n,
        sn_slope,
    }
}
