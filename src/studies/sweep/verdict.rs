//! Will the chain last at each speed of a sweep? The design checks of
//! each case's run summary (docs/design-checks.md) in one row per speed:
//! the static safety factor, the catalogue rating's margin, the fatigue
//! damage per hour and life; and the weakest speed by each.
//!
//! Pure functions of the cases' summaries: nothing here computes a check
//! (the summary's `rating` and `fatigue` blocks do) or writes a file.

use super::CaseOutcome;
use super::report::completed;
use crate::analysis::design::Life;

/// The design checks of one speed; a check the run has no data for is
/// `None` (a chain without a designation has no safety factor and no
/// fatigue count; a scene without a load has no margin).
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The driver's speed, rpm.
    pub rpm: f64,
    /// Tensile strength over the largest link force in the window.
    pub static_safety_factor: Option<f64>,
    /// Tensile strength over the largest segment's mean link force.
    pub mean_static_safety_factor: Option<f64>,
    /// The catalogue rating's design power over the run's transmitted
    /// power (below 1: overloaded by the catalogue's measure).
    pub rating_margin: Option<f64>,
    /// The rating's design power, W.
    pub design_power_w: Option<f64>,
    /// The run's transmitted (mean driver) power, W.
    pub transmitted_power_w: Option<f64>,
    /// Miner's damage per hour of operation at this speed.
    pub damage_per_hour: Option<f64>,
    /// The fatigue life at this speed alone.
    pub fatigue_life_h: Option<Life>,
    /// The fatigue limit over the largest counted cycle.
    pub fatigue_safety_factor: Option<f64>,
}

/// One [`Verdict`] per completed case, in speed order (a run-up's windows,
/// which have no run summary, and failed cases are left out).
pub fn verdicts(cases: &[CaseOutcome]) -> Vec<Verdict> {
    completed(cases)
        .into_iter()
        .filter_map(|c| {
            let s = c.summary.as_ref()?;
            let rating = s.rating.as_ref();
            let fatigue = s.fatigue.as_ref();
            Some(Verdict {
                rpm: c.rpm,
                static_safety_factor: rating.and_then(|r| r.static_safety_factor),
                mean_static_safety_factor: rating.and_then(|r| r.mean_static_safety_factor),
                rating_margin: rating.and_then(|r| r.margin),
                design_power_w: rating.map(|r| r.design_power_w),
                transmitted_power_w: rating.and_then(|r| r.transmitted_power_w),
                damage_per_hour: fatigue.map(|f| f.damage_per_hour),
                fatigue_life_h: fatigue.map(|f| f.life_h),
                fatigue_safety_factor: fatigue.and_then(|f| f.fatigue_safety_factor),
            })
        })
        .collect()
}

/// The weakest speed by one check.
#[derive(Clone, Debug, PartialEq)]
pub struct Weakest {
    /// What is compared (`smallest static safety factor`, …).
    pub check: &'static str,
    /// The speed, rpm.
    pub rpm: f64,
    /// Its value there.
    pub value: f64,
}

/// The weakest speed by each check some speed has: the smallest static
/// safety factor, the smallest rating margin, the smallest fatigue safety
/// factor and the largest damage per hour (only where some speed
/// accumulates damage). The first of equal speeds is kept.
pub fn weakest(verdicts: &[Verdict]) -> Vec<Weakest> {
    type Get = fn(&Verdict) -> Option<f64>;
    let checks: [(&'static str, Get, bool); 4] = [
        (
            "smallest static safety factor",
            |v| v.static_safety_factor,
            false,
        ),
        ("smallest rating margin", |v| v.rating_margin, false),
        (
            "smallest fatigue safety factor",
            |v| v.fatigue_safety_factor,
            false,
        ),
        (
            "largest fatigue damage per hour",
            |v| v.damage_per_hour.filter(|&d| d > 0.0),
            true,
        ),
    ];
    checks
        .iter()
        .filter_map(|&(check, get, largest)| {
            verdicts
                .iter()
                .filter_map(|v| get(v).filter(|x| x.is_finite()).map(|x| (v.rpm, x)))
                .reduce(|a, b| {
                    let better = if largest { b.1 > a.1 } else { b.1 < a.1 };
                    if better { b } else { a }
                })
                .map(|(rpm, value)| Weakest { check, rpm, value })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn verdict(rpm: f64, factor: f64, margin: Option<f64>, damage: f64) -> Verdict {
        Verdict {
            rpm,
            static_safety_factor: Some(factor),
            mean_static_safety_factor: Some(2.0 * factor),
            rating_margin: margin,
            design_power_w: Some(1000.0),
            transmitted_power_w: margin.map(|m| 1000.0 / m),
            damage_per_hour: Some(damage),
            fatigue_life_h: Some(Life::of_rate_per_hour(damage)),
            fatigue_safety_factor: Some(factor / 3.0),
        }
    }

    #[test]
    fn the_weakest_speed_is_found_per_check_and_no_damage_names_none() {
        let v = [
            verdict(100.0, 8.0, Some(0.9), 0.0),
            verdict(200.0, 5.0, Some(1.5), 0.0),
            verdict(300.0, 6.0, None, 0.0),
        ];
        let w = weakest(&v);
        let at = |check: &str| {
            w.iter()
                .find(|w| w.check == check)
                .map(|w| (w.rpm, w.value))
        };
        assert_eq!(at("smallest static safety factor"), Some((200.0, 5.0)));
        assert_eq!(at("smallest rating margin"), Some((100.0, 0.9)));
        assert_eq!(
            at("smallest fatigue safety factor"),
            Some((200.0, 5.0 / 3.0))
        );
        assert_eq!(at("largest fatigue damage per hour"), None);
        let damaged = [
            verdict(100.0, 8.0, None, 1e-5),
            verdict(200.0, 8.0, None, 3e-4),
        ];
        let w = weakest(&damaged);
        assert_eq!(w.len(), 3, "{w:?}");
        assert_eq!(
            w.iter().find(|w| w.check.contains("damage")).map(|w| w.rpm),
            Some(200.0)
        );
    }
}
