//! The matrix's CSV rows (`stress.csv`, `stress_limits.csv`,
//! `stress_blowups.csv`) and the per-roller cost of the roller-count series.

use super::{CaseResult, Limit, RunRecord, Verdict};
use crate::scene::Integrator;

/// The column header of `stress.csv`.
pub const CSV_HEADER: &str = "case,rollers,sprockets,rpm,e,damping_ratio,kg,profile,integrator,dt_s,stable,detector,wall_per_sim_s";

/// The column header of `stress_limits.csv`.
pub const LIMITS_CSV_HEADER: &str = "case,rollers,sprockets,profile,integrator,estimated_dt_s,largest_stable_dt_s,first_unstable_dt_s,detector,blow_up_t_s,wall_per_sim_s_at_limit,false_alarm_dts";

/// The column header of `stress_blowups.csv` (one row per unstable run).
pub const BLOWUPS_CSV_HEADER: &str = "case,integrator,dt_s,detector,t_s,body,value,limit";

/// `stress.csv`'s rows of one cell (no header).
pub fn csv_rows(result: &CaseResult) -> Vec<String> {
    let i = &result.info;
    result
        .runs
        .iter()
        .map(|r| {
            format!(
                "{},{},{},{},{},{},{},{},{},{},{},{},{:.6}",
                i.name,
                i.rollers,
                i.sprockets,
                num(i.rpm),
                num(i.restitution),
                num(i.damping_ratio),
                num(i.contact_stiffness),
                i.profile,
                r.integrator.name(),
                num(r.dt_s),
                r.verdict.is_stable(),
                r.verdict.detector(),
                r.wall_per_sim_s()
            )
        })
        .collect()
}

/// A number in the CSVs: up to 6 significant digits, no float noise
/// (`7.5e-6`, not `7.500000000000001e-6`).
pub fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let mag = x.abs().log10().floor();
    if (-3.0..6.0).contains(&mag) {
        let decimals = (5.0 - mag).max(0.0) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            s
        }
    } else {
        let s = format!("{x:.5e}");
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

fn opt(x: Option<f64>) -> String {
    x.map(num).unwrap_or_default()
}

/// `stress_limits.csv`'s rows of one cell (no header).
pub fn limits_csv_rows(result: &CaseResult) -> Vec<String> {
    let i = &result.info;
    result
        .limits
        .iter()
        .map(|l| {
            let fail = first_failure(result, l);
            format!(
                "{},{},{},{},{},{},{},{},{},{},{},{}",
                i.name,
                i.rollers,
                i.sprockets,
                i.profile,
                l.integrator.name(),
                opt(l.estimated_dt_s.is_finite().then_some(l.estimated_dt_s)),
                opt(l.largest_stable_dt_s),
                opt(l.first_unstable_dt_s),
                fail.map_or("", |r| r.verdict.detector()),
                opt(fail.and_then(|r| r.verdict.stop_t_s())),
                l.wall_per_sim_s_at_limit
                    .map(|w| format!("{w:.6}"))
                    .unwrap_or_default(),
                l.false_alarms_dt_s
                    .iter()
                    .map(|d| num(*d))
                    .collect::<Vec<_>>()
                    .join(" "),
            )
        })
        .collect()
}

/// `stress_blowups.csv`'s rows of one cell (no header).
pub fn blowup_csv_rows(result: &CaseResult) -> Vec<String> {
    result
        .runs
        .iter()
        .filter_map(|r| match &r.verdict {
            Verdict::BlowUp {
                detector,
                t_s,
                body,
                value,
                limit,
            } => Some(format!(
                "{},{},{},{},{},{},{},{}",
                result.info.name,
                r.integrator.name(),
                num(r.dt_s),
                detector,
                num(*t_s),
                body.replace(',', ";"),
                num(*value),
                num(*limit)
            )),
            Verdict::Timeout { t_s } => Some(format!(
                "{},{},{},timeout,{},,,",
                result.info.name,
                r.integrator.name(),
                num(r.dt_s),
                num(*t_s)
            )),
            Verdict::Stable => None,
        })
        .collect()
}

/// The run at a limit's first failing step.
pub fn first_failure<'a>(result: &'a CaseResult, limit: &Limit) -> Option<&'a RunRecord> {
    let dt = limit.first_unstable_dt_s?;
    result
        .runs
        .iter()
        .find(|r| r.integrator == limit.integrator && r.dt_s == dt && !r.verdict.is_stable())
}

/// Per-roller cost of one integrator across the roller-count series, at
/// one step every member ran stable.
#[derive(Clone, Debug, PartialEq)]
pub struct RollerCost {
    /// The integrator.
    pub integrator: Integrator,
    /// The common step, s.
    pub dt_s: f64,
    /// (case, rollers, ns per roller-step), by roller count.
    pub points: Vec<(String, usize, f64)>,
}

impl RollerCost {
    /// Largest over smallest ns per roller-step.
    pub fn spread(&self) -> f64 {
        let ns = self.points.iter().map(|p| p.2);
        let max = ns.clone().fold(f64::NEG_INFINITY, f64::max);
        let min = ns.fold(f64::INFINITY, f64::min);
        if min > 0.0 { max / min } else { f64::NAN }
    }
}

/// Per-roller cost from the cells marked `cost_series`: for every
/// integrator they all ran, at the common stable step closest to 10 µs.
pub fn roller_costs(results: &[CaseResult]) -> Vec<RollerCost> {
    let mut series: Vec<&CaseResult> = results.iter().filter(|r| r.cost_series).collect();
    series.sort_by_key(|r| r.info.rollers);
    if series.len() < 2 {
        return Vec::new();
    }
    let stable_dts = |r: &CaseResult, i: Integrator| -> Vec<f64> {
        r.runs
            .iter()
            .filter(|x| x.integrator == i && x.verdict.is_stable() && !x.refinement)
            .map(|x| x.dt_s)
            .collect()
    };
    let mut out = Vec::new();
    for (_, integrator) in Integrator::ALL {
        let mut common = stable_dts(series[0], integrator);
        for r in &series[1..] {
            let other = stable_dts(r, integrator);
            common.retain(|d| other.iter().any(|o| (o / d - 1.0).abs() < 1e-9));
        }
        let Some(dt) = common
            .iter()
            .copied()
            .min_by(|a, b| (a / 1e-5).ln().abs().total_cmp(&(b / 1e-5).ln().abs()))
        else {
            continue;
        };
        let points = series
            .iter()
            .filter_map(|r| {
                r.runs
                    .iter()
                    .find(|x| {
                        x.integrator == integrator
                            && x.verdict.is_stable()
                            && (x.dt_s / dt - 1.0).abs() < 1e-9
                    })
                    .map(|x| {
                        (
                            r.info.name.clone(),
                            r.info.rollers,
                            x.ns_per_roller_step(r.info.rollers),
                        )
                    })
            })
            .collect();
        out.push(RollerCost {
            integrator,
            dt_s: dt,
            points,
        });
    }
    out
}
