//! Stepping: a drive in a rapier world, advanced either by the plugin's own
//! substepping (the fast path) or by rapier itself, with the same forces;
//! blow-up detection; observers that see the run at a chosen sample rate.
//!
//! [`Simulation::new`] builds the drive from a scene, inserts its bodies into
//! a rapier world, and brings it to static equilibrium at the pretension.
//! [`Simulation::run`] advances it, calling an [`Observer`] at every sample.
//! What observers compute is their business ([`crate::analysis`]).

#[cfg(test)]
mod arms_tests;
mod blow_up;
#[cfg(test)]
mod catenary_tests;
pub(crate) mod checkpoint;
#[cfg(test)]
mod checkpoint_tests;
#[cfg(test)]
mod contact_builds_tests;
#[cfg(test)]
mod detectors_tests;
mod energy;
#[cfg(test)]
mod equilibrium_errors_tests;
#[cfg(test)]
mod equilibrium_sweep_tests;
#[cfg(test)]
mod equilibrium_tests;
mod fanout;
#[cfg(test)]
mod fit_tests;
mod guide_entry;
pub(crate) mod integrate;
#[cfg(test)]
mod integrators_tests;
mod jumps;
#[cfg(test)]
mod jumps_tests;
#[cfg(test)]
mod paper_tests;
pub(crate) mod parallel;
mod sample_rate;
pub(crate) mod settled;
mod setup;
pub(crate) mod setup_stage;
mod sliding;
mod statics;
#[cfg(test)]
mod statics_tests;
mod stepper;
#[cfg(test)]
mod stepping_tests;
mod take_up;
mod tension_search;
#[cfg(test)]
mod threads_tests;
#[cfg(test)]
mod users_tests;
mod worn;
#[cfg(test)]
mod worn_tests;

pub use crate::geometry::{ArmReach, LayoutError};
pub use crate::model::BuildError;
pub(crate) use blow_up::{BlowUpLimits, Detector, GrowthWatch, check_blow_up};
pub use checkpoint::{CheckpointError, Snapshot};
pub(crate) use energy::{PowerLedger, PowerMeans};
pub use fanout::Fanout;
pub(crate) use integrate::{Integration, IntegrationStats};
pub use jumps::ToothJump;
pub(crate) use jumps::{JumpWatch, TipRide};
pub use sample_rate::{SampleRate, SampleRateError};
pub(crate) use sliding::JointSliding;
#[cfg(test)]
pub(crate) use statics::fitting_counts;
pub use statics::{EquilibriumError, FitError, StaticEquilibrium};
pub(crate) use statics::{
    FIT_TOLERANCE_M, RelaxSettings, arm_take_up_of, count_verdicts, default_direction,
    fit_sprocket, force_residual, free_strand_tension, needed_pitches_of, relax,
};
pub(crate) use stepper::{Relaxation, driver_speed, symplectic_euler, symplectic_euler_with_links};

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rapier2d_f64::prelude::*;

use blow_up::check_with;

use crate::forces::{ForceElement, ForceGenerator, ForceTimes, Forces};
use crate::geometry::Layout;
use crate::model::rapier::{ChainBodies, SprocketBody};
use crate::model::{BodyModel, DriveModel, DriveState, ScalarModel};
use crate::scene::{JumpAction, Overrides, Scene, SceneError, Stepping};

#[cfg(test)]
pub(crate) use energy::{Energy, Powers, balance_energy_j};

/// Why a simulation could not be built or stopped early.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The scene cannot be laid out.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// No static equilibrium.
    #[error("static equilibrium: {0}")]
    Equilibrium(EquilibriumError),
    /// The run blew up.
    #[error(
        "blow-up at t = {t_s:.6} s: {detector} detector fired on {body} ({value:e} against limit {limit:e}){detail}"
    )]
    BlowUp {
        /// Simulated time, s.
        t_s: f64,
        /// Detector name.
        detector: &'static str,
        /// The body concerned, e.g. "roller 17".
        body: String,
        /// The value that tripped it.
        value: f64,
        /// The limit.
        limit: f64,
        /// The quantity's recent history and the possible causes, starting
        /// with "; " (or empty).
        detail: String,
    },
    /// A roller jumped a tooth in a run set to stop there
    /// (`checks.tooth_jump = "stop"`).
    #[error(
        "tooth jump at t = {:.4} s: roller {} moved {} gap(s) {} on sprocket {} (checks.tooth_jump = \"stop\")",
        .0.t_s, .0.roller, .0.gaps.abs(), if .0.ahead { "ahead" } else { "behind" }, .0.sprocket + 1
    )]
    ToothJump(ToothJump),
}

