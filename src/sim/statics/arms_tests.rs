//! Tensioner arms as Newton unknowns: the solve balances each arm's moment
//! about its pivot (the tensioner's push against the shoe's contact), and
//! its rest state is the one the dynamic relaxation reaches on its own.
//! The arm's balance against a hand closed form (the strands' tension
//! through the shoe's centre) is `sim::arms_tests`.

use super::newton::solve;
use super::relax::{RelaxSettings, relax_until};
use super::{REST_FORCE, free_strand_tension};
use crate::forces::{ForceGenerator, TensionerArm};
use crate::model::{DriveModel, DriveState};
use crate::scene::{PretensionRule, Scene, StepLimits};
use crate::sim::settled::new_forces;

/// The drives of `tests/data` and `assets` with tensioner arms whose arms
/// hold the chain. `user_moto_10b_free_arm` is left out: its chain is longer
/// than its path and its arm touches no roller (no smooth rest state from
/// the layout; Newton stalls and the relaxation moves it on, `newton::settle`).
const ARM_DRIVES: [&str; 4] = [
    "tests/data/user_moto_10b_guide_arm.toml",
    "tests/data/user_timing_06b_arm.toml",
    "tests/data/user_flat_hydraulic_arm.toml",
    "assets/timing-drive.toml",
];

/// A drive laid out, its links at the rest length the rest-length rule
/// starts from (the pitch less the pretension's stretch) or at the pitch
/// (tensioner-preload rule).
fn laid_out(file: &str) -> (Scene, DriveModel, DriveState, ForceGenerator) {
    let path = format!("{}/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).expect("the scene file exists");
    let scene = Scene::from_toml(&text).expect("valid");
    let (mut model, state, _) = DriveModel::build(&scene).expect("lays out");
    if matches!(scene.chain.pretension_by, PretensionRule::RestLength) {
        model.rest_length_m -= scene.chain.pretension_n / model.stiffness_n_m;
    }
    let forces = new_forces(&scene, &model);
    (scene, model, state, forces)
}

/// Largest arm moment out of balance over the arm's reach, N.
fn arm_residual_n(forces: &ForceGenerator) -> f64 {
    forces
        .elements_of::<TensionerArm>()
        .map(|a| forces.output().body_force[a.at_rest().body()].abs() / a.at_rest().reach_m())
        .fold(0.0, f64::max)
}

/// Regression: Newton's unknowns were the rollers and free sprockets only,
/// so a drive with an arm left the arm where it was laid out with its
/// moment unbalanced (and such drives relaxed dynamically, for seconds).
/// From the layout, the solve now ends with every roller's force and every
/// arm's moment over its reach below 10⁻⁸ of the pretension.
#[test]
fn newton_balances_the_arms() {
    for file in ARM_DRIVES {
        let (scene, model, mut state, mut forces) = laid_out(file);
        let tolerance_n = 1e-8 * scene.chain.pretension_n;
        let end = solve(&model, &mut state, &mut forces, tolerance_n, 40);
        assert!(end.converged, "{file}: {end:?}");
        let arm_n = arm_residual_n(&forces);
        assert!(
            arm_n <= tolerance_n,
            "{file}: arm moment / reach {arm_n:e} N"
        );
    }
}

/// The rest state Newton finds is the relaxation's: from the same layout
/// and rest length, the relaxation alone (repeated until its forces are
/// below 10⁻⁷ of the pretension) reaches the same static tension within
/// 0.1 % and the same arm angles within 10⁻⁴ rad.
#[test]
fn newton_and_the_relaxation_agree_on_arm_drives() {
    for file in ARM_DRIVES {
        let (scene, model, start, mut forces) = laid_out(file);
        let scale_n = scene.chain.pretension_n;
        let mut newton = start.clone();
        let end = solve(&model, &mut newton, &mut forces, 1e-9 * scale_n, 40);
        assert!(end.converged, "{file}: {end:?}");
        let newton_n = free_strand_tension(&model, &newton, &forces).expect("free links");
        let mut relaxed = start;
        let settings = RelaxSettings {
            dt_s: scene.solver.dt_s.min(0.8 * StepLimits::of(&scene).links_s),
            max_time_s: scene.equilibrium.max_relax_s,
            rate_per_s: 60.0,
            rest_speed_m_s: 1e-9,
            max_stretch_m: 1e-2,
        };
        for _ in 0..5 {
            relax_until(
                &model,
                &mut relaxed,
                &mut forces,
                &settings,
                Some(REST_FORCE * scale_n),
            )
            .expect("relaxes");
        }
        let relaxed_n = free_strand_tension(&model, &relaxed, &forces).expect("free links");
        assert!(
            (newton_n / relaxed_n - 1.0).abs() < 1e-3,
            "{file}: Newton {newton_n} N, relaxation {relaxed_n} N"
        );
        for (a, b) in newton.q.iter().zip(&relaxed.q) {
            assert!(
                (a - b).abs() < 1e-4,
                "{file}: arm at {a} rad against {b} rad"
            );
        }
    }
}
