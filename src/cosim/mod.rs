//! A chain drive inside someone else's rapier world: [`ChainDrive`].
//!
//! The drive adds its rollers and sprockets to the user's `RigidBodySet` and
//! `ColliderSet` (a sprocket may be mounted on a body the user already has:
//! a wheel, a motor shaft with its own joints), then advances itself in
//! substeps of the scene's `dt_s` inside every step of the user's world, at
//! the user's dt (e.g. 1/60 s). It never touches the user's integration
//! parameters.
//!
//! # One frame
//!
//! ```text
//! drive.before_step(&mut bodies, &colliders, gravity, dt)   // chain substeps to the
//!                                      // frame's end; bodies get start pose + mean velocity
//! pipeline.step(..., &drive.hooks(&user_hooks), ...)   // the user's own step
//! drive.after_step(&mut bodies, &narrow_phase, dt)   // what rapier did to the chain
//! ```
//! ([`ChainDrive::step_world`] does the three for a [`PhysicsWorld`].)
//!
//! - **Chain → world.** Before the step every roller body is put at its
//!   frame-start position with the frame's mean velocity, so rapier's own
//!   integration lands it where the chain will be at the frame's end.
//!   Sprockets are treated alike (angle and mean angular speed). Roller and
//!   sprocket bodies are kinematic for rapier.
//! - **The user's colliders at the rollers, in the substeps** (see
//!   [`Coupling`] for the contact law and what is found when). Fixed
//!   colliders (guides, rails) and kinematic ones push the rollers; dynamic
//!   bodies near the chain (a box on a conveyor) are *carried*: integrated
//!   with the chain at its dt for the frame, then given to rapier's step at
//!   their frame-start pose with the frame's mean velocity, their gravity,
//!   user force and damping taken out (the substeps applied them) and put
//!   back after. Their other contacts and joints act in rapier's step; the
//!   velocity change they cause is kept, and the part of the substeps'
//!   velocity change (end minus mean) that points into one of those contacts
//!   is dropped, so a box held by a stop stays held.
//!   [`ChainDrive::chain_force_on`] gives the rollers' mean force on a body. rapier's own roller contact with a
//!   carried body is computed (events fire) but solves no impulse. Mean
//!   roller forces from all of these: [`ChainDrive::body_forces`].
//! - **World → chain through rapier.** With [`Coupling::carry_dynamic`]
//!   off, or for a body that reached the chain faster than the frame's pair
//!   search allows, rapier's solver meets the kinematic rollers as
//!   infinitely heavy, and after its step the contact impulses it applied
//!   become a force impulse / dt on each roller over the next frame
//!   ([`ChainDrive::external_forces`]). That explicit, lagged coupling is
//!   fine for bodies up to a few roller masses; a box of 100 roller masses
//!   blows it up (the box takes the rollers' speed every frame, and the
//!   impulse hits 20 g rollers a frame later), which is why bodies are carried.
//! - **Mounted sprockets.** A mounted sprocket's user torque (a motor) is
//!   taken out of rapier's step and applied inside the chain's substeps,
//!   together with the angular-velocity change its joints caused, so the
//!   chain and the motor are integrated together at the small dt (a motor
//!   feels the load at once). Its centre starts each frame at its body's
//!   position and moves on at the body's velocity through the substeps, as
//!   rapier's step will move the body (a swinging tensioner arm does not
//!   jump into the rollers at each frame); the contact damping sees the
//!   centre's velocity. The chain's mean force on it is applied to the body
//!   as a user force over rapier's step. A mounted body's own other colliders do not
//!   touch the chain.
//! - Not coupled: other bodies hitting a sprocket the drive owns (its
//!   kinematic body does not pass their impulses on; mount the sprocket on
//!   your own body if that matters); roller rotation (rollers slide on a guide).
//!
//! rapier's own contact never acts between two of the drive's colliders:
//! [`ChainHooks`] filters those pairs and hands every other pair to the
//! user's hooks, so stock contacts keep working.
//!
//! Cost: with none of the user's colliders near the chain the substeps do
//! exactly what a standalone run does; [`ChainDrive::stage_times`] tells
//! where a frame's wall time goes.

