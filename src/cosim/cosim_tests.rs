//! The drive inside a user's rapier world: stepped at 1/60 s with other
//! bodies, motors and loads on mounted bodies.

use crate::cosim::{ChainDrive, Coupling};
use crate::forces::Culling;
use crate::scene::Scene;
use crate::sim::Simulation;
use approx::{abs_diff_eq, assert_abs_diff_eq};
use rapier2d_f64::prelude::*;

/// A two-sprocket horizontal conveyor: #40 chain (P = 12.7 mm would do; here
/// 25.4 mm), 20 teeth each, centres 40 pitches apart, 100 rollers.
pub fn conveyor(driver: &str, load_torque_n_m: f64) -> Scene {
    conveyor_in_gravity(-9.81, driver, load_torque_n_m)
}

/// [`conveyor`] with gravity `gravity_y` along y, m/s².
fn conveyor_in_gravity(gravity_y: f64, driver: &str, load_torque_n_m: f64) -> Scene {
    let text = format!(
        r#"
name = "conveyor"
gravity_m_s2 = [0.0, {gravity_y}]
[chain]
rollers = 100
pitch_m = 0.0254
roller_radius_m = 0.00397
roller_mass_kg = 0.02
stiffness_n_m = 1e7
damping_n_s_m = 5.0
pretension_n = 200.0
[contact]
stiffness = 2e8
restitution = 0.5
min_approach_speed_m_s = 0.1
[[sprockets]]
name = "driver"
center_m = [0.0, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
{driver}
[[sprockets]]
name = "tail"
center_m = [1.016, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
role = "free"
load_torque_n_m = {load_torque_n_m}
[solver]
dt_s = 1e-5
"#
    );
    Scene::from_toml(&text).expect("conveyor scene")
}

/// A 2 kg motor body on a fixed axle with the conveyor sprocket's 0.01 kg·m².
fn motor_body() -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic()
        .lock_translations()
        .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01))
}

fn world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

#[test]
fn paper_drive_in_a_60_hz_world_matches_the_standalone_run() {
    // The co-simulation substeps the chain by symplectic Euler; the
    // standalone run is asked for the same scheme.
    let scene = Scene::l60mc()
        .with(&crate::scene::Overrides {
            integrator: Some(crate::scene::Integrator::SymplecticEuler),
            ..Default::default()
        })
        .expect("valid");
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    let mut alone = Simulation::new(&scene).expect("standalone");
    let frames = 90; // 1.5 s
    let mut forces_cosim = Vec::new();
    let mut forces_alone = Vec::new();
    for _ in 0..frames {
        drive.step_world(&mut w, &(), &()).expect("frame");
        alone
            .run(
                drive.state().t_s,
                1_000_000,
                &mut crate::sim::NoObserver,
                None,
            )
            .expect("run");
        forces_cosim.push(drive.forces().link_force.clone());
        forces_alone.push(alone.forces.output().link_force.clone());
    }
    // Same substeps, same forces: the chain evolves as it does standalone.
    assert_abs_diff_eq!(drive.state().t_s, 1.5, epsilon = scene.solver().dt_s);
    let worst = (0..drive.state().rollers())
        .map(|i| {
            (drive.state().x[i] - alone.state.x[i]).hypot(drive.state().y[i] - alone.state.y[i])
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst:e}");
    // Segment-level: mean and peak link force over the last 30 frames within 1%.
    let stats = |rows: &[Vec<f64>]| {
        let all: Vec<f64> = rows[frames - 30..].iter().flatten().copied().collect();
        (
            all.iter().sum::<f64>() / all.len() as f64,
            all.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    let (a, b) = (stats(&forces_cosim), stats(&forces_alone));
    assert!(
        ((a.0 - b.0) / b.0).abs() < 0.01 && ((a.1 - b.1) / b.1).abs() < 0.01,
        "{a:?} vs {b:?}"
    );
    // The rapier bodies follow the chain.
    let p = w.bodies[drive.roller_bodies()[7]].translation();
    assert_abs_diff_eq!(p.x, drive.state().x[7], epsilon = 1e-9);
    assert_abs_diff_eq!(p.y, drive.state().y[7], epsilon = 1e-9);
}

#[test]
fn stock_contacts_keep_working_next_to_the_drive() {
    let scene = Scene::l60mc();
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    // A ground box beside the drive and a bouncy ball dropped on it.
    let ground = w
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(3.0, -1.0)));
    w.colliders
        .insert_with_parent(ColliderBuilder::cuboid(0.5, 0.1), ground, &mut w.bodies);
    let ball = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 0.0)));
    w.colliders.insert_with_parent(
        ColliderBuilder::ball(0.05).restitution(0.8),
        ball,
        &mut w.bodies,
    );
    let mut lowest = f64::INFINITY;
    let mut bounced_up = false;
    for _ in 0..60 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        let b = &w.bodies[ball];
        lowest = lowest.min(b.translation().y);
        bounced_up |= b.linvel().y > 1.0;
    }
    // Resting height: box top −0.9 + radius 0.05.
    assert!(lowest > -0.86, "the ball went through the box: {lowest}");
    assert!(bounced_up, "the ball did not bounce");
}

