//! Several carried bodies and several drives in one rapier world: stacks,
//! queues against a stop, two conveyors with a transfer box.

use chaindrive::cosim::{ChainDrive, DriveSet};
use chaindrive::scene::Scene;
use rapier2d_f64::prelude::*;

const PITCH_M: f64 = 0.0254;
const ROLLER_RADIUS_M: f64 = 0.00397;
/// Half sizes of the boxes, m.
const HX: f64 = 0.05;
const HY: f64 = 0.025;

/// A horizontal conveyor of two 20-tooth sprockets (the one of
/// `cosim::conveyor`, #80-size rollers on 25.4 mm pitch) with `rollers`
/// rollers: centres (rollers − 20) / 2 pitches apart, the driver at the
/// origin turning at `rpm` (ramped over 0.5 s). Its upper strand runs towards −x.
fn conveyor(rollers: usize, rpm: f64) -> Scene {
    conveyor_at(rollers, rpm, 0.0)
}

/// [`conveyor`] with its driver at `x0` m on the x axis.
fn conveyor_at(rollers: usize, rpm: f64, x0: f64) -> Scene {
    conveyor_in(rollers, rpm, x0, -9.81)
}

/// [`conveyor_at`] with the scene's gravity `gravity_y` along y, m/s² (the
/// world's gravity acts on the boxes whatever the scene's).
fn conveyor_in(rollers: usize, rpm: f64, x0: f64, gravity_y: f64) -> Scene {
    let tail = x0 + (rollers - 20) as f64 / 2.0 * PITCH_M;
    let text = format!(
        r#"
name = "long conveyor"
gravity_m_s2 = [0.0, {gravity_y}]
[chain]
rollers = {rollers}
pitch_m = {PITCH_M}
roller_radius_m = {ROLLER_RADIUS_M}
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
center_m = [{x0}, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
role = "driver"
speed_rpm = {rpm}
ramp_s = 0.5
[[sprockets]]
name = "tail"
center_m = [{tail}, 0.0]
teeth = 20
mass_kg = 2.0
inertia_kg_m2 = 0.01
wrap = "ccw"
role = "free"
[solver]
dt_s = 1e-5
"#
    );
    Scene::from_toml(&text).expect("conveyor scene")
}

/// Chain speed at `rpm` on a 20-tooth sprocket, m/s: ω R with the pitch
/// radius R = P / (2 sin(π / 20)).
fn chain_speed(rpm: f64) -> f64 {
    rpm / 60.0 * std::f64::consts::TAU * PITCH_M / (2.0 * (std::f64::consts::PI / 20.0).sin())
}

/// Height of the upper strand's roller tops on a 20-tooth sprocket pair:
/// the pitch radius at a tooth-gap's chord, R cos(π / 20), plus the roller radius.
fn strand_top() -> f64 {
    let r = PITCH_M / (2.0 * (std::f64::consts::PI / 20.0).sin());
    r * (std::f64::consts::PI / 20.0).cos() + ROLLER_RADIUS_M
}

fn world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

/// A `mass_kg` box, 100 × 50 mm, friction 0.8, at `(x, y)`.
fn add_box(w: &mut PhysicsWorld, x: f64, y: f64, mass_kg: f64) -> RigidBodyHandle {
    let b = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(x, y)));
    w.colliders.insert_with_parent(
        ColliderBuilder::cuboid(HX, HY)
            .density(mass_kg / (4.0 * HX * HY))
            .friction(0.8),
        b,
        &mut w.bodies,
    );
    b
}

/// A stack of two `mass_kg` boxes laid near the tail of a 200-roller
/// conveyor at 60 rpm, run for `seconds` at `hz`: the boxes' mean x speeds
/// over the last `window_s`, and the largest slip of the top box on the
/// lower one over that window, m.
fn stack(mass_kg: f64, hz: f64, seconds: f64, window_s: f64) -> Result<(f64, f64, f64), String> {
    let scene = conveyor(200, 60.0);
    let mut w = world();
    w.integration_parameters.dt = 1.0 / hz;
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    let top = strand_top();
    let lower = add_box(&mut w, 2.15, top + HY + 1e-4, mass_kg);
    let upper = add_box(&mut w, 2.15, top + 3.0 * HY + 2e-4, mass_kg);
    let frames = (seconds * hz).round() as usize;
    let window = (window_s * hz).round() as usize;
    let (mut v_lower, mut v_upper, mut slip) = (0.0, 0.0, 0.0f64);
    let mut x0 = None;
    for frame in 0..frames {
        drive
            .step_world(&mut w, &(), &())
            .map_err(|e| format!("frame {frame}: {e}"))?;
        let (a, b) = (&w.bodies[lower], &w.bodies[upper]);
        if frame >= frames - window {
            v_lower += a.linvel().x / window as f64;
            v_upper += b.linvel().x / window as f64;
            let dx = b.translation().x - a.translation().x;
            slip = slip.max((dx - *x0.get_or_insert(dx)).abs());
        }
    }
    Ok((v_lower, v_upper, slip))
}

