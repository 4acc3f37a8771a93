//! Putting a drive into the user's rapier sets and taking it out again.

use std::collections::HashMap;
use std::sync::Arc;

use rapier2d_f64::prelude::*;

use super::settled::{self, Settled};
use super::*;
use crate::forces::ForceGenerator;

impl ChainDrive {
    /// Builds `scene`'s drive, brings it to static equilibrium, and inserts it
    /// into the user's sets. `mounts[k]`, where given, is `Some(body)` where
    /// the user's body carries sprocket k (`None`, or no entry, where the
    /// drive owns the sprocket's body); more entries than sprockets is an error. A mount must be in `bodies`, carry one
    /// sprocket only, and sit at the sprocket's centre in the scene (within
    /// `MOUNT_CENTRE_TOLERANCE_M`). A dynamic mount turns with the chain
    /// (its rotational inertia as the chain sees it is the body's, not the
    /// scene's `inertia_kg_m2`); a kinematic or fixed one turns its sprocket at its
    /// own angular speed. A mount already turning sets the chain moving with
    /// it along its path (the free sprockets turning with the chain); mounts
    /// or a driver at speeds the chain cannot share are an error. A mount keeps its rotation: the
    /// sprocket's collider is turned on it to the chain's angle.
    ///
    /// Cost: the static equilibrium, then a body and a collider per roller.
    /// Where no sprocket of the scene is held (a driver), one mounted
    /// sprocket (a kinematic or fixed mount first, else the first dynamic
    /// one) is held at rest for the solve, which reacts the loads at rest
    /// there, so Newton's method settles the drive: milliseconds for the
    /// examples' drives (3 ms for the 100-roller conveyor on a motor body).
    /// A drive with every sprocket free and none mounted relaxes instead,
    /// for seconds. [`ChainDriveBuilder::settled_from`] skips the
    /// equilibrium for a drive inserted again.
    pub fn insert(
        scene: &Scene,
        mounts: &[Option<RigidBodyHandle>],
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
    ) -> Result<Self, CosimError> {
        let settled = settled::settle(scene, settled::held_for_the_solve(scene, mounts, bodies))?;
        Self::insert_settled(settled, mounts, bodies, colliders, false)
    }

    /// [`Self::insert`] from a drive already settled (its own insertion's,
    /// or another drive's of the same scene), started moving at the
    /// driver's speed where `start_moving` says so
    /// ([`ChainDriveBuilder::start_moving`]).
    pub(crate) fn insert_settled(
        settled: Arc<settled::Settled>,
        mounts: &[Option<RigidBodyHandle>],
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
        start_moving: bool,
    ) -> Result<Self, CosimError> {
        let settled::Settled {
            scene,
            model,
            state,
            forces,
            equilibrium,
            limits,
            ..
        } = Settled::clone(&settled);
        check_mounts(&model, mounts, bodies)?;
        let (mut model, mut state, mut forces) = (model, state, forces);
        take_mount_inertia(&mut model, mounts, bodies, colliders);
        if start_moving {
            start_at_driver_speed(&mut model, &mut state, &mut forces, mounts)?;
        }
        start_with_turning_mounts(&model, &mut state, &mut forces, mounts, bodies)?;
        let (links, handles) = insert_sprockets(&model, &state, mounts, bodies, colliders);
        let (rollers, roller_colliders) =
            insert_rollers(&state, scene.chain.roller_radius_m, bodies, colliders);
        let n = state.rollers();
        let sprocket_count = links.len();
        let mut owned: HashMap<ColliderHandle, bool> =
            handles.into_iter().map(|h| (h, false)).collect();
        owned.extend(roller_colliders.iter().map(|&h| (h, true)));
        let notes = Notes::starting_with(equilibrium.warnings());
        Ok(Self {
            handles: Handles::new(
                links.iter().map(|l| l.body).collect(),
                owned,
                rollers,
                roller_colliders,
            ),
            mounts: Mounts::new(links),
            coupling: Coupling::new(&scene.contact),
            stage_times: FrameTimes::default(),
            contacts: BodyContacts::new(n, scene.chain.roller_mass_kg, scene.chain.roller_radius_m),
            scratch: FrameScratch::new(n, sprocket_count),
            driver: model.driver(),
            scene,
            model,
            state,
            forces,
            equilibrium,
            limits,
            parking: Parking::new(n),
            clock: FrameClock::default(),
            notes,
            settled,
        })
    }
}