#[test]
fn motor_torque_against_a_load_gives_tension_difference_t_over_r() {
    let torque = 10.0;
    let scene = conveyor("role = \"free\"", -torque);
    let mut w = world();
    let motor = w.bodies.insert(motor_body());
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    w.bodies[motor].add_torque(torque, true);
    let (mut lower, mut upper, mut n) = (0.0, 0.0, 0.0);
    for frame in 0..180 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        if frame >= 60 {
            // Strand 1 runs along the bottom from sprocket 1 to 2, strand 2 back on top.
            let seg =
                crate::test_support::strand_means(drive.model(), drive.state(), drive.forces());
            if let [Some(a), Some(b)] = seg[..] {
                lower += a;
                upper += b;
                n += 1.0;
            }
        }
    }
    let r = drive.model().sprockets[0].pitch_radius_m;
    let diff = (upper - lower) / n;
    // Motor CCW: it pulls the upper strand (leaving the tail) tight. Each
    // sprocket's wrap (a half circle of chain at the pitch radius, mass
    // π R m_r / p, its centroid 2R/π out) turns its sprocket the way the
    // torque does, adding m_r g 2R² / p / R to the difference: 1.25 N.
    let chain = &drive.scene().chain;
    let wrap_n = chain.roller_mass_kg * 9.81 * 2.0 * r / chain.pitch_m;
    let want = torque / r + wrap_n;
    assert!(
        ((diff.abs() - want) / want).abs() < 0.02,
        "difference {diff} N, T/R + the wraps' weight = {want} N"
    );
}

#[test]
fn box_on_the_upper_strand_moves_at_chain_speed() {
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.5", 0.0);
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    let r = drive.model().sprockets[0].pitch_radius_m;
    let top = r + 0.00397;
    // A 0.1 kg box near the tail; the upper strand carries it towards the driver.
    let bx = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.9, top + 0.03)));
    w.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.025)
            .density(20.0)
            .friction(0.8),
        bx,
        &mut w.bodies,
    );
    let mut speeds = Vec::new();
    for frame in 0..75 {
        drive.step_world(&mut w, &(), &()).expect("frame");
        if frame >= 45 {
            speeds.push(w.bodies[bx].linvel().x);
        }
    }
    let v_chain = std::f64::consts::TAU * r; // 60 rpm
    let v_box = speeds.iter().sum::<f64>() / speeds.len() as f64;
    // The upper strand runs from sprocket 2 back to 1: towards −x.
    assert!(
        ((v_box + v_chain) / v_chain).abs() < 0.05,
        "box {v_box} m/s, chain {v_chain} m/s"
    );
}

