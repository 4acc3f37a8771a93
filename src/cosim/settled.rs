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
            .take(scene.sprockets.len())
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::strand_means;

    fn conveyor() -> Scene {
        Scene::from_toml(include_str!("../../assets/conveyor.toml")).expect("valid")
    }

    #[test]
    fn a_motor_body_is_held_for_the_solve_and_a_scene_driver_is_not() {
        let mut bodies = RigidBodySet::new();
        let motor = bodies.insert(RigidBodyBuilder::dynamic());
        let carriage = bodies.insert(RigidBodyBuilder::dynamic());
        let kinematic = bodies.insert(RigidBodyBuilder::kinematic_velocity_based());
        let scene = conveyor();
        assert_eq!(held_for_the_solve(&scene, &[Some(motor)], &bodies), Some(0));
        assert_eq!(
            held_for_the_solve(&scene, &[Some(carriage), Some(kinematic)], &bodies),
            Some(1)
        );
        assert_eq!(held_for_the_solve(&scene, &[], &bodies), None);
        // More mounts than sprockets is insertion's error to name, not a
        // sprocket to hold.
        assert_eq!(
            held_for_the_solve(&scene, &[None, None, Some(motor)], &bodies),
            None
        );
        assert_eq!(
            held_for_the_solve(&Scene::l60mc(), &[Some(motor)], &bodies),
            None
        );
    }

    #[test]
    fn the_held_solve_agrees_with_the_relaxation_on_the_strand_tensions() {
        // The relaxation (nothing held: the tail's −0.5 N·m load turns the
        // chain against the relaxation's damping until its time is up) and
        // Newton with the head held: the free strands' tensions agree
        // within 2 % of the pretension (10 N); the held solve is at rest to
        // 1e-7 of the pretension, the relaxation only to about 3e-5.
        let scene = conveyor();
        let slow = settle(&scene, None).expect("relaxation");
        let held = settle(&scene, Some(0)).expect("held");
        let means = |s: &Settled| strand_means(&s.model, &s.state, s.forces.output());
        let (a, b) = (means(&slow), means(&held));
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            let (Some(x), Some(y)) = (x, y) else {
                panic!("a strand without free links: {a:?} {b:?}");
            };
            assert!((x - y).abs() < 10.0, "relaxation {a:?} N, held {b:?} N");
        }
        assert!(
            held.equilibrium.force_residual <= 1e-7,
            "{:?}",
            held.equilibrium
        );
        assert!(
            (held.equilibrium.tension_n - slow.equilibrium.tension_n).abs() < 10.0,
            "{:?} {:?}",
            held.equilibrium,
            slow.equilibrium
        );
    }
}
