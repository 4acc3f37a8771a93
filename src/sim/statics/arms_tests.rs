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
/// than its path and its arm touches no roller (Newton from the layout
/// stalls; `newton::settle` settles it from taut, tested below).
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

/// `user_moto_10b_free_arm`: a chain 6.56 mm longer than its path, laid
/// with its free links 0.504 % short of the pitch (every free strand
/// compressed), whose spring arm ends clear of the chain. Newton stalls
/// from the layout and, without the start from taut, the relaxation runs;
/// with it (`taut`), none does. Checked against balances by hand: the
/// chain's torque on the wheel, Σ (rᵢ − c) × (links' pull + weight) over
/// the rollers near its pitch circle (each in balance with the teeth;
/// links' forces K (ℓ − ℓ₀) from the positions), equals the load's
/// 100 N·m within 10⁻⁴; the arm's spring (60 N preload, 5000 N/m) pushes
/// nothing at rest, so its travel is 60 / 5000 = 12 mm within 1 µm.
#[test]
fn the_free_arm_drive_settles_from_taut_without_relaxing() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/user_moto_10b_free_arm.toml"
    );
    let text = std::fs::read_to_string(path).expect("the scene file exists");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let relaxations = |off: bool| {
        super::taut::OFF.with(|o| o.set(off));
        let before = super::RELAXATIONS.with(std::cell::Cell::get);
        let sim = crate::sim::Simulation::new(&scene).expect("a rest state");
        super::taut::OFF.with(|o| o.set(false));
        (super::RELAXATIONS.with(std::cell::Cell::get) - before, sim)
    };
    // Without the start from taut, Newton stalls and the relaxation runs.
    let (without, _) = relaxations(true);
    assert!(
        without > 0,
        "{without} relaxations without the start from taut"
    );
    let (with, sim) = relaxations(false);
    assert_eq!(with, 0, "{:?}", sim.equilibrium);
    let model = sim.model();
    let state = &sim.state;
    let n = state.x.len();
    let (k, l0, m) = (
        model.stiffness_n_m,
        model.rest_length_m,
        model.roller_mass_kg,
    );
    let [gx, gy] = model.gravity_m_s2;
    let wheel = &scene.sprockets[1];
    let c = wheel.center_m;
    let near =
        |i: usize| (state.x[i] - c[0]).hypot(state.y[i] - c[1]) < wheel.pitch_radius_m + 2e-3;
    let mut torque = 0.0;
    let mut counted = 0;
    for i in (0..n).filter(|&i| near(i)) {
        let mut f = [m * gx, m * gy];
        for j in [(i + 1) % n, (i + n - 1) % n] {
            let (dx, dy) = (state.x[j] - state.x[i], state.y[j] - state.y[i]);
            let l = dx.hypot(dy);
            let pull = k * (l - l0) / l;
            f[0] += pull * dx;
            f[1] += pull * dy;
        }
        torque += (state.x[i] - c[0]) * f[1] - (state.y[i] - c[1]) * f[0];
        counted += 1;
    }
    assert!(counted > 20, "{counted} rollers near the wheel");
    let load = wheel.load_torque_n_m();
    assert!(
        (torque + load).abs() <= 1e-4 * load.abs(),
        "chain torque {torque} N·m against the load {load} N·m"
    );
    let arm = &sim.forces.output().tensioners[0];
    assert!(
        (arm.travel_m - 60.0 / 5000.0).abs() <= 1e-6,
        "travel {} m, push {} N",
        arm.travel_m,
        arm.plunger_force_n
    );
}