#[test]
fn motor_spin_up_is_consistent_with_the_chain_reaction() {
    let torque = 1.0;
    let scene = conveyor("role = \"free\"", 0.0);
    let mut w = world();
    let motor = w.bodies.insert(motor_body());
    let mut drive =
        ChainDrive::insert(&scene, &[Some(motor)], &mut w.bodies, &mut w.colliders).expect("drive");
    w.bodies[motor].add_torque(torque, true);
    let frames = 30;
    for _ in 0..frames {
        drive.step_world(&mut w, &(), &()).expect("frame");
    }
    let t = frames as f64 / 60.0;
    let alpha = drive.state().omega[0] / t;
    // Rigid-chain estimate: J_eff = J1 + J2 (equal sprockets) + m_chain R².
    let r = drive.model().sprockets[0].pitch_radius_m;
    let j_eff = 0.01 + 0.01 + 100.0 * 0.02 * r * r;
    let expected = torque / j_eff;
    assert!(
        ((alpha - expected) / expected).abs() < 0.05,
        "α = {alpha}, expected {expected}"
    );
    // And the body the user sees turns with the chain's sprocket.
    assert!(
        (w.bodies[motor].angvel() - drive.state().omega[0]).abs()
            < 0.05 * drive.state().omega[0].abs()
    );
}

/// Pitch, roller radius, roller mass, link stiffness, rollers and centre
/// distance of [`conveyor`].
const PITCH_M: f64 = 0.0254;

const ROLLER_RADIUS_M: f64 = 0.00397;

const ROLLER_MASS_KG: f64 = 0.02;

const LINK_STIFFNESS_N_M: f64 = 1e7;

const ROLLERS: f64 = 100.0;

const CENTRES_M: f64 = 1.016;

/// The mean link force over the upper strand's links well inside the span, N.
fn upper_strand_tension(drive: &ChainDrive, top: f64) -> f64 {
    let s = drive.state();
    let n = s.rollers();
    let links: Vec<f64> = (0..n)
        .filter(|&i| {
            let j = (i + 1) % n;
            let inside =
                |k: usize| s.x[k] > 0.15 && s.x[k] < CENTRES_M - 0.15 && s.y[k] > 0.5 * top;
            inside(i) && inside(j)
        })
        .map(|i| drive.forces().link_force[i])
        .collect();
    links.iter().sum::<f64>() / links.len().max(1) as f64
}

