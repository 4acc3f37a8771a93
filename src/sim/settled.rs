//! What every way of settling a drive shares: the force elements a scene
//! asks for ([`new_forces`]) and the settled drive's parts ([`Settled`]).

use super::StaticEquilibrium;
use super::parallel;
use crate::forces::{
    ContactLawParams, ForceGenerator, GuideElement, JointFrictionElement, TensionerArm,
};
use crate::geometry::Layout;
use crate::model::{DriveModel, DriveState};
use crate::scene::{Scene, TensionerKind};

/// The force elements `scene` asks for, beside the links and the tooth
/// contact: joint friction, the tensioner arms, the guides.
pub(crate) fn new_forces(scene: &Scene, model: &DriveModel) -> ForceGenerator {
    let mut forces = ForceGenerator::new(
        ContactLawParams::new(&scene.contact),
        model,
        scene.chain.rollers,
    );
    // The roller loops on two threads where the setting and size say so.
    forces.set_fork(Some(Box::new(parallel::Split::new(scene.solver.threads))));
    if let Some(joints) = scene.chain.joint_friction {
        forces.add(Box::new(JointFrictionElement::new(
            joints,
            scene.chain.rollers,
        )));
    }
    let mut scalar = 0;
    for (k, t) in scene.tensioners.iter().enumerate() {
        let chamber = matches!(t.kind, TensionerKind::Hydraulic(_)).then(|| {
            scalar += 1;
            scalar - 1
        });
        forces.add(Box::new(TensionerArm::new(
            t,
            k,
            chamber,
            ContactLawParams::new(&scene.contact),
            scene.chain.rollers,
            scene.chain.roller_radius_m,
        )));
    }
    for guide in &scene.guides {
        forces.add(Box::new(GuideElement::fixed(guide, &scene.chain)));
    }
    forces
}

/// A settled drive: its scene as settled (a tensioner where it ended), the
/// model, the state at rest, the forces there, the layout and the rest state.
pub(crate) type Settled = (
    Scene,
    DriveModel,
    DriveState,
    ForceGenerator,
    Layout,
    StaticEquilibrium,
);
