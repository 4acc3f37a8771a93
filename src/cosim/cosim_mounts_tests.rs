//! Mounted bodies that translate: a carriage carrying the conveyor's tail,
//! held out by a spring, moves with the chain inside the substeps.

use super::cosim_tests::conveyor;
use crate::cosim::{ChainDrive, CosimError, Coupling, MountForce, MountSpring};
use rapier2d_f64::prelude::*;

/// The conveyor's tail centre, m (40 pitches of 25.4 mm from the driver).
const TAIL_X_M: f64 = 1.016;

/// The conveyor's chain pretension, N.
const PRETENSION_N: f64 = 200.0;

/// The spring's rate, N/m.
const SPRING_N_M: f64 = 2e5;

fn world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

/// Runs `frames` at 60 Hz of the motor-driven conveyor (60 rpm, ramped in
/// over 0.2 s) with its tail on a carriage of `mass_kg` held by a spring of
/// `SPRING_N_M` preloaded to twice the pretension; the spring's force set each frame the way rapier documents it
/// (`reset_forces`, then `add_force`); the largest excursion of
/// the carriage from the tail's centre, m.
fn run_carriage(mass_kg: f64, frames: usize) -> Result<f64, CosimError> {
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0);
    let preload_n = 2.0 * PRETENSION_N;
    let mut w = world();
    // Free along the chain's line only; the scene's sprocket inertia.
    let cart = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(TAIL_X_M, 0.0))
            .enabled_translations(true, false)
            .additional_mass_properties(MassProperties::new(Vector::ZERO, mass_kg, 0.01)),
    );
    let mut drive =
        ChainDrive::insert(&scene, &[None, Some(cart)], &mut w.bodies, &mut w.colliders)?;
    let mut worst = 0.0f64;
    for _ in 0..frames {
        let x = w.bodies[cart].translation().x;
        let b = &mut w.bodies[cart];
        b.reset_forces(false);
        b.add_force(
            Vector::new(preload_n - SPRING_N_M * (x - TAIL_X_M), 0.0),
            true,
        );
        drive.step_world(&mut w, &(), &())?;
        let p = w.bodies[cart].translation();
        worst = worst.max((p.x - TAIL_X_M).hypot(p.y));
    }
    Ok(worst)
}

#[test]
fn a_light_sprung_carriage_holds_at_60_hz() {
    // The spring's preload balances the two strands' pull on the tail, 2 T0
    // = 400 N (force balance on the sprocket; the sag's vertical share is
    // below 1 %), so the carriage should stay at the tail's centre: an
    // imbalance ΔF moves it ΔF / (k_chain + k_spring), k_chain = 2 k / 50 =
    // 4e5 N/m for two strands of 50 links of 1e7 N/m, 6e5 N/m with the
    // spring (a 20 % imbalance, 80 N, is 0.13 mm). The 2 mm tolerance is
    // the hold asked of a tensioner. Its translation integrated once per
    // frame by rapier, a 2 kg carriage has ω dt = √(6e5 / 2) / 60 ≈ 9 > 2
    // against the chain and blew up at 0.033 s (penetration).
    for mass_kg in [1.0, 2.0] {
        let worst = run_carriage(mass_kg, 120).unwrap_or_else(|e| panic!("{mass_kg} kg: {e}"));
        assert!(worst < 0.002, "{mass_kg} kg: the carriage moved {worst} m");
    }
}

/// The spring's force law on the carriage (`ChainDrive::set_mount_force`):
/// evaluated in every substep at the carriage's position there.
fn spring() -> MountSpring {
    MountSpring {
        anchor_m: Vector::new(TAIL_X_M, 0.0),
        axis: Vector::X,
        stiffness_n_m: SPRING_N_M,
        damping_n_s_m: 0.0,
        preload_n: 2.0 * PRETENSION_N,
    }
}

/// Like [`run_carriage`], with the spring given to the drive as the
/// carriage's force law; `release`: the frame after which another law
/// replaces it. The carriage's x at the end of every frame, m.
fn run_sprung<L: MountForce + Clone + 'static>(
    mass_kg: f64,
    frames: usize,
    release: Option<(usize, L)>,
) -> Result<Vec<f64>, CosimError> {
    run_sprung_with(mass_kg, frames, release, false)
}

