//! The drive's rapier bodies: sprockets are rigid bodies (the driver
//! kinematic, the others dynamic with their translation locked, so they turn
//! about fixed centres), rollers are dynamic balls with their rotation locked
//! (the model neglects roller rotation).
//!
//! rapier's own contact never acts between rollers and sprockets, nor between
//! rollers: their colliders belong to [`CHAIN_GROUP`] and filter it out. Any
//! other collider in the world (default groups) still touches rollers and
//! sprockets as usual. The chain's forces are applied by the stepping stage ([`crate::sim`]).
//!
//! This module moves data between the drive's arrays and the bodies; it
//! does not step anything.

use rapier2d_f64::prelude::*;

use super::{DriveModel, DriveState};

/// The collision group of every roller and sprocket collider.
pub(crate) const CHAIN_GROUP: Group = Group::GROUP_32;

/// Handles of the drive's bodies in a rapier world.
#[derive(Clone, Debug)]
pub(crate) struct ChainBodies {
    /// Roller bodies, in chain order.
    pub rollers: Vec<RigidBodyHandle>,
    /// Sprocket bodies, in scene order.
    pub sprockets: Vec<RigidBodyHandle>,
}

/// What a sprocket body needs beyond the model.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SprocketBody {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Polar inertia, kg·m².
    pub inertia_kg_m2: f64,
}

/// Arc step of the sprocket colliders' tessellation: the chord error is
/// r (1 − cos(step/2)), 4 µm on a 27 mm seating arc.
pub(crate) const COLLIDER_ARC_STEP_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// The sprocket's outline as a closed parry polyline (parry has no arc
/// primitive), tessellated at [`COLLIDER_ARC_STEP_RAD`]. Other bodies of the
/// scene collide with it, ray casts see it, viewers draw it; the chain's own
/// contact uses the exact geometry instead.
pub(crate) fn sprocket_shape(profile: &crate::geometry::ToothProfile) -> SharedShape {
    let points: Vec<Vector> = profile
        .outline(COLLIDER_ARC_STEP_RAD)
        .iter()
        .map(|p| Vector::new(p.x_m, p.y_m))
        .collect();
    let n = points.len() as u32;
    let indices = (0..n).map(|i| [i, (i + 1) % n]).collect();
    SharedShape::polyline(points, Some(indices))
}

fn chain_groups() -> InteractionGroups {
    InteractionGroups::new(
        CHAIN_GROUP,
        Group::ALL.difference(CHAIN_GROUP),
        InteractionTestMode::And,
    )
}

impl ChainBodies {
    /// Adds the drive's bodies and colliders to `bodies`/`colliders`, placed at `state`.
    pub(crate) fn insert(
        model: &DriveModel,
        state: &DriveState,
        sprocket_bodies: &[SprocketBody],
        roller_radius_m: f64,
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
    ) -> Self {
        let sprockets = model
            .sprockets
            .iter()
            .zip(sprocket_bodies)
            .enumerate()
            .map(|(i, (sp, b))| {
                let builder = if sp.speed_law.is_some() {
                    RigidBodyBuilder::kinematic_velocity_based()
                } else {
                    RigidBodyBuilder::dynamic()
                        .lock_translations()
                        .additional_mass_properties(MassProperties::new(
                            Vector::ZERO,
                            b.mass_kg,
                            b.inertia_kg_m2,
                        ))
                };
                let body = builder
                    .translation(Vector::new(sp.center_m[0], sp.center_m[1]))
                    .rotation(state.theta[i])
                    .angvel(state.omega[i])
                    .can_sleep(false)
                    .build();
                let handle = bodies.insert(body);
                let collider = ColliderBuilder::new(sprocket_shape(&sp.profile))
                    .density(0.0)
                    .collision_groups(chain_groups())
                    .build();
                colliders.insert_with_parent(collider, handle, bodies);
                handle
            })
            .collect();
        let rollers = (0..state.rollers())
            .map(|i| {
                let body = RigidBodyBuilder::dynamic()
                    .translation(Vector::new(state.x[i], state.y[i]))
                    .linvel(Vector::new(state.vx[i], state.vy[i]))
                    .lock_rotations()
                    .additional_mass(model.roller_mass_kg)
                    .can_sleep(false)
                    .build();
                let handle = bodies.insert(body);
                let collider = ColliderBuilder::ball(roller_radius_m)
                    .density(0.0)
                    .collision_groups(chain_groups())
                    .build();
                colliders.insert_with_parent(collider, handle, bodies);
                handle
            })
            .collect();
        Self { rollers, sprockets }
    }

    /// Writes the drive's state into the bodies (the substepped mode's sync).
    pub(crate) fn write_state(&self, state: &DriveState, bodies: &mut RigidBodySet) {
        for (i, h) in self.rollers.iter().enumerate() {
            if let Some(b) = bodies.get_mut(*h) {
                b.set_translation(Vector::new(state.x[i], state.y[i]), false);
                b.set_linvel(Vector::new(state.vx[i], state.vy[i]), false);
            }
        }
        for (i, h) in self.sprockets.iter().enumerate() {
            if let Some(b) = bodies.get_mut(*h) {
                b.set_rotation(Rotation::new(state.theta[i]), false);
                b.set_angvel(state.omega[i], false);
            }
        }
    }

    /// Reads the bodies into the drive's state (the rapier-integrated mode).
    ///
    /// Sprocket angles are unwrapped against the previous value so they stay
    /// continuous over many turns.
    pub(crate) fn read_state(&self, bodies: &RigidBodySet, state: &mut DriveState) {
        for (i, h) in self.rollers.iter().enumerate() {
            if let Some(b) = bodies.get(*h) {
                let (p, v) = (b.translation(), b.linvel());
                state.x[i] = p.x;
                state.y[i] = p.y;
                state.vx[i] = v.x;
                state.vy[i] = v.y;
            }
        }
        for (i, h) in self.sprockets.iter().enumerate() {
            if let Some(b) = bodies.get(*h) {
                let a = b.rotation().angle();
                let prev = state.theta[i];
                let turns = ((prev - a) / std::f64::consts::TAU).round();
                state.theta[i] = a + turns * std::f64::consts::TAU;
                state.omega[i] = b.angvel();
            }
        }
    }
}