/// Checks `mounts` against the drive's sprockets: at most one per sprocket,
/// each a body of `bodies` carrying one sprocket, at its centre.
fn check_mounts(
    model: &DriveModel,
    mounts: &[Option<RigidBodyHandle>],
    bodies: &RigidBodySet,
) -> Result<(), CosimError> {
    let count = model.sprocket_count();
    if mounts.len() > count {
        return Err(CosimError::input(
            "mounts",
            format!(
                "{} entries for {count} sprockets: give at most one per sprocket, in the \
                 scene's order (None, or no entry, where the drive owns the sprocket's body)",
                mounts.len()
            ),
        ));
    }
    for (k, mount) in mounts.iter().enumerate() {
        let Some(h) = *mount else { continue };
        let field = format!("mounts[{k}]");
        let Some(b) = bodies.get(h) else {
            return Err(CosimError::input(
                field,
                "no such body in the RigidBodySet (removed, or from another set)",
            ));
        };
        if let Some(j) = mounts[..k].iter().position(|m| *m == Some(h)) {
            return Err(CosimError::input(
                field,
                format!(
                    "the body already carries sprocket {j} (mounts[{j}]): one body carries one \
                     sprocket"
                ),
            ));
        }
        let c = b.translation();
        let want = model.sprockets[k].center_m;
        let off = (c.x - want[0]).hypot(c.y - want[1]);
        if !(off <= MOUNT_CENTRE_TOLERANCE_M) {
            return Err(CosimError::input(
                format!("sprockets[{k}].center_m"),
                format!(
                    "[{}, {}] m, but its mount (mounts[{k}]) is at [{}, {}] m, {off:.3e} m \
                     away: place the body at the sprocket's centre (within {:e} m) or the \
                     sprocket at the body's",
                    want[0], want[1], c.x, c.y, MOUNT_CENTRE_TOLERANCE_M
                ),
            ));
        }
    }
    Ok(())
}

/// A dynamic mount's rotational inertia is the body's (rapier's, with its
/// colliders and locks: a body whose rotation is locked holds its
/// sprocket); rapier computes a new body's mass properties at its next
/// step: now.
fn take_mount_inertia(
    model: &mut DriveModel,
    mounts: &[Option<RigidBodyHandle>],
    bodies: &mut RigidBodySet,
    colliders: &ColliderSet,
) {
    for (k, mount) in mounts.iter().enumerate() {
        if let Some(b) = mount
            .and_then(|h| bodies.get_mut(h))
            .filter(|b| b.is_dynamic())
        {
            b.recompute_mass_properties_from_colliders(colliders);
            model.sprockets[k].inv_inertia = b.mass_properties().effective_world_inv_inertia;
        }
    }
}

/// The drive set moving at its driver's full speed from the start (see
/// [`ChainDriveBuilder::start_moving`]): the driver's ramp dropped, the
/// chain given the belt motion that speed gives it.
fn start_at_driver_speed(
    model: &mut DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    mounts: &[Option<RigidBodyHandle>],
) -> Result<(), CosimError> {
    let Some(d) = model.driver() else {
        return Err(CosimError::input(
            "start_moving",
            "the scene has no driver with a speed (a sprocket with `speed_rpm`): a drive \
             started moving starts at its driver's speed; turn a mount's body instead",
        ));
    };
    if mounts.get(d).copied().flatten().is_some() {
        return Err(CosimError::input(
            "start_moving",
            format!(
                "the driver is mounted (mounts[{d}]): the mount's own angular speed at \
                 insertion sets the chain moving; give the body its speed instead"
            ),
        ));
    }
    let Some(law) = model.sprockets[d].speed_law.as_mut() else {
        return Ok(());
    };
    law.ramp_s = 0.0;
    let omega = law.speed_at(0.0);
    let Some(belt) = motion::belt_speed(model, state, d, omega) else {
        return Err(CosimError::input(
            "start_moving",
            "the chain's path on the driver has coinciding rollers: start the drive at rest",
        ));
    };
    motion::set_belt_motion(model, state, belt);
    forces.forget_reach();
    forces.evaluate(model, state);
    Ok(())
}

