//! Run time against error: every integrator over a ladder of steps (or
//! tolerances) on a short horizon, against a reference solution.
//!
//! # The measure
//!
//! All runs start from one *warm* state: the scene run with its own settings
//! through the driver's ramp (`warmup_s`), so the horizon sees the drive at
//! speed — polygonal action, impacts, engagement. From there each method
//! integrates `horizon_s`, sampling on a fixed grid (`grid_s`, a multiple of
//! every fixed step tried):
//! - the free sprockets' speeds,
//! - the force of one link,
//! - the contact force of one roller.
//!
//! Unless chosen, the link is the one whose force varies most over the
//! reference run, and the roller the one that engages and leaves a sprocket
//! most often in it (a roller seated all along would test little).
//!
//! The error of a run is the largest, over those signals, of the relative
//! RMS difference to the reference on the grid:
//! `sqrt(Σ (s − s_ref)²) / sqrt(Σ s_ref²)` (the sprocket speeds as one signal).
//!
//! # The reference
//!
//! Dormand–Prince 5(4) at a tight tolerance, confirmed by classical RK4 at a
//! small step: their mutual error is reported and must lie well below every
//! error in the table ([`WorkPrecision::reference_agreement`]).
//!
//! # The horizon
//!
//! Chain drives are chaotic over long times (impacts amplify small
//! differences), so errors over a long horizon measure that growth, not the
//! integrator. [`WorkPrecision::perturbation_growth`] shows the horizon is
//! short enough: the reference run repeated with one roller moved by 1 nm
//! differs from the reference by a relative RMS that stays far below the
//! errors studied.

use std::time::Instant;

use super::ladder::{Ladder, LadderError, LadderRun, Rung, Setting, warm};
use super::queue::WorkQueue;
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::{Integrator, Scene};
use crate::sim::{BlowUpLimits, Integration, SimError, check_blow_up};

/// What to study.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Time run with the scene's own integrator before the horizon, s.
    pub warmup_s: f64,
    /// The horizon, s.
    pub horizon_s: f64,
    /// Sample grid step, s.
    pub grid_s: f64,
    /// The link whose force is compared (`None`: chosen from the reference).
    pub link: Option<usize>,
    /// The roller whose contact force is compared (`None`: chosen from the reference).
    pub roller: Option<usize>,
    /// Methods and their settings.
    pub ladder: Ladder,
    /// Reference: the adaptive scheme's tolerance.
    pub reference_tolerance: f64,
    /// Check of the reference: RK4's step, s.
    pub reference_rk4_step_s: f64,
}

impl Settings {
    /// The default study for a scene: every scheme over a ladder of steps
    /// from 1 µs up to past the explicit limits.
    pub fn default_for(horizon_s: f64) -> Self {
        Self {
            warmup_s: 1.2,
            horizon_s,
            grid_s: 2e-4,
            link: None,
            roller: None,
            ladder: Ladder::every_scheme(
                &[1e-6, 2e-6, 4e-6, 5e-6, 1e-5, 2e-5, 2.5e-5, 4e-5, 5e-5],
                &[1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4],
            ),
            reference_tolerance: 1e-6,
            reference_rk4_step_s: 5e-7,
        }
    }
}

/// The sampled signals of one run (grid-point-major).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridSignals {
    /// Free sprockets' speeds, all of them per grid point, rad/s.
    pub omega_rad_s: Vec<f64>,
    /// Every link's force per grid point, N.
    pub link_force_n: Vec<f64>,
    /// Every roller's contact force per grid point, N.
    pub contact_force_n: Vec<f64>,
    /// Rollers (= links).
    pub rollers: usize,
}

/// Which link and roller the error compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Probe {
    /// Link index.
    pub link: usize,
    /// Roller index.
    pub roller: usize,
}