/// [`run_sprung`], the circular teeth with their tips
/// ([`Coupling::tooth_tips`]) where `tips`.
fn run_sprung_with<L: MountForce + Clone + 'static>(
    mass_kg: f64,
    frames: usize,
    release: Option<(usize, L)>,
    tips: bool,
) -> Result<Vec<f64>, CosimError> {
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0);
    let mut w = world();
    let cart = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(TAIL_X_M, 0.0))
            .enabled_translations(true, false)
            .additional_mass_properties(MassProperties::new(Vector::ZERO, mass_kg, 0.01)),
    );
    let mut drive =
        ChainDrive::insert(&scene, &[None, Some(cart)], &mut w.bodies, &mut w.colliders)?;
    let tail = drive.sprocket(1)?;
    drive.set_mount_force(tail, spring())?;
    drive.set_coupling(Coupling {
        tooth_tips: tips,
        ..*drive.coupling()
    })?;
    let mut xs = Vec::with_capacity(frames);
    for frame in 0..frames {
        if let Some((_, law)) = release.as_ref().filter(|r| r.0 == frame) {
            drive.set_mount_force(tail, law.clone())?;
        }
        drive.step_world(&mut w, &(), &())?;
        xs.push(w.bodies[cart].translation().x);
    }
    Ok(xs)
}

fn largest_excursion(xs: &[f64]) -> f64 {
    xs.iter().map(|x| (x - TAIL_X_M).abs()).fold(0.0, f64::max)
}

#[test]
fn every_carriage_mass_holds_with_its_spring_in_the_substeps() {
    // The same balance as `a_light_sprung_carriage_holds_at_60_hz` (preload
    // 2 T0 = 400 N against the two strands' pull; an imbalance ΔF moves the
    // carriage ΔF / 6e5 N/m, 20 % of it 0.13 mm; tolerance 2 mm). The spring
    // as a force set once per frame is a zero-order hold on a carriage that
    // moves inside the frame: measured, 5, 20 and 50 kg carriages blew up
    // (at 0.69, 0.53 and 0.87 s) and 200 kg swung 3.2 mm. Given to the
    // substeps, the spring acts where the carriage is.
    for mass_kg in [1.0, 2.0, 5.0, 20.0, 50.0, 200.0] {
        let xs = run_sprung::<MountSpring>(mass_kg, 120, None)
            .unwrap_or_else(|e| panic!("{mass_kg} kg: {e}"));
        let worst = largest_excursion(&xs);
        assert!(worst < 0.002, "{mass_kg} kg: the carriage moved {worst} m");
    }
}

#[test]
fn a_carriage_released_onto_its_damper_moves_on_without_a_blow_up() {
    // 1, 5 and 20 kg carriages held by their spring for 0.5 s, then
    // released onto a damper alone (c = 5000 N·s/m, no spring): the strands'
    // pull, 2 T0 = 400 N at most, draws the carriage in at no more than the
    // damper's terminal speed 2 T0 / c = 0.08 m/s, by more than the chain's
    // elastic stretch 2 T0 / k_chain = 400 / 4e5 = 1 mm (then the sag's
    // pull, a few newtons, keeps it creeping in): every frame moves it
    // inwards, by less than that speed allows. (Released onto nothing:
    // `a_carriage_released_onto_nothing_moves_on_without_a_blow_up`.)
    let (hold, frames, c) = (30, 120, 5000.0);
    let v_max = 2.0 * PRETENSION_N / c;
    let dt = 1.0 / 60.0;
    for mass_kg in [1.0, 5.0, 20.0] {
        let damper = MountSpring {
            stiffness_n_m: 0.0,
            damping_n_s_m: c,
            preload_n: 0.0,
            ..spring()
        };
        let xs = run_sprung(mass_kg, frames, Some((hold, damper)))
            .unwrap_or_else(|e| panic!("{mass_kg} kg: {e}"));
        let travel = xs[hold - 1] - xs[frames - 1];
        assert!(
            travel > 2.0 * PRETENSION_N / 4e5,
            "{mass_kg} kg: moved in by {travel} m only"
        );
        for f in hold + 1..frames {
            let step = xs[f - 1] - xs[f];
            assert!(
                step > 0.0 && step < v_max * dt,
                "{mass_kg} kg, frame {f}: moved {step} m inwards"
            );
        }
    }
}

