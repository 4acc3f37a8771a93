//! The jump margin: where, along one scene value (a tensioner's preload, the
//! chain's pretension, its elongation), a drive changes from jumping teeth to
//! running clean over a given time. A roller riding a tooth's tip counts as
//! a jump here (docs/design-checks.md, "The jump margin"). A bracketing search over runs: both ends
//! of the range are run first, one must jump and the other not; then each
//! round runs `jobs` values evenly spaced inside the bracket, in parallel on
//! the work queue, and keeps the two neighbours where the outcome changes,
//! until the bracket is narrower than the tolerance.
//!
//! The answer is conservative where the outcome is not monotone along the
//! value: the bracket ends at the jumping value furthest from the jumping
//! end, so every value tried beyond the bracket ran clean; a clean value
//! tried inside the jumping side is reported (`monotone = false`).
//!
//! What it does not do: build or run a simulation (the caller's `run`
//! closure does: `chaindrive jump-margin`), or say anything of values it did
//! not try.

use super::queue::WorkQueue;

/// What one run did.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub(crate) struct Outcome {
    /// The first tooth jump's time, s; `None`: no jump.
    pub first_jump_s: Option<f64>,
    /// The first time a roller rode a tooth's tip, s; `None`: none did.
    pub first_tip_ride_s: Option<f64>,
}

impl Outcome {
    /// A run that jumped at `t_s` and rode no tip.
    #[cfg(test)]
    fn jump_at(t_s: f64) -> Self {
        Self {
            first_jump_s: Some(t_s),
            first_tip_ride_s: None,
        }
    }
}

/// What one run at one value did.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub(crate) struct Probe {
    /// The value tried.
    pub value: f64,
    /// What the run did.
    #[serde(flatten)]
    pub outcome: Outcome,
}

impl Probe {
    /// Whether the run jumped a tooth or rode a tip: not clean.
    pub(crate) fn jumped(&self) -> bool {
        self.outcome.first_jump_s.is_some() || self.outcome.first_tip_ride_s.is_some()
    }
}

/// The search's answer.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub(crate) struct Margin {
    /// The value tried nearest the boundary that still jumped.
    pub jumping: f64,
    /// The value tried nearest the boundary that ran clean.
    pub clean: f64,
    /// Whether the low end of the range is the jumping one (a force that
    /// must be large enough) or the high end (an elongation that must stay
    /// small enough).
    pub low_end_jumps: bool,
    /// False where a value on the jumping side of the bracket ran clean.
    pub monotone: bool,
    /// Every run, in the order of their values.
    pub probes: Vec<Probe>,
}

/// Why the search has no answer.
#[derive(Debug, thiserror::Error)]
pub(crate) enum MarginError {
    /// Both ends jump, or neither.
    #[error(
        "no boundary in the range: the run at {from} {} and the run at {to} {}; allowed: a range whose one end jumps and whose other runs clean (widen it)",
        said(*from_jumps),
        said(*to_jumps)
    )]
    NoBoundary {
        from: f64,
        to: f64,
        from_jumps: bool,
        to_jumps: bool,
    },
    /// A run failed.
    #[error("the run at {value}: {message}")]
    Run { value: f64, message: String },
    /// A bad setting.
    #[error("{0}")]
    Setting(String),
}

fn said(jumps: bool) -> &'static str {
    if jumps { "jumped" } else { "ran clean" }
}

/// The range and how finely to search it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Range {
    pub from: f64,
    pub to: f64,
    /// Stop once the bracket is at most this wide (same unit as the value).
    pub tolerance: f64,
    /// Runs at once (and values per round).
    pub jobs: usize,
}

impl Range {
    /// Refuses a range that is not two finite numbers, the first the
    /// smaller, or a tolerance that is not a finite number > 0.
    pub(crate) fn check(&self) -> Result<(), MarginError> {
        let Self {
            from,
            to,
            tolerance,
            ..
        } = *self;
        if !(from.is_finite() && to.is_finite() && from < to) {
            return Err(MarginError::Setting(format!(
                "--from {from} --to {to}: allowed: two finite numbers, the first the smaller"
            )));
        }
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(MarginError::Setting(format!(
                "--tolerance {tolerance}: allowed: a number > 0"
            )));
        }
        Ok(())
    }
}