mod bodies;

pub use bodies::Coupling;

use std::collections::HashMap;
use std::time::Instant;

use rapier2d_f64::prelude::*;

use bodies::{BodyContacts, DriveView};

use crate::model::rapier::sprocket_shape;
use crate::model::{DriveModel, DriveState};
use crate::scene::Scene;
use crate::sim::{
    BlowUpLimits, SimError, Simulation, StaticEquilibrium, check_blow_up, symplectic_euler,
};

/// Per-frame coupling of one sprocket to its rapier body.
#[derive(Clone, Copy, Debug)]
struct SprocketLink {
    body: RigidBodyHandle,
    /// Whether the body is the user's (mounted) rather than the drive's own.
    mounted: bool,
    /// The user's torque, stashed during rapier's step, N·m.
    user_torque_n_m: f64,
    /// Mean angular speed given to rapier for this frame, rad/s.
    mean_omega: f64,
    /// The chain's mean force on the sprocket over the frame, N.
    mean_chain_force: [f64; 2],
    /// A mounted body's position at the frame's start, m.
    frame_start_m: [f64; 2],
}

/// A chain drive living in a user's rapier world.
pub struct ChainDrive {
    /// The scene it was built from.
    pub scene: Scene,
    /// Constant parameters (sprocket centres and loads refreshed per frame).
    pub model: DriveModel,
    /// The chain's state.
    pub state: DriveState,
    /// Forces at `state`.
    pub forces: crate::forces::ForceGenerator,
    /// The static equilibrium reached before t = 0.
    pub equilibrium: StaticEquilibrium,
    /// Blow-up limits.
    pub limits: BlowUpLimits,
    /// Roller bodies.
    pub rollers: Vec<RigidBodyHandle>,
    /// Sprocket bodies (the user's, where mounted).
    pub sprockets: Vec<RigidBodyHandle>,
    /// How the user's colliders near the rollers are treated (see [`Coupling`]).
    pub coupling: Coupling,
    /// Wall time spent per stage, accumulated over frames.
    pub stage_times: FrameTimes,
    /// The drive's colliders; `true` for a roller's.
    colliders: HashMap<ColliderHandle, bool>,
    roller_colliders: Vec<ColliderHandle>,
    links: Vec<SprocketLink>,
    /// Mounted sprockets' bodies.
    mounted: Vec<RigidBodyHandle>,
    /// Frame-start roller positions.
    start: Vec<[f64; 2]>,
    /// Scratch: frame-start sprocket angles; the chain's force on each sprocket summed over the frame.
    theta0: Vec<f64>,
    force_sum: Vec<[f64; 2]>,
    /// External force on each roller from rapier's contacts, N (held over a frame).
    external: Vec<[f64; 2]>,
    /// Whether `external` holds any non-zero force.
    any_external: bool,
    /// The user's colliders in the substeps.
    contacts: BodyContacts,
    /// World time the chain has been advanced to, s.
    world_time_s: f64,
}

/// Wall time of a drive's stages, summed over frames, s.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameTimes {
    /// Frames counted.
    pub frames: u64,
    /// Finding the user's colliders near the chain (once per frame).
    pub search_s: f64,
    /// The chain's substeps (forces, contacts with the user's colliders, integration).
    pub substeps_s: f64,
    /// Setting the drive's bodies for rapier's step, reading rapier's results.
    pub sync_s: f64,
    /// rapier's own step (only counted by [`ChainDrive::step_world`]).
    pub world_s: f64,
    /// Roller–collider point projections in the substeps.
    pub projections: u64,
}

impl FrameTimes {
    /// Mean wall time per frame of all stages, s.
    pub fn per_frame_s(&self) -> f64 {
        (self.search_s + self.substeps_s + self.sync_s + self.world_s) / self.frames.max(1) as f64
    }
}

