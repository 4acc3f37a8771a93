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
//! Misuse — a bad mount, a bad dt, a world stepped by another dt, not at
//! all or without the drive's hooks, `before_step` twice, a removed roller
//! body, a non-finite gravity or user torque, a drive of another world in a
//! [`DriveSet`] — is a [`CosimError`] naming its cause before the frame
//! writes anything, never a panic; a world gravity other than the scene's
//! is a warning ([`ChainDrive::warnings`]); a blow-up's
//! possible causes name the coupling's limit. [`ChainDrive::remove`] takes
//! the drive out of the world again.
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
//! - **Mounted sprockets.** A sprocket may sit on the user's body (see
//!   [`ChainDrive::insert`]). On a *dynamic* body, its user torque (a motor)
//!   is taken out of rapier's step and applied inside the chain's substeps,
//!   together with the angular-velocity change its joints caused, so the
//!   chain and the motor are integrated together at the small dt (a motor
//!   feels the load at once). Its centre starts each frame at its body's
//!   position and moves with it through the substeps (a swinging tensioner
//!   arm does not jump into the rollers at each frame); the contact damping
//!   sees the centre's velocity. Its user force is kept with rapier's
//!   semantics, and its translation is integrated in the substeps too, under the chain's
//!   force, the user's force and gravity (along its free axes, or a
//!   prismatic joint's axis read by [`ChainDrive::read_joints`]); rapier's
//!   step moves it at the frame's mean velocity with its gravity and user
//!   force taken out, and the velocity change its joints and contacts cause
//!   is kept. A body whose position a joint fixes (a hub on a revolute joint
//!   to a carriage) is moved by rapier once per frame: a light one meets the
//!   chain's stiffness explicitly and can blow up (docs/architecture.md,
//!   "Mounted sprockets", has the numbers).
//!   A *kinematic* (or fixed) body turns its sprocket at its own angular
//!   speed. A mounted body's own other colliders do not touch the chain.
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

mod access;
mod bodies;
mod builder;
mod checks;
#[cfg(test)]
mod cosim_api_tests;
#[cfg(test)]
mod cosim_checks_tests;
#[cfg(test)]
mod cosim_mounts_tests;
#[cfg(test)]
mod cosim_parking_tests;
#[cfg(test)]
mod cosim_seam_tests;
#[cfg(test)]
mod cosim_tests;
mod error;
mod frame;
mod handles;
mod hooks;
mod lifecycle;
mod motion;
mod mounts;
mod observe;
mod parking;
mod seam;
mod set;
mod settled;
mod sprockets;

pub use bodies::Coupling;
pub use builder::{ChainDriveBuilder, SprocketKey};
pub use error::CosimError;
pub use mounts::{MountForce, MountSpring};
pub use set::{DriveSet, SetHooks};
pub use sprockets::SprocketId;

use std::time::Instant;

use rapier2d_f64::prelude::*;

use bodies::{BodyContacts, DriveView};
use checks::Notes;
use frame::{FrameClock, FrameScratch};
use handles::Handles;
use mounts::{Mount, MountJoints, Mounts, SprocketLink};
use parking::Parking;

use crate::model::rapier::sprocket_shape;
use crate::model::{DriveModel, DriveState};
use crate::scene::{Scene, SpeedLaw};
use crate::sim::{
    BlowUpLimits, SimError, StaticEquilibrium, check_blow_up, symplectic_euler_with_links,
};

use error::at_coupling_limit;

/// How far a mount's body may sit from its sprocket's centre in the scene, m.
pub(crate) const MOUNT_CENTRE_TOLERANCE_M: f64 = 1e-6;

/// How far rapier's step may leave a roller body from the chain's roller, m
/// (more means the world stepped by another dt than the drive's frame).
const ROLLER_SYNC_TOLERANCE_M: f64 = 1e-7;

