//! The extension seam of a co-simulated drive: a user's force element and
//! scalar state act inside the substeps.

use super::cosim_tests::conveyor;
use crate::cosim::ChainDrive;
use crate::forces::{ForceElement, Forces};
use crate::model::{DriveModel, DriveState, ScalarModel};
use rapier2d_f64::prelude::*;

/// Viscous drag −c·v on every roller inside a band x ∈ [x_lo, x_hi]; the
/// power it takes is the rate of scalar `energy` (the energy dissipated, J).
#[derive(Clone, Debug)]
struct DragZone {
    c_n_s_m: f64,
    x_lo_m: f64,
    x_hi_m: f64,
    energy: usize,
}

impl ForceElement for DragZone {
    fn name(&self) -> &'static str {
        "drag zone"
    }

    fn evaluate(&mut self, _model: &DriveModel, state: &DriveState, out: &mut Forces) {
        let mut power_w = 0.0;
        for i in 0..state.rollers() {
            if (self.x_lo_m..=self.x_hi_m).contains(&state.x[i]) {
                let (vx, vy) = (state.vx[i], state.vy[i]);
                out.fx[i] -= self.c_n_s_m * vx;
                out.fy[i] -= self.c_n_s_m * vy;
                power_w += self.c_n_s_m * (vx * vx + vy * vy);
            }
        }
        out.scalar_rate[self.energy] += power_w;
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

const FRAME_S: f64 = 1.0 / 60.0;
/// Frames before the mean (driver ramp 0.2 s, then the drag's transient).
const SETTLE_FRAMES: usize = 60;
/// Frames averaged: 0.5 s, ten roller pitches at 60 rpm.
const MEAN_FRAMES: usize = 30;

/// The driver's mean chain torque over the window, N·m, and the scalar's
/// growth over it (J) when `drag` is given.
fn run(drag: Option<f64>) -> (f64, f64) {
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0);
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..Default::default()
    };
    w.integration_parameters.dt = FRAME_S;
    let mut drive = ChainDrive::builder(&scene).build(&mut w).expect("drive");
    if let Some(c) = drag {
        let energy = drive.add_scalar(
            ScalarModel {
                name: "dissipated".into(),
                error_scale: 1.0,
            },
            0.0,
        );
        assert_eq!(energy, 0);
        drive.add_force_element(Box::new(DragZone {
            c_n_s_m: c,
            x_lo_m: -1.0,
            x_hi_m: 2.0,
            energy,
        }));
    }
    for _ in 0..SETTLE_FRAMES {
        drive.step_world(&mut w, &(), &()).expect("frame");
    }
    let z0 = drive.state().z.first().copied().unwrap_or(0.0);
    let mut torque = 0.0;
    for _ in 0..MEAN_FRAMES {
        drive.step_world(&mut w, &(), &()).expect("frame");
        torque += drive.forces().chain_torque[0];
    }
    let z1 = drive.state().z.first().copied().unwrap_or(0.0);
    (torque / MEAN_FRAMES as f64, z1 - z0)
}

#[test]
fn a_drag_zone_in_a_cosimulated_conveyor_costs_the_driver_c_n_v_r() {
    // Closed form: drag −c·v on each of the N rollers (the zone holds the
    // whole chain) dissipates c·N·v², with every roller at the chain speed
    // v = ω·r; the driver at ω pays it as a torque T = c·N·v²/ω = c·N·ω·r².
    // r lies between the mean strand radius z·p/(2π) and the pitch radius
    // p/(2 sin(π/z)) (the polygon's speed ripple): 0.4 % apart, so r² is
    // taken at their mean and the test holds 3 %. The scalar, advanced in
    // the substeps, must hold the same energy: T·ω·Δt.
    let c = 1.0;
    let (n, p, z) = (100.0, 0.0254, 20.0_f64);
    let omega = 2.0 * std::f64::consts::PI;
    let r =
        0.5 * (z * p / (2.0 * std::f64::consts::PI) + p / (2.0 * (std::f64::consts::PI / z).sin()));
    let expected_n_m = c * n * omega * r * r;
    let (free, _) = run(None);
    let (dragged, energy_j) = run(Some(c));
    // The chain's torque on the driver: more negative by T.
    let extra = free - dragged;
    assert!(
        // Frame-end samples of a torque with the polygon's ripple (one
        // pitch = 3 frames: three phases) scatter by ~10 %; without the
        // element acting on the chain the difference would be 0.
        (extra / expected_n_m - 1.0).abs() < 0.15,
        "torque {extra} N·m against {expected_n_m}"
    );
    let window_s = MEAN_FRAMES as f64 * FRAME_S;
    let expected_j = expected_n_m * omega * window_s;
    assert!(
        (energy_j / expected_j - 1.0).abs() < 0.03,
        "energy {energy_j} J against {expected_j}"
    );
}

/// A spring −k·q on the user's body 0: a harmonic oscillator beside the chain.
#[derive(Clone, Debug)]
struct Spring {
    stiffness_n_m: f64,
}

impl ForceElement for Spring {
    fn name(&self) -> &'static str {
        "spring"
    }

    fn evaluate(&mut self, _model: &DriveModel, state: &DriveState, out: &mut Forces) {
        out.body_force[0] -= self.stiffness_n_m * state.q[0];
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

#[test]
fn a_drive_in_a_set_advances_its_own_users_body_in_the_substeps() {
    // A 0.1 kg body on a 395 N/m spring (ω = √(k/m) = 62.8 rad/s, 10 Hz) in
    // drive A of a set of two conveyors: q(t) = q₀ cos ωt. A frame of 1/60 s
    // is a sixth of its period (ω·dt = 1.05): advanced once per frame by
    // symplectic Euler its phase would err by ~10 % a period; in the 1e-5 s
    // substeps it follows the closed form to 1e-3 of q₀ over a second.
    // Drive B, without the element, has no user body.
    use crate::cosim::DriveSet;
    use crate::model::BodyModel;
    let (mass_kg, k_n_m, q0_m) = (0.1, 394.784_176_043_574_3, 0.01); // k = m (2π·10)²
    let omega = (k_n_m / mass_kg).sqrt();
    let a = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0);
    let b = conveyor("role = \"driver\"\nspeed_rpm = 30.0\nramp_s = 0.2", 0.0);
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..Default::default()
    };
    w.integration_parameters.dt = FRAME_S;
    let mut set = DriveSet::new();
    set.push(ChainDrive::builder(&a).build(&mut w).expect("A"));
    set.push(
        ChainDrive::builder(&b)
            .insert_at(Pose::translation(0.0, 1.0))
            .build(&mut w)
            .expect("B"),
    );
    let drive = &mut set.drives_mut()[0];
    let body = drive.add_body(
        BodyModel {
            name: "oscillator".into(),
            inv_mass: 1.0 / mass_kg,
            error_scale: 1e-3,
        },
        q0_m,
        0.0,
    );
    assert_eq!(body, 0);
    drive.add_force_element(Box::new(Spring {
        stiffness_n_m: k_n_m,
    }));
    let mut worst = 0.0f64;
    for _ in 0..60 {
        set.step_world(&mut w, &(), &()).expect("frame");
        let s = set.drives()[0].state();
        let exact = q0_m * (omega * s.t_s).cos();
        worst = worst.max((s.q[0] - exact).abs());
    }
    assert!(worst < 1e-3 * q0_m, "off the closed form by {worst} m");
    assert!(set.drives()[1].state().q.is_empty());
}
