//! The matrix's CSV rows (`stress.csv`, `stress_limits.csv`,
//! `stress_blowups.csv`) and the per-roller cost of the roller-count series.

use serde::Serialize;

use super::{CaseResult, Limit, RunRecord, Verdict};
use crate::scene::Integrator;

/// The column header of `stress.csv`.
pub(crate) const CSV_HEADER: &str = "case,rollers,sprockets,rpm,e,damping_ratio,kg,profile,integrator,dt_s,stable,detector,wall_per_sim_s";

/// The column header of `stress_limits.csv`.
pub(crate) const LIMITS_CSV_HEADER: &str = "case,rollers,sprockets,profile,integrator,estimated_dt_s,largest_stable_dt_s,first_unstable_dt_s,detector,blow_up_t_s,wall_per_sim_s_at_limit,false_alarm_dts";

/// The column header of `stress_blowups.csv` (one row per unstable run).
pub(crate) const BLOWUPS_CSV_HEADER: &str = "case,integrator,dt_s,detector,t_s,body,value,limit";

/// One row of `stress.csv`: one run. Numbers are already formatted (up to
/// 6 significant digits, `7.5e-6` rather than `7.500000000000001e-6`); the column names are the
/// field names ([`CSV_HEADER`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct RunRow {
    /// Case name.
    pub case: String,
    /// Rollers.
    pub rollers: usize,
    /// Sprockets.
    pub sprockets: usize,
    /// Driver speed, rpm.
    pub rpm: String,
    /// Restitution.
    pub e: String,
    /// Link damping over critical.
    pub damping_ratio: String,
    /// Contact stiffness K_g.
    pub kg: String,
    /// Profile name.
    pub profile: &'static str,
    /// Integrator name.
    pub integrator: &'static str,
    /// Step, s.
    pub dt_s: String,
    /// Whether the run reached the horizon.
    pub stable: bool,
    /// The blow-up detector that fired (empty: none).
    pub detector: &'static str,
    /// Wall time per simulated second.
    pub wall_per_sim_s: String,
}

/// `stress.csv`'s rows of one cell (no header).
pub(crate) fn csv_rows(result: &CaseResult) -> Vec<RunRow> {
    let i = &result.info;
    result
        .runs
        .iter()
        .map(|r| RunRow {
            case: i.name.clone(),
            rollers: i.rollers,
            sprockets: i.sprockets,
            rpm: num(i.rpm),
            e: num(i.restitution),
            damping_ratio: num(i.damping_ratio),
            kg: num(i.contact_stiffness),
            profile: i.profile,
            integrator: r.integrator.name(),
            dt_s: num(r.dt_s),
            stable: r.verdict.is_stable(),
            detector: r.verdict.detector(),
            wall_per_sim_s: format!("{:.6}", r.wall_per_sim_s()),
        })
        .collect()
}

/// A number in the CSVs: up to 6 significant digits, no float noise
/// (`7.5e-6`, not `7.500000000000001e-6`).
pub(crate) fn num(x: f64) -> String {
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

/// One row of `stress_limits.csv`: one integrator's limits on one cell
/// (empty fields: not found).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct LimitRow {
    /// Case name.
    pub case: String,
    /// Rollers.
    pub rollers: usize,
    /// Sprockets.
    pub sprockets: usize,
    /// Profile name.
    pub profile: &'static str,
    /// Integrator name.
    pub integrator: &'static str,
    /// The stability estimate, s.
    pub estimated_dt_s: String,
    /// Largest stable step, s.
    pub largest_stable_dt_s: String,
    /// First unstable step, s.
    pub first_unstable_dt_s: String,
    /// The detector of the first failure.
    pub detector: &'static str,
    /// When it fired, s.
    pub blow_up_t_s: String,
    /// Wall time per simulated second at the largest stable step.
    pub wall_per_sim_s_at_limit: String,
    /// Failing steps below a stable one, space-separated, s.
    pub false_alarm_dts: String,
}

/// `stress_limits.csv`'s rows of one cell (no header).
pub(crate) fn limits_csv_rows(result: &CaseResult) -> Vec<LimitRow> {
    let i = &result.info;
    result
        .limits
        .iter()
        .map(|l| {
            let fail = first_failure(result, l);
            LimitRow {
                case: i.name.clone(),
                rollers: i.rollers,
                sprockets: i.sprockets,
                profile: i.profile,
                integrator: l.integrator.name(),
                estimated_dt_s: opt(l.estimated_dt_s.is_finite().then_some(l.estimated_dt_s)),
                largest_stable_dt_s: opt(l.largest_stable_dt_s),
                first_unstable_dt_s: opt(l.first_unstable_dt_s),
                detector: fail.map_or("", |r| r.verdict.detector()),
                blow_up_t_s: opt(fail.and_then(|r| r.verdict.stop_t_s())),
                wall_per_sim_s_at_limit: l
                    .wall_per_sim_s_at_limit
                    .map(|w| format!("{w:.6}"))
                    .unwrap_or_default(),
                false_alarm_dts: l
                    .false_alarms_dt_s
                    .iter()
                    .map(|d| num(*d))
                    .collect::<Vec<_>>()
                    .join(" "),
            }
        })
        .collect()
}