#[test]
fn probe_stack() {
    for hz in [60.0, 240.0] {
        for m in [0.05, 0.2] {
            eprintln!("{hz} Hz {m} kg: {:?}", stack(m, hz, 3.0, 2.0));
        }
    }
    eprintln!("chain {}", chain_speed(60.0));
}


/// A 2 kg motor body on a fixed axle at `(x, 0)` with a conveyor sprocket's 0.01 kg·m².
fn motor(w: &mut PhysicsWorld, x: f64) -> RigidBodyHandle {
    w.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(x, 0.0))
            .lock_translations()
            .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.01)),
    )
}

/// What a transfer run saw, frame by frame.
#[derive(Debug, PartialEq)]
struct Transfer {
    /// The box's position and velocity after every frame.
    path: Vec<[f64; 4]>,
    /// The smallest gravity scale the box had after a frame.
    min_gravity_scale: f64,
    /// The motors' user torques after every frame, smallest and largest.
    motor_torque: [f64; 2],
    /// The tail sprockets' mean angular speeds over the last second, rad/s.
    tail_speed: [f64; 2],
}

/// Two conveyors end to end, both at 60 rpm, their upper strands running
/// towards −x: A from x = 0 to 1.016 m, B from −1.196 to −0.18 m, their
/// wrapped rollers 10 mm apart. Each tail sprocket sits on a motor body
/// pushing it forward with 1 N·m. A 0.2 kg box laid on A at x = 0.5 m
/// crosses onto B. `order` puts the drives into the set: `[0, 1]` A first.
fn transfer(order: [usize; 2], seconds: f64) -> Result<Transfer, String> {
    let mut w = world();
    let tails = [motor(&mut w, 1.016), motor(&mut w, -0.18)];
    let scenes = [conveyor_at(100, 60.0, 0.0), conveyor_at(100, 60.0, -1.196)];
    let mut set = DriveSet::new();
    for &i in &order {
        let drive = ChainDrive::insert(
            &scenes[i],
            &[None, Some(tails[i])],
            &mut w.bodies,
            &mut w.colliders,
        )
        .map_err(|e| e.to_string())?;
        set.push(drive);
    }
    let torque = 1.0;
    for &m in &tails {
        w.bodies[m].add_torque(torque, true);
    }
    let bx = add_box(&mut w, 0.5, strand_top() + HY + 1e-4, 0.2);
    let frames = (seconds * 60.0) as usize;
    let mut run = Transfer {
        path: Vec::new(),
        min_gravity_scale: f64::INFINITY,
        motor_torque: [f64::INFINITY, f64::NEG_INFINITY],
        tail_speed: [0.0; 2],
    };
    for frame in 0..frames {
        set.step_world(&mut w, &(), &())
            .map_err(|e| format!("frame {frame}: {e}"))?;
        let b = &w.bodies[bx];
        let (p, v) = (b.translation(), b.linvel());
        run.path.push([p.x, p.y, v.x, v.y]);
        run.min_gravity_scale = run.min_gravity_scale.min(b.gravity_scale());
        for (k, &m) in tails.iter().enumerate() {
            let t = w.bodies[m].user_torque();
            run.motor_torque = [run.motor_torque[0].min(t), run.motor_torque[1].max(t)];
            if frame >= frames - 60 {
                run.tail_speed[k] += w.bodies[m].angvel() / 60.0;
            }
        }
    }
    Ok(run)
}

#[test]
fn probe_transfer() {
    let a = transfer([0, 1], 3.0);
    match &a {
        Ok(t) => {
            for (f, p) in t.path.iter().enumerate().step_by(15) {
                eprintln!("f{f} {p:?}");
            }
            eprintln!("g {} torque {:?} tails {:?}", t.min_gravity_scale, t.motor_torque, t.tail_speed);
        }
        Err(e) => eprintln!("{e}"),
    }
    let b = transfer([1, 0], 3.0);
    eprintln!("same: {}", a == b);
}