impl GridSignals {
    fn column(values: &[f64], stride: usize, index: usize) -> impl Iterator<Item = f64> + '_ {
        values.iter().skip(index).step_by(stride.max(1)).copied()
    }

    /// The chosen link's force over the grid.
    pub fn link(&self, link: usize) -> Vec<f64> {
        Self::column(&self.link_force_n, self.rollers, link).collect()
    }

    /// The chosen roller's contact force over the grid.
    pub fn contact(&self, roller: usize) -> Vec<f64> {
        Self::column(&self.contact_force_n, self.rollers, roller).collect()
    }

    /// The probe a reference run suggests: the link whose force varies most,
    /// the roller whose contact starts or ends most often (ties: the larger
    /// mean contact force).
    pub fn suggest_probe(&self) -> Probe {
        let n = self.rollers.max(1);
        let var = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len().max(1) as f64;
            v.iter().map(|x| (x - m) * (x - m)).sum::<f64>()
        };
        let link = (0..n)
            .max_by(|&a, &b| var(&self.link(a)).total_cmp(&var(&self.link(b))))
            .unwrap_or(0);
        let score = |r: usize| {
            let c = self.contact(r);
            let changes = c
                .windows(2)
                .filter(|w| (w[0] > 0.0) != (w[1] > 0.0))
                .count();
            (changes, c.iter().sum::<f64>())
        };
        let roller = (0..n)
            .max_by(|&a, &b| {
                let (sa, sb) = (score(a), score(b));
                sa.0.cmp(&sb.0).then(sa.1.total_cmp(&sb.1))
            })
            .unwrap_or(0);
        Probe { link, roller }
    }

    /// Relative RMS differences of the three signals to `reference`, the largest.
    pub fn error_against(&self, reference: &Self, probe: Probe) -> f64 {
        let [a, b, c] = self.errors_against(reference, probe);
        a.max(b).max(c)
    }

    /// Relative RMS differences of the sprocket speeds, the link force and
    /// the contact force to `reference`.
    pub fn errors_against(&self, reference: &Self, probe: Probe) -> [f64; 3] {
        fn rel(a: &[f64], b: &[f64]) -> f64 {
            if a.len() != b.len() {
                return f64::INFINITY;
            }
            let (mut num, mut den) = (0.0, 0.0);
            for (x, r) in a.iter().zip(b) {
                num += (x - r) * (x - r);
                den += r * r;
            }
            if den > 0.0 {
                (num / den).sqrt()
            } else {
                num.sqrt()
            }
        }
        [
            rel(&self.omega_rad_s, &reference.omega_rad_s),
            rel(&self.link(probe.link), &reference.link(probe.link)),
            rel(
                &self.contact(probe.roller),
                &reference.contact(probe.roller),
            ),
        ]
    }
}

/// The warm start every run begins from.
#[derive(Clone, Debug)]
pub struct Start {
    /// The scene.
    pub scene: Scene,
    /// The model.
    pub model: DriveModel,
    /// The state at the horizon's start.
    pub state: DriveState,
    /// Forces at it, with the contact memory.
    pub forces: ForceGenerator,
    /// Blow-up limits.
    pub limits: BlowUpLimits,
}

impl Start {
    /// Builds the scene, settles it and runs `warmup_s` with its own
    /// settings ([`warm`]).
    ///
    /// # Errors
    ///
    /// The drive cannot be laid out or settled, or the warm-up blows up.
    pub fn warm(scene: &Scene, warmup_s: f64) -> Result<Self, SimError> {
        let sim = warm(scene, warmup_s)?;
        let mut forces = sim.forces.clone();
        // GridSignals compare from the horizon's start: forget nothing, but
        // re-evaluate so every method starts from identical buffers.
        forces.evaluate(&sim.model, &sim.state);
        Ok(Self {
            scene: sim.scene.clone(),
            model: sim.model.clone(),
            state: sim.state.clone(),
            forces,
            limits: sim.limits,
        })
    }
}

/// One run of one method: the sampled signals, or why it stopped (its
/// wall time is the integration's).
pub type Run = LadderRun<GridSignals>;

