//! One frame of a co-simulated drive: [`ChainDrive::before_step`] (the
//! checks, the mounts and the user's colliders near the chain read, then the
//! chain's substeps to the frame's end and its bodies set for rapier's step)
//! and [`ChainDrive::after_step`] (what rapier's step did to the chain, and
//! the users' forces, torques and gravity scales put back).

use std::sync::atomic::{AtomicU64, Ordering};

use rapier2d_f64::prelude::*;

use super::*;
use crate::forces::Forces;

impl ChainDrive {
    /// Advances the chain to the end of the coming frame of `dt_s` and sets
    /// its bodies for rapier's step. Call right before the user's step, with
    /// the world's gravity (carried bodies feel it in the substeps) and the
    /// world's dt. A blow-up of the chain is an error (the bodies are then
    /// left as they were), as are a dt that is not positive and finite and a
    /// mount removed from `bodies`.
    pub fn before_step(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        self.check_world(bodies, colliders, gravity, dt_s)?;
        let frame = self.begin_frame(bodies, colliders, gravity, dt_s, None)?;
        self.run_frame(bodies, dt_s, frame)
    }

    /// The first half of [`Self::before_step`], after
    /// [`Self::check_world`]: mounts read, the user's colliders near the
    /// chain found (leaving `others`' bodies alone). Touches only mounted
    /// bodies' user torques.
    pub(super) fn begin_frame(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        dt_s: f64,
        others: Option<&Others<'_>>,
    ) -> Result<FrameStart, CosimError> {
        self.note_gravity(gravity);
        let started = Instant::now();
        // Sprockets: centres, user torques (taken out of rapier's step).
        let moving =
            self.mounts
                .begin_frame(&mut self.model.sprockets, bodies, colliders, gravity, dt_s);
        if moving {
            // The kept reach sets assumed the old centres and speeds.
            self.forces.forget_reach();
        }
        self.scratch.take_start(&self.state);
        let handles = &self.handles;
        let owns = |h: ColliderHandle| handles.owns(h) || others.is_some_and(|o| (o.owns)(h));
        let mounts = &self.mounts;
        let mounted =
            |b: RigidBodyHandle| mounts.holds_body(b) || others.is_some_and(|o| (o.mounted)(b));
        self.contacts.prepare(
            &self.coupling,
            &DriveView {
                owns: &owns,
                mounted: &mounted,
                roller_colliders: self.handles.roller_colliders(),
                state: &self.state,
            },
            bodies,
            colliders,
            gravity,
            dt_s,
        );
        self.mark_reach(bodies, colliders, others, dt_s);
        Ok(FrameStart { started, moving })
    }

    /// The second half of [`Self::before_step`]: the substeps, and the
    /// bodies set for rapier's step.
    pub(super) fn run_frame(
        &mut self,
        bodies: &mut RigidBodySet,
        dt_s: f64,
        frame: FrameStart,
    ) -> Result<(), CosimError> {
        let searched = Instant::now();
        let substeps = self.substeps(dt_s, frame.moving)?;
        self.end_frame(bodies, dt_s, frame, substeps, searched)
    }

    /// After the substeps (`searched`: when they began): the frame's checks,
    /// the bodies set for rapier's step, the stage times counted.
    pub(super) fn end_frame(
        &mut self,
        bodies: &mut RigidBodySet,
        dt_s: f64,
        frame: FrameStart,
        substeps: u64,
        searched: Instant,
    ) -> Result<(), CosimError> {
        self.check_substeps(bodies, substeps, dt_s)?;
        let stepped = Instant::now();
        self.hand_back(bodies, substeps, dt_s);
        self.clock.open(dt_s);
        let t = &mut self.stage_times;
        t.frames += 1;
        t.search_s += (searched - frame.started).as_secs_f64();
        t.substeps_s += (stepped - searched).as_secs_f64();
        t.sync_s += stepped.elapsed().as_secs_f64();
        t.projections = self.contacts.projections;
        Ok(())
    }

    /// Substeps at the scene's dt until the world's frame end of `dt_s`,
    /// moving the mounts with them where any moves; how many it took.
    fn substeps(&mut self, dt_s: f64, moving: bool) -> Result<u64, CosimError> {
        let (substeps, t0) = self.open_substeps(dt_s);
        let with_bodies = !self.contacts.is_empty();
        for step in 1..=substeps {
            self.substep_forces(step, with_bodies);
            self.substep_advance(step, t0, moving, with_bodies, dt_s)?;
        }
        Ok(substeps)
    }

