//! Blow-up detection (docs/model.md, “Blow-up detection”): the limits, the
//! growth detector's memory, and the checks run after every step.

use super::SimError;
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::Scene;

/// Blow-up thresholds (docs/model.md, “Blow-up detection”): the scene's
/// `[solver.limits]` with their defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BlowUpLimits {
    /// Largest penetration, m (default: the roller radius, the roller's
    /// centre on the tooth's surface).
    pub max_penetration_m: f64,
    /// Largest |link length − rest length|, m (default: 10 % of the pitch).
    pub max_stretch_m: f64,
    /// Growth of the largest link stretch within [`Self::growth_steps`] steps
    /// that no dynamics of the drive explains (default: 100).
    pub growth_factor: f64,
    /// The growth detector's window, steps (default: 20).
    pub growth_steps: u32,
    /// Below this stretch growth is not judged, m: the static stretch
    /// (pretension / K), or 10⁻⁴ of the pitch if larger.
    pub growth_floor_m: f64,
}

impl BlowUpLimits {
    /// The scene's limits.
    pub(crate) fn for_scene(scene: &Scene) -> Self {
        let l = scene.solver.limits;
        Self {
            max_penetration_m: l.max_penetration_m,
            max_stretch_m: l.max_stretch_m,
            growth_factor: l.growth_factor,
            growth_steps: l.growth_steps,
            growth_floor_m: (scene.chain.pretension_n / scene.chain.stiffness_n_m)
                .max(1e-4 * scene.chain.pitch_m),
        }
    }
}

/// The growth detector's memory: the largest link stretch of the last
/// steps, in a ring allocated once.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub(crate) struct GrowthWatch {
    ring: Vec<f64>,
    next: usize,
    filled: usize,
}

/// How many past values a blow-up message quotes.
const HISTORY_SHOWN: usize = 8;

impl GrowthWatch {
    /// A watch over `steps` steps.
    pub(crate) fn new(steps: u32) -> Self {
        let len = steps as usize + 1;
        Self {
            ring: vec![0.0; len],
            next: 0,
            filled: 0,
        }
    }

    /// Records this step's largest stretch; returns the value `steps` steps
    /// ago (0 before that many steps: growth is then judged against the
    /// floor, the static stretch, so a blow-up in the first steps is caught
    /// too).
    fn push(&mut self, stretch_m: f64) -> f64 {
        let len = self.ring.len();
        self.ring[self.next] = stretch_m;
        self.next = (self.next + 1) % len;
        self.filled = (self.filled + 1).min(len);
        // After the write, `next` indexes the oldest value of a full ring.
        if self.filled == len {
            self.ring[self.next]
        } else {
            0.0
        }
    }

    /// The last values, oldest first, m.
    pub(crate) fn recent(&self) -> Vec<f64> {
        let len = self.ring.len();
        let n = self.filled.min(HISTORY_SHOWN);
        (0..n)
            .map(|k| self.ring[(self.next + len - n + k) % len])
            .collect()
    }
}

fn history_text(history: &[f64]) -> String {
    if history.is_empty() {
        return String::new();
    }
    let values: Vec<String> = history.iter().map(|v| format!("{v:.3e}")).collect();
    format!(
        "; largest link stretch over the last {} steps: [{}] m",
        history.len(),
        values.join(", ")
    )
}

/// Which detector fired.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Detector {
    /// A non-finite number in the state or the forces.
    NonFinite,
    /// A roller sank deeper than the limit into a tooth.
    Penetration,
    /// A link stretched or shrank beyond the limit.
    Stretch,
    /// The largest link stretch grew faster than the dynamics explains.
    Growth,
    /// The adaptive scheme's step fell below its minimum.
    StepSize,
}