/// Integrates `horizon_s` from `start` with one method.
pub fn integrate(start: &Start, rung: Rung, settings: &Settings) -> Run {
    let model = &start.model;
    let mut state = start.state.clone();
    let mut forces = start.forces.clone();
    let dt = rung.setting.step_s(settings.grid_s);
    let tolerance = match rung.setting {
        Setting::Step(_) => start.scene.solver.tolerance,
        Setting::Tolerance(tol) => tol,
    };
    let mut integration = Integration::new(
        rung.integrator,
        tolerance,
        model,
        &state,
        &mut forces,
        start.scene.chain.pretension_n / model.stiffness_n_m,
    );
    let grid_points = (settings.horizon_s / settings.grid_s).round() as usize;
    let per_grid = (settings.grid_s / dt).round().max(1.0) as usize;
    let mut signals = GridSignals {
        rollers: state.rollers(),
        ..GridSignals::default()
    };
    let t0 = state.t_s;
    let started = Instant::now();
    let mut failure = None;
    'grid: for g in 1..=grid_points {
        for _ in 0..per_grid {
            let stepped = integration
                .advance(model, &mut state, &mut forces, dt)
                .and_then(|()| check_blow_up(model, &state, &forces, &start.limits));
            if let Err(e) = stepped {
                failure = Some(e.to_string());
                break 'grid;
            }
        }
        state.t_s = t0 + g as f64 * settings.grid_s;
        for (s, sp) in model.sprockets.iter().enumerate() {
            if sp.speed_law.is_none() {
                signals.omega_rad_s.push(state.omega[s]);
            }
        }
        signals
            .link_force_n
            .extend_from_slice(&forces.output().link_force);
        signals
            .contact_force_n
            .extend_from_slice(&forces.output().contact_force);
    }
    let wall_s = started.elapsed().as_secs_f64();
    let stats = integration.stats;
    Run {
        integrator: rung.integrator,
        setting: rung.setting,
        dt_s: rung.setting.mean_step_s(settings.horizon_s, stats.steps),
        wall_s,
        sim_s: state.t_s - t0,
        stats,
        outcome: failure.map_or(Ok(signals), Err),
    }
}

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The run.
    pub run: Run,
    /// Its error against the reference (∞ for a failed run).
    pub error: f64,
    /// The error's parts: sprocket speeds, link force, contact force.
    pub errors: [f64; 3],
    /// The method's observed order of convergence (same in all its rows):
    /// the slope of log error against log dt over the points between the
    /// reference's own error level and 0.5; for the adaptive scheme, against
    /// log tolerance (1 = error proportional to the tolerance).
    pub order: Option<f64>,
    /// Whether no other run is both faster and more accurate.
    pub pareto: bool,
}

/// The study's result.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecision {
    /// The horizon, s.
    pub horizon_s: f64,
    /// Every run.
    pub rows: Vec<Row>,
    /// The link and roller compared.
    pub probe: Probe,
    /// Error of the RK4 check run against the adaptive reference.
    pub reference_agreement: f64,
    /// Relative RMS difference of the reference to itself with one roller
    /// moved by 1 nm at the start: how much the horizon amplifies a tiny
    /// perturbation.
    pub perturbation_growth: f64,
}