impl ChainDrive {
    /// Builds `scene`'s drive, brings it to static equilibrium, and inserts it
    /// into the user's sets. `mounts[k]`, where given, is the user's body that
    /// carries sprocket k (its centre should be at the scene's centre; its
    /// rotational inertia as the chain sees it is the scene's `inertia_kg_m2`).
    pub fn insert(
        scene: &Scene,
        mounts: &[Option<RigidBodyHandle>],
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
    ) -> Result<Self, SimError> {
        let sim = Simulation::new(scene)?;
        let Simulation {
            scene,
            model,
            state,
            forces,
            equilibrium,
            limits,
            ..
        } = sim;
        let hooks = ActiveHooks::FILTER_CONTACT_PAIRS;
        let mut handles = Vec::new();
        let mut links = Vec::with_capacity(model.sprocket_count());
        for (k, sp) in model.sprockets.iter().enumerate() {
            let (body, mounted) = match mounts.get(k).copied().flatten() {
                Some(h) => (h, true),
                None => {
                    let b = RigidBodyBuilder::kinematic_velocity_based()
                        .translation(Vector::new(sp.center_m[0], sp.center_m[1]))
                        .rotation(state.theta[k])
                        .can_sleep(false)
                        .build();
                    (bodies.insert(b), false)
                }
            };
            if let Some(b) = bodies.get_mut(body) {
                b.set_rotation(Rotation::new(state.theta[k]), true);
            }
            let collider = ColliderBuilder::new(sprocket_shape(&sp.profile))
                .density(0.0)
                .active_hooks(hooks)
                .build();
            handles.push(colliders.insert_with_parent(collider, body, bodies));
            links.push(SprocketLink {
                body,
                mounted,
                user_torque_n_m: 0.0,
                mean_omega: 0.0,
                mean_chain_force: [0.0; 2],
                frame_start_m: sp.center_m,
            });
        }
        let mut roller_colliders = Vec::with_capacity(state.rollers());
        let rollers = (0..state.rollers())
            .map(|i| {
                let body = RigidBodyBuilder::kinematic_velocity_based()
                    .translation(Vector::new(state.x[i], state.y[i]))
                    .can_sleep(false)
                    .build();
                let h = bodies.insert(body);
                let collider = ColliderBuilder::ball(scene.chain.roller_radius_m)
                    .density(0.0)
                    .active_hooks(hooks)
                    .build();
                let c = colliders.insert_with_parent(collider, h, bodies);
                handles.push(c);
                roller_colliders.push(c);
                h
            })
            .collect();
        let n = state.rollers();
        let sprocket_count = links.len();
        Ok(Self {
            sprockets: links.iter().map(|l| l.body).collect(),
            mounted: links.iter().filter(|l| l.mounted).map(|l| l.body).collect(),
            coupling: Coupling::new(&scene.contact),
            stage_times: FrameTimes::default(),
            contacts: BodyContacts::new(n, scene.chain.roller_mass_kg, scene.chain.roller_radius_m),
            theta0: vec![0.0; sprocket_count],
            force_sum: vec![[0.0; 2]; sprocket_count],
            any_external: false,
            scene,
            model,
            state,
            forces,
            equilibrium,
            limits,
            rollers,
            colliders: handles
                .into_iter()
                .map(|h| (h, roller_colliders.contains(&h)))
                .collect(),
            roller_colliders,
            links,
            start: vec![[0.0; 2]; n],
            external: vec![[0.0; 2]; n],
            world_time_s: 0.0,
        })
    }

