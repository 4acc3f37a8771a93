//! Pin–bushing joint friction and where the power goes: field errors, every
//! integrator and stepping, the energy balance and the friction loss against
//! a closed form (docs/model.md, “Joint friction”, “Where the power goes”).

use chaindrive::analysis::{RunSummary, Signals};
use chaindrive::scene::{Integrator, L60MC_TOML, Overrides, Scene, Stepping};
use chaindrive::sim::{PowerMeans, SampleRate, Simulation};

/// The paper's drive with pin–bushing friction (`assets/l60mc-friction.toml`).
const L60MC_FRICTION_TOML: &str = include_str!("../../assets/l60mc-friction.toml");

fn error_of(text: &str) -> String {
    match Scene::from_toml(text) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("scene accepted:\n{text}"),
    }
}

fn with_chain_fields(fields: &str) -> String {
    L60MC_TOML.replace(
        "pretension_by = \"rest_length\"\n",
        &format!("pretension_by = \"rest_length\"\n{fields}\n"),
    )
}

#[test]
fn joint_friction_fields_are_checked() {
    for (fields, path, words) in [
        (
            "pin_radius_m = 0.017\njoint_friction = -0.1",
            "chain.joint_friction",
            ">= 0",
        ),
        (
            "pin_radius_m = 0.017\njoint_friction = 1.5",
            "chain.joint_friction",
            "[0, 1]",
        ),
        (
            "pin_radius_m = 0.017\njoint_friction = nan",
            "chain.joint_friction",
            "finite",
        ),
        (
            "pin_radius_m = 0.027\njoint_friction = 0.1",
            "chain.pin_radius_m",
            "smaller than chain.roller_radius_m",
        ),
        ("joint_friction = 0.1", "chain.pin_radius_m", "is needed"),
        (
            "pin_radius_m = 0.017\njoint_friction = 0.1\njoint_friction_speed_rad_s = 0.0",
            "chain.joint_friction_speed_rad_s",
            "> 0",
        ),
        (
            "joint_damping_n_m_s_rad = -1.0",
            "chain.joint_damping_n_m_s_rad",
            ">= 0",
        ),
    ] {
        let e = error_of(&with_chain_fields(fields));
        assert!(e.contains(path) && e.contains(words), "{fields}: {e}");
    }
}

/// The friction scene shortened to `duration_s`, with `integrator` and `stepping`.
fn friction_scene(duration_s: f64, integrator: Integrator, stepping: Stepping) -> Scene {
    Scene::from_toml(L60MC_FRICTION_TOML)
        .expect("the friction scene is valid")
        .with(&Overrides {
            duration_s: Some(duration_s),
            integrator: Some(integrator),
            stepping: Some(stepping),
            ..Overrides::default()
        })
        .expect("valid overrides")
}

#[test]
fn joint_friction_runs_under_every_integrator_and_stepping() {
    // 20 ms from static equilibrium: no blow-up, finite forces, and the
    // friction dissipates (a negative power in the last evaluation or zero
    // at rest, never positive).
    let mut cases: Vec<(Integrator, Stepping)> = [
        Integrator::SymplecticEuler,
        Integrator::VelocityVerlet,
        Integrator::Rk4,
        Integrator::DormandPrince45,
        Integrator::ImplicitDamping,
    ]
    .into_iter()
    .map(|i| (i, Stepping::Substepped))
    .collect();
    cases.push((Integrator::SymplecticEuler, Stepping::Rapier));
    for (integrator, stepping) in cases {
        let scene = friction_scene(0.02, integrator, stepping);
        let mut sim = Simulation::new(&scene).expect("equilibrium with friction");
        sim.run(0.02, 100, &mut chaindrive::sim::NoObserver, None)
            .unwrap_or_else(|e| panic!("{integrator:?} {stepping:?}: {e}"));
        let out = sim.forces.output();
        assert_eq!(out.joint_moment_n_m.len(), scene.chain().rollers);
        assert!(out.joint_moment_n_m.iter().all(|m| m.is_finite()));
        assert!(out.joint_friction_power_w <= 0.0, "{integrator:?}");
    }
}