/// A chain drive living in a user's rapier world.
///
/// Its scene, model and state are read through getters ([`Self::scene`],
/// [`Self::model`], [`Self::state`], ...); what a user changes mid-run has a
/// setter ([`Self::set_load_torque`], [`Self::set_driver_speed`],
/// [`Self::set_governor_target`], [`Self::set_driver_torque`],
/// [`Self::set_coupling`]), since the drive refreshes parts of its model at
/// every frame.
pub struct ChainDrive {
    /// The scene it was built from.
    scene: Scene,
    /// Constant parameters (sprocket centres and loads refreshed per frame).
    model: DriveModel,
    /// The chain's state.
    state: DriveState,
    /// Forces at `state`.
    forces: crate::forces::ForceGenerator,
    /// The static equilibrium reached before t = 0.
    equilibrium: StaticEquilibrium,
    /// Blow-up limits.
    limits: BlowUpLimits,
    /// The scene's driver (the sprocket with a speed law), if any.
    driver: Option<usize>,
    /// How the user's colliders near the rollers are treated (see [`Coupling`]).
    coupling: Coupling,
    /// The drive's bodies and colliders in the user's sets (`handles.rs`).
    handles: Handles,
    /// Each sprocket's body, its force law and joints (`mounts.rs`).
    mounts: Mounts,
    /// Which roller bodies are in rapier's step (`parking.rs`).
    parking: Parking,
    /// The user's colliders in the substeps (`bodies.rs`).
    contacts: BodyContacts,
    /// World time, chain steps, the frame under way (`frame.rs`).
    clock: FrameClock,
    /// The frame's start and what it carries to the next (`frame.rs`).
    scratch: FrameScratch,
    /// What the drive noticed that may surprise (`checks.rs`; see [`Self::warnings`]).
    notes: Notes,
    /// Wall time spent per stage, accumulated over frames.
    stage_times: FrameTimes,
    /// The drive as it settled, before insertion: inserted again by
    /// [`ChainDriveBuilder::settled_from`] without settling anew.
    settled: std::sync::Arc<settled::Settled>,
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
    /// Sets the sprocket's load torque, N·m, from now on (without the
    /// scene's ramp). It adds to a mounted body's user torque.
    pub fn set_load_torque(&mut self, id: SprocketId, torque_n_m: f64) -> Result<(), CosimError> {
        let k = id.index();
        if !torque_n_m.is_finite() {
            return Err(CosimError::input(
                format!("sprockets[{k}].load_torque_n_m"),
                format!("{torque_n_m}: a finite torque, N·m"),
            ));
        }
        let Some(sp) = self.model.sprockets.get_mut(k) else {
            return Err(CosimError::input(
                "sprocket",
                format!(
                    "{k}: an id of another drive (this one has {} sprockets)",
                    self.scene.sprockets().len()
                ),
            ));
        };
        sp.load_torque_n_m = torque_n_m;
        sp.load_ramp_s = 0.0;
        Ok(())
    }

    /// Sets the driver's speed, rad/s (counter-clockwise positive), from now
    /// on (without the scene's ramp). An error when the scene has no driver
    /// or the driver sits on a kinematic mount (which sets its speed).
    pub fn set_driver_speed(&mut self, speed_rad_s: f64) -> Result<(), CosimError> {
        let Some(k) = self.driver else {
            return Err(CosimError::input(
                "sprockets[].role",
                "the scene has no driver: turn a mounted body instead",
            ));
        };
        if self.mounts.mount_of(k) == Some(Mount::Kinematic) {
            return Err(CosimError::input(
                format!("mounts[{k}]"),
                "the driver sits on a kinematic body, whose angular speed turns it: set the body's",
            ));
        }
        if !speed_rad_s.is_finite() {
            return Err(CosimError::input(
                format!("sprockets[{k}].speed_rpm"),
                format!("{speed_rad_s} rad/s: a finite speed"),
            ));
        }
        if let Some(sp) = self.model.sprockets.get_mut(k) {
            sp.speed_law = Some(SpeedLaw::ramped(speed_rad_s, 0.0));
        }
        Ok(())
    }

