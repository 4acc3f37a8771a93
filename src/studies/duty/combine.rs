//! A duty cycle's finished points combined into lives, one per check with a
//! rate per hour, and the shortest ([super]'s docs). It reads the cases'
//! summaries; it runs nothing.

use serde::{Deserialize, Serialize};

use super::DutyCycle;
use crate::analysis::RunSummary;
use crate::analysis::design::Life;
use crate::studies::study::{StudyDir, StudyError};

/// One point's outcome.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointResult {
    /// Its name.
    pub name: String,
    /// Its weight (hours, or a fraction of the time).
    pub hours: f64,
    /// Its share of the time.
    pub time_share: f64,
    /// The values set, `path = value, …`.
    pub set: String,
    /// `ok`, `warned` (finished with warnings), `failed` or `missing` (not run yet).
    pub status: String,
    /// Why it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The driver's mean power, W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub driver_power_w: Option<f64>,
    /// The catalogue rating's margin (design power over transmitted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rating_margin: Option<f64>,
    /// Tensile strength over the largest link force.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_safety_factor: Option<f64>,
    /// Fatigue limit over the largest cycle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fatigue_safety_factor: Option<f64>,
    /// Miner's damage per hour at this point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damage_per_hour: Option<f64>,
    /// The fatigue life were the chain run at this point alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fatigue_life_h: Option<Life>,
    /// Its share of the cycle's damage, rᵢ hᵢ / Σ rⱼ hⱼ.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damage_share: Option<f64>,
    /// The wear elongation rate at this point, % per 1000 h (where the
    /// scene asks for the wear check).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elongation_pct_per_1000h: Option<f64>,
    /// The elongation that ends the chain's life, %.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elongation_limit_pct: Option<f64>,
    /// The wear life were the chain run at this point alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear_life_h: Option<Life>,
    /// The run's warnings.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// One check's life over the cycle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LimitLife {
    /// The check (`fatigue`, `wear`).
    pub check: String,
    /// What its rate counts (`Miner's damage`, `wear elongation, %`).
    pub quantity: String,
    /// The value at which its life ends (1 for Miner's damage, the
    /// elongation limit in % for wear).
    pub limit: f64,
    /// The cycle's mean rate per hour, Σ rᵢ hᵢ / Σ hᵢ.
    pub rate_per_hour: f64,
    /// limit / rate.
    pub life_h: Life,
    /// The point with the largest rᵢ hᵢ (absent where nothing accumulates).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dominated_by: Option<String>,
}

/// A duty cycle's lives.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DutyLife {
    /// Hours in one block of the cycle (1 with fractions).
    pub block_hours: f64,
    /// Whether the weights are fractions of the time.
    pub by_fraction: bool,
    /// Each point.
    pub points: Vec<PointResult>,
    /// Each check's life (one per check that every point could give).
    pub limits: Vec<LimitLife>,
    /// The shortest of the limits' lives (absent when none could be had).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub life_h: Option<Life>,
    /// The check whose life is the shortest.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub governed_by: Option<String>,
    /// What is missing, and why.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// The point's outcome from its case's files.
fn point_result(
    dir: &StudyDir,
    k: usize,
    point: &super::DutyPoint,
    block: f64,
) -> Result<PointResult, StudyError> {
    let status = dir.status(k)?;
    let summary: Option<RunSummary> = match dir.summary(k)? {
        Some(v) => {
            Some(serde_json::from_value(v).map_err(|e| StudyError::io(&dir.case_dir(k), e))?)
        }
        None => None,
    };
    let state = match (&status, &summary) {
        (None, _) => "missing",
        (Some(s), _) if !s.ok => "failed",
        (Some(s), _) if !s.warnings.is_empty() => "warned",
        _ => "ok",
    };
    let fatigue = summary.as_ref().and_then(|s| s.fatigue.as_ref());
    let rating = summary.as_ref().and_then(|s| s.rating.as_ref());
    let wear = summary.as_ref().and_then(|s| s.wear.as_ref());
    Ok(PointResult {
        name: point.name.clone(),
        hours: point.hours,
        time_share: if block > 0.0 {
            point.hours / block
        } else {
            0.0
        },
        set: point
            .set
            .iter()
            .map(|(p, v)| format!("{p} = {v}"))
            .collect::<Vec<_>>()
            .join(", "),
        status: state.to_owned(),
        error: status.as_ref().and_then(|s| s.error.clone()),
        driver_power_w: summary.as_ref().map(|s| s.driver_mean_power_w),
        rating_margin: rating.and_then(|r| r.margin),
        static_safety_factor: rating.and_then(|r| r.static_safety_factor),
        fatigue_safety_factor: fatigue.and_then(|f| f.fatigue_safety_factor),
        damage_per_hour: fatigue.map(|f| f.damage_per_hour),
        fatigue_life_h: fatigue.map(|f| f.life_h),
        damage_share: None,
        elongation_pct_per_1000h: wear.map(|w| w.elongation_pct_per_1000h),
        elongation_limit_pct: wear.map(|w| w.elongation_limit_pct),
        wear_life_h: wear.map(|w| w.life_h),
        warnings: status.map(|s| s.warnings).unwrap_or_default(),
    })
}