#[test]
fn a_fixed_guide_deflects_a_tensioned_strand_and_carries_2_t_sin_theta() {
    // Gravity off, both sprockets free, no load: the chain carries one
    // tension T everywhere (a free sprocket's moment balance makes its two
    // strands' tensions equal, and a symmetric wrap passes it on unchanged).
    let scene = conveyor_in_gravity(0.0, "role = \"free\"", 0.0);
    let (frames_lower, frames_settle, frames_mean) = (45, 60, 60);
    let run = |guide: bool| {
        let mut w = PhysicsWorld::default();
        let mut drive =
            ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
        // The layout seats a roller half a pitch past each sprocket's top:
        // the upper strand runs straight, at y0, from x = P/2 to C − P/2
        // (39 links), and its middle link straddles x = C/2.
        let s = drive.state();
        let y0 = drive.model().sprockets[0].pitch_radius_m * (std::f64::consts::PI / 20.0).cos();
        let roller_at = |x: f64| {
            (0..s.rollers()).find(|&i| {
                abs_diff_eq!(s.x[i], x, epsilon = 1e-4) && abs_diff_eq!(s.y[i], y0, epsilon = 1e-4)
            })
        };
        let middle = [0.5 * (CENTRES_M - PITCH_M), 0.5 * (CENTRES_M + PITCH_M)];
        let ends = [0.5 * PITCH_M, CENTRES_M - 0.5 * PITCH_M];
        assert!(
            middle.iter().chain(&ends).all(|&x| roller_at(x).is_some()),
            "not the layout this test assumes"
        );
        // A flat guide 40 mm long over the middle link, 1 mm clear of its two
        // rollers, lowered (kinematic) by 6 mm on a smooth velocity profile,
        // then fixed: those rollers end d = 5 mm below the strand line.
        let half_height = 0.005;
        let travel = 0.006;
        let y_start = y0 + ROLLER_RADIUS_M + half_height + 0.001;
        let body = w.bodies.insert(
            RigidBodyBuilder::kinematic_velocity_based()
                .translation(Vector::new(0.5 * CENTRES_M, y_start)),
        );
        w.colliders.insert_with_parent(
            // Friction off: the transverse balance alone.
            ColliderBuilder::cuboid(0.02, half_height)
                .friction(0.0)
                .enabled(guide),
            body,
            &mut w.bodies,
        );
        let dt = w.integration_parameters.dt;
        let lowering = frames_lower as f64 * dt;
        let (mut force, mut tension) = ([0.0f64; 2], 0.0);
        let mut deflections = Vec::new();
        for frame in 0..frames_lower + frames_settle + frames_mean {
            if frame < frames_lower {
                let t = (frame as f64 + 0.5) * dt;
                let v = -travel / lowering * (1.0 - (std::f64::consts::TAU * t / lowering).cos());
                w.bodies[body].set_linvel(Vector::new(0.0, v), true);
            } else if frame == frames_lower {
                w.bodies[body].set_body_type(RigidBodyType::Fixed, true);
            }
            drive.step_world(&mut w, &(), &()).expect("frame");
            if frame >= frames_lower + frames_settle {
                for f in drive.body_forces() {
                    force[0] += f[0] / frames_mean as f64;
                    force[1] += f[1] / frames_mean as f64;
                }
                tension += upper_strand_tension(&drive, y0) / frames_mean as f64;
            }
        }
        // Deflection of every upper-strand roller, by its distance from the strand's nearer end.
        let s = drive.state();
        for i in 0..s.rollers() {
            if s.y[i] > 0.5 * y0 && s.x[i] > ends[0] - 1e-3 && s.x[i] < ends[1] + 1e-3 {
                let from_end = (s.x[i] - ends[0]).min(ends[1] - s.x[i]).max(0.0);
                deflections.push((from_end, y0 - s.y[i]));
            }
        }
        let d = y0 + ROLLER_RADIUS_M + half_height - w.bodies[body].translation().y;
        (force, tension, d, deflections)
    };
    let (f0, t0, _, shape0) = run(false);
    let (f, t, d, shape) = run(true);
    // Without the guide nothing pushes the strand and it stays straight.
    assert!(f0 == [0.0; 2], "{f0:?}");
    let worst0 = shape0.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    assert!(worst0 < 1e-5, "{worst0:e}");
    // With it, the two middle rollers sit on the guide's face (Hertz
    // approach ≈ 4 µm at 2 N each against 2e8 N/m^1.5) and each half strand
    // is straight: deflection d · (distance from its end) / a, a = C/2 − P.
    let a = 0.5 * CENTRES_M - PITCH_M;
    assert_abs_diff_eq!(d, 0.005, epsilon = 2e-4);
    let worst = shape
        .iter()
        .map(|&(from_end, w)| (w - d * (from_end / a).min(1.0)).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 0.02 * d,
        "worst departure from the straight strand {worst:e} m"
    );
    // Tension: the 100 links of stiffness K in series take up the strand's
    // extra length ΔL = 2 (√(a² + d²) − a):  T = T0 + K ΔL / N.
    let extra = 2.0 * ((a * a + d * d).sqrt() - a);
    let expected_t = t0 + LINK_STIFFNESS_N_M * extra / ROLLERS;
    assert!(
        ((t - expected_t) / expected_t).abs() < 0.005,
        "T {t} vs {expected_t} (T0 {t0})"
    );
    // The guide's push balances the two half strands: F = 2 T sin θ, tan θ = d / a.
    let theta = (d / a).atan();
    let expected_f = -2.0 * expected_t * theta.sin();
    assert!(f[0].abs() < 0.01 * expected_f.abs(), "{f:?}");
    assert!(
        ((f[1] - expected_f) / expected_f).abs() < 0.01,
        "guide force {} N, 2 T sin θ = {expected_f} N",
        f[1]
    );
}