/// Runs `frames` at 60 Hz with the tail on a hub turning on a revolute joint
/// to a carriage of `mass_kg` that slides along x on a prismatic joint to
/// the ground, its spring the joint's position motor (force-based, 2e5 N/m,
/// target = preload / rate beyond the tail's centre, so 2 T0 at the centre).
/// The largest excursion of the carriage from the tail's centre, m.
fn run_prismatic(mass_kg: f64, frames: usize) -> Result<f64, CosimError> {
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0);
    let mut w = world();
    let ground = w.bodies.insert(RigidBodyBuilder::fixed());
    let cart = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(TAIL_X_M, 0.0))
            .additional_mass_properties(MassProperties::new(Vector::ZERO, mass_kg, 0.01)),
    );
    let hub = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(TAIL_X_M, 0.0))
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 0.1, 0.01)),
    );
    let mut slide = PrismaticJointBuilder::new(Vector::X)
        .local_anchor1(Vector::new(TAIL_X_M, 0.0))
        .motor_position(2.0 * PRETENSION_N / SPRING_N_M, SPRING_N_M, 0.0)
        .motor_model(MotorModel::ForceBased)
        .build();
    slide.data.set_motor_max_force(JointAxis::LinX, f64::MAX);
    w.impulse_joints.insert(ground, cart, slide, true);
    w.impulse_joints
        .insert(cart, hub, RevoluteJointBuilder::new(), true);
    let mut drive =
        ChainDrive::insert(&scene, &[None, Some(hub)], &mut w.bodies, &mut w.colliders)?;
    let mut worst = 0.0f64;
    for _ in 0..frames {
        drive.step_world(&mut w, &(), &())?;
        let p = w.bodies[cart].translation();
        let h = w.bodies[hub].translation();
        worst = worst
            .max((p.x - TAIL_X_M).hypot(p.y))
            .max((h.x - TAIL_X_M).hypot(h.y));
    }
    Ok(worst)
}

#[test]
fn a_carriage_on_a_prismatic_joint_with_a_position_motor_holds() {
    // The motor is the spring (2e5 N/m, 400 N at the tail's centre), so the
    // same balance as the sprung carriage: within 2 mm. The joint's motor
    // acted in rapier's step only, once per frame on the carriage alone
    // (measured: a 5 kg carriage's offset flipped sign and grew ×2.7 per
    // frame, and the hub on its revolute joint met the chain explicitly, a
    // blow-up in the first frames); now the carriage, the hub and the motor
    // move with the chain in the substeps. (A carriage inserted with the
    // drive has no mass properties before rapier's first step: read as
    // fixed, it was left to rapier in the first frame and thrown 63 mm.)
    for mass_kg in [1.0, 2.0, 5.0, 20.0] {
        let worst = run_prismatic(mass_kg, 120).unwrap_or_else(|e| panic!("{mass_kg} kg: {e}"));
        assert!(worst < 0.002, "{mass_kg} kg: the carriage moved {worst} m");
    }
}

#[test]
fn a_mount_whose_rotation_a_prismatic_joint_locks_is_an_error() {
    // The sprocket on the carriage itself: the prismatic joint locks the
    // body's rotation, so the sprocket could not turn (measured before: the
    // tail turned at 0.8 rad/s while the head turned at 2.0, the chain
    // sliding over it). An error naming the mount and the cure.
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.2", 0.0);
    let mut w = world();
    let ground = w.bodies.insert(RigidBodyBuilder::fixed());
    let cart = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(TAIL_X_M, 0.0))
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 5.0, 0.01)),
    );
    w.impulse_joints.insert(
        ground,
        cart,
        PrismaticJointBuilder::new(Vector::X).local_anchor1(Vector::new(TAIL_X_M, 0.0)),
        true,
    );
    let mut drive =
        ChainDrive::insert(&scene, &[None, Some(cart)], &mut w.bodies, &mut w.colliders)
            .expect("insert");
    let e = drive
        .step_world(&mut w, &(), &())
        .expect_err("a locked sprocket");
    let text = e.to_string();
    assert!(text.contains("mounts[1]"), "{text}");
    assert!(text.contains("rotation"), "{text}");
    assert!(text.contains("revolute joint"), "{text}");
}