    /// The drive as an observer sees it (a recorder, a signal sampler), at
    /// the end of the last substep.
    pub fn sample(&self) -> crate::sim::Sample<'_> {
        crate::sim::Sample {
            model: &self.model,
            state: &self.state,
            forces: self.forces.output(),
        }
    }

    /// The force each roller receives from rapier's contacts with bodies
    /// that are not carried (held over the coming frame), N.
    pub fn external_forces(&self) -> &[[f64; 2]] {
        &self.external
    }

    /// The mean force each roller received over the last frame from the
    /// user's colliders handled in the substeps (guides, kinematic and
    /// carried bodies; see [`Coupling`]), N.
    pub fn body_forces(&self) -> &[[f64; 2]] {
        &self.contacts.roller_force_mean
    }

    /// Whether `body` was carried in the substeps this frame.
    pub fn carries(&self, body: RigidBodyHandle) -> bool {
        self.contacts.carries(body)
    }

    /// The rollers' mean force on `body` over the last frame, N, if it was
    /// carried (the chain's force on your box).
    pub fn chain_force_on(&self, body: RigidBodyHandle) -> Option<[f64; 2]> {
        self.contacts.chain_force_on(body)
    }

    /// Whether a collider belongs to the drive.
    pub fn owns_collider(&self, h: ColliderHandle) -> bool {
        self.colliders.contains_key(&h)
    }

    /// Whether a collider is one of the drive's rollers.
    pub fn is_roller_collider(&self, h: ColliderHandle) -> bool {
        self.colliders.get(&h).copied().unwrap_or(false)
    }

    /// Hooks for the user's step: drive–drive pairs are filtered out, every
    /// other pair goes to `user`.
    pub fn hooks<'a, H: PhysicsHooks>(&'a self, user: &'a H) -> ChainHooks<'a, H> {
        ChainHooks { drive: self, user }
    }

    /// Advances the chain to the end of the coming frame of `dt_s` and sets
    /// its bodies for rapier's step. Call right before the user's step, with
    /// the world's gravity (carried bodies feel it in the substeps). A
    /// blow-up of the chain is an error (the bodies are then left as they were).
    pub fn before_step(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        dt_s: f64,
    ) -> Result<(), SimError> {
        let started = Instant::now();
        // Sprockets: centres, user torques (taken out of rapier's step). A
        // mounted body moves on through the frame at its velocity (rapier's
        // step will take it there): its sprocket follows in the substeps.
        let mut moving = false;
        for (k, link) in self.links.iter_mut().enumerate() {
            let Some(b) = bodies.get_mut(link.body) else {
                continue;
            };
            let sprocket = &mut self.model.sprockets[k];
            if link.mounted {
                let (c, v) = (b.translation(), b.linvel());
                moving |= sprocket.center_m != [c.x, c.y]
                    || sprocket.center_velocity_m_s != [0.0; 2]
                    || v != Vector::ZERO;
                sprocket.center_m = [c.x, c.y];
                sprocket.center_velocity_m_s = [v.x, v.y];
                link.frame_start_m = [c.x, c.y];
                link.user_torque_n_m = b.user_torque();
                b.reset_torques(false);
            }
            // The scene's load keeps its ramp; the user's torque does not ramp.
            sprocket.user_torque_n_m = link.user_torque_n_m;
        }
        if moving {
            // The kept reach sets assumed the old centres and speeds.
            self.forces.forget_reach();
        }
        for (s, p) in self
            .start
            .iter_mut()
            .zip(self.state.x.iter().zip(&self.state.y))
        {
            *s = [*p.0, *p.1];
        }
        self.theta0.copy_from_slice(&self.state.theta);
        let colliders_map = &self.colliders;
        let owns = |h: ColliderHandle| colliders_map.contains_key(&h);
        self.contacts.prepare(
            &self.coupling,
            &DriveView {
                owns: &owns,
                mounted: &self.mounted,
                roller_colliders: &self.roller_colliders,
                state: &self.state,
            },
            bodies,
            colliders,
            gravity,
            dt_s,
        );
        let searched = Instant::now();
        // Substeps at the scene's dt until the world's frame end; the chain's
        // clock lags the world's by less than one substep and is counted from
        // the frame's start as `Simulation::run` counts it, so a drive with no
        // outside contact evolves exactly as it does standalone.
        self.world_time_s += dt_s;
        let dt = self.scene.solver.dt_s;
        let t0 = self.state.t_s;
        let substeps = ((self.world_time_s - t0) / dt + 1e-9).floor().max(0.0) as u64;
        self.force_sum.fill([0.0; 2]);
        let with_bodies = !self.contacts.is_empty();
        for step in 1..=substeps {
            if self.any_external {
                for (i, f) in self.external.iter().enumerate() {
                    self.forces.output_mut().fx[i] += f[0];
                    self.forces.output_mut().fy[i] += f[1];
                }
            }
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
            symplectic_euler(&self.model, &mut self.state, &self.forces, dt, None);
            if with_bodies {
                self.contacts.integrate(dt);
            }
            self.state.t_s = t0 + step as f64 * dt;
            if moving {
                let tau = step as f64 * dt;
                for (link, sprocket) in self.links.iter().zip(&mut self.model.sprockets) {
                    if link.mounted {
                        let [vx, vy] = sprocket.center_velocity_m_s;
                        sprocket.center_m = [
                            link.frame_start_m[0] + vx * tau,
                            link.frame_start_m[1] + vy * tau,
                        ];
                    }
                }
            }
            self.forces.evaluate(&self.model, &self.state);
            check_blow_up(&self.model, &self.state, &self.forces, &self.limits)?;
            for (sum, f) in self
                .force_sum
                .iter_mut()
                .zip(&self.forces.output().chain_force)
            {
                sum[0] += f[0];
                sum[1] += f[1];
            }
        }
        if self.contacts.max_depth_m > self.limits.max_penetration_m {
            return Err(SimError::BlowUp {
                t_s: self.state.t_s,
                detector: crate::sim::Detector::Penetration.name(),
                body: "a roller against a user's collider".to_owned(),
                value: self.contacts.max_depth_m,
                limit: self.limits.max_penetration_m,
                detail: String::new(),
            });
        }
        if !self.contacts.finish_substeps(bodies, substeps, dt_s) {
            return Err(SimError::BlowUp {
                t_s: self.state.t_s,
                detector: crate::sim::Detector::NonFinite.name(),
                body: "a carried body".to_owned(),
                value: f64::NAN,
                limit: 0.0,
                detail: String::new(),
            });
        }
        let stepped = Instant::now();
        let span = dt_s.max(f64::MIN_POSITIVE);
        for i in 0..self.state.rollers() {
            let v = [
                (self.state.x[i] - self.start[i][0]) / span,
                (self.state.y[i] - self.start[i][1]) / span,
            ];
            if let Some(b) = bodies.get_mut(self.rollers[i]) {
                b.set_translation(Vector::new(self.start[i][0], self.start[i][1]), true);
                b.set_linvel(Vector::new(v[0], v[1]), true);
            }
        }
        let n = substeps.max(1) as f64;
        for (k, link) in self.links.iter_mut().enumerate() {
            link.mean_omega = (self.state.theta[k] - self.theta0[k]) / span;
            link.mean_chain_force = [self.force_sum[k][0] / n, self.force_sum[k][1] / n];
            if let Some(b) = bodies.get_mut(link.body) {
                b.set_rotation(Rotation::new(self.theta0[k]), true);
                b.set_angvel(link.mean_omega, true);
                if link.mounted {
                    b.reset_forces(false);
                    b.add_force(
                        Vector::new(link.mean_chain_force[0], link.mean_chain_force[1]),
                        true,
                    );
                }
            }
        }
        let t = &mut self.stage_times;
        t.frames += 1;
        t.search_s += (searched - started).as_secs_f64();
        t.substeps_s += (stepped - searched).as_secs_f64();
        t.sync_s += stepped.elapsed().as_secs_f64();
        t.projections = self.contacts.projections;
        Ok(())
    }

    /// Reads what rapier's step did to the drive's bodies beyond the chain's
    /// own motion — the contact impulses bodies that are not carried
    /// exchanged with the rollers, the speed change joints gave mounted
    /// sprockets, what other contacts and joints did to carried bodies — and
    /// restores the users' torques, forces and gravity scales. Call right
    /// after the user's step.
    pub fn after_step(&mut self, bodies: &mut RigidBodySet, narrow_phase: &NarrowPhase, dt_s: f64) {
        let started = Instant::now();
        let span = dt_s.max(f64::MIN_POSITIVE);
        self.any_external = false;
        for (i, &rc) in self.roller_colliders.iter().enumerate() {
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
            self.external[i] = [impulse[0] / span, impulse[1] / span];
            self.any_external |= impulse != [0.0; 2];
        }
        for (k, link) in self.links.iter().enumerate() {
            if !link.mounted {
                continue;
            }
            if let Some(b) = bodies.get_mut(link.body) {
                // The body's joints changed its speed by this much during rapier's step.
                self.state.omega[k] += b.angvel() - link.mean_omega;
                b.reset_forces(false);
                b.add_torque(link.user_torque_n_m, false);
            }
        }
        let colliders = &self.colliders;
        let is_roller = |h: ColliderHandle| colliders.get(&h).copied().unwrap_or(false);
        self.contacts.after_step(bodies, narrow_phase, &is_roller);
        self.stage_times.sync_s += started.elapsed().as_secs_f64();
    }

    /// One frame of a [`PhysicsWorld`] with the user's hooks and events.
    pub fn step_world(
        &mut self,
        world: &mut PhysicsWorld,
        user_hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) -> Result<(), SimError> {
        let dt = world.integration_parameters.dt;
        self.before_step(&mut world.bodies, &world.colliders, world.gravity, dt)?;
        let hooks = ChainHooks {
            drive: &*self,
            user: &DynHooks(user_hooks),
        };
        let started = Instant::now();
        world.step_with_events(&hooks, events);
        self.stage_times.world_s += started.elapsed().as_secs_f64();
        self.after_step(&mut world.bodies, &world.narrow_phase, dt);
        Ok(())
    }
}