/// A mount that already turns sets the chain moving with it; the other
/// mounts and the driver must turn at the speeds the chain gives them.
fn start_with_turning_mounts(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    mounts: &[Option<RigidBodyHandle>],
    bodies: &RigidBodySet,
) -> Result<(), CosimError> {
    let turning: Vec<(usize, f64)> = mounts
        .iter()
        .enumerate()
        .filter_map(|(k, m)| bodies.get((*m)?).map(|b| (k, b.angvel())))
        .collect();
    if let Some(&(k0, w0)) = turning.iter().find(|(_, w)| *w != 0.0) {
        let Some(belt) = motion::belt_speed(model, state, k0, w0) else {
            return Err(CosimError::input(
                format!("mounts[{k0}]"),
                "the chain's path on the sprocket has coinciding rollers: insert the drive \
                 with its mounts at rest",
            ));
        };
        for &(k, w) in &turning {
            let want = motion::sprocket_speed(model, state, k, belt);
            if (w - want).abs() > 0.01 * w0.abs() {
                return Err(CosimError::input(
                    format!("mounts[{k}]"),
                    format!(
                        "the body turns at {w} rad/s, but the chain moving with mounts[{k0}] \
                         at {w0} rad/s turns its sprocket at {want} rad/s: give the mounts \
                         speeds the chain can share"
                    ),
                ));
            }
        }
        if let Some(d) = model
            .driver()
            .filter(|&d| mounts.get(d).copied().flatten().is_none())
        {
            let law = model.sprockets[d]
                .speed_law
                .map_or(0.0, |l| l.speed_at(0.0));
            let want = motion::sprocket_speed(model, state, d, belt);
            if (law - want).abs() > 0.01 * want.abs() {
                return Err(CosimError::input(
                    format!("sprockets[{d}].speed_rpm"),
                    format!(
                        "the driver starts at {law} rad/s, but mounts[{k0}] turning at {w0} \
                         rad/s moves the chain at {want} rad/s on it: start the driver at the \
                         mounts' speed, or insert them at rest"
                    ),
                ));
            }
        }
        motion::set_belt_motion(model, state, belt);
        for &(k, w) in &turning {
            state.omega[k] = w;
        }
        forces.forget_reach();
        forces.evaluate(model, state);
    }
    Ok(())
}