/// A `mass_kg` box, 100 × 50 mm, friction 0.8, laid on the upper strand of
/// a conveyor driven at `rpm`, at `x_m` from the driver, with rapier's linear
/// damping `damping`. Runs `frames` at 60 Hz; returns the box's mean x speed
/// and the rollers' mean force from the user's bodies (both ways of
/// coupling) over the last `window` frames, and the box's y speed change over them.
fn box_on_conveyor(
    mass_kg: f64,
    rpm: f64,
    x_m: f64,
    damping: f64,
    carry: bool,
    (frames, window): (usize, usize),
) -> Result<(f64, [f64; 2], f64), String> {
    let scene = conveyor(
        &format!("role = \"driver\"\nspeed_rpm = {rpm}\nramp_s = 0.5"),
        0.0,
    );
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    drive
        .set_coupling(Coupling {
            carry_dynamic: carry,
            ..*drive.coupling()
        })
        .expect("coupling");
    let top = drive.model().sprockets[0].pitch_radius_m + ROLLER_RADIUS_M;
    let bx = w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(x_m, top + 0.0255))
            .linear_damping(damping),
    );
    w.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.025)
            .density(mass_kg / (0.1 * 0.05))
            .friction(0.8),
        bx,
        &mut w.bodies,
    );
    let (mut speed, mut force, mut vy0) = (0.0, [0.0f64; 2], 0.0);
    for frame in 0..frames {
        if frame == frames - window {
            vy0 = w.bodies[bx].linvel().y;
        }
        drive
            .step_world(&mut w, &(), &())
            .map_err(|e| format!("frame {frame}: {e}"))?;
        if frame >= frames - window {
            speed += w.bodies[bx].linvel().x / window as f64;
            let (external, bodies) = (drive.external_forces(), drive.body_forces());
            for (e, b) in external.iter().zip(bodies) {
                force[0] += (e[0] + b[0]) / window as f64;
                force[1] += (e[1] + b[1]) / window as f64;
            }
        }
    }
    Ok((speed, force, w.bodies[bx].linvel().y - vy0))
}

/// 100 roller masses.
const HEAVY_BOX_KG: f64 = 100.0 * ROLLER_MASS_KG;

#[test]
fn a_box_of_100_roller_masses_rides_the_running_chain() {
    // Near the tail; over 1.5 s it travels about 0.64 m towards the driver.
    let (frames, window) = (90, 30);
    let (speed, force, dvy) =
        box_on_conveyor(HEAVY_BOX_KG, 60.0, 0.9, 0.0, true, (frames, window)).expect("no blow-up");
    // Pitch radius of a 20-tooth sprocket, R = P / (2 sin(π / 20)); 60 rpm;
    // the upper strand runs towards −x.
    let r = PITCH_M / (2.0 * (std::f64::consts::PI / 20.0).sin());
    let v_chain = std::f64::consts::TAU * r;
    assert!(
        ((speed + v_chain) / v_chain).abs() < 0.05,
        "box {speed} m/s, chain {v_chain} m/s"
    );
    // Momentum: what the rollers took from the box over the window is its
    // weight less its vertical momentum change: Σ f_y = −m g − m Δv_y / T.
    // (The box bounces on the strand it sags, about 3 Hz: Δv_y is not small.)
    let weight = HEAVY_BOX_KG * 9.81;
    let balance = -weight - HEAVY_BOX_KG * dvy / (window as f64 / 60.0);
    assert!(
        ((force[1] - balance) / weight).abs() < 0.01,
        "Σ f_y = {} N, balance {balance} N",
        force[1]
    );
}