#[test]
fn probe_bare_pair() {
    let mut w = world();
    let tails = [motor(&mut w, 1.016), motor(&mut w, -0.18)];
    let scenes = [conveyor_at(100, 60.0, 0.0), conveyor_at(100, 60.0, -1.196)];
    let mut drives: Vec<ChainDrive> = (0..2)
        .map(|i| {
            ChainDrive::insert(&scenes[i], &[None, Some(tails[i])], &mut w.bodies, &mut w.colliders)
                .expect("drive")
        })
        .collect();
    for &m in &tails {
        w.bodies[m].add_torque(1.0, true);
    }
    let bx = add_box(&mut w, 0.5, strand_top() + HY + 1e-4, 0.2);
    let dt = w.integration_parameters.dt;
    for frame in 0..180 {
        let r: Result<(), chaindrive::cosim::CosimError> = (|| {
            for d in drives.iter_mut() {
                d.before_step(&mut w.bodies, &w.colliders, w.gravity, dt)?;
            }
            let inner = drives[1].hooks(&());
            let hooks = drives[0].hooks(&inner);
            w.step_with_events(&hooks, &());
            for d in drives.iter_mut() {
                d.after_step(&mut w.bodies, &w.narrow_phase, dt)?;
            }
            Ok(())
        })();
        if let Err(e) = r {
            eprintln!("frame {frame}: {e}");
            break;
        }
        if frame % 15 == 0 {
            let b = &w.bodies[bx];
            eprintln!(
                "f{frame} box {:?} v {:?} g {} torques {} {} tails {} {}",
                b.translation(),
                b.linvel(),
                b.gravity_scale(),
                w.bodies[tails[0]].user_torque(),
                w.bodies[tails[1]].user_torque(),
                w.bodies[tails[0]].angvel(),
                w.bodies[tails[1]].angvel()
            );
        }
    }
}

/// `n` boxes of `mass_kg` queued against a fixed stop on the 100-roller
/// conveyor at 60 rpm, weightless, whose upper strand runs on a
/// frictionless wear strip, for `seconds` at 60 Hz. After the first second (the
/// ramp and the 1 mm gaps closed) every frame is checked: returns the
/// largest distance of the first box from the stop, of each box from the
/// next, and of any box from resting height on the strand, m, and the
/// largest tilt, rad.
fn queue(n: usize, mass_kg: f64, seconds: f64) -> Result<[f64; 4], String> {
    // A weightless chain (the strand straight on the strip from the start).
    let scene = conveyor_in(100, 60.0, 0.0, 0.0);
    let mut w = world();
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
    let r = PITCH_M / (2.0 * (std::f64::consts::PI / 20.0).sin());
    let y0 = r * (std::f64::consts::PI / 20.0).cos();
    let frictionless = |c: ColliderBuilder| {
        c.friction(0.0)
            .friction_combine_rule(CoefficientCombineRule::Min)
    };
    w.colliders.insert(frictionless(
        ColliderBuilder::cuboid(0.4, 0.005)
            .translation(Vector::new(0.5, y0 - ROLLER_RADIUS_M - 0.005)),
    ));
    let top = strand_top();
    // The stop's face at x = 0.35, 5 mm clear of the rollers.
    let face = 0.35;
    w.colliders.insert(frictionless(
        ColliderBuilder::cuboid(0.01, 0.0225).translation(Vector::new(face - 0.01, top + 0.0275)),
    ));
    let boxes: Vec<RigidBodyHandle> = (0..n)
        .map(|k| {
            let x = face + HX + 1e-3 + k as f64 * (2.0 * HX + 1e-3);
            add_box(&mut w, x, top + HY + 1e-4, mass_kg)
        })
        .collect();
    let mut worst = [0.0f64; 4];
    for frame in 0..(seconds * 60.0) as usize {
        drive
            .step_world(&mut w, &(), &())
            .map_err(|e| format!("frame {frame}: {e}"))?;
        if frame < 60 {
            continue;
        }
        let x: Vec<f64> = boxes.iter().map(|&b| w.bodies[b].translation().x).collect();
        worst[0] = worst[0].max((x[0] - HX - face).abs());
        for k in 1..n {
            worst[1] = worst[1].max((x[k] - x[k - 1] - 2.0 * HX).abs());
        }
        for &b in &boxes {
            let body = &w.bodies[b];
            worst[2] = worst[2].max((body.translation().y - top - HY).abs());
            worst[3] = worst[3].max(body.rotation().angle().abs());
        }
    }
    Ok(worst)
}

#[test]
fn probe_queue() {
    for n in [1, 2, 3] {
        eprintln!("queue {n}: {:?}", queue(n, 0.2, 10.0));
    }
}
