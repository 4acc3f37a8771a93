//! The statistics window: which stretch of a run the summary's statistics
//! cover, chosen before the run so that its means can be counted every step
//! ([`super::Signals`]) and its power flow ([`crate::sim::PowerLedger`])
//! from the same instant.
//!
//! - **The default** is the last [`DEFAULT_WINDOW_S`] of the run, started no
//!   earlier than the end of the scene's last ramp ([`last_ramp`]: a driver's
//!   speed ramp or a governed driver's target ramp, a run-up, a load ramp).
//!   No settling time is added after the ramp: a window mean is moved by a
//!   transient only through the momentum it changes over the window (a
//!   sprocket's torque mean by J Δω / T), which a ringing drive keeps
//!   bounded; a slow settling (a tensioner filling, a governor's integral,
//!   the strands' vibration building up) has no time scale the scene tells,
//!   and the stationarity test flags it from the window's own samples
//!   (docs/model.md, "Statistics window").
//! - **A chosen length** W is the last W seconds, wherever the ramps end.
//! - A run too short for any window after its ramps keeps the last
//!   [`DEFAULT_WINDOW_S`] (or the whole run) and its summary carries a
//!   warning naming the ramp ([`super::RunSummary::warnings`]), as does a
//!   chosen window that reaches into a ramp: the run still gives its
//!   transient (a run-up is often the point of the run), but no mean of it
//!   reads as a steady state.
//!
//! It does not run anything, nor compute statistics ([`super::RunSummary`]).

use crate::scene::Scene;
use crate::sim::Simulation;

use super::Signals;

/// Length of the statistics window unless chosen, s.
pub(crate) const DEFAULT_WINDOW_S: f64 = 1.0;

/// Times closer than this are the same instant (a window "after" a ramp
/// that ends a rounding error after its start), s.
const SAME_INSTANT_S: f64 = 1e-9;

/// The end of a scene's last ramp.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Ramp {
    /// What ramps, for people: "the driver's speed ramp of sprocket 1
    /// (crankshaft)".
    pub what: String,
    /// When it ends, s.
    pub end_s: f64,
}

/// The ramp of `scene` that ends last, if any ends after t = 0: the drivers'
/// speed ramps (a governed driver's target), their run-ups, the loads' ramps.
pub(crate) fn last_ramp(scene: &Scene) -> Option<Ramp> {
    let mut last: Option<Ramp> = None;
    let mut consider = |what: String, end_s: f64| {
        if end_s > 0.0 && last.as_ref().is_none_or(|r| end_s > r.end_s) {
            last = Some(Ramp { what, end_s });
        }
    };
    for (i, sp) in scene.sprockets.iter().enumerate() {
        let name = format!("sprocket {} ({})", i + 1, sp.name);
        if let Some(law) = sp.speed_law() {
            let kind = if sp.excitation.governor.is_some() {
                "governor's target ramp"
            } else {
                "speed ramp"
            };
            consider(format!("the {kind} of {name}"), law.ramp_s);
            if let Some(r) = law.run_up {
                consider(format!("the run-up of {name}"), r.start_s + r.duration_s);
            }
        }
        consider(format!("the load ramp of {name}"), sp.load_ramp_s());
    }
    last
}

/// Why a chosen window cannot be had.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WindowError {
    /// Not a positive number.
    #[error("the statistics window must be a number of seconds > 0, got {0}")]
    NotPositive(f64),
    /// Longer than the run.
    #[error(
        "the statistics window ({window_s} s) must not be longer than the run (solver.duration_s = {duration_s} s)"
    )]
    LongerThanRun {
        /// The window asked for, s.
        window_s: f64,
        /// The run's duration, s.
        duration_s: f64,
    },
}

/// The statistics window of a run, known before it starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StatsWindow {
    start_s: f64,
    end_s: f64,
}

impl StatsWindow {
    /// The window of a run of `scene` to its `solver.duration_s`: the last
    /// `window_s` seconds, or with `None` the default (module docs).
    ///
    /// # Errors
    ///
    /// A chosen length that is not a positive number or is longer than the run.
    pub fn of(scene: &Scene, window_s: Option<f64>) -> Result<Self, WindowError> {
        let end_s = scene.solver.duration_s;
        let start_s = match window_s {
            Some(w) => {
                if !(w.is_finite() && w > 0.0) {
                    return Err(WindowError::NotPositive(w));
                }
                if w > end_s * (1.0 + 1e-12) {
                    return Err(WindowError::LongerThanRun {
                        window_s: w,
                        duration_s: end_s,
                    });
                }
                (end_s - w).max(0.0)
            }
            None => default_start_s(scene, end_s),
        };
        Ok(Self { start_s, end_s })
    }