    /// How many substeps bring the chain to the world's frame end of
    /// `dt_s`, and the chain's time at the frame's start, s.
    pub(super) fn open_substeps(&mut self, dt_s: f64) -> (u64, f64) {
        // The chain's clock lags the world's by less than one substep and is
        // counted from the start (steps × dt) as `Simulation::run` counts it,
        // so a drive with no outside contact evolves exactly as it does
        // standalone.
        let t0 = self.state.t_s;
        let substeps = self.clock.substeps(dt_s, t0, self.scene.solver.dt_s);
        self.scratch.force_sum.fill([0.0; 2]);
        (substeps, t0)
    }

    /// The first half of substep `step` (from 1) of a frame: the held external forces and the user's
    /// colliders' forces at the current state (their reactions on carried
    /// bodies summed, not yet applied) where `with_bodies` (the frame has
    /// any carried body or pair).
    #[inline(always)]
    pub(super) fn substep_forces(&mut self, step: u64, with_bodies: bool) {
        let dt = self.scene.solver.dt_s;
        self.scratch.add_external(self.forces.output_mut());
        if with_bodies {
            let tau = (step - 1) as f64 * dt;
            self.contacts.apply(
                &self.coupling,
                &self.state,
                self.forces.output_mut(),
                tau,
                dt,
            );
        }
    }

    /// The second half of substep `step` of a frame that began at the
    /// chain's time `t0`: the chain and (`with_bodies`) the carried bodies
    /// advanced, the mounts moved (`moving`), the forces at the new state,
    /// the blow-up check (a frame of `dt_s` names the coupling's limit).
    #[inline(always)]
    pub(super) fn substep_advance(
        &mut self,
        step: u64,
        t0: f64,
        moving: bool,
        with_bodies: bool,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        let dt = self.scene.solver.dt_s;
        // The rollers' update and the links at the new state in one
        // pass (large drives); the mounts' move does not touch the links.
        let linked =
            symplectic_euler_with_links(&self.model, &mut self.state, &mut self.forces, dt);
        if with_bodies {
            self.contacts.integrate(dt);
        }
        self.state.t_s = self.clock.tick(dt);
        if moving {
            self.mounts.move_centres(
                &mut self.model.sprockets,
                &self.forces.output().chain_force,
                step,
                t0,
                dt,
            );
        }
        if linked {
            self.forces.evaluate_after_links(&self.model, &self.state);
        } else {
            self.forces.evaluate(&self.model, &self.state);
        }
        check_blow_up(&self.model, &self.state, &self.forces, &self.limits)
            .map_err(|e| at_coupling_limit(e, dt_s))?;
        self.scratch
            .add_chain_force(&self.forces.output().chain_force);
        Ok(())
    }

    /// The frame's checks after its substeps: no roller too deep in a
    /// user's collider, every carried and mounted body finite.
    fn check_substeps(
        &mut self,
        bodies: &mut RigidBodySet,
        substeps: u64,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        if self.contacts.max_depth_m > self.limits.max_penetration_m {
            return Err(at_coupling_limit(
                SimError::BlowUp {
                    t_s: self.state.t_s,
                    detector: crate::sim::Detector::Penetration.name(),
                    body: "a roller against a user's collider".to_owned(),
                    value: self.contacts.max_depth_m,
                    limit: self.limits.max_penetration_m,
                    detail: String::new(),
                },
                dt_s,
            ));
        }
        if !self.contacts.finish_substeps(bodies, substeps, dt_s) {
            return Err(at_coupling_limit(
                SimError::BlowUp {
                    t_s: self.state.t_s,
                    detector: crate::sim::Detector::NonFinite.name(),
                    body: "a carried body".to_owned(),
                    value: f64::NAN,
                    limit: 0.0,
                    detail: String::new(),
                },
                dt_s,
            ));
        }
        if !self.mounts.close_substeps(substeps, dt_s) {
            return Err(at_coupling_limit(
                SimError::BlowUp {
                    t_s: self.state.t_s,
                    detector: crate::sim::Detector::NonFinite.name(),
                    body: "a mounted body".to_owned(),
                    value: f64::NAN,
                    limit: 0.0,
                    detail: String::new(),
                },
                dt_s,
            ));
        }
        Ok(())
    }