#[test]
fn a_resting_box_of_100_roller_masses_puts_its_weight_on_the_rollers() {
    // Chain held (driver at 0 rpm), box in the middle of the upper strand,
    // its bounce on the strand damped by rapier's linear damping (which
    // carried bodies feel in the substeps). Settled after 1.5 s but for the
    // strand's own, undamped, transverse vibration (±0.1 mm, ±4 N a frame):
    // the mean over one second.
    let (frames, window) = (150, 60);
    let (_, force, dvy) =
        box_on_conveyor(HEAVY_BOX_KG, 0.0, 0.508, 5.0, true, (frames, window)).expect("no blow-up");
    let weight = HEAVY_BOX_KG * 9.81;
    // Σ f_y = −m g − m Δv_y / T; the last term is below 0.5 % here.
    let momentum = HEAVY_BOX_KG * dvy / (window as f64 / 60.0);
    assert!(
        momentum.abs() < 0.005 * weight,
        "still bouncing: {momentum} N"
    );
    assert!(
        ((force[1] + weight) / weight).abs() < 0.01,
        "Σ f_y = {} N, m g = {weight} N",
        force[1]
    );
    assert!(force[0].abs() < 0.01 * weight, "Σ f_x = {} N", force[0]);
}

#[test]
fn the_one_frame_lag_blows_up_under_a_box_of_100_roller_masses() {
    // Why dynamic bodies are carried in the substeps: rapier treats the
    // kinematic rollers as infinitely heavy, so the box takes their speed
    // each frame, and the impulse, applied to 20 g rollers a frame later,
    // pumps energy into the strand. On a held chain the strand blows up
    // within half a second; carried in the substeps, the same box rests.
    let run = box_on_conveyor(HEAVY_BOX_KG, 0.0, 0.508, 0.0, false, (90, 30));
    assert!(run.is_err(), "{run:?}");
    assert!(box_on_conveyor(HEAVY_BOX_KG, 0.0, 0.508, 0.0, true, (90, 30)).is_ok());
    // A light box is fine that way.
    assert!(box_on_conveyor(0.1, 60.0, 0.9, 0.0, false, (90, 30)).is_ok());
}

#[test]
fn a_box_held_by_a_stop_drags_on_the_sliding_chain_with_mu_m_g() {
    // A weightless chain (the scene's gravity off; the world's acts on the
    // box) runs on a frictionless fixed wear strip that keeps its upper strand
    // straight. It carries a box into a frictionless fixed stop (a stock rapier
    // contact, acting on the carried box in rapier's step), then slides under
    // it. Coulomb: the box pushes the rollers with (μ m g, −m g),
    // μ = (0.5 + 0.8) / 2 — rapier's default roller friction and the box's,
    // by rapier's default (average) rule.
    let scene = conveyor_in_gravity(
        0.0,
        "role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.5",
        0.0,
    );
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    let y0 = drive.model().sprockets[0].pitch_radius_m * (std::f64::consts::PI / 20.0).cos();
    let frictionless = |c: ColliderBuilder| {
        c.friction(0.0)
            .friction_combine_rule(CoefficientCombineRule::Min)
    };
    // The strip's top touches the strand's rollers from below.
    w.colliders.insert(frictionless(
        ColliderBuilder::cuboid(0.4, 0.005)
            .translation(Vector::new(0.5, y0 - ROLLER_RADIUS_M - 0.005)),
    ));
    let top = y0 + ROLLER_RADIUS_M;
    let bx = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.65, top + 0.0251)));
    w.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.025)
            .density(HEAVY_BOX_KG / (0.1 * 0.05))
            .friction(0.8),
        bx,
        &mut w.bodies,
    );
    // The stop's face at x = 0.55, 5 mm clear of the rollers.
    w.colliders.insert(frictionless(
        ColliderBuilder::cuboid(0.01, 0.0225).translation(Vector::new(0.54, top + 0.0275)),
    ));
    // A long window: the force scatters frame to frame as rollers pass under
    // the box (measured: 30-frame means of f_x between +0.1 % and +6.2 % of
    // μ m g; a 4 s mean moved from +2.1 % to +3.4 % with a last-bit change
    // of the chain's clock, so the mean is taken over 9 s).
    let (frames, window) = (600, 540);
    let mut force = [0.0f64; 2];
    let (mut farthest, mut mean_speed) = (0.0f64, 0.0);
    for frame in 0..frames {
        drive.step_world(&mut w, &(), &()).expect("frame");
        if frame >= frames - window {
            // Held: at the stop in every frame, at rest on average (a roller
            // passing under it kicks it by up to 0.03 m/s for a frame).
            let b = &w.bodies[bx];
            farthest = farthest.max((b.translation().x - 0.6).abs());
            mean_speed += b.linvel().x / window as f64;
        }
        if frame >= frames - window {
            // What the box does to the rollers (the strip's own pushes aside).
            let f = drive.chain_force_on(bx).expect("carried");
            force[0] -= f[0] / window as f64;
            force[1] -= f[1] / window as f64;
        }
    }
    assert!(mean_speed.abs() < 0.01, "box not held: {mean_speed} m/s");
    assert!(farthest < 2e-3, "box {farthest} m from the stop");
    let weight = HEAVY_BOX_KG * 9.81;
    let mu = 0.5 * (0.5 + 0.8);
    // The normal force is the weight (measured: 0.35 % over it: the stop
    // pushes above the line of the friction).
    assert!(
        ((force[1] + weight) / weight).abs() < 0.02,
        "Σ f_y = {} N, m g = {weight} N",
        force[1]
    );
    // Coulomb: f_x = μ N, within 3 %. Measured 2.1 % over: beyond the sliding
    // friction, the box's trailing edge rides up every arriving roller by its
    // Hertz approach, and each such climb pushes it along.
    let ratio = force[0] / -force[1];
    assert!(
        ((ratio - mu) / mu).abs() < 0.03,
        "Σ f_x / Σ f_y = {ratio} ({} N / {} N), μ = {mu}",
        force[0],
        -force[1]
    );
}

