//! The integrators: observed orders of convergence on a smooth run, the
//! adaptive scheme's tolerance, energy conservation of the symplectic
//! schemes, and the implicit scheme's stability where explicit ones fail.

use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::{Integrator, L60MC_TOML, Overrides, ProfileKind, Scene};
use crate::sim::{Energy, Integration, Simulation, check_blow_up};
use crate::test_support::allocations;

/// A state to integrate from, with its model and forces.
struct Start {
    model: DriveModel,
    state: DriveState,
    forces: ForceGenerator,
    stretch_m: f64,
    scene: Scene,
}

impl Start {
    fn of(scene: &Scene) -> Self {
        let sim = Simulation::new(scene).expect("settles");
        Self {
            stretch_m: scene.chain().pretension_n / sim.model.stiffness_n_m,
            model: sim.model,
            state: sim.state,
            forces: sim.forces,
            scene: scene.clone(),
        }
    }

    /// Integrates `steps` steps of `dt_s` with `scheme`; returns the end state
    /// and how many rollers touched a sprocket after every step (min, max).
    fn integrate(
        &self,
        scheme: Integrator,
        tolerance: f64,
        dt_s: f64,
        steps: usize,
    ) -> (DriveState, (usize, usize)) {
        let mut state = self.state.clone();
        let mut forces = self.forces.clone();
        forces.evaluate(&self.model, &state);
        let mut integration = Integration::new(
            scheme,
            tolerance,
            &self.model,
            &state,
            &mut forces,
            self.stretch_m,
        );
        let limits = crate::sim::BlowUpLimits::for_scene(&self.scene);
        let (mut lo, mut hi) = (usize::MAX, 0);
        for _ in 0..steps {
            integration
                .advance(&self.model, &mut state, &mut forces, dt_s)
                .expect("step");
            check_blow_up(&self.model, &state, &forces, &limits).expect("stable");
            let touching = forces.output().touching.iter().filter(|t| **t).count();
            lo = lo.min(touching);
            hi = hi.max(touching);
        }
        (state, (lo, hi))
    }
}

/// Largest roller position difference, m.
fn distance(a: &DriveState, b: &DriveState) -> f64 {
    (0..a.rollers())
        .map(|i| (a.x[i] - b.x[i]).hypot(a.y[i] - b.y[i]))
        .fold(0.0, f64::max)
}

/// The paper's drive (real profile: a continuous contact force) at static
/// equilibrium, its free rollers set vibrating transversely (0.05 m/s in a
/// sine along the chain) — smooth, and no roller engages or leaves a tooth
/// within the 2 ms horizon (checked).
fn smooth_start() -> Start {
    let scene = Scene::l60mc()
        .with(&Overrides {
            profile: Some(ProfileKind::Real),
            ..Overrides::default()
        })
        .expect("valid scene");
    let mut start = Start::of(&scene);
    let n = start.state.rollers();
    for i in 0..n {
        if !start.forces.output().touching[i] {
            let phase = std::f64::consts::TAU * 7.0 * i as f64 / n as f64;
            start.state.vy[i] += 0.05 * phase.sin();
            start.state.vx[i] += 0.02 * phase.cos();
        }
    }
    start.forces.evaluate(&start.model, &start.state);
    start
}

#[test]
fn fixed_step_methods_converge_at_their_nominal_order() {
    const HORIZON_S: f64 = 2e-3;
    let start = smooth_start();
    // Reference: RK4 at 0.25 µs (its error, ~(ω h)⁴, is below 1e-12 m here).
    let reference_dt = 2.5e-7;
    let (reference, touching) = start.integrate(
        Integrator::Rk4,
        0.0,
        reference_dt,
        (HORIZON_S / reference_dt).round() as usize,
    );
    assert_eq!(touching.0, touching.1, "a contact began or ended");
    for (scheme, steps) in [
        (Integrator::SymplecticEuler, [4e-6, 2e-6, 1e-6]),
        (Integrator::ImplicitDamping, [4e-6, 2e-6, 1e-6]),
        (Integrator::VelocityVerlet, [8e-6, 4e-6, 2e-6]),
        (Integrator::VerletImplicitDamping, [8e-6, 4e-6, 2e-6]),
        (Integrator::Rk4, [2e-5, 1e-5, 5e-6]),
    ] {
        let errors: Vec<f64> = steps
            .iter()
            .map(|&dt| {
                let (end, touching) =
                    start.integrate(scheme, 0.0, dt, (HORIZON_S / dt).round() as usize);
                assert_eq!(
                    touching.0, touching.1,
                    "{scheme:?}: a contact began or ended"
                );
                distance(&end, &reference)
            })
            .collect();
        // Observed order from the two finer halvings, by least squares on log2.
        let order = ((errors[0] / errors[1]).log2() + (errors[1] / errors[2]).log2()) / 2.0;
        let nominal = f64::from(scheme.order());
        eprintln!("{scheme:?}: errors {errors:?} m, observed order {order:.2}");
        assert!(
            (order - nominal).abs() <= 0.3,
            "{scheme:?}: errors {errors:?} give order {order:.2}, nominal {nominal}"
        );
    }
}