    /// The drive as an observer sees it (a recorder, a signal sampler), at
    /// the end of the last substep.
    pub fn sample(&self) -> crate::sim::Sample<'_> {
        crate::sim::Sample {
            model: &self.model,
            state: &self.state,
            forces: self.forces.output(),
            jumps: &[],
            rides: &[],
        }
    }

    /// The force each roller receives from rapier's contacts with bodies
    /// that are not carried (held over the coming frame), N.
    pub fn external_forces(&self) -> &[Vector] {
        self.scratch.external()
    }

    /// The mean force each roller received over the last frame from the
    /// user's colliders handled in the substeps (guides, kinematic and
    /// carried bodies; see [`Coupling`]), N.
    pub fn body_forces(&self) -> &[Vector] {
        &self.contacts.roller_force_mean
    }

    /// Whether `body` was carried in the substeps this frame.
    pub fn carries(&self, body: RigidBodyHandle) -> bool {
        self.contacts.carries(body)
    }

    /// The rollers' mean force on `body` over the last frame, N, if it was
    /// carried (the chain's force on your box).
    pub fn chain_force_on(&self, body: RigidBodyHandle) -> Option<Vector> {
        self.contacts.chain_force_on(body)
    }

    /// Whether `b` is one of the drive's mounted bodies, or a carriage one of
    /// them turns on (the drive moves those itself).
    pub(crate) fn holds_body(&self, b: RigidBodyHandle) -> bool {
        self.mounts.holds_body(b)
    }

    /// Whether a collider belongs to the drive.
    pub fn owns_collider(&self, h: ColliderHandle) -> bool {
        self.handles.owns(h)
    }

    /// Whether a collider is one of the drive's rollers.
    pub fn is_roller_collider(&self, h: ColliderHandle) -> bool {
        self.handles.is_roller(h)
    }

    /// Hooks for the user's step: drive–drive pairs are filtered out, every
    /// other pair goes to `user`.
    pub fn hooks<'a, H: PhysicsHooks>(&'a self, user: &'a H) -> ChainHooks<'a, H> {
        ChainHooks { drive: self, user }
    }

    /// Reads the joints on dynamic mounts, for the coming frames until the
    /// next call. A prismatic (or pin-slot) joint's free axis is the only
    /// one along which the substeps move its body, and its motor (stiffness,
    /// damping, target, largest force) and limits act in the substeps; a hub
    /// on a revolute joint to a dynamic carriage translates with the
    /// carriage (and the carriage's prismatic joint, if any, is read the
    /// same way); a joint that ties the body's position to a fixed or
    /// kinematic body leaves its translation to rapier's step. A joint that
    /// locks the body's rotation to a fixed or kinematic body (a prismatic
    /// joint does) holds its sprocket: [`Self::before_step`] then returns an
    /// error naming the mount, as it does for arrangements it cannot run.
    ///
    /// Call it before [`Self::before_step`] when mounts have joints and their
    /// set changed ([`Self::step_world`] calls it every frame). A motor the
    /// substeps imitate must not act again in rapier's step: stepping by
    /// hand, wrap the step in [`Self::joint_motors_off`] and
    /// [`Self::joint_motors_on`] ([`Self::step_world`] does).
    pub fn read_joints(&mut self, bodies: &RigidBodySet, joints: &ImpulseJointSet) {
        self.mounts.read_joints(bodies, joints);
    }

    /// Switches off, in `joints`, the joint motors the substeps imitate (a
    /// mount's prismatic joint's motor), for the world's step; undo with
    /// [`Self::joint_motors_on`] right after it.
    pub fn joint_motors_off(&mut self, joints: &mut ImpulseJointSet) {
        self.mounts.motors_off(joints);
    }

    /// Switches back on the motors [`Self::joint_motors_off`] switched off.
    pub fn joint_motors_on(&mut self, joints: &mut ImpulseJointSet) {
        self.mounts.motors_on(joints);
    }

    /// Gives the sprocket's dynamic mount a force law called in every substep with the
    /// body's position and velocity there (a spring, a damper: see
    /// [`MountForce`], [`MountSpring`]); it replaces an earlier one. This is
    /// the way to attach a stiff spring to a mount: a force the user sets
    /// with rapier's `add_force` is held over the frame while the body
    /// moves with the chain, and a stiff one held that way can drive the
    /// body unstable. It adds to the body's user force. Where rapier moves
    /// the body (a joint fixes its position) the law is evaluated once per
    /// frame. An error unless the sprocket sits on a dynamic body.
    pub fn set_mount_force(
        &mut self,
        id: SprocketId,
        law: impl MountForce + 'static,
    ) -> Result<(), CosimError> {
        self.mounts.set_law(id.index(), Some(Box::new(law)))
    }

    /// Takes away the sprocket's mount force law (a released carriage).
    pub fn clear_mount_force(&mut self, id: SprocketId) -> Result<(), CosimError> {
        self.mounts.set_law(id.index(), None)
    }

    /// One frame of a [`PhysicsWorld`] with the user's hooks and events.
    pub fn step_world(
        &mut self,
        world: &mut PhysicsWorld,
        user_hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) -> Result<(), CosimError> {
        let dt = world.integration_parameters.dt;
        self.read_joints(&world.bodies, &world.impulse_joints);
        self.before_step(&mut world.bodies, &world.colliders, world.gravity, dt)?;
        self.joint_motors_off(&mut world.impulse_joints);
        let hooks = ChainHooks {
            drive: &*self,
            user: &DynHooks(user_hooks),
        };
        let started = Instant::now();
        world.step_with_events(&hooks, events);
        self.stage_times.world_s += started.elapsed().as_secs_f64();
        self.joint_motors_on(&mut world.impulse_joints);
        self.after_step(&mut world.bodies, &world.narrow_phase, dt)
    }
}

/// What [`ChainDrive::begin_frame`] hands on to [`ChainDrive::run_frame`].
#[derive(Clone, Copy, Debug)]
struct FrameStart {
    started: Instant,
    /// Whether a sprocket centre moves this frame.
    moving: bool,
}

/// The other drives of a set: their colliders and mounted bodies, which a
/// drive leaves alone.
struct Others<'a> {
    owns: &'a dyn Fn(ColliderHandle) -> bool,
    mounted: &'a dyn Fn(RigidBodyHandle) -> bool,
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
        hooks::filter_contact_pair(self.drive, self.user, c)
    }

    fn filter_intersection_pair(&self, c: &PairFilterContext) -> bool {
        hooks::filter_intersection_pair(self.drive, self.user, c)
    }

    fn modify_solver_contacts(&self, c: &mut ContactModificationContext) {
        self.user.modify_solver_contacts(c)
    }
}