#[test]
fn a_sprocket_on_a_swinging_arm_follows_it_through_the_frame() {
    // The tail sprocket on a kinematic arm swinging ±3 mm across the chain at
    // 10 Hz (up to 0.19 m/s), the chain at 12 rpm. Unless the sprocket
    // follows the arm through the frame's substeps it jumps up to 3 mm into
    // the rollers at each frame (measured: a penetration blow-up in the first
    // frame). The arm, kinematic, turns the sprocket at the chain's speed.
    // Kept reach sets must allow for the mount's speed: with caching
    // on (without its safety margin) and off, the run is bitwise identical.
    // (A set misjudged at a reach circle's edge seldom changes a contact, so
    // this comparison guards the rule more than it can catch a slip of it.)
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 12.0\nramp_s = 0.2", 0.0);
    const AMPLITUDE_M: f64 = 0.003;
    const HZ: f64 = 10.0;
    use std::f64::consts::TAU;
    let run = |cached: bool| {
        let mut w = world();
        let arm = w.bodies.insert(
            RigidBodyBuilder::kinematic_velocity_based().translation(Vector::new(1.016, 0.0)),
        );
        let mut drive =
            ChainDrive::insert(&scene, &[None, Some(arm)], &mut w.bodies, &mut w.colliders)
                .expect("drive");
        drive.set_culling(cached.then_some(Culling {
            // No margin beyond the fastest roller: only the mount's own
            // speed in the bound keeps the kept sets right.
            speed_factor: 1.0,
            speed_floor_m_s: 0.0,
            max_skip_s: 0.1,
        }));
        let dt = w.integration_parameters.dt;
        let mut swing = 0.0f64;
        for frame in 0..60 {
            let t = frame as f64 * dt;
            let v = AMPLITUDE_M * TAU * HZ * (TAU * HZ * t).cos();
            w.bodies[arm].set_linvel(Vector::new(0.0, v), true);
            // A kinematic mount turns its sprocket: at the driver's speed
            // (equal tooth counts), the law's mean over the coming frame.
            let law = drive.model().sprockets[0].speed_law.expect("driver");
            w.bodies[arm].set_angvel(0.5 * (law.speed_at(t) + law.speed_at(t + dt)), true);
            drive.step_world(&mut w, &(), &()).expect("frame");
            swing = swing.max(w.bodies[arm].translation().y.abs());
        }
        assert!(swing > 0.8 * AMPLITUDE_M, "the arm swung {swing} m");
        drive.state().clone()
    };
    assert_eq!(run(true), run(false));
}