#[test]
fn adaptive_scheme_meets_its_tolerance() {
    const HORIZON_S: f64 = 2e-3;
    let start = smooth_start();
    let reference_dt = 2.5e-7;
    let (reference, _) = start.integrate(
        Integrator::Rk4,
        0.0,
        reference_dt,
        (HORIZON_S / reference_dt).round() as usize,
    );
    // The tolerance is relative to the static link stretch T₀/K: a position
    // error of tol · T₀/K per step. Over the horizon's ~40 steps the global
    // error stays within a few times that, and falls with the tolerance.
    let mut previous = f64::INFINITY;
    for tol in [1e-2, 1e-3, 1e-4] {
        let (end, _) = start.integrate(Integrator::DormandPrince45, tol, 1e-4, 20);
        let error = distance(&end, &reference) / start.stretch_m;
        assert!(error <= 10.0 * tol, "tol {tol}: error {error:e} (in T₀/K)");
        assert!(
            error < previous,
            "tol {tol}: error {error:e} not below {previous:e}"
        );
        previous = error;
    }
}

/// The paper's drive with nothing driving it and nothing dissipating:
/// e = 1 (χ = 0), D = 0, every sprocket free; the chain set running at 1 m/s
/// along itself, the sprockets turning with it.
fn free_running_conservative() -> Start {
    let text = L60MC_TOML
        .replace("role = \"driver\"", "role = \"free\"")
        .replace("speed_rpm = 120.0", "")
        .replace("ramp_s = 1.0", "")
        .replace("damping_n_s_m = 250.0", "damping_n_s_m = 0.0")
        .replace("restitution = 0.0 ", "restitution = 1.0 ");
    let real = Overrides {
        profile: Some(ProfileKind::Real),
        ..Overrides::default()
    };
    let scene = Scene::from_toml_with(&text, &real).expect("valid scene");
    assert_eq!(scene.contact().restitution, 1.0);
    let mut start = Start::of(&scene);
    let (s, n) = (&mut start.state, start.model.sprockets.len());
    let rollers = s.rollers();
    for i in 0..rollers {
        let (next, prev) = ((i + 1) % rollers, (i + rollers - 1) % rollers);
        let (tx, ty) = (s.x[next] - s.x[prev], s.y[next] - s.y[prev]);
        let norm = tx.hypot(ty);
        s.vx[i] = tx / norm;
        s.vy[i] = ty / norm;
    }
    // Each sprocket turns with the rollers seated on it: ω = mean (r × v)/|r|².
    for k in 0..n {
        let c = start.model.sprockets[k].center_m;
        let (mut sum, mut count) = (0.0, 0);
        for i in 0..rollers {
            let (rx, ry) = (s.x[i] - c[0], s.y[i] - c[1]);
            if start.forces.output().touching[i] && rx.hypot(ry) < start.model.sprockets[k].reach_m
            {
                sum += (rx * s.vy[i] - ry * s.vx[i]) / (rx * rx + ry * ry);
                count += 1;
            }
        }
        s.omega[k] = sum / f64::from(count.max(1));
    }
    start.forces.evaluate(&start.model, &start.state);
    start
}