/// Searches `range` with `run(value)`: what the run at that value did
/// (module docs). `progress` sees each run as it finishes.
pub(crate) fn search(
    range: Range,
    run: impl Fn(f64) -> Result<Outcome, String> + Sync,
    mut progress: impl FnMut(&Probe),
) -> Result<Margin, MarginError> {
    range.check()?;
    let Range {
        from,
        to,
        tolerance,
        jobs,
    } = range;
    let mut probes = Vec::new();
    let mut batch =
        |values: Vec<f64>, probes: &mut Vec<Probe>| -> Result<Vec<Probe>, MarginError> {
            let results = WorkQueue::new(&values).threads(jobs).try_run(
                |_, &value| Some(run(value).map(|outcome| Probe { value, outcome })),
                |k, r| match r {
                    Ok(p) => {
                        progress(p);
                        Ok(())
                    }
                    Err(message) => Err(MarginError::Run {
                        value: values[k],
                        message: message.clone(),
                    }),
                },
            )?;
            let done: Vec<Probe> = results
                .into_iter()
                .flatten()
                .filter_map(Result::ok)
                .collect();
            probes.extend(done.iter().copied());
            Ok(done)
        };
    let ends = batch(vec![from, to], &mut probes)?;
    let (low, high) = match ends.as_slice() {
        [low, high] => (*low, *high),
        _ => return Err(MarginError::Setting("a run did not finish".to_owned())),
    };
    if low.jumped() == high.jumped() {
        return Err(MarginError::NoBoundary {
            from,
            to,
            from_jumps: low.jumped(),
            to_jumps: high.jumped(),
        });
    }
    let low_end_jumps = low.jumped();
    // `a` jumps, `b` runs clean; they may be either way round.
    let (mut a, mut b) = if low_end_jumps {
        (from, to)
    } else {
        (to, from)
    };
    let mut monotone = true;
    while (b - a).abs() > tolerance {
        let n = jobs.max(1);
        let values: Vec<f64> = (1..=n)
            .map(|i| a + (b - a) * i as f64 / (n + 1) as f64)
            .collect();
        let tried = batch(values, &mut probes)?;
        // From the jumping end towards the clean one: the last that jumped.
        let last = tried.iter().rposition(Probe::jumped);
        if let Some(j) = last {
            monotone &= tried[..j].iter().all(Probe::jumped);
            a = tried[j].value;
        }
        b = tried.get(last.map_or(0, |j| j + 1)).map_or(b, |p| p.value);
    }
    probes.sort_by(|p, q| p.value.total_cmp(&q.value));
    Ok(Margin {
        jumping: a,
        clean: b,
        low_end_jumps,
        monotone,
        probes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A drive that jumps below `threshold` and runs clean at or above it.
    fn below(threshold: f64) -> impl Fn(f64) -> Result<Outcome, String> + Sync {
        move |v| Ok(jumps_if(v < threshold))
    }

    fn jumps_if(jumps: bool) -> Outcome {
        if jumps {
            Outcome::jump_at(0.1)
        } else {
            Outcome::default()
        }
    }

    #[test]
    fn the_bracket_holds_the_threshold_and_is_within_the_tolerance() {
        for jobs in [1, 2, 3] {
            let range = Range {
                from: 0.0,
                to: 1000.0,
                tolerance: 5.0,
                jobs,
            };
            let m = search(range, below(437.0), |_| {}).expect("a boundary");
            assert!(m.low_end_jumps && m.monotone);
            assert!(m.jumping < 437.0 && 437.0 <= m.clean, "{m:?}");
            assert!(m.clean - m.jumping <= 5.0, "{m:?}");
            // Each round cuts the bracket by jobs + 1: 1000/(j+1)^r <= 5.
            let rounds = (200.0_f64.ln() / ((jobs + 1) as f64).ln()).ceil() as usize;
            assert!(m.probes.len() <= 2 + rounds * jobs, "{}", m.probes.len());
        }
    }

    #[test]
    fn a_drive_that_jumps_at_the_high_end_is_bracketed_the_other_way_round() {
        // An elongation: clean below 0.8 %, jumping above.
        let range = Range {
            from: 0.0,
            to: 2.0,
            tolerance: 0.01,
            jobs: 2,
        };
        let m = search(range, |e| Ok(jumps_if(e > 0.8)), |_| {}).expect("a boundary");
        assert!(!m.low_end_jumps);
        assert!(m.clean <= 0.8 && 0.8 < m.jumping && m.jumping - m.clean <= 0.01);
    }

    #[test]
    fn a_clean_island_on_the_jumping_side_is_reported_and_the_answer_stays_above_the_last_jump() {
        // Clean in (200, 300) as well as from 600 on.
        let run = |v: f64| Ok(jumps_if(!(v > 200.0 && v < 300.0) && v < 600.0));
        let range = Range {
            from: 0.0,
            to: 1000.0,
            tolerance: 1.0,
            jobs: 3,
        };
        let m = search(range, run, |_| {}).expect("a boundary");
        assert!(!m.monotone, "{m:?}");
        assert!(m.jumping < 600.0 && 600.0 <= m.clean, "{m:?}");
    }

    #[test]
    fn a_run_that_rides_a_tip_without_jumping_counts_as_jumping() {
        // Rides the tips below 300 without ever jumping a tooth.
        let run = |v: f64| {
            Ok(Outcome {
                first_jump_s: None,
                first_tip_ride_s: (v < 300.0).then_some(0.05),
            })
        };
        let range = Range {
            from: 0.0,
            to: 1000.0,
            tolerance: 10.0,
            jobs: 2,
        };
        let m = search(range, run, |_| {}).expect("a boundary");
        assert!(
            m.low_end_jumps && m.jumping < 300.0 && 300.0 <= m.clean,
            "{m:?}"
        );
    }

    #[test]
    fn no_boundary_and_bad_ranges_are_errors_that_say_so() {
        let range = Range {
            from: 0.0,
            to: 10.0,
            tolerance: 1.0,
            jobs: 1,
        };
        let e = search(range, below(20.0), |_| {}).expect_err("both jump");
        assert!(
            e.to_string()
                .contains("the run at 0 jumped and the run at 10 jumped"),
            "{e}"
        );
        let bad = Range { from: 5.0, ..range };
        let bad = Range { to: 1.0, ..bad };
        assert!(search(bad, below(3.0), |_| {}).is_err());
        let e = search(range, |_| Err("blew up".to_owned()), |_| {}).expect_err("fails");
        assert!(e.to_string().contains("blew up"), "{e}");
    }
}