/// Least-squares slope of log(error) against log(dt) over the points whose
/// error lies between `floor` and 0.5 (the asymptotic range).
pub fn observed_order(points: &[(f64, f64)], floor: f64) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(dt, e)| e.is_finite() && *e > floor && *e < 0.5 && *dt > 0.0)
        .map(|(dt, e)| (dt.ln(), e.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (x, y) in &pts {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
    }
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Runs the study, one run at a time (so that each wall time is measured
/// alone). `progress` is called with each finished run and its errors.
///
/// # Errors
///
/// The warm start cannot be made, or the reference run fails.
pub fn study(
    scene: &Scene,
    settings: &Settings,
    mut progress: impl FnMut(&Run, [f64; 3]),
) -> Result<WorkPrecision, LadderError> {
    let start = Start::warm(scene, settings.warmup_s)?;
    let reference_rung = Rung {
        integrator: Integrator::DormandPrince45,
        setting: Setting::Tolerance(settings.reference_tolerance),
    };
    let reference = integrate(&start, reference_rung, settings);
    let reference_signals = reference
        .outcome
        .map_err(|e| LadderError::reference(reference_rung, e))?;
    let check_rung = Rung {
        integrator: Integrator::Rk4,
        setting: Setting::Step(settings.reference_rk4_step_s),
    };
    let check = integrate(&start, check_rung, settings);
    let suggested = reference_signals.suggest_probe();
    let n = reference_signals.rollers.max(1);
    let probe = Probe {
        link: settings.link.map_or(suggested.link, |l| l % n),
        roller: settings.roller.map_or(suggested.roller, |r| r % n),
    };
    let reference_agreement = check.outcome.as_ref().map_or(f64::INFINITY, |s| {
        s.error_against(&reference_signals, probe)
    });
    let mut moved = start.clone();
    moved.state.x[probe.roller] += 1e-9;
    let perturbed = integrate(&moved, reference_rung, settings);
    let perturbation_growth = perturbed.outcome.as_ref().map_or(f64::INFINITY, |s| {
        s.error_against(&reference_signals, probe)
    });
    let errors_of = |run: &Run| {
        run.outcome.as_ref().map_or([f64::INFINITY; 3], |s| {
            s.errors_against(&reference_signals, probe)
        })
    };
    let rungs: Vec<Rung> = settings.ladder.rungs().collect();
    let runs = WorkQueue::new(&rungs).run(
        |_, &rung| Some(integrate(&start, rung, settings)),
        |_, run| progress(run, errors_of(run)),
    );
    let mut rows: Vec<Row> = runs
        .into_iter()
        .flatten()
        .map(|run| {
            let errors = errors_of(&run);
            Row {
                run,
                error: errors[0].max(errors[1]).max(errors[2]),
                errors,
                order: None,
                pareto: false,
            }
        })
        .collect();
    let mut first = 0;
    for (_, ladder) in &settings.ladder.methods {
        let first_of_next = first + ladder.len();
        // Fixed steps: error against dt. Adaptive: error against the
        // tolerance (its "order" is then the tolerance proportionality, 1 ideally).
        let points: Vec<(f64, f64)> = rows[first..first_of_next]
            .iter()
            .map(|r| match r.run.setting {
                Setting::Step(dt) => (dt, r.error),
                Setting::Tolerance(tol) => (tol, r.error),
            })
            .collect();
        let floor = 10.0 * reference_agreement.max(perturbation_growth);
        let order = observed_order(&points, floor);
        for r in &mut rows[first..first_of_next] {
            r.order = order;
        }
        first = first_of_next;
    }
    for i in 0..rows.len() {
        let (w, e) = (rows[i].run.wall_s, rows[i].error);
        rows[i].pareto = e.is_finite()
            && !rows
                .iter()
                .any(|o| o.error.is_finite() && o.run.wall_s < w && o.error < e);
    }
    Ok(WorkPrecision {
        horizon_s: settings.horizon_s,
        rows,
        probe,
        reference_agreement,
        perturbation_growth,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law() {
        // e = 3 dt²: slope 2 exactly; points outside (floor, 0.5) are ignored.
        let pts: Vec<(f64, f64)> = [1e-6, 1e-5, 1e-4, 1e-3]
            .iter()
            .map(|&d| (d, 3e4 * d * d))
            .chain([(1.0, 10.0)])
            .collect();
        let order = observed_order(&pts, 1e-12).expect("enough points");
        assert!((order - 2.0).abs() < 1e-12, "{order}");
    }

    #[test]
    fn relative_rms_of_the_probed_link() {
        // Two rollers, two grid points: link 1's force is (3, 4) then (3, 4.5).
        let r = GridSignals {
            omega_rad_s: vec![1.0, 1.0],
            link_force_n: vec![9.0, 3.0, 9.0, 4.0],
            contact_force_n: vec![0.0, 1.0, 0.0, 1.0],
            rollers: 2,
        };
        let mut s = r.clone();
        s.link_force_n[3] = 4.5;
        let probe = Probe { link: 1, roller: 1 };
        // sqrt(0.25 / 25) = 0.1
        assert!((s.error_against(&r, probe) - 0.1).abs() < 1e-15);
        // Link 0 is untouched.
        assert_eq!(s.error_against(&r, Probe { link: 0, roller: 1 }), 0.0);
    }
}
