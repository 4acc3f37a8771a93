//! The static equilibrium a drive is inserted from: which sprocket is held
//! while the drive settles, the settling itself, and the settled drive kept
//! so that the same drive can be inserted again (into another world, or
//! after [`ChainDrive::remove`]) without settling anew
//! ([`super::ChainDriveBuilder::settled_from`]). What it does not do: put
//! anything into a rapier world (`lifecycle` does).

use std::sync::Arc;

use rapier2d_f64::prelude::*;

use super::CosimError;
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::Scene;
use crate::sim::StaticEquilibrium;
use crate::sim::{BlowUpLimits, Simulation};

/// A drive at static equilibrium, before anything of a world touches it:
/// what insertion starts from. Shared (an `Arc`) between a drive and the
/// drives inserted again from it.
#[derive(Clone)]
pub(crate) struct Settled {
    /// The scene as given to insertion (with the builder's pose applied).
    pub(crate) given: Scene,
    /// The sprocket held at rest while the drive settled, if insertion
    /// chose one ([`held_for_the_solve`]).
    pub(crate) held: Option<usize>,
    pub(crate) scene: Scene,
    pub(crate) model: DriveModel,
    pub(crate) state: DriveState,
    pub(crate) forces: ForceGenerator,
    pub(crate) equilibrium: StaticEquilibrium,
    pub(crate) limits: BlowUpLimits,
}

impl std::fmt::Debug for Settled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Settled")
            .field("scene", &self.given.name)
            .field("held", &self.held)
            .field("equilibrium", &self.equilibrium)
            .finish_non_exhaustive()
    }
}

/// The sprocket to hold at rest while a drive with these mounts settles:
/// `None` where the scene already holds one (a driver, kinematic or
/// torque-driven) or nothing is mounted; else one mounted sprocket, a
/// kinematic or fixed mount first (it turns only as the user turns it),
/// then the first dynamic one (the user's motor, whose torque is the
/// user's business: at rest it reacts the loads).
///
/// Without a held sprocket every sprocket turns freely, no rest state
/// exists where a load acts, and the statics fall back to seconds of
/// relaxation; with one, Newton's method settles the drive in tens of
/// milliseconds. One sprocket only: holding a second one would fix its
/// angle against the chain's and leave a tooth's reaction in it.
pub(crate) fn held_for_the_solve(
    scene: &Scene,
    mounts: &[Option<RigidBodyHandle>],
    bodies: &RigidBodySet,
) -> Option<usize> {
    let scene_holds = scene
        .sprockets
        .iter()
        .any(|s| s.speed_law().is_some() || s.excitation.governor.is_some());
    if scene_holds {
        return None;
    }
    let mounted = || {
        mounts
            .iter()
            .enumerate()
            .filter_map(|(k, m)| bodies.get((*m)?).map(|b| (k, b)))
    };
    mounted()
        .find(|(_, b)| !b.is_dynamic())
        .or_else(|| mounted().next())
        .map(|(k, _)| k)
}

/// Settles `scene`'s drive with `held` held at rest for the solve (see
/// [`held_for_the_solve`]).
pub(crate) fn settle(scene: &Scene, held: Option<usize>) -> Result<Arc<Settled>, CosimError> {
    let mut hold = vec![false; scene.sprockets.len()];
    if let Some(k) = held {
        hold[k] = true;
    }
    let Simulation {
        scene: settled_scene,
        model,
        state,
        forces,
        equilibrium,
        limits,
        ..
    } = Simulation::new_holding(scene, &hold)?;
    Ok(Arc::new(Settled {
        given: scene.clone(),
        held,
        scene: settled_scene,
        model,
        state,
        forces,
        equilibrium,
        limits,
    }))
}
