//! The force-element seam: further bodies and scalar states advanced by
//! every integrator under forces from an element of the user's, and the
//! blow-up detectors' reports.

use crate::forces::{ForceElement, Forces};
use crate::model::{BodyModel, DriveModel, DriveState, ScalarModel};
use crate::scene::{Integrator, Overrides, Scene};
use crate::sim::{BlowUpLimits, SimError, Simulation, check_blow_up};
use std::any::Any;

/// A linear spring on body coordinate 0 (Q = −k q) and a first-order decay
/// of scalar state 0 (ż = −z / τ): nothing to do with the chain.
#[derive(Clone, Debug)]
struct Oscillator {
    stiffness: f64,
    tau_s: f64,
}

impl ForceElement for Oscillator {
    fn name(&self) -> &'static str {
        "oscillator"
    }

    fn evaluate(&mut self, _model: &DriveModel, state: &DriveState, out: &mut Forces) {
        out.body_force[0] += -self.stiffness * state.q[0];
        out.scalar_rate[0] += -state.z[0] / self.tau_s;
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

#[test]
fn every_integrator_advances_further_bodies_and_scalar_states() {
    // Closed forms: q(t) = q₀ cos(ω t), ω = √(k/m), from rest; z(t) = z₀ e^(−t/τ).
    // m = 2 kg, k = 2000 N/m: ω = 31.6 rad/s (period 0.2 s); τ = 20 ms.
    // Over 0.05 s at dt = 10 µs every scheme is well within 1e-3 of the
    // amplitude and 1 % of z (the first-order schemes' error is about
    // ω² t dt / 2 ≈ 2.5e-4 and t dt / (2 τ²) ≈ 6e-3 respectively).
    let (mass, stiffness, tau, q0, z0) = (2.0, 2000.0, 0.02, 0.01, 1.0);
    let omega = f64::sqrt(stiffness / mass);
    for scheme in [
        Integrator::SymplecticEuler,
        Integrator::VelocityVerlet,
        Integrator::Rk4,
        Integrator::DormandPrince45,
        Integrator::ImplicitDamping,
    ] {
        let scene = Scene::l60mc()
            .with(&Overrides {
                integrator: Some(scheme),
                ..Overrides::default()
            })
            .expect("a valid scheme");
        let mut sim = Simulation::new(&scene).expect("the paper's drive settles");
        let body = sim.add_body(
            BodyModel {
                name: "test arm".to_owned(),
                inv_mass: 1.0 / mass,
                error_scale: 1e-5,
            },
            q0,
            0.0,
        );
        let scalar = sim.add_scalar(
            ScalarModel {
                name: "test pressure".to_owned(),
                error_scale: 1e-5,
            },
            z0,
        );
        sim.add_force_element(Box::new(Oscillator {
            stiffness,
            tau_s: tau,
        }));
        assert!(sim.forces.element::<Oscillator>().is_some());
        let dt = 1e-5;
        let steps = 5000;
        for _ in 0..steps {
            sim.step(dt).expect("step");
        }
        let t = steps as f64 * dt;
        let q = sim.state.q[body];
        let z = sim.state.z[scalar];
        let q_exact = q0 * (omega * t).cos();
        let z_exact = z0 * (-t / tau).exp();
        assert!(
            (q - q_exact).abs() < 1e-3 * q0,
            "{scheme:?}: q = {q}, closed form {q_exact}"
        );
        assert!(
            ((z - z_exact) / z_exact).abs() < 0.01,
            "{scheme:?}: z = {z}, closed form {z_exact}"
        );
    }
}

/// The body named by a blow-up report.
fn blamed(result: Result<(), SimError>) -> String {
    match result {
        Err(SimError::BlowUp { body, .. }) => body,
        other => panic!("expected a blow-up, got {other:?}"),
    }
}

#[test]
fn blow_up_names_the_deepest_roller_not_the_one_with_the_largest_force() {
    // Two rollers seated on the crankshaft sprocket, pushed towards its
    // centre: roller a by 3 mm and separating at 1 m/s (its damped force
    // clamps to zero), roller b by 2 mm at rest (the larger force).
    let mut sim = Simulation::new(&Scene::l60mc()).expect("settles");
    let seated: Vec<usize> = (0..sim.state.rollers())
        .filter(|&i| sim.forces.output().touching[i])
        .filter(|&i| {
            let c = sim.model.sprockets[0].center_m;
            let (dx, dy) = (sim.state.x[i] - c[0], sim.state.y[i] - c[1]);
            (dx * dx + dy * dy).sqrt() < 1.0
        })
        .collect();
    let (a, b) = (seated[2], seated[6]);
    let c = sim.model.sprockets[0].center_m;
    for (i, push_m, speed_m_s) in [(a, 3e-3, 1.0), (b, 2e-3, 0.0)] {
        let (dx, dy) = (sim.state.x[i] - c[0], sim.state.y[i] - c[1]);
        let r = (dx * dx + dy * dy).sqrt();
        let (ux, uy) = (dx / r, dy / r);
        sim.state.x[i] -= push_m * ux;
        sim.state.y[i] -= push_m * uy;
        sim.state.vx[i] = speed_m_s * ux;
        sim.state.vy[i] = speed_m_s * uy;
    }
    sim.forces.evaluate(&sim.model, &sim.state);
    let out = sim.forces.output();
    assert!(out.contact_force[b] > out.contact_force[a], "the set-up");
    let limits = BlowUpLimits {
        max_penetration_m: 1e-3,
        max_stretch_m: 1.0,
        ..BlowUpLimits::for_scene(&sim.scene)
    };
    let body = blamed(check_blow_up(&sim.model, &sim.state, &sim.forces, &limits));
    assert_eq!(body, format!("roller {a}"));
}

#[test]
fn blow_up_names_the_most_stretched_link_not_the_one_with_the_largest_force() {
    // On a free strand: roller r moved 0.1 mm along its link (link r − 1
    // stretched most), roller s = r + 8 moving at 1 m/s along its link with
    // very strong link damping (link s − 1 carries the largest force).
    let mut sim = Simulation::new(&Scene::l60mc()).expect("settles");
    let n = sim.state.rollers();
    let free = |i: usize| !sim.forces.output().touching[i % n];
    let r = (1..n - 12)
        .find(|&r| (r - 1..=r + 10).all(free))
        .expect("a free strand of 12 rollers");
    let s = r + 8;
    let along = |state: &DriveState, i: usize| {
        let (dx, dy) = (state.x[i] - state.x[i - 1], state.y[i] - state.y[i - 1]);
        let l = (dx * dx + dy * dy).sqrt();
        (dx / l, dy / l)
    };
    let (ux, uy) = along(&sim.state, r);
    sim.state.x[r] += 1e-4 * ux;
    sim.state.y[r] += 1e-4 * uy;
    let (ux, uy) = along(&sim.state, s);
    sim.state.vx[s] = ux;
    sim.state.vy[s] = uy;
    sim.model.damping_n_s_m = 1e9;
    sim.forces.evaluate(&sim.model, &sim.state);
    let force = &sim.forces.output().link_force;
    assert!(force[s - 1].abs() > force[r - 1].abs(), "the set-up");
    let limits = BlowUpLimits {
        max_penetration_m: 1.0,
        max_stretch_m: 5e-5,
        ..BlowUpLimits::for_scene(&sim.scene)
    };
    let body = blamed(check_blow_up(&sim.model, &sim.state, &sim.forces, &limits));
    assert_eq!(body, format!("link {}", r - 1));
}

#[test]
fn a_drive_without_a_driver_has_none() {
    // The conveyor scene's sprockets are both free (a co-simulated motor
    // turns the head): no sprocket may stand in for a driver.
    let scene = Scene::from_toml(include_str!("../../assets/conveyor.toml")).expect("scene");
    let (model, _, _) = DriveModel::build(&scene).expect("layout");
    assert_eq!(model.driver(), None);
    let paper = DriveModel::build(&Scene::l60mc()).expect("layout").0;
    assert_eq!(paper.driver(), Some(0));
}
