//! The pair filter of [`super::ChainHooks`] (one drive) and
//! [`super::SetHooks`] (a set): one filter over the drives it stands for.

use rapier2d_f64::prelude::*;

use super::{ChainDrive, DriveSet};

/// The drives a pair filter stands for.
pub(super) trait Drives {
    /// Whether the collider is one of the drives'.
    fn owns(&self, h: ColliderHandle) -> bool;
    /// Whether the collider is one of the drives' rollers.
    fn is_roller(&self, h: ColliderHandle) -> bool;
    /// Whether one of the drives carries the body this frame.
    fn carries(&self, b: RigidBodyHandle) -> bool;
    /// Counts a call of the filter on every drive (the check that the world
    /// was stepped with the drives' hooks reads it).
    fn count_call(&self);
}

impl Drives for ChainDrive {
    fn owns(&self, h: ColliderHandle) -> bool {
        self.owns_collider(h)
    }
    fn is_roller(&self, h: ColliderHandle) -> bool {
        self.is_roller_collider(h)
    }
    fn carries(&self, b: RigidBodyHandle) -> bool {
        ChainDrive::carries(self, b)
    }
    fn count_call(&self) {
        self.clock.count_hook_call();
    }
}

impl Drives for DriveSet {
    fn owns(&self, h: ColliderHandle) -> bool {
        self.owns_collider(h)
    }
    fn is_roller(&self, h: ColliderHandle) -> bool {
        self.drives().iter().any(|d| d.is_roller_collider(h))
    }
    fn carries(&self, b: RigidBodyHandle) -> bool {
        DriveSet::carries(self, b)
    }
    fn count_call(&self) {
        for d in self.drives() {
            d.count_call();
        }
    }
}

/// Two of the drives' colliders: no contact; a roller and a body carried in
/// the substeps: contacts (and events) without impulses; every other pair
/// the user's filter where the user's collider asked for it, else rapier's
/// default.
pub(super) fn filter_contact_pair<D: Drives, H: PhysicsHooks>(
    drives: &D,
    user: &H,
    c: &PairFilterContext,
) -> Option<SolverFlags> {
    drives.count_call();
    let carried = |b: Option<RigidBodyHandle>| b.is_some_and(|b| drives.carries(b));
    if drives.owns(c.collider1) && drives.owns(c.collider2) {
        None
    } else if (drives.is_roller(c.collider1) && carried(c.rigid_body2))
        || (drives.is_roller(c.collider2) && carried(c.rigid_body1))
    {
        Some(SolverFlags::empty())
    } else if needs_user(drives, c) {
        user.filter_contact_pair(c)
    } else {
        Some(SolverFlags::COMPUTE_RIGID_IMPULSES)
    }
}

/// Two of the drives' colliders do not intersect; every other pair is the
/// user's filter's where the user's collider asked for it.
pub(super) fn filter_intersection_pair<D: Drives, H: PhysicsHooks>(
    drives: &D,
    user: &H,
    c: &PairFilterContext,
) -> bool {
    !(drives.owns(c.collider1) && drives.owns(c.collider2))
        && (!needs_user(drives, c) || user.filter_intersection_pair(c))
}

/// Whether one of the pair's colliders, not the drives', asked for the
/// user's filter itself (rapier only calls hooks for flagged colliders; the
/// drives flag every pair they are in, so the user's filter is asked only
/// when the user's collider asked for it too).
fn needs_user<D: Drives>(drives: &D, c: &PairFilterContext) -> bool {
    let asks = |h: ColliderHandle| {
        !drives.owns(h)
            && c.colliders.get(h).is_some_and(|col| {
                col.active_hooks()
                    .contains(ActiveHooks::FILTER_CONTACT_PAIRS)
            })
    };
    asks(c.collider1) || asks(c.collider2)
}
