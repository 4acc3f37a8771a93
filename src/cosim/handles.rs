//! The drive's bodies and colliders in the user's sets: [`Handles`].
//!
//! Set when the drive is inserted and read ever after (which collider is
//! the drive's, which a roller's); the drive never adds or removes one
//! between its insertion and [`super::ChainDrive::remove`].

use std::collections::HashMap;

use rapier2d_f64::prelude::*;

/// The handles of what the drive put into the user's sets.
#[derive(Debug)]
pub(super) struct Handles {
    /// Roller bodies, in the chain's order.
    rollers: Vec<RigidBodyHandle>,
    /// Sprocket bodies (the user's, where mounted), in the scene's order.
    sprockets: Vec<RigidBodyHandle>,
    /// The drive's colliders; `true` for a roller's.
    colliders: HashMap<ColliderHandle, bool>,
    /// Roller colliders, in the chain's order.
    roller_colliders: Vec<ColliderHandle>,
}

impl Handles {
    /// The sprockets' bodies, the drive's colliders (`true` for a
    /// roller's), the rollers' bodies and colliders.
    pub(super) fn new(
        sprockets: Vec<RigidBodyHandle>,
        colliders: HashMap<ColliderHandle, bool>,
        rollers: Vec<RigidBodyHandle>,
        roller_colliders: Vec<ColliderHandle>,
    ) -> Self {
        Self {
            rollers,
            sprockets,
            colliders,
            roller_colliders,
        }
    }

    /// Roller bodies, in the chain's order.
    pub(super) fn rollers(&self) -> &[RigidBodyHandle] {
        &self.rollers
    }

    /// Sprocket bodies, in the scene's order.
    pub(super) fn sprockets(&self) -> &[RigidBodyHandle] {
        &self.sprockets
    }

    /// Roller colliders, in the chain's order.
    pub(super) fn roller_colliders(&self) -> &[ColliderHandle] {
        &self.roller_colliders
    }

    /// Whether a collider is the drive's.
    pub(super) fn owns(&self, h: ColliderHandle) -> bool {
        self.colliders.contains_key(&h)
    }

    /// Whether a collider is one of the drive's rollers.
    pub(super) fn is_roller(&self, h: ColliderHandle) -> bool {
        self.colliders.get(&h).copied().unwrap_or(false)
    }
}