/// One row of `stress_blowups.csv`: one unstable run (a timeout leaves
/// body, value and limit empty).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct BlowupRow {
    /// Case name.
    pub case: String,
    /// Integrator name.
    pub integrator: &'static str,
    /// Step, s.
    pub dt_s: String,
    /// The detector that fired, or `timeout`.
    pub detector: &'static str,
    /// When, s.
    pub t_s: String,
    /// The body it names (commas replaced by `;`).
    pub body: String,
    /// The value it saw.
    pub value: String,
    /// The limit it crossed.
    pub limit: String,
}

/// `stress_blowups.csv`'s rows of one cell (no header).
pub(crate) fn blowup_csv_rows(result: &CaseResult) -> Vec<BlowupRow> {
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
            } => Some(BlowupRow {
                case: result.info.name.clone(),
                integrator: r.integrator.name(),
                dt_s: num(r.dt_s),
                detector,
                t_s: num(*t_s),
                body: body.replace(',', ";"),
                value: num(*value),
                limit: num(*limit),
            }),
            Verdict::Timeout { t_s } => Some(BlowupRow {
                case: result.info.name.clone(),
                integrator: r.integrator.name(),
                dt_s: num(r.dt_s),
                detector: "timeout",
                t_s: num(*t_s),
                body: String::new(),
                value: String::new(),
                limit: String::new(),
            }),
            Verdict::Stable => None,
        })
        .collect()
}

/// The run at a limit's first failing step.
pub(crate) fn first_failure<'a>(result: &'a CaseResult, limit: &Limit) -> Option<&'a RunRecord> {
    let dt = limit.first_unstable_dt_s?;
    result
        .runs
        .iter()
        .find(|r| r.integrator == limit.integrator && r.dt_s == dt && !r.verdict.is_stable())
}

/// Per-roller cost of one integrator across the roller-count series, at
/// one step every member ran stable.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RollerCost {
    /// The integrator.
    pub integrator: Integrator,
    /// The common step, s.
    pub dt_s: f64,
    /// (case, rollers, ns per roller-step), by roller count.
    pub points: Vec<(String, usize, f64)>,
}

impl RollerCost {
    /// Largest over smallest ns per roller-step.
    pub(crate) fn spread(&self) -> f64 {
        let ns = self.points.iter().map(|p| p.2);
        let max = ns.clone().fold(f64::NEG_INFINITY, f64::max);
        let min = ns.fold(f64::INFINITY, f64::min);
        if min > 0.0 { max / min } else { f64::NAN }
    }
}

/// Per-roller cost from the cells marked `cost_series`: for every
/// integrator they all ran, at the common stable step closest to 10 µs.
pub(crate) fn roller_costs(results: &[CaseResult]) -> Vec<RollerCost> {
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
    for &integrator in Integrator::ALL {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The header csv writes from a row type's field names.
    fn header_of<T: Serialize>(row: &T) -> String {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.serialize(row).expect("serializes");
        let bytes = w.into_inner().expect("flushes");
        let text = String::from_utf8(bytes).expect("UTF-8");
        text.lines().next().unwrap_or_default().to_owned()
    }

    #[test]
    fn row_fields_name_the_promised_columns() {
        let run = RunRow {
            case: "c".into(),
            rollers: 1,
            sprockets: 2,
            rpm: num(120.0),
            e: num(0.0),
            damping_ratio: num(0.0025),
            kg: num(1e9),
            profile: "circular",
            integrator: "rk4",
            dt_s: num(7.5e-6),
            stable: true,
            detector: "",
            wall_per_sim_s: "1.000000".into(),
        };
        assert_eq!(header_of(&run), CSV_HEADER);
        let limit = LimitRow {
            case: "c".into(),
            rollers: 1,
            sprockets: 2,
            profile: "real",
            integrator: "rk4",
            estimated_dt_s: String::new(),
            largest_stable_dt_s: String::new(),
            first_unstable_dt_s: String::new(),
            detector: "",
            blow_up_t_s: String::new(),
            wall_per_sim_s_at_limit: String::new(),
            false_alarm_dts: String::new(),
        };
        assert_eq!(header_of(&limit), LIMITS_CSV_HEADER);
        let blowup = BlowupRow {
            case: "c".into(),
            integrator: "rk4",
            dt_s: num(1e-3),
            detector: "timeout",
            t_s: num(0.5),
            body: String::new(),
            value: String::new(),
            limit: String::new(),
        };
        assert_eq!(header_of(&blowup), BLOWUPS_CSV_HEADER);
    }

    #[test]
    fn numbers_carry_no_float_noise() {
        assert_eq!(num(7.500000000000001e-6), "7.5e-6");
        assert_eq!(num(120.0), "120");
        assert_eq!(num(0.0025), "0.0025");
    }
}