    /// Hands the frame back to rapier: the rollers synced, each sprocket's
    /// body set to turn (and a mount to move) over the frame `span` as the
    /// substeps did, the chain's mean force on it.
    fn hand_back(&mut self, bodies: &mut RigidBodySet, substeps: u64, span: f64) {
        self.sync_rollers(bodies, span);
        self.mounts.hand_back(
            bodies,
            &self.state,
            &self.scratch.theta0,
            &self.scratch.force_sum,
            substeps,
            span,
        );
    }

    /// Reads what rapier's step did to the drive's bodies beyond the chain's
    /// own motion — the contact impulses bodies that are not carried
    /// exchanged with the rollers, the speed change joints gave mounted
    /// sprockets, what other contacts and joints did to carried bodies — and
    /// restores the users' torques, forces and gravity scales. Call right
    /// after the user's step, with the same `dt_s` as [`Self::before_step`].
    ///
    /// An error, touching nothing, when the frame does not add up: no
    /// `before_step` before it, another `dt_s`, a world stepped by another dt
    /// (the roller bodies are not where the chain is), or a world stepped
    /// without [`Self::hooks`] while a dynamic body carries a sprocket.
    pub fn after_step(
        &mut self,
        bodies: &mut RigidBodySet,
        narrow_phase: &NarrowPhase,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        self.check_frame(bodies, narrow_phase, dt_s)?;
        self.clock.close();
        let started = Instant::now();
        self.scratch.read_impulses(
            narrow_phase,
            self.handles.roller_colliders(),
            self.parking.active(),
            dt_s,
        );
        self.mounts.after_step(bodies, &mut self.state.omega);
        let handles = &self.handles;
        let is_roller = |h: ColliderHandle| handles.is_roller(h);
        self.contacts.after_step(bodies, narrow_phase, &is_roller);
        self.stage_times.sync_s += started.elapsed().as_secs_f64();
        Ok(())
    }
}

/// The drive's clocks: the world's time the chain has been advanced to, the
/// chain's own steps, and the frame under way between `before_step` and
/// `after_step` with the calls of the drive's pair filter during it.
#[derive(Debug, Default)]
pub(super) struct FrameClock {
    /// World time the chain has been advanced to, s.
    world_time_s: f64,
    /// Chain steps taken since the drive was inserted: its clock is
    /// `t = steps × dt` from the start, as `Simulation::run` counts it.
    steps: u64,
    /// The frame's dt given to `before_step`, s (0 before the first frame).
    frame_dt_s: f64,
    /// Whether `before_step` set the bodies up and `after_step` has not run yet.
    in_frame: bool,
    /// Calls of the drive's pair filter (counts whether the world's step
    /// used the drive's hooks).
    hook_calls: AtomicU64,
    /// `hook_calls` when the frame began.
    hook_calls_at_frame: u64,
}

impl FrameClock {
    /// Advances the world's time by the frame's `dt_s`: how many chain
    /// steps of `dt` bring the chain from `t0` to the frame's end (its
    /// clock lags the world's by less than one step).
    fn substeps(&mut self, dt_s: f64, t0: f64, dt: f64) -> u64 {
        self.world_time_s += dt_s;
        ((self.world_time_s - t0) / dt + 1e-9).floor().max(0.0) as u64
    }

    /// Counts one chain step of `dt`: the chain's time after it, s.
    fn tick(&mut self, dt: f64) -> f64 {
        self.steps += 1;
        self.steps as f64 * dt
    }

    /// The bodies are set for the world's step of `dt_s`.
    fn open(&mut self, dt_s: f64) {
        self.frame_dt_s = dt_s;
        self.in_frame = true;
        self.hook_calls_at_frame = self.hook_calls.load(Ordering::Relaxed);
    }

    /// The world's step was read back.
    fn close(&mut self) {
        self.in_frame = false;
    }

    /// Whether `before_step` set the bodies up and `after_step` has not run yet.
    pub(super) fn in_frame(&self) -> bool {
        self.in_frame
    }

    /// The last frame's dt, s (0 before the first frame).
    pub(super) fn frame_dt_s(&self) -> f64 {
        self.frame_dt_s
    }