impl From<EquilibriumError> for SimError {
    fn from(e: EquilibriumError) -> Self {
        Self::Equilibrium(e)
    }
}

/// What an observer sees at a sample.
pub struct Sample<'a> {
    /// The drive's parameters.
    pub model: &'a DriveModel,
    /// The state.
    pub state: &'a DriveState,
    /// Forces at the state (as evaluated for the step that led here).
    pub forces: &'a Forces,
    /// Every tooth jump seen so far, in order (the tooth-jump detector).
    pub jumps: &'a [ToothJump],
    /// Every roller that came to ride a tooth's tip so far, in order (the
    /// same detector, on the real tooth form).
    pub(crate) rides: &'a [TipRide],
}

/// Watches a run. Every method has a no-op default.
pub trait Observer {
    /// Called at every sample (at the run's sample rate), and once at t = 0.
    fn sample(&mut self, _sample: &Sample<'_>) {}
    /// Called after every integration step whose end time is ≥ the value
    /// returned by [`Observer::per_step_from_s`]; for statistics that must not
    /// miss a peak.
    fn step(&mut self, _sample: &Sample<'_>) {}
    /// First time at which [`Observer::step`] is wanted (∞ = never).
    fn per_step_from_s(&self) -> f64 {
        f64::INFINITY
    }
}

/// An observer that watches nothing.
pub(crate) struct NoObserver;
impl Observer for NoObserver {}

/// `()` watches nothing: `sim.run(until_s, every, &mut (), None)` for a run
/// whose end state is all that is wanted.
impl Observer for () {}

/// Where a run's wall time went (`Simulation::timings`), s.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Integration steps timed.
    pub steps: u64,
    /// Force evaluations timed.
    pub force_evaluations: u64,
    /// Each force element's name and its total time, s, in evaluation order.
    pub force_elements: Vec<(&'static str, f64)>,
    /// Stepping, force evaluations included.
    pub stepping_s: f64,
    /// The blow-up detectors.
    pub blow_up_checks_s: f64,
    /// The observers (sampling, statistics, recording hand-off).
    pub observers_s: f64,
}

impl StageTimes {
    /// The integrator's own arithmetic: stepping minus the force evaluations.
    pub fn integrator_s(&self) -> f64 {
        self.stepping_s - self.forces_s()
    }

    /// All force elements together, s.
    pub fn forces_s(&self) -> f64 {
        self.force_elements.iter().map(|(_, s)| s).sum()
    }

    /// Adds a later piece of the same run.
    pub(crate) fn add(&mut self, piece: Self) {
        self.steps += piece.steps;
        self.stepping_s += piece.stepping_s;
        self.blow_up_checks_s += piece.blow_up_checks_s;
        self.observers_s += piece.observers_s;
        self.force_evaluations += piece.force_evaluations;
        for (k, (name, s)) in piece.force_elements.into_iter().enumerate() {
            match self.force_elements.get_mut(k) {
                Some(e) => e.1 += s,
                None => self.force_elements.push((name, s)),
            }
        }
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutcome {
    /// Integration steps taken.
    pub steps: u64,
    /// Wall time of the stepping loop, s.
    pub wall_s: f64,
    /// Whether the run was interrupted before its end.
    pub interrupted: bool,
    /// Largest penetration seen, m.
    pub max_penetration_m: f64,
    /// Per-stage wall times, when `Simulation::timings` was on.
    pub stage_times: Option<StageTimes>,
}

/// A chain drive in a rapier world.
pub struct Simulation {
    /// The scene it was built from.
    pub(crate) scene: Scene,
    /// Constant parameters.
    pub(crate) model: DriveModel,
    /// State.
    pub(crate) state: DriveState,
    /// Force generator with its buffers.
    pub(crate) forces: ForceGenerator,
    /// The initial layout.
    pub(crate) layout: Layout,
    /// The static equilibrium reached before t = 0.
    pub(crate) equilibrium: StaticEquilibrium,
    /// The rapier world holding the drive's bodies.
    pub(crate) world: PhysicsWorld,
    /// Handles of the drive's bodies.
    pub(crate) bodies: ChainBodies,
    /// Blow-up limits.
    pub(crate) limits: BlowUpLimits,
    /// The growth detector's history.
    pub(crate) growth: GrowthWatch,
    /// The chain's integrator (substepped stepping).
    pub(crate) integration: Integration,
    /// Time every stage of [`Simulation::run`] (off by default: a few clock
    /// reads per step).
    pub(crate) timings: bool,
    /// Where the power goes, counted every step from a chosen time
    /// ([`Simulation::track_power`]; off by default).
    pub(crate) power: Option<PowerLedger>,
    /// Every joint's sliding, counted every step from a chosen time for the
    /// wear check ([`Simulation::track_sliding`]; off by default).
    pub(crate) sliding: Option<JointSliding>,
    /// The tooth-jump detector, looking at every sample.
    pub(crate) jumps: JumpWatch,
    /// Whether any roller touched a sprocket at rest (t = 0).
    pub(crate) meshed_at_rest: bool,
    /// The run's clock (see [`Clock`]).
    clock: Clock,
}

/// The stepping loop's clock: time = origin + steps × dt, counted from the
/// run's start, so that a run done in pieces (between checkpoints) steps at
/// the same times, bit for bit, as a run done at once, and long runs do not
/// accumulate rounding.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Clock {
    origin_s: f64,
    dt_s: f64,
    steps: u64,
}

impl Clock {
    fn now_s(&self) -> f64 {
        self.origin_s + self.steps as f64 * self.dt_s
    }
}

impl Simulation {
    /// Builds the drive, inserts it into a fresh rapier world and brings it to
    /// static equilibrium.
    pub fn new(scene: &Scene) -> Result<Self, SimError> {
        Self::new_holding(scene, &[])
    }

    /// [`Simulation::new`], the sprockets k with `held[k]` held at rest while
    /// the drive settles (missing entries: not held): the statics' entry
    /// point for a co-simulation whose mounted sprockets' torques are the
    /// user's bodies' business. A drive with a held sprocket settles by
    /// Newton's method instead of a long relaxation. The sprockets turn freely again
    /// afterwards. Only the rest-length and tensioner-preload rules hold
    /// them; the tensioner rule settles as [`Simulation::new`] does.
    pub(crate) fn new_holding(scene: &Scene, held: &[bool]) -> Result<Self, SimError> {
        let (settled, limits) = setup::settle(scene, held)?;
        let (scene, model, state, forces, layout, equilibrium) = settled;
        Ok(Self::assemble(
            scene,
            model,
            state,
            forces,
            layout,
            equilibrium,
            limits,
        ))
    }

    /// A copy of this simulation, settled and at its present state, that
    /// runs with `overrides` applied to its scene (another integrator, step
    /// or tolerance): a fresh rapier world holding the bodies where they
    /// are, the forces with their contact memory. A study that runs one
    /// settled drive with several schemes starts each run from a fork, so
    /// the runs differ only in what `overrides` changes.
    ///
    /// # Errors
    ///
    /// The scene with `overrides` applied is not valid (a step that is not
    /// finite and positive, for one); the error names the field.
    pub fn fork(&self, overrides: &Overrides) -> Result<Self, SceneError> {
        let scene = self.scene.with(overrides)?;
        Ok(Self::assemble(
            scene,
            self.model.clone(),
            self.state.clone(),
            self.forces.clone(),
            self.layout.clone(),
            self.equilibrium.clone(),
            self.limits,
        ))
    }

    /// A simulation of a drive already settled: a fresh rapier world holding
    /// its bodies at `state`, and the scene's integrator. [`Simulation::new`]
    /// and [`Simulation::fork`] end here.
    fn assemble(
        scene: Scene,
        model: DriveModel,
        mut state: DriveState,
        mut forces: ForceGenerator,
        layout: Layout,
        equilibrium: StaticEquilibrium,
        limits: BlowUpLimits,
    ) -> Self {
        // A driver with speed harmonics starts at its law's speed ω(t, θ), so
        // that a Runge–Kutta scheme's first stage turns it at that speed.
        for (s, sp) in model.sprockets.iter().enumerate() {
            if !sp.speed_harmonics.is_empty() {
                state.omega[s] = sp.driver_speed_at(state.t_s, state.theta[s]);
            }
        }
        let mut world = PhysicsWorld {
            gravity: Vector::new(scene.gravity_m_s2[0], scene.gravity_m_s2[1]),
            ..PhysicsWorld::default()
        };
        world.integration_parameters.dt = scene.solver.dt_s;
        world.integration_parameters.num_solver_iterations = 1;
        let sprocket_bodies: Vec<SprocketBody> = scene
            .sprockets
            .iter()
            .map(|s| SprocketBody {
                mass_kg: s.mass_kg,
                inertia_kg_m2: s.inertia_kg_m2,
            })
            .collect();
        let meshed_at_rest = forces.output().touching.iter().any(|&t| t);
        let integration = Integration::new(
            scene.solver.integrator,
            scene.solver.tolerance,
            &model,
            &state,
            &mut forces,
            scene.chain.pretension_n / model.stiffness_n_m,
        );
        let jumps = JumpWatch::new(&model, scene.chain.rollers);
        let bodies = ChainBodies::insert(
            &model,
            &state,
            &sprocket_bodies,
            scene.chain.roller_radius_m,
            &mut world.bodies,
            &mut world.colliders,
        );
        Self {
            scene,
            model,
            state,
            forces,
            layout,
            equilibrium,
            world,
            bodies,
            limits,
            growth: GrowthWatch::new(limits.growth_steps),
            integration,
            timings: false,
            power: None,
            sliding: None,
            jumps,
            meshed_at_rest,
            clock: Clock::default(),
        }
    }

    /// The warning for a chain that meshes with no sprocket at rest, if so.
    pub(crate) fn unmeshed_warning(&self) -> Option<String> {
        (!self.meshed_at_rest).then(|| {
            format!(
                "the chain meshes with no sprocket at rest: no roller touches a tooth (static tension {:.1} N), so the drive carries nothing until the chain catches a tooth, if it ever does: check that the chain lies on the sprockets (their centres, wraps and the roller count) or take up its slack (a worn chain on fixed centres gains {:.1} mm)",
                self.equilibrium.tension_n,
                1e3 * self.scene.chain.wear_gain_m()
            )
        })
    }

    /// One chain step of `dt_s` in the scene's stepping mode.
    ///
    /// Invariant: `forces` always holds the forces at `state`. A step
    /// integrates with them, then evaluates the forces at the new state (which
    /// also advances the contact memory and feeds the blow-up detectors).
    ///
    /// Fails only when the adaptive scheme's step collapses.
    pub fn step(&mut self, dt_s: f64) -> Result<(), SimError> {
        match self.scene.solver.stepping {
            Stepping::Substepped => {
                self.integration
                    .advance(&self.model, &mut self.state, &mut self.forces, dt_s)?;
            }
            Stepping::Rapier => {
                self.rapier_step(dt_s);
                self.forces.evaluate(&self.model, &self.state);
            }
        }
        Ok(())
    }

    /// One step integrated by rapier: the generator's forces are applied to
    /// the bodies, the driver's speed is set, and rapier steps the world.
    fn rapier_step(&mut self, dt_s: f64) {
        apply_forces(
            &self.bodies,
            &self.model,
            &self.state,
            self.forces.output(),
            &mut self.world.bodies,
        );
        if let Some(driver) = self.model.driver() {
            let omega = driver_speed(
                &self.model,
                driver,
                self.state.t_s,
                self.state.theta[driver],
                dt_s,
            );
            if let Some(b) = self.world.bodies.get_mut(self.bodies.sprockets[driver]) {
                b.set_angvel(omega, false);
            }
        }
        self.world.integration_parameters.dt = dt_s;
        self.world.step();
        self.bodies.read_state(&self.world.bodies, &mut self.state);
        // Further bodies and scalar states are not rapier's: symplectic Euler
        // under the same forces, beside rapier's step.
        stepper::advance_extras(
            &self.model,
            &mut self.state,
            self.forces.output(),
            dt_s,
            1.0,
        );
        self.state.t_s += dt_s;
    }

    /// Adds a further body coordinate ([`BodyModel`]) at coordinate `q` and
    /// speed `u`; returns its index in [`DriveState::q`]. Its forces come from
    /// force elements ([`Self::add_force_element`]).
    pub fn add_body(&mut self, body: BodyModel, q: f64, u: f64) -> usize {
        let i = self.model.push_body(&mut self.state, body, q, u);
        self.refit();
        i
    }

    /// Adds a scalar state ([`ScalarModel`]) at `z`; returns its index in
    /// [`DriveState::z`].
    pub fn add_scalar(&mut self, scalar: ScalarModel, z: f64) -> usize {
        let i = self.model.push_scalar(&mut self.state, scalar, z);
        self.refit();
        i
    }

    /// Adds a force element, evaluated after the links, the contact and the
    /// elements added before it.
    pub fn add_force_element(&mut self, element: Box<dyn ForceElement>) {
        self.forces.add(element);
        self.refit();
    }

    /// After the drive's make-up changed: outputs and integrator buffers
    /// sized anew, forces evaluated at the current state.
    fn refit(&mut self) {
        self.forces.fit(&self.model);
        self.integration = Integration::new(
            self.integration.scheme(),
            self.scene.solver.tolerance,
            &self.model,
            &self.state,
            &mut self.forces,
            self.scene.chain.pretension_n / self.model.stiffness_n_m,
        );
        self.forces.evaluate(&self.model, &self.state);
    }

    /// Counts every step's powers from `from_s` on (`PowerLedger`).
    pub fn track_power(&mut self, from_s: f64) {
        self.power = Some(PowerLedger::new(from_s));
    }

    /// Counts every joint's sliding from `from_s` on (`JointSliding`): the
    /// links' pass writes each link's angular velocity from now on.
    pub fn track_sliding(&mut self, from_s: f64) {
        self.forces.want_link_rates();
        self.sliding = Some(JointSliding::new(from_s, self.state.rollers()));
    }

    /// Writes the drive's state into its rapier bodies.
    pub fn sync_world(&mut self) {
        self.bodies.write_state(&self.state, &mut self.world.bodies);
    }

    /// Checks the blow-up detectors against the last force evaluation, the
    /// growth detector included (this records the step in its history).
    pub fn check_blow_up(&mut self) -> Result<(), SimError> {
        check_with(
            &self.model,
            &self.state,
            &self.forces,
            &self.limits,
            Some(&mut self.growth),
        )
    }

    /// Runs until `until_s`, with the scene's dt, calling `observer` every
    /// `sample_every` steps. `stop` (e.g. set by Ctrl-C) ends the run early
    /// with `interrupted = true`.
    pub fn run(
        &mut self,
        until_s: f64,
        sample_every: u64,
        observer: &mut dyn Observer,
        stop: Option<&AtomicBool>,
    ) -> Result<RunOutcome, SimError> {
        let dt = self.scene.solver.dt_s;
        // The clock goes on where the last run left it; a state moved from
        // outside (or another step) starts it anew.
        if self.clock.dt_s != dt || self.clock.now_s() != self.state.t_s {
            self.clock = Clock {
                origin_s: self.state.t_s,
                dt_s: dt,
                steps: 0,
            };
        }
        let target = ((until_s - self.clock.origin_s) / dt).round().max(0.0) as u64;
        let total = target.saturating_sub(self.clock.steps);
        let sample_every = sample_every.max(1);
        let per_step_from = observer.per_step_from_s();
        let mut max_pen = 0.0f64;
        let started = Instant::now();
        let mut interrupted = false;
        if self.state.t_s == 0.0 {
            self.jumps.look(&self.model, &self.state);
            observer.sample(&self.sample());
        }
        let stop_at_jump = self.scene.checks.tooth_jump == JumpAction::Stop;
        let mut steps = 0;
        let mut times = self.timings.then(StageTimes::default);
        if times.is_some() {
            self.forces.timing = Some(ForceTimes::default());
        }
        let clock = |on: bool| on.then(Instant::now);
        let lap = |since: Option<Instant>| since.map_or(0.0, |t| t.elapsed().as_secs_f64());
        let timed = times.is_some();
        while steps < total {
            let t = clock(timed);
            self.step(dt)?;
            let stepped = lap(t);
            steps += 1;
            self.clock.steps += 1;
            self.state.t_s = self.clock.now_s();
            let t = clock(timed);
            self.check_blow_up()?;
            let checked = lap(t);
            max_pen = max_pen.max(self.forces.output().max_penetration_m);
            if let Some(ledger) = &mut self.power {
                ledger.step(&self.model, &self.state, &self.forces);
            }
            if let Some(sliding) = &mut self.sliding {
                sliding.step(self.state.t_s, self.forces.output());
            }
            let t = clock(timed);
            if self.state.t_s >= per_step_from {
                observer.step(&self.sample());
            }
            let sampled = self.clock.steps % sample_every == 0;
            if sampled {
                let found = self.jumps.look(&self.model, &self.state);
                observer.sample(&self.sample());
                if found > 0
                    && stop_at_jump
                    && let Some(first) = self.jumps.jumps().get(self.jumps.jumps().len() - found)
                {
                    return Err(SimError::ToothJump(*first));
                }
            }
            if let Some(times) = &mut times {
                times.steps += 1;
                times.stepping_s += stepped;
                times.blow_up_checks_s += checked;
                times.observers_s += lap(t);
            }
            if sampled && stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                interrupted = true;
                break;
            }
        }
        if let Some(times) = &mut times {
            let forces = self.forces.timing.take().unwrap_or_default();
            times.force_evaluations = forces.evaluations;
            times.force_elements = forces.elements;
        }
        if let Some(ledger) = &mut self.power {
            ledger.close(&self.model, &self.state, &self.forces);
        }
        self.sync_world();
        Ok(RunOutcome {
            steps,
            wall_s: started.elapsed().as_secs_f64(),
            interrupted,
            max_penetration_m: max_pen,
            stage_times: times,
        })
    }

    /// The scene the drive was built from.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The drive's constant parameters.
    pub fn model(&self) -> &DriveModel {
        &self.model
    }

    /// The drive's state now.
    pub fn state(&self) -> &DriveState {
        &self.state
    }

    /// The forces of the last evaluation (at [`Self::state`] after a step).
    pub fn forces(&self) -> &Forces {
        self.forces.output()
    }

    /// The static equilibrium reached before t = 0.
    pub fn equilibrium(&self) -> &StaticEquilibrium {
        &self.equilibrium
    }

    /// Times every stage of [`Self::run`] from now on, or stops timing
    /// (off by default: a few clock reads per step); the times come back in
    /// [`RunOutcome::stage_times`].
    pub fn set_timings(&mut self, on: bool) {
        self.timings = on;
    }

    /// The current sample view.
    pub fn sample(&self) -> Sample<'_> {
        Sample {
            model: &self.model,
            state: &self.state,
            forces: self.forces.output(),
            jumps: self.jumps.jumps(),
            rides: self.jumps.rides(),
        }
    }
}

/// Replaces the drive's bodies' user forces by the generator's (rapier keeps
/// user forces across steps, so they are reset first). Gravity on the rollers
/// is left to rapier: it is taken out of the generator's roller forces.
fn apply_forces(
    handles: &ChainBodies,
    model: &DriveModel,
    state: &DriveState,
    forces: &Forces,
    bodies: &mut RigidBodySet,
) {
    let m = model.roller_mass_kg;
    let g = model.gravity_m_s2;
    for (i, h) in handles.rollers.iter().enumerate() {
        if let Some(b) = bodies.get_mut(*h) {
            b.reset_forces(false);
            b.add_force(
                Vector::new(forces.fx[i] - m * g[0], forces.fy[i] - m * g[1]),
                false,
            );
        }
    }
    for (i, (h, sp)) in handles.sprockets.iter().zip(&model.sprockets).enumerate() {
        if let Some(b) = bodies.get_mut(*h) {
            b.reset_forces(false);
            b.reset_torques(false);
            if sp.speed_law.is_none() {
                b.add_torque(
                    forces.chain_torque[i]
                        + sp.torque_at(state.t_s, state.theta[i], state.omega[i]),
                    false,
                );
            }
        }
    }
}
