//! Observers of a co-simulated drive (a recording is one:
//! [`crate::record::Recorder::co_simulated`] with the drive's scene).
//!
//! An observer ([`crate::sim::Observer`]; several through
//! [`crate::sim::Fanout`]) sees a co-simulated drive **once per world
//! frame**, at the frame's end (the chain's state after its last substep):
//! [`ChainDrive::step_world_observed`] calls its [`Observer::sample`] after
//! the frame; [`Observer::step`] is not called (the substeps' states are
//! not kept). [`ChainDrive::observe`] hands it the current state at any
//! time (at insertion, for a recording's first sample).

use rapier2d_f64::prelude::*;

use super::{ChainDrive, CosimError, DriveSet};
use crate::sim::Observer;

impl ChainDrive {
    /// Hands `observer` the drive's current sample ([`Self::sample`]) once.
    pub fn observe(&self, observer: &mut dyn Observer) {
        observer.sample(&self.sample());
    }

    /// One frame of `world` ([`Self::step_world`]), then `observer`'s
    /// [`Observer::sample`] with the drive at the frame's end. On an error
    /// the observer is not called.
    pub fn step_world_observed(
        &mut self,
        world: &mut PhysicsWorld,
        user_hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
        observer: &mut dyn Observer,
    ) -> Result<(), CosimError> {
        self.step_world(world, user_hooks, events)?;
        self.observe(observer);
        Ok(())
    }
}

impl DriveSet {
    /// One frame of `world` ([`Self::step_world`]), then each drive's
    /// observer ([`Observer::sample`], `observers[i]` for drive `i`, one per
    /// drive: a recorder each, say) with the drive at the frame's end. An
    /// error, before anything is stepped, when the observers are not one per
    /// drive; on a stepping error no observer is called.
    pub fn step_world_observed(
        &mut self,
        world: &mut PhysicsWorld,
        user_hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
        observers: &mut [&mut dyn Observer],
    ) -> Result<(), CosimError> {
        if observers.len() != self.drives().len() {
            return Err(CosimError::input(
                "observers",
                format!(
                    "{} observers for {} drives: one per drive, in the set's order",
                    observers.len(),
                    self.drives().len()
                ),
            ));
        }
        self.step_world(world, user_hooks, events)?;
        for (drive, observer) in self.drives().iter().zip(observers.iter_mut()) {
            drive.observe(&mut **observer);
        }
        Ok(())
    }
}
