//! The contact pass's AVX2 build against its baseline build, through whole
//! runs (so it lives with the stepping, which may drive the force elements).

use crate::scene::{Integrator, Overrides, ProfileKind, Scene};
use crate::sim::Simulation;

#[test]
fn avx2_and_baseline_contacts_agree_to_the_bit() {
    // The run-time choice of the contact pass's build changes no
    // result: the paper's drive run 0.2 s through its run-up with the
    // AVX2 build and with the baseline one ends in the same bits, for
    // both profiles (the real one has rollers in shared runs) and with
    // the damping rows (implicit damping) as without.
    #[cfg(target_arch = "x86_64")]
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    for (profile, integrator) in [
        (ProfileKind::Circular, Integrator::SymplecticEuler),
        (ProfileKind::Real, Integrator::SymplecticEuler),
        (ProfileKind::Circular, Integrator::ImplicitDamping),
    ] {
        let scene = Scene::l60mc()
            .with(&Overrides {
                profile: Some(profile),
                integrator: Some(integrator),
                ..Overrides::default()
            })
            .expect("valid scene");
        let mut a = Simulation::new(&scene).expect("sim");
        let mut b = Simulation::new(&scene).expect("sim");
        b.forces.contact.avx2 = false;
        let dt = scene.solver().dt_s;
        for _ in 0..20_000 {
            a.step(dt).expect("stable step");
            b.step(dt).expect("stable step");
        }
        let case = format!("{profile:?}, {integrator:?}");
        assert_eq!(a.state, b.state, "{case}");
        let (fa, fb) = (a.forces.output(), b.forces.output());
        assert_eq!(fa.chain_torque, fb.chain_torque, "{case}");
        assert_eq!(fa.contact_force, fb.contact_force, "{case}");
        assert_eq!(fa.contact_energy_j, fb.contact_energy_j, "{case}");
        assert_eq!(
            fa.contact_damping_power_w, fb.contact_damping_power_w,
            "{case}"
        );
    }
}

#[test]
fn kept_gap_directions_change_nothing() {
    // The circular seats' pass keeps each roller's hinted gap direction
    // between evaluations. Oracle: forgetting them before every step (so
    // every direction is read from its sprocket's table again) ends the
    // paper's drive's 0.2 s run-up in the same bits.
    let scene = Scene::l60mc();
    let mut a = Simulation::new(&scene).expect("sim");
    let mut b = Simulation::new(&scene).expect("sim");
    let dt = scene.solver().dt_s;
    for _ in 0..20_000 {
        a.step(dt).expect("stable step");
        b.forces.contact.forget_gap_directions();
        b.step(dt).expect("stable step");
    }
    assert_eq!(a.state, b.state);
    let (fa, fb) = (a.forces.output(), b.forces.output());
    assert_eq!(fa.chain_torque, fb.chain_torque);
    assert_eq!(fa.contact_force, fb.contact_force);
}
