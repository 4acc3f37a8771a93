//! The drive's bodies and colliders in the user's sets: [`Handles`].
//!
//! Set when the drive is inserted and read ever after (which collider is
//! the drive's, which a roller's); the drive never adds or removes one
//! between its insertion and [`super::ChainDrive::remove`].

use std::collections::HashMap;

use rapier2d_f64::prelude::*;

/// The drive's mark on a collider slot: the slot's generation when the
/// drive's collider took it, and whether it is a roller's.
#[derive(Clone, Copy, Debug)]
struct Owned {
    generation: u32,
    roller: bool,
}

/// The handles of what the drive put into the user's sets.
#[derive(Debug)]
pub(super) struct Handles {
    /// Roller bodies, in the chain's order.
    rollers: Vec<RigidBodyHandle>,
    /// Sprocket bodies (the user's, where mounted), in the scene's order.
    sprockets: Vec<RigidBodyHandle>,
    /// The drive's colliders by their handle's slot index (a direct look-up:
    /// the frame's search asks this of every collider in the world).
    colliders: Vec<Option<Owned>>,
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
        let mut table = Vec::new();
        for (h, roller) in colliders {
            let (index, generation) = h.into_raw_parts();
            let index = index as usize;
            if table.len() <= index {
                table.resize(index + 1, None);
            }
            table[index] = Some(Owned { generation, roller });
        }
        Self {
            rollers,
            sprockets,
            colliders: table,
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
        self.owned(h).is_some()
    }

    /// Whether a collider is one of the drive's rollers.
    pub(super) fn is_roller(&self, h: ColliderHandle) -> bool {
        self.owned(h).is_some_and(|o| o.roller)
    }

    /// The drive's mark on `h`, if `h` is the drive's collider (its slot and
    /// generation both match).
    #[inline]
    fn owned(&self, h: ColliderHandle) -> Option<Owned> {
        let (index, generation) = h.into_raw_parts();
        self.colliders
            .get(index as usize)
            .copied()
            .flatten()
            .filter(|o| o.generation == generation)
    }
}