    /// Where the window starts, s: its statistics count the steps from the
    /// first that ends at or after it.
    pub fn start_s(&self) -> f64 {
        self.start_s
    }

    /// Its length, s.
    pub fn length_s(&self) -> f64 {
        self.end_s - self.start_s
    }

    /// Prepares `sim` and its signals for a run summarised over this window:
    /// the power flow counted from its start ([`Simulation::track_power`]),
    /// the joints' sliding where the scene asks for the wear check
    /// ([`Simulation::track_sliding`]), and signals sampled at `rate_hz` that
    /// count every step from its start and keep only its rows
    /// ([`Signals::keep_window`]), with every link's force counted for the
    /// fatigue check where the scene has the chain data it needs
    /// ([`Signals::count_fatigue_of`]). Give the signals
    /// (or an observer that hands them every step) to [`Simulation::run`],
    /// then [`super::RunSummary::of_run_in`] summarises.
    pub fn observe(&self, sim: &mut Simulation, rate_hz: f64) -> Signals {
        sim.track_power(self.start_s);
        // The wear check's sliding, where the scene asks for it.
        if sim.scene.checks.wear.is_some() {
            sim.track_sliding(self.start_s);
        }
        let mut signals = Signals::new(&sim.model, rate_hz, self.start_s);
        signals.keep_window(self.length_s());
        signals.count_fatigue_of(&sim.scene);
        signals
    }
}

/// The default window's start in a run to `end_s`: the last
/// [`DEFAULT_WINDOW_S`], not before the last ramp's end; where the ramps
/// leave no window, the last [`DEFAULT_WINDOW_S`] (or the whole run).
pub(crate) fn default_start_s(scene: &Scene, end_s: f64) -> f64 {
    let last = (end_s - DEFAULT_WINDOW_S).max(0.0);
    match last_ramp(scene) {
        Some(r) if r.end_s > last && r.end_s < end_s - SAME_INSTANT_S => r.end_s,
        _ => last,
    }
}

/// Whether a window from `start_s` holds part of `ramp`.
pub(crate) fn holds(start_s: f64, ramp: &Ramp) -> bool {
    start_s < ramp.end_s - SAME_INSTANT_S
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::L60MC_TOML;

    fn paper(duration_s: f64) -> Scene {
        Scene::from_toml(
            &L60MC_TOML.replace("duration_s = 10.0", &format!("duration_s = {duration_s}")),
        )
        .expect("valid")
    }

    #[test]
    fn the_default_window_is_the_last_second_after_the_ramp() {
        // The paper's drive ramps to speed over 1 s.
        let ramp = last_ramp(&paper(10.0)).expect("a ramp");
        assert_eq!(ramp.end_s, 1.0);
        assert!(
            ramp.what.contains("speed ramp of sprocket 1"),
            "{}",
            ramp.what
        );
        let w = StatsWindow::of(&paper(10.0), None).expect("window");
        assert_eq!((w.start_s(), w.length_s()), (9.0, 1.0));
        // 1.5 s: the last second would start at 0.5 s, inside the ramp.
        let w = StatsWindow::of(&paper(1.5), None).expect("window");
        assert_eq!((w.start_s(), w.length_s()), (1.0, 0.5));
    }

    #[test]
    fn a_run_that_ends_with_its_ramp_keeps_the_last_second() {
        let w = StatsWindow::of(&paper(1.0), None).expect("window");
        assert_eq!((w.start_s(), w.length_s()), (0.0, 1.0));
        assert!(holds(w.start_s(), &last_ramp(&paper(1.0)).expect("ramp")));
    }

    #[test]
    fn a_chosen_window_is_the_last_seconds_and_checked() {
        let w = StatsWindow::of(&paper(1.5), Some(1.5)).expect("window");
        assert_eq!((w.start_s(), w.length_s()), (0.0, 1.5));
        assert_eq!(
            StatsWindow::of(&paper(1.5), Some(0.0)),
            Err(WindowError::NotPositive(0.0))
        );
        assert!(matches!(
            StatsWindow::of(&paper(1.5), Some(2.0)),
            Err(WindowError::LongerThanRun { .. })
        ));
        assert!(StatsWindow::of(&paper(1.5), Some(f64::NAN)).is_err());
    }
}