impl Detector {
    /// Name for messages and outputs.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::NonFinite => "non-finite",
            Self::Penetration => "penetration",
            Self::Stretch => "link-stretch",
            Self::Growth => "stretch-growth",
            Self::StepSize => "step-size",
        }
    }

    /// What else than a too large step could have made it fire.
    fn causes(self) -> &'static str {
        match self {
            Self::NonFinite => {
                "a step above the stability limit (reduce solver.dt_s, or set it to \"auto\"), or a force element or load that returned NaN"
            }
            Self::Penetration => {
                "a step above the stability limit, or a contact too soft for the load (contact.stiffness); if the depth is real, raise solver.limits.max_penetration_m"
            }
            Self::Stretch => {
                "a step above the stability limit, or links too soft for the load (chain.stiffness_n_m); if the stretch is real, raise solver.limits.max_stretch_m"
            }
            Self::Growth => {
                "a step above the stability limit (reduce solver.dt_s, or set it to \"auto\"); an impact that really loads the chain this fast would need a larger solver.limits.growth_factor"
            }
            Self::StepSize => {
                "a stiff event the adaptive scheme cannot resolve (loosen solver.tolerance)"
            }
        }
    }
}

/// Checks the blow-up detectors against the last force evaluation at `state`:
/// non-finite values, the penetration and stretch ceilings. The growth
/// detector needs a history: [`super::Simulation::run`] keeps one.
///
/// A detector that fires names the body where its quantity is largest: the
/// roller that penetrates a tooth deepest, the link stretched (or
/// compressed) most.
pub(crate) fn check_blow_up(
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
    limits: &BlowUpLimits,
) -> Result<(), SimError> {
    check_with(model, state, forces, limits, None)
}

/// [`check_blow_up`], and the growth detector when `watch` is given (it
/// records this step's stretch).
pub(super) fn check_with(
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
    limits: &BlowUpLimits,
    mut watch: Option<&mut GrowthWatch>,
) -> Result<(), SimError> {
    let f = forces.output();
    let past = watch.as_mut().map(|w| w.push(f.max_stretch_m));
    let watch = watch.as_deref();
    // The history is read only when a detector fires: no allocation per step.
    let fail = |detector: Detector, body: String, value: f64, limit: f64| {
        let history = watch.map(GrowthWatch::recent).unwrap_or_default();
        Err(SimError::BlowUp {
            t_s: state.t_s,
            detector: detector.name(),
            body,
            value,
            limit,
            detail: format!(
                "{}; possible causes: {}",
                history_text(&history),
                detector.causes()
            ),
        })
    };
    let nan_body = || {
        let roller =
            (0..state.rollers()).find(|&i| !(state.x[i].is_finite() && state.y[i].is_finite()));
        let body =
            (0..state.q.len()).find(|&k| !(state.q[k].is_finite() && state.u[k].is_finite()));
        let scalar = state.z.iter().position(|z| !z.is_finite());
        match (roller, body, scalar) {
            (Some(i), _, _) => format!("roller {i}"),
            (None, Some(k), _) => model.bodies[k].name.clone(),
            (None, None, Some(k)) => model.scalars[k].name.clone(),
            (None, None, None) => "the chain".to_owned(),
        }
    };
    let extras_finite = state
        .q
        .iter()
        .chain(&state.u)
        .chain(&state.z)
        .all(|v| v.is_finite());
    if !f.max_stretch_m.is_finite() || !f.max_penetration_m.is_finite() || !extras_finite {
        return fail(Detector::NonFinite, nan_body(), f64::NAN, 0.0);
    }
    if f.max_penetration_m > limits.max_penetration_m {
        let body = forces
            .contact
            .deepest_roller(model, state)
            .map_or_else(|| "a roller".to_owned(), |(i, _)| format!("roller {i}"));
        return fail(
            Detector::Penetration,
            body,
            f.max_penetration_m,
            limits.max_penetration_m,
        );
    }
    let most_stretched = || {
        let stretch = forces.links.stretch();
        let i = (0..stretch.len())
            .max_by(|&a, &b| stretch[a].abs().total_cmp(&stretch[b].abs()))
            .unwrap_or(0);
        format!("link {i}")
    };
    if f.max_stretch_m > limits.max_stretch_m {
        return fail(
            Detector::Stretch,
            most_stretched(),
            f.max_stretch_m,
            limits.max_stretch_m,
        );
    }
    if let Some(past) = past {
        // Growth relative to the static stretch at least: a slack chain's
        // tiny stretches may grow by any factor.
        let growth = f.max_stretch_m / past.max(limits.growth_floor_m);
        if growth >= limits.growth_factor {
            return fail(
                Detector::Growth,
                most_stretched(),
                growth,
                limits.growth_factor,
            );
        }
    }
    Ok(())
}