/// Combines the finished points of `cycle`, run in `dir`: a point's rate
/// rᵢ (Miner's damage per hour for fatigue) for hᵢ hours adds rᵢ hᵢ per
/// block of Σ hᵢ hours, each check's life is its limit over the block's
/// mean rate, and the cycle's life is the shortest of its checks'.
///
/// # Errors
/// A case's files that cannot be read.
pub fn combine(cycle: &DutyCycle, dir: &StudyDir) -> Result<DutyLife, StudyError> {
    let block = cycle.block_hours();
    let mut points = Vec::with_capacity(cycle.points.len());
    for (k, point) in cycle.points.iter().enumerate() {
        points.push(point_result(dir, k, point, block)?);
    }
    let mut notes = Vec::new();
    let mut limits = Vec::new();
    let lacking: Vec<String> = points
        .iter()
        .filter(|p| p.damage_per_hour.is_none())
        .map(|p| match p.status.as_str() {
            "missing" => format!("{}: not run yet", p.name),
            "failed" => format!(
                "{}: failed ({})",
                p.name,
                p.error.as_deref().unwrap_or("no message")
            ),
            _ => format!(
                "{}: no fatigue block (the chain's tensile strength, from chain.tensile_strength_n or chain.designation, is needed)",
                p.name
            ),
        })
        .collect();
    if lacking.is_empty() {
        let weighted: Vec<f64> = points
            .iter()
            .map(|p| p.damage_per_hour.unwrap_or(0.0) * p.hours)
            .collect();
        let total: f64 = weighted.iter().sum();
        for (p, w) in points.iter_mut().zip(&weighted) {
            p.damage_share = Some(if total > 0.0 { w / total } else { 0.0 });
        }
        let dominated_by = (total > 0.0)
            .then(|| {
                weighted
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .map(|(i, _)| points[i].name.clone())
            })
            .flatten();
        let rate = if block > 0.0 { total / block } else { 0.0 };
        limits.push(LimitLife {
            check: "fatigue".to_owned(),
            quantity: "Miner's damage".to_owned(),
            limit: 1.0,
            rate_per_hour: rate,
            life_h: Life::of_rate_per_hour(rate),
            dominated_by,
        });
    } else {
        notes.push(format!("no fatigue life: {}", lacking.join("; ")));
    }
    limits.extend(wear_limit(&points, block, &mut notes));
    let shortest = limits.iter().reduce(|a, b| {
        if b.life_h.is_shorter_than(a.life_h) {
            b
        } else {
            a
        }
    });
    Ok(DutyLife {
        block_hours: block,
        by_fraction: cycle.by_fraction,
        life_h: shortest.map(|l| l.life_h),
        governed_by: shortest.map(|l| l.check.clone()),
        points,
        limits,
        notes,
    })
}

/// The cycle's wear life, where any point has a wear block: every point
/// needs one (the same limit, the scene's), else a note says which lack it.
fn wear_limit(points: &[PointResult], block: f64, notes: &mut Vec<String>) -> Option<LimitLife> {
    let limit_pct = points.iter().find_map(|p| p.elongation_limit_pct)?;
    let lacking: Vec<&str> = points
        .iter()
        .filter(|p| p.elongation_pct_per_1000h.is_none())
        .map(|p| p.name.as_str())
        .collect();
    if !lacking.is_empty() {
        notes.push(format!(
            "no wear life: no wear block at {} (not run, failed, or checks.wear unset there)",
            lacking.join(", ")
        ));
        return None;
    }
    // Per hour: % per 1000 h over 1000.
    let weighted: Vec<f64> = points
        .iter()
        .map(|p| p.elongation_pct_per_1000h.unwrap_or(0.0) * 1e-3 * p.hours)
        .collect();
    let total: f64 = weighted.iter().sum();
    let dominated_by = (total > 0.0)
        .then(|| {
            weighted
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map(|(i, _)| points[i].name.clone())
        })
        .flatten();
    let rate = if block > 0.0 { total / block } else { 0.0 };
    Some(LimitLife {
        check: "wear".to_owned(),
        quantity: "wear elongation, %".to_owned(),
        limit: limit_pct,
        rate_per_hour: rate,
        life_h: Life::of_rate_per_hour(rate / limit_pct),
        dominated_by,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(name: &str, hours: f64, rate: Option<f64>) -> PointResult {
        PointResult {
            name: name.to_owned(),
            hours,
            time_share: 0.0,
            set: String::new(),
            status: "ok".to_owned(),
            error: None,
            driver_power_w: None,
            rating_margin: None,
            static_safety_factor: None,
            fatigue_safety_factor: None,
            damage_per_hour: None,
            fatigue_life_h: None,
            damage_share: None,
            elongation_pct_per_1000h: rate,
            elongation_limit_pct: rate.map(|_| 3.0),
            wear_life_h: None,
            warnings: Vec::new(),
        }
    }

    #[test]
    fn the_cycles_wear_life_is_the_limit_over_the_hour_weighted_rate() {
        // 1 % per 1000 h for 3 h and 3 % per 1000 h for 1 h: 6 % per 1000 h
        // over 4 h, 1.5e-3 % per hour; to 3 %: 2000 h.
        let mut notes = Vec::new();
        let points = [point("a", 3.0, Some(1.0)), point("b", 1.0, Some(3.0))];
        let l = wear_limit(&points, 4.0, &mut notes).expect("a wear life");
        approx::assert_relative_eq!(l.rate_per_hour, 1.5e-3, max_relative = 1e-12);
        approx::assert_relative_eq!(
            l.life_h.hours().unwrap_or(0.0),
            2000.0,
            max_relative = 1e-12
        );
        assert_eq!(l.limit, 3.0);
        assert!(notes.is_empty());
        // A point without a wear block: no life, a note naming it.
        let points = [point("a", 3.0, Some(1.0)), point("b", 1.0, None)];
        assert!(wear_limit(&points, 4.0, &mut notes).is_none());
        assert!(
            notes
                .iter()
                .any(|n| n.contains("no wear life") && n.contains('b'))
        );
        // No point with one: nothing said.
        let mut quiet = Vec::new();
        assert!(wear_limit(&[point("a", 1.0, None)], 1.0, &mut quiet).is_none());
        assert!(quiet.is_empty());
    }
}
