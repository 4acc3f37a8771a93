//! A scene's `[checks]` section: settings of the design checks
//! (docs/design-checks.md, "Settings"), all optional: which checks a run
//! measures for, the constants of their models where a user has better data
//! than the defaults, and what a tooth jump does to a run.
//!
//! ```toml
//! [checks]
//! fatigue_limit_n = 9000.0     # the fatigue check's own S-N curve
//! sn_slope = 10.0
//! wear = true                  # count every joint's sliding (the wear check)
//! wear_coefficient = 1e-6      # Archard's k, dimensionless (the default)
//! wear_hardness_pa = 6.9e9     # H of the pin and bushing surfaces (the default)
//! elongation_limit_pct = 1.0   # default: the smaller of 3 % and 200/z_max %
//! tooth_jump = "count"         # or "stop": the run ends at the first jump
//! ```
//!
//! The wear check needs the chain's pin diameter and bushing length (from
//! `chain.designation`, or `chain.pin_radius_m` and `chain.bushing_length_m`);
//! asking for it without them is an error naming the fields.
//!
//! It checks the values; what they mean is [`crate::analysis::design`]'s.

use serde::{Deserialize, Serialize};

use super::checker::Checker;

/// Slopes allowed for an S–N curve: steels' lie within (welded joints near
/// 3, plain and notched plates 5 to 15).
pub const SN_SLOPE_RANGE: std::ops::RangeInclusive<f64> = 2.0..=30.0;

/// Archard's dimensionless wear coefficient k when the scene gives none: the
/// order of magnitude of mild wear of lubricated steel on steel
/// (docs/design-checks.md, "Wear": its sources and its cross-check against
/// the catalogue ratings' 15,000 h to 3 %).
pub const DEFAULT_WEAR_COEFFICIENT: f64 = 1e-6;

/// The hardness H of the pin and bushing surfaces when the scene gives
/// none, Pa: case-hardened chain steel of about 700 HV (≈ 60 HRC),
/// 700 × 9.807 MPa.
pub const DEFAULT_WEAR_HARDNESS_PA: f64 = 6.9e9;

/// The elongation limit's cap, %: the catalogues' largest allowable wear
/// elongation.
pub const ELONGATION_LIMIT_CAP_PCT: f64 = 3.0;

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
    /// Count every joint's sliding for the wear check (default false).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear: Option<bool>,
    /// Archard's wear coefficient k, dimensionless, in (0, 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear_coefficient: Option<f64>,
    /// Hardness H of the pin and bushing surfaces, Pa.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear_hardness_pa: Option<f64>,
    /// The wear elongation that ends the chain's life, %.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elongation_limit_pct: Option<f64>,
    /// What a tooth jump does: `"count"` (the default) or `"stop"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tooth_jump: Option<String>,
}

impl ChecksFile {
    /// Whether nothing is set (the section is then not written).
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// What a tooth jump does to a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum JumpAction {
    /// The run goes on; the summary and the recording list every jump.
    #[default]
    Count,
    /// The run ends at the first jump with an error naming it.
    Stop,
}

/// The wear check's constants (docs/design-checks.md, "Wear").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WearSettings {
    /// Archard's k, dimensionless.
    pub coefficient: f64,
    /// H, Pa.
    pub hardness_pa: f64,
    /// The limit written in the scene, %; `None`: the default.
    pub elongation_limit_pct: Option<f64>,
}

/// Validated `[checks]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Checks {
    /// The fatigue limit given, N.
    pub fatigue_limit_n: Option<f64>,
    /// The S–N slope given.
    pub sn_slope: Option<f64>,
    /// The wear check's constants where the scene asks for it.
    pub wear: Option<WearSettings>,
    /// What a tooth jump does.
    pub tooth_jump: JumpAction,
}

/// Checks `[checks]`. `bearing` is whether the chain has a pin diameter and
/// a bushing length (the wear check's bearing area); `strength` the chain's
/// tensile strength, N, where it has one: a fatigue limit is below it (a
/// pulsating load of the strength's peak breaks the chain in one cycle).
pub(super) fn check_checks(
    c: &mut Checker,
    f: &ChecksFile,
    bearing: bool,
    strength: Option<f64>,
) -> Checks {
    let fatigue_limit_n = f
        .fatigue_limit_n
        .map(|v| c.positive("checks.fatigue_limit_n", v));
    if let (Some(limit), Some(strength)) = (fatigue_limit_n, strength)
        && limit >= strength
    {
        c.fail(
            "checks.fatigue_limit_n",
            format!(
                "must be below the chain's tensile strength of {:.1} kN (chain.tensile_strength_n, or its designation's): a pulsating load of that peak breaks the chain at once, and makers' maximum allowable loads are a small fraction of it; got {limit}",
                strength / 1e3
            ),
        );
    }
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
        wear: check_wear(c, f, bearing),
        tooth_jump: check_tooth_jump(c, f),
    }
}

/// The wear check's settings, where `[checks]` asks for it.
fn check_wear(c: &mut Checker, f: &ChecksFile, bearing: bool) -> Option<WearSettings> {
    let coefficient = f
        .wear_coefficient
        .map(|k| c.positive("checks.wear_coefficient", k));
    if let Some(k) = coefficient
        && k >= 1.0
    {
        c.fail(
            "checks.wear_coefficient",
            format!(
                "must lie in (0, 1) (Archard's k, dimensionless; lubricated steel about 1e-6, dry up to 1e-2), got {k}"
            ),
        );
    }
    let hardness = f
        .wear_hardness_pa
        .map(|h| c.positive("checks.wear_hardness_pa", h));
    let limit = f
        .elongation_limit_pct
        .map(|e| c.positive("checks.elongation_limit_pct", e));
    if let Some(e) = limit
        && e >= 100.0
    {
        c.fail(
            "checks.elongation_limit_pct",
            format!("must lie in (0, 100) % (catalogues: at most 3 %), got {e}"),
        );
    }
    let wanted = f.wear.unwrap_or(false);
    if wanted && !bearing {
        c.fail(
            "checks.wear",
            "needs the chain's bearing area: give chain.pin_radius_m and chain.bushing_length_m, or a chain.designation whose row has the pin diameter and plate thickness (the motorcycle chains' have not)",
        );
    }
    wanted.then(|| WearSettings {
        coefficient: coefficient.unwrap_or(DEFAULT_WEAR_COEFFICIENT),
        hardness_pa: hardness.unwrap_or(DEFAULT_WEAR_HARDNESS_PA),
        elongation_limit_pct: limit,
    })
}

/// What a tooth jump does, from `checks.tooth_jump`.
fn check_tooth_jump(c: &mut Checker, f: &ChecksFile) -> JumpAction {
    match f.tooth_jump.as_deref() {
        None | Some("count") => JumpAction::Count,
        Some("stop") => JumpAction::Stop,
        Some(other) => {
            c.fail(
                "checks.tooth_jump",
                format!("unknown value \"{other}\"; allowed: \"count\", \"stop\""),
            );
            JumpAction::Count
        }
    }
}