#[test]
fn symplectic_schemes_keep_the_energy_of_a_free_running_drive_bounded() {
    let start = free_running_conservative();
    let e0 = Energy::of(&start.model, &start.state, &start.forces);
    assert!(e0.kinetic_j > 100.0, "the drive is running: {e0:?}");
    for (scheme, dt) in [
        (Integrator::SymplecticEuler, 1e-5),
        (Integrator::VelocityVerlet, 1e-5),
    ] {
        let mut state = start.state.clone();
        let mut forces = start.forces.clone();
        let mut integration = Integration::new(
            scheme,
            0.0,
            &start.model,
            &state,
            &mut forces,
            start.stretch_m,
        );
        // Largest |E − E₀| relative to the kinetic energy, in each half second.
        let mut drift = [0.0f64; 2];
        let steps = (1.0 / dt) as usize;
        for k in 1..=steps {
            integration
                .advance(&start.model, &mut state, &mut forces, dt)
                .expect("step");
            if k % 100 == 0 {
                let e = Energy::of(&start.model, &state, &forces);
                let rel = ((e.total_j() - e0.total_j()) / e0.kinetic_j).abs();
                drift[usize::from(k > steps / 2)] = drift[usize::from(k > steps / 2)].max(rel);
            }
        }
        // Bounded: small, and not growing from the first half second to the second.
        assert!(
            drift[0] < 0.02 && drift[1] < 0.02,
            "{scheme:?}: drift {drift:?}"
        );
        assert!(
            drift[1] < 1.5 * drift[0] + 1e-4,
            "{scheme:?}: drift grows {drift:?}"
        );
    }
}

#[test]
fn implicit_damping_stays_accurate_where_the_explicit_step_fails() {
    // The paper's drive at 30 rpm with the approach-speed floor at 2 mm/s:
    // the Lankarani–Nikravesh damping of a slowly begun contact reaches
    // c = ¾ · 21 kN / 2 mm/s ≈ 8e6 N·s/m, so symplectic Euler needs
    // dt < 2 m_r / c ≈ 0.8 µs there (docs/model.md, “Guards” and
    // “Time scales and stability”).
    let text = L60MC_TOML
        .replace("speed_rpm = 120.0", "speed_rpm = 30.0")
        .replace(
            "min_approach_speed_m_s = 0.05",
            "min_approach_speed_m_s = 0.002",
        );
    let max_penetration = |scheme: Integrator, dt: f64| {
        let overrides = Overrides {
            integrator: Some(scheme),
            dt_s: Some(dt),
            ..Overrides::default()
        };
        let scene = Scene::from_toml_with(&text, &overrides).expect("valid scene");
        let mut sim = Simulation::new(&scene).expect("settles");
        sim.run(0.6, u64::MAX, &mut crate::sim::NoObserver, None)
            .map(|outcome| outcome.max_penetration_m)
    };
    // Reference: symplectic Euler at 5 µs (2 µs agrees with it within 0.3 %).
    let reference = max_penetration(Integrator::SymplecticEuler, 5e-6).expect("stable");
    let implicit = max_penetration(Integrator::ImplicitDamping, 5e-5).expect("stable");
    assert!(
        (implicit / reference - 1.0).abs() < 0.05,
        "implicit {implicit:e} against {reference:e}"
    );
    // Explicit at the same step: blows up (or, at best, chatters far off).
    match max_penetration(Integrator::SymplecticEuler, 5e-5) {
        Err(e) => assert!(e.to_string().contains("blow-up"), "{e}"),
        Ok(explicit) => assert!(
            explicit / reference > 1.3,
            "explicit {explicit:e} against {reference:e}: the chattering contacts should show"
        ),
    }
}

#[test]
fn no_integrator_allocates_in_the_step_loop() {
    let scene = Scene::l60mc()
        .with(&Overrides {
            profile: Some(ProfileKind::Real),
            ..Overrides::default()
        })
        .expect("valid scene");
    let start = Start::of(&scene);
    for &scheme in Integrator::ALL {
        let mut state = start.state.clone();
        let mut forces = start.forces.clone();
        let mut integration = Integration::new(
            scheme,
            1e-3,
            &start.model,
            &state,
            &mut forces,
            start.stretch_m,
        );
        let limits = crate::sim::BlowUpLimits::for_scene(&scene);
        let before = allocations::count();
        for _ in 0..2000 {
            integration
                .advance(&start.model, &mut state, &mut forces, 1e-5)
                .expect("step");
            check_blow_up(&start.model, &state, &forces, &limits).expect("stable");
        }
        let made = allocations::count() - before;
        assert_eq!(made, 0, "{scheme:?} allocated {made} times in 2000 steps");
    }
}

#[test]
fn a_run_allocates_nothing_per_step() {
    let mut sim = Simulation::new(&Scene::l60mc()).expect("settles");
    sim.run(0.001, 10, &mut crate::sim::NoObserver, None)
        .expect("warm-up");
    let before = allocations::count();
    let outcome = sim
        .run(0.021, 10, &mut crate::sim::NoObserver, None)
        .expect("stable");
    let made = allocations::count() - before;
    assert_eq!(outcome.steps, 2000);
    // Whatever a run allocates, it does not grow with its length.
    assert!(made < 20, "{made} allocations in 2000 steps");
}