struct DynHooks<'a>(&'a dyn PhysicsHooks);

impl PhysicsHooks for DynHooks<'_> {
    fn filter_contact_pair(&self, c: &PairFilterContext) -> Option<SolverFlags> {
        self.0.filter_contact_pair(c)
    }
    fn filter_intersection_pair(&self, c: &PairFilterContext) -> bool {
        self.0.filter_intersection_pair(c)
    }
    fn modify_solver_contacts(&self, c: &mut ContactModificationContext) {
        self.0.modify_solver_contacts(c)
    }
}

/// Keeps rapier's solver out of roller–sprocket and roller–roller pairs and
/// defers everything else to the user's hooks.
pub struct ChainHooks<'a, H: PhysicsHooks> {
    drive: &'a ChainDrive,
    user: &'a H,
}

impl<H: PhysicsHooks> PhysicsHooks for ChainHooks<'_, H> {
    fn filter_contact_pair(&self, c: &PairFilterContext) -> Option<SolverFlags> {
        if self.drive.owns_collider(c.collider1) && self.drive.owns_collider(c.collider2) {
            None
        } else if self.carried_pair(c) {
            // The substeps handle it: contacts (and events) without impulses.
            Some(SolverFlags::empty())
        } else if self.needs_user(c) {
            self.user.filter_contact_pair(c)
        } else {
            Some(SolverFlags::COMPUTE_RIGID_IMPULSES)
        }
    }

    fn filter_intersection_pair(&self, c: &PairFilterContext) -> bool {
        !(self.drive.owns_collider(c.collider1) && self.drive.owns_collider(c.collider2))
            && (!self.needs_user(c) || self.user.filter_intersection_pair(c))
    }

    fn modify_solver_contacts(&self, c: &mut ContactModificationContext) {
        self.user.modify_solver_contacts(c)
    }
}

impl<H: PhysicsHooks> ChainHooks<'_, H> {
    /// A roller and a body carried in the substeps.
    fn carried_pair(&self, c: &PairFilterContext) -> bool {
        let d = self.drive;
        let carried = |b: Option<RigidBodyHandle>| b.is_some_and(|b| d.carries(b));
        (d.is_roller_collider(c.collider1) && carried(c.rigid_body2))
            || (d.is_roller_collider(c.collider2) && carried(c.rigid_body1))
    }

    /// Whether one of the pair's colliders asked for the user's filter itself
    /// (rapier only calls hooks for flagged colliders; ours flag every pair
    /// they are in, so the user's filter is asked only when the user's
    /// collider asked for it too).
    fn needs_user(&self, c: &PairFilterContext) -> bool {
        let asks = |h: ColliderHandle| {
            !self.drive.owns_collider(h)
                && c.colliders.get(h).is_some_and(|col| {
                    col.active_hooks()
                        .contains(ActiveHooks::FILTER_CONTACT_PAIRS)
                })
        };
        asks(c.collider1) || asks(c.collider2)
    }
}
