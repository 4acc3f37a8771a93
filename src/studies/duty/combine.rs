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
    /// The run's warnings.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// One check's life over the cycle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LimitLife {
    /// The check (`fatigue`).
    pub check: String,
    /// What its rate counts (`Miner's damage`).
    pub quantity: String,
    /// The value at which its life ends (1 for Miner's damage).
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
        warnings: status.map(|s| s.warnings).unwrap_or_default(),
    })
}

/// Combines the finished points of `cycle`, run in `dir` ([super]'s docs).
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
                "{}: no fatigue block (the chain's tensile strength, from chain.designation, is needed)",
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