/// A carriage's end of travel `travel_m` inwards of the tail's centre: a
/// stiff one-sided spring–damper (1e6 N/m, 2000 N·s/m), no force before it.
#[derive(Clone, Copy)]
struct EndStop {
    travel_m: f64,
}

impl MountForce for EndStop {
    fn force(&self, position_m: Vector, velocity_m_s: Vector, _t_s: f64) -> Vector {
        let over = TAIL_X_M - self.travel_m - position_m.x;
        if over > 0.0 {
            Vector::new((1e6 * over - 2000.0 * velocity_m_s.x).max(0.0), 0.0)
        } else {
            Vector::ZERO
        }
    }
}

#[test]
fn a_carriage_released_onto_nothing_moves_on_without_a_blow_up() {
    // 1, 5 and 20 kg carriages held by their spring for 0.5 s, then released
    // onto nothing but an end of travel 0.1 m in (`EndStop`), for 2 s at 60
    // Hz. The strands' pull, 2 T0 = 400 N, draws the carriage in; its
    // energy comes from the chain's elastic stretch, ½ k_chain x² = 0.2 J
    // (k_chain = 4e5 N/m, x = 2 T0 / k_chain = 1 mm), and, as the strands go
    // slack and sag, from their fall: 0.2 m of slack (twice the travel) hung
    // as two parabolas of span S = 1.016 m lets each strand sag by at most
    // d = √(3 S ΔL / 8) = 0.195 m (ΔL = 0.1 m each; an even split is the
    // largest), its centre of mass falling 2 d / 3, so 2 × 0.8 kg × g ×
    // 0.13 m = 2.04 J at most (the energy is concave in the split). So the
    // carriage moves in every frame until it reaches its stop, never faster
    // than √(2 × 2.24 J / m) (2.1, 0.95, 0.47 m/s; the driver's work on the
    // slack chain is left out, the chain's own motion too), and reaches the
    // stop within the 2 s. Measured before: released onto nothing, the
    // carriage blew up within 0.04 s (1 kg: link 44 stretched 3.3 mm at
    // 0.53 s), at 60, 240 and 1000 Hz and at dt 2.5 µs, because a roller
    // sliding over a tooth at its seat's centre radius met the circular
    // seating arc at 1.2 mm depth at once (docs/model.md, "Tooth tips");
    // with the tips (`Coupling::tooth_tips`) it meets the tooth's tip first.
    // Without them the same run still blows up (checked below).
    let (hold, frames, travel_m) = (30, 150, 0.1);
    let stretch_j = 0.5 * 4e5 * (2.0 * PRETENSION_N / 4e5f64).powi(2);
    let sag_m = (3.0 * 1.016 * travel_m / 8.0f64).sqrt();
    let fall_j = 2.0 * 40.0 * 0.02 * 9.81 * 2.0 * sag_m / 3.0;
    let dt = 1.0 / 60.0;
    for mass_kg in [1.0, 5.0, 20.0] {
        let xs = run_sprung_with(mass_kg, frames, Some((hold, EndStop { travel_m })), true)
            .unwrap_or_else(|e| panic!("{mass_kg} kg: {e}"));
        let v_max = (2.0 * (stretch_j + fall_j) / mass_kg).sqrt();
        let stop = TAIL_X_M - travel_m;
        let arrival = (hold..frames)
            .find(|&f| xs[f] < stop + 1e-3)
            .unwrap_or_else(|| {
                panic!("{mass_kg} kg: not at its stop after 2 s: {:?}", &xs[hold..])
            });
        for f in hold..frames {
            let v = (xs[f - 1] - xs[f]) / dt;
            assert!(
                v.abs() < v_max,
                "{mass_kg} kg, frame {f}: {v} m/s, more than {v_max} m/s"
            );
            assert!(
                f > arrival || v > 0.0,
                "{mass_kg} kg, frame {f}: moved out at {v} m/s before its stop"
            );
        }
    }
    let without = run_sprung_with(1.0, frames, Some((hold, EndStop { travel_m })), false);
    assert!(without.is_err(), "without the tips: {without:?}");
}