    /// Counts a call of the drive's pair filter.
    pub(super) fn count_hook_call(&self) {
        self.hook_calls.fetch_add(1, Ordering::Relaxed);
    }

    /// Whether the pair filter was called since the frame began.
    pub(super) fn hooked(&self) -> bool {
        self.hook_calls.load(Ordering::Relaxed) != self.hook_calls_at_frame
    }
}

/// What one frame keeps between its stages: the rollers and sprockets at
/// the frame's start, the chain's force on each sprocket summed over the
/// substeps, and the force rapier's contacts put on each roller (read after
/// the world's step, held over the next frame).
#[derive(Debug)]
pub(super) struct FrameScratch {
    /// Frame-start roller positions, m.
    start: Vec<[f64; 2]>,
    /// Frame-start sprocket angles, rad.
    theta0: Vec<f64>,
    /// The chain's force on each sprocket summed over the frame's substeps, N.
    force_sum: Vec<[f64; 2]>,
    /// External force on each roller from rapier's contacts, N (held over a frame).
    external: Vec<Vector>,
    /// Whether `external` holds any non-zero force.
    any_external: bool,
}

impl FrameScratch {
    /// Buffers for `rollers` rollers and `sprockets` sprockets, no external force.
    pub(super) fn new(rollers: usize, sprockets: usize) -> Self {
        Self {
            start: vec![[0.0; 2]; rollers],
            theta0: vec![0.0; sprockets],
            force_sum: vec![[0.0; 2]; sprockets],
            external: vec![Vector::ZERO; rollers],
            any_external: false,
        }
    }

    /// The rollers' positions at the frame's start, m.
    pub(super) fn start(&self) -> &[[f64; 2]] {
        &self.start
    }

    /// The force each roller receives from rapier's contacts, N.
    pub(super) fn external(&self) -> &[Vector] {
        &self.external
    }

    /// Keeps `state`'s roller positions and sprocket angles as the frame's start.
    fn take_start(&mut self, state: &DriveState) {
        for (s, p) in self.start.iter_mut().zip(state.x.iter().zip(&state.y)) {
            *s = [*p.0, *p.1];
        }
        self.theta0.copy_from_slice(&state.theta);
    }

    /// Adds the held external forces to the rollers' forces.
    fn add_external(&self, out: &mut Forces) {
        if self.any_external {
            for (i, f) in self.external.iter().enumerate() {
                out.fx[i] += f.x;
                out.fy[i] += f.y;
            }
        }
    }

    /// Adds one substep's chain force on each sprocket to the frame's sum.
    fn add_chain_force(&mut self, chain_force: &[[f64; 2]]) {
        for (sum, f) in self.force_sum.iter_mut().zip(chain_force) {
            sum[0] += f[0];
            sum[1] += f[1];
        }
    }

    /// Reads the contact impulses rapier's step applied to each active
    /// roller's collider as a force impulse / `span` (zero for a parked one).
    fn read_impulses(
        &mut self,
        narrow_phase: &NarrowPhase,
        roller_colliders: &[ColliderHandle],
        active: &[bool],
        span: f64,
    ) {
        self.any_external = false;
        for (i, &rc) in roller_colliders.iter().enumerate() {
            if !active[i] {
                self.external[i] = Vector::ZERO;
                continue;
            }
            let mut impulse = [0.0f64; 2];
            for pair in narrow_phase.contact_pairs_with(rc) {
                if !pair.has_any_active_contact() {
                    continue;
                }
                // rapier applies `impulse` along −normal and the friction impulse along
                // its perpendicular to collider 1's body, the opposite to collider 2's.
                let sign = if pair.collider1 == rc { 1.0 } else { -1.0 };
                for manifold in pair.manifolds() {
                    let d = -manifold.data.normal;
                    let t = Vector::new(-d.y, d.x);
                    for point in &manifold.points {
                        let (n, f) = (point.data.impulse, point.data.tangent_impulse[0]);
                        impulse[0] += sign * (n * d.x + f * t.x);
                        impulse[1] += sign * (n * d.y + f * t.y);
                    }
                }
            }
            self.external[i] = Vector::new(impulse[0] / span, impulse[1] / span);
            self.any_external |= impulse != [0.0; 2];
        }
    }
}
