//! A body carried by several drives of a set in the same frame: every drive
//! that finds it near its rollers carries its own copy, each copy is pushed
//! by that drive's rollers (and the contacts that drive follows), and in
//! every substep all copies are advanced with the sum of all the drives'
//! forces, so they stay one body. One drive, its keeper, hands it to
//! rapier's step and reads it back; a contact between carried bodies is
//! followed by one drive only, so it acts once.

use rapier2d_f64::prelude::*;

use super::*;

/// One drive's push on a shared body in a substep: force, N; torque, N·m;
/// roller contacts.
pub(in crate::cosim) type Push = (Vector, f64, u32);

impl BodyContacts {
    /// Marks `body` as carried by other drives too this frame; `keeper`:
    /// whether this drive hands it to rapier. Nothing, if not carried here.
    pub(in crate::cosim) fn share(&mut self, body: RigidBodyHandle, keeper: bool) {
        if let Some(c) = self.carried.iter_mut().find(|c| c.body == body) {
            c.shared = true;
            c.keeper = keeper;
        }
    }

    /// Drops the contacts between carried bodies that another drive follows:
    /// a contact one of whose bodies is shared is followed by the keeper of
    /// the shared body with the lower handle (every drive that carries
    /// both finds the same contact).
    pub(in crate::cosim) fn drop_touches_kept_elsewhere(&mut self) {
        let carried = &self.carried;
        let shared_body = |m: &Motion| match *m {
            Motion::Carried(k) => carried
                .get(k)
                .filter(|c| c.shared)
                .map(|c| (c.body.into_raw_parts(), c.keeper)),
            _ => None,
        };
        self.touches.retain(|t| {
            let sides = [shared_body(&t.a.motion), shared_body(&t.b.motion)];
            match sides.iter().flatten().min_by_key(|s| s.0) {
                Some(&(_, keeper)) => keeper,
                None => true,
            }
        });
    }

    /// This drive's push on `body` in the substep just applied, if it carries it.
    pub(in crate::cosim) fn push_on(&self, body: RigidBodyHandle) -> Option<Push> {
        self.carried
            .iter()
            .find(|c| c.body == body)
            .map(|c| (c.force, c.torque, c.contacts_now))
    }

    /// Sets the sum of every drive's push on the shared `body` for the
    /// coming integration: its copy here advances with it, and its next
    /// substep divides friction's effective mass among all roller contacts.
    pub(in crate::cosim) fn set_total(&mut self, body: RigidBodyHandle, total: Push) {
        if let Some(c) = self.carried.iter_mut().find(|c| c.body == body) {
            c.total = (total.0, total.1);
            c.contacts_now = total.2;
        }
    }

    /// The bodies marked shared this frame.
    pub(in crate::cosim) fn shared_bodies(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.carried.iter().filter(|c| c.shared).map(|c| c.body)
    }
}