/// Each sprocket's body (its mount, or one the drive adds) with the
/// sprocket's collider on it: the couplings and the colliders' handles.
fn insert_sprockets(
    model: &DriveModel,
    state: &DriveState,
    mounts: &[Option<RigidBodyHandle>],
    bodies: &mut RigidBodySet,
    colliders: &mut ColliderSet,
) -> (Vec<SprocketLink>, Vec<ColliderHandle>) {
    let hooks = ActiveHooks::FILTER_CONTACT_PAIRS;
    let mut handles = Vec::new();
    let mut links = Vec::with_capacity(model.sprockets.len());
    for (k, sp) in model.sprockets.iter().enumerate() {
        let mounted = mounts.get(k).copied().flatten();
        // Every sprocket's body may turn faster than rapier's default cap of
        // π/4 per step (47 rad/s at 60 Hz), which would hold
        // a dynamic mount back in rapier's step and leave a kinematic one
        // behind its sprocket: the chain sets the speed, so the cap is lifted.
        let (body, mount, angle_offset) =
            match mounted.and_then(|h| bodies.get_mut(h).map(|b| (h, b))) {
                Some((h, b)) => {
                    b.set_allow_fast_rotation(true);
                    let mount = if b.is_dynamic() {
                        Mount::Dynamic
                    } else {
                        Mount::Kinematic
                    };
                    (h, mount, b.rotation().angle() - state.theta[k])
                }
                None => {
                    let b = RigidBodyBuilder::kinematic_velocity_based()
                        .translation(Vector::new(sp.center_m[0], sp.center_m[1]))
                        .rotation(state.theta[k])
                        .can_sleep(false)
                        .allow_fast_rotation(true)
                        .build();
                    (bodies.insert(b), Mount::Own, 0.0)
                }
            };
        let collider = ColliderBuilder::new(sprocket_shape(&sp.profile))
            .position(Pose::rotation(-angle_offset))
            .density(0.0)
            .active_hooks(hooks)
            .build();
        handles.push(colliders.insert_with_parent(collider, body, bodies));
        links.push(SprocketLink {
            body,
            mount,
            angle_offset,
            user_torque_n_m: 0.0,
            user_force: Vector::ZERO,
            mean_omega: 0.0,
            mean_chain_force: [0.0; 2],
            frame_start_m: sp.center_m,
            translation: None,
            joints: MountJoints::default(),
        });
    }
    (links, handles)
}

/// A kinematic body and a ball collider of `roller_radius_m` per roller:
/// the bodies and the colliders.
fn insert_rollers(
    state: &DriveState,
    roller_radius_m: f64,
    bodies: &mut RigidBodySet,
    colliders: &mut ColliderSet,
) -> (Vec<RigidBodyHandle>, Vec<ColliderHandle>) {
    let hooks = ActiveHooks::FILTER_CONTACT_PAIRS;
    let mut roller_colliders = Vec::with_capacity(state.rollers());
    let rollers: Vec<RigidBodyHandle> = (0..state.rollers())
        .map(|i| {
            let body = RigidBodyBuilder::kinematic_velocity_based()
                .translation(Vector::new(state.x[i], state.y[i]))
                .can_sleep(false)
                .build();
            let h = bodies.insert(body);
            let collider = ColliderBuilder::ball(roller_radius_m)
                .density(0.0)
                .active_hooks(hooks)
                .build();
            let c = colliders.insert_with_parent(collider, h, bodies);
            roller_colliders.push(c);
            h
        })
        .collect();
    (rollers, roller_colliders)
}

impl ChainDrive {
    /// Removes every body and collider the drive added from the user's sets:
    /// its own sprocket and roller bodies with their colliders, and the
    /// sprocket colliders it put on mounted bodies (which stay, with their
    /// user forces and torques). The drive adds no joints.
    pub fn remove(self, world: &mut PhysicsWorld) {
        let PhysicsWorld {
            islands,
            bodies,
            colliders,
            impulse_joints,
            multibody_joints,
            soft_bodies,
            ..
        } = world;
        for link in self.mounts.links() {
            if link.mount == Mount::Own {
                continue;
            }
            let on_mount = bodies
                .get(link.body)
                .map(|b| b.colliders().to_vec())
                .unwrap_or_default();
            for c in on_mount {
                if self.handles.owns(c) {
                    colliders.remove(c, islands, bodies, soft_bodies, true);
                }
            }
            if let Some(b) = bodies.get_mut(link.body) {
                b.reset_forces(false);
                b.reset_torques(false);
                b.add_force(link.user_force, false);
                b.add_torque(link.user_torque_n_m, true);
            }
        }
        let own = self
            .mounts
            .links()
            .iter()
            .filter(|l| l.mount == Mount::Own)
            .map(|l| l.body)
            .chain(self.handles.rollers().iter().copied());
        for h in own {
            bodies.remove(
                h,
                islands,
                colliders,
                impulse_joints,
                multibody_joints,
                soft_bodies,
                true,
            );
        }
    }
}