/// A run of `scene` to `duration_s` counting the powers over its last
/// `window_s`; its summary and the ledger's means.
fn counted(scene: &Scene, duration_s: f64, window_s: f64) -> (RunSummary, PowerMeans) {
    let mut sim = Simulation::new(scene).expect("equilibrium");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("whole steps");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, duration_s - window_s);
    sim.track_power(duration_s - window_s);
    let out = sim
        .run(duration_s, sampling.every, &mut signals, None)
        .expect("run");
    let means = sim
        .power
        .as_ref()
        .and_then(|p| p.means())
        .expect("powers counted");
    (RunSummary::of_run(&sim, &out, &signals, 0.0), means)
}

#[test]
fn energy_balance_closes_within_one_percent_and_fails_without_any_term() {
    // Over the last 0.5 s of a 1.5 s run (after the driver's 1 s ramp):
    // P_driver = P_friction + P_links + P_contacts + P_load + ΔE/T, all
    // counted by the ledger from the forces, independently of the energy
    // (kinetic, elastic, gravity) measured at the window's ends. Tolerance:
    // 1 % of the driver's power (the summary's warning threshold).
    let scene = friction_scene(1.5, Integrator::SymplecticEuler, Stepping::Substepped);
    let (summary, p) = counted(&scene, 1.5, 0.5);
    let error = p.balance_error();
    assert!(error.abs() < 0.01, "balance error {error:e}, {p:?}");
    assert_eq!(summary.energy_balance_error, Some(error));
    assert!(
        !summary
            .warnings
            .iter()
            .any(|w| w.starts_with("power balance"))
    );
    // The test can fail: leaving out either term that carries power here
    // breaks the balance by more than the tolerance (the links' dampers
    // dissipate under 0.1 % of the driver's power on this drive, below it).
    let m = p.mean;
    let rate = p.energy_change_j / p.duration_s;
    let terms = [
        ("joint friction", m.joint_friction_w),
        ("contact damping", m.contact_damping_w),
    ];
    for (name, dropped) in terms {
        let residual = (m.driver_w - (m.losses_w() - dropped) - m.load_w - rate) / m.driver_w;
        assert!(
            residual.abs() > 0.01,
            "without {name}: residual {residual:e}"
        );
    }
}

#[test]
fn friction_power_matches_articulation_closed_form() {
    // docs/model.md, “Joint friction”: on a steady drive each joint turns by
    // 2π/z on entering and again on leaving a sprocket, z|ω|/2π times a
    // second, loaded by the strand's tension (quasi-static, Coulomb: the
    // articulation speed ≈ |ω| ≫ ω_s = 1 rad/s). So
    //     P ≈ μ r_pin Σ_s (T_in,s + T_out,s) |ω_s|,
    // T from the segments' own mean forces, |ω| from the sprockets' mean
    // speeds (neither from the friction code). The closed form leaves out the
    // strands' vibration (adds) and the tension's fall along the wrap
    // (subtracts); tolerance 25 %.
    let scene = friction_scene(2.0, Integrator::SymplecticEuler, Stepping::Substepped);
    let (summary, p) = counted(&scene, 2.0, 1.0);
    let j = scene.chain().joint_friction.expect("friction on");
    let mut predicted = 0.0;
    for strand in &summary.strands {
        let t = summary.segments[strand.segment - 1].mean_link_force_n;
        for s in [strand.from, strand.to] {
            let omega = summary.sprockets[s - 1].mean_speed_rad_s.abs();
            predicted += j.friction * j.pin_radius_m * t * omega;
        }
    }
    let measured = p.mean.joint_friction_w;
    let rel = (measured - predicted) / predicted;
    assert!(
        rel.abs() < 0.25,
        "friction power {measured:.0} W against the closed form {predicted:.0} W ({:+.1} %)",
        100.0 * rel
    );
}
