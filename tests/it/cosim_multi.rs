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
    add_box_of(w, HX, x, y, mass_kg)
}

/// A `mass_kg` box 2 `hx` long and 50 mm high, friction 0.8, at `(x, y)`.
fn add_box_of(w: &mut PhysicsWorld, hx: f64, x: f64, y: f64, mass_kg: f64) -> RigidBodyHandle {
    let b = w
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(x, y)));
    w.colliders.insert_with_parent(
        ColliderBuilder::cuboid(hx, HY)
            .density(mass_kg / (4.0 * hx * HY))
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
    /// The box's position, velocity and angle after every frame.
    path: Vec<[f64; 5]>,
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
/// pushing it forward with 1 N·m. A 0.2 kg box, 100 mm long, laid on A at
/// x = 0.5 m, goes towards B. `order` puts the drives into the set: `[0, 1]` A first.
fn transfer(order: [usize; 2], seconds: f64) -> Result<Transfer, String> {
    transfer_of(order, HX, seconds)
}

/// [`transfer`] with a box 2 `hx` long.
fn transfer_of(order: [usize; 2], hx: f64, seconds: f64) -> Result<Transfer, String> {
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
    let bx = add_box_of(&mut w, hx, 0.5, strand_top() + HY + 1e-4, 0.2);
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
        run.path.push([p.x, p.y, v.x, v.y, b.rotation().angle()]);
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
fn a_stack_of_two_boxes_rides_at_chain_speed() {
    // Before: the lower of two 0.2 kg boxes rode at 0.61 m/s at 60 Hz while
    // the top one slid off it (0.21 m); at 240 Hz a 0.05 kg top box, out of
    // the rollers' reach, was left to rapier's step and fell off backwards.
    let v = chain_speed(60.0); // ω R = 2π · 1 rev/s · 81.2 mm = 0.510 m/s
    for (mass_kg, hz) in [(0.2, 60.0), (0.05, 240.0)] {
        let (lower, upper, slip) =
            stack(mass_kg, hz, 3.0, 2.0).unwrap_or_else(|e| panic!("{mass_kg} kg, {hz} Hz: {e}"));
        // Both ride with the upper strand (towards −x) within 5 %, and the top
        // box stays on the lower one (its half length is 50 mm; measured
        // 7.2 mm and 17.6 mm of creep over 2 s).
        for speed in [lower, upper] {
            assert!(
                ((speed + v) / v).abs() < 0.05,
                "{mass_kg} kg, {hz} Hz: boxes at {lower} and {upper} m/s, chain {v} m/s"
            );
        }
        assert!(slip < 0.025, "{mass_kg} kg, {hz} Hz: top box slid {slip} m");
    }
}

#[test]
fn three_boxes_queue_against_a_stop_for_10_s() {
    // Before: a queue blew up (penetration) within seconds. Resting against
    // each other: the substeps' contact law compresses a 2 N pair by
    // (2 N / 2e8 N/m^1.5)^(2/3) ≈ 5 µm, so every gap is well under 1 mm
    // (measured: 0.04 mm at the stop, 0.19 mm between boxes, 0.28 mm off
    // resting height, tilt 0.004 rad).
    let [stop, gap, height, tilt] = queue(3, 0.2, 10.0).expect("no blow-up");
    assert!(stop < 1e-3, "first box {stop} m from the stop");
    assert!(gap < 1e-3, "boxes {gap} m apart");
    assert!(height < 1e-3, "a box {height} m off the strand");
    assert!(tilt < 0.02, "a box tilted by {tilt} rad");
}

#[test]
fn two_conveyors_keep_a_transfer_boxs_gravity_and_their_motors() {
    // Before (two drives stepped one after the other): each took the other's
    // motor for a box to carry (B's tail at 7.1 rad/s on a chain turning it
    // at 6.3) and the box lost its gravity for good after 1 s, floating off
    // at 0.28 m/s.
    for order in [[0, 1], [1, 0]] {
        let a = transfer(order, 4.0).unwrap_or_else(|e| panic!("{order:?}: {e}"));
        assert_eq!(a.min_gravity_scale, 1.0);
        assert_eq!(a.motor_torque, [1.0, 1.0]);
        // Each tail turns with its chain: ω = 2π rad/s at 60 rpm on equal sprockets.
        let omega = std::f64::consts::TAU;
        for w in a.tail_speed {
            assert!(
                ((w - omega) / omega).abs() < 0.02,
                "{order:?}: tail at {w} rad/s"
            );
        }
    }
}

#[test]
fn a_box_crosses_from_one_conveyor_to_the_other_at_chain_speed() {
    // The geometry: the strands' flat tops end at the two sprockets' tops,
    // x = 0 (A's driver) and x = -0.18 m (B's tail), 180 mm apart, and the
    // wrapped rollers' outer surfaces are 10 mm apart at the gap (pitch
    // radius 81.2 mm + roller radius 4 mm on each side). A 250 mm box
    // bridges the gap: while its centre crosses it, one end rests on A's
    // wrap and the other on B's, both chains holding it in the same
    // substeps. Before (a body near two chains carried by one drive per
    // frame, the other's rollers passing through it): a chain blew up at
    // 1.45 s. (A 100 mm box cannot bridge 180 mm: it drops into the valley
    // between the wraps, where A's rollers move down and B's up, and is
    // spun there before B throws it out; see the next test.)
    let a = transfer_of([0, 1], 0.125, 3.0).expect("A first");
    let b = transfer_of([1, 0], 0.125, 3.0).expect("B first");
    // Two drives' forces on the box are summed (a + b = b + a): the order
    // changes no bit.
    assert_eq!(a, b);
    // The box crossed onto B (whose upper strand runs from x = -0.18 to
    // -1.196 m) and rides it at chain speed, level, resting on its strand.
    let v = chain_speed(60.0);
    let last = a.path.last().copied().unwrap_or_default();
    assert!(last[0] < -0.5, "box at x = {} m", last[0]);
    let window = &a.path[a.path.len() - 30..];
    let speed = window.iter().map(|p| p[2]).sum::<f64>() / window.len() as f64;
    assert!(
        ((speed + v) / v).abs() < 0.05,
        "box at {speed} m/s, chain {v} m/s"
    );
    // The strand sags under its own weight w = 0.02 kg · 9.81 / 25.4 mm =
    // 7.7 N/m and the box's 1.96 N over the L = 1.016 m span at T = 200 N:
    // w L² / (8 T) + W L / (4 T) = 5.0 + 2.5 mm at most (mid-span), below
    // the straight strand's top.
    for p in window {
        let drop = strand_top() + HY - p[1];
        assert!(
            drop > -2e-3 && drop < 7.5e-3 + 2e-3,
            "box {drop} m below the strand's top"
        );
        assert!(p[4].abs() < 0.05, "box tilted by {} rad", p[4]);
    }
}

#[test]
fn the_sets_order_does_not_change_a_box_in_the_gap() {
    // A first or B first: the same bits, the box's path and both tails'
    // speeds, also at the gap where both chains hold the 100 mm box
    // (it reaches A's end at x = 0 in frame 74 and is spun in the valley
    // between the wraps: a chaotic path, which any difference in the order
    // of operations would part). Before (one drive carrying the box per
    // frame, a tie broken by handle): the orders parted from frame 82 on,
    // and with B first the run blew up at 2.17 s.
    let a = transfer([0, 1], 3.0).expect("A first");
    let b = transfer([1, 0], 3.0).expect("B first");
    assert_eq!(a.path, b.path);
    assert_eq!(a.tail_speed[0], b.tail_speed[0]);
    assert_eq!(a.tail_speed[1], b.tail_speed[1]);
    assert_eq!(a.motor_torque, b.motor_torque);
}

/// Where the vertical speeds of boxes queued against a stop come from (a
/// diagnostic, not a check: `cargo test --release --test it
/// queued_boxes_vertical_speed -- --ignored --nocapture`, `NOSTOP=1` for the
/// boxes riding free, `REST=e` for another restitution). Prints, per frame
/// rate, the largest and RMS vertical speed of the first box at frame ends,
/// the largest mean vertical speed over a frame (Δy / dt) and how often the
/// speed changes sign; docs/architecture.md, "Bodies touching carried
/// bodies", has the numbers and the explanation.
#[test]
#[ignore]
fn queued_boxes_vertical_speed() {
    let e: f64 = std::env::var("REST")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.5);
    for hz in [60.0, 240.0, 2000.0] {
        let scene = conveyor_in(100, 60.0, 0.0, 0.0);
        let text = scene
            .source_toml()
            .expect("text")
            .replace("restitution = 0.5", &format!("restitution = {e}"));
        let scene = Scene::from_toml(&text).expect("scene");
        let mut w = world();
        w.integration_parameters.dt = 1.0 / hz;
        let mut drive =
            ChainDrive::insert(&scene, &[], &mut w.bodies, &mut w.colliders).expect("drive");
        let r = PITCH_M / (2.0 * (std::f64::consts::PI / 20.0).sin());
        let y0 = r * (std::f64::consts::PI / 20.0).cos();
        let fl = |c: ColliderBuilder| {
            c.friction(0.0)
                .friction_combine_rule(CoefficientCombineRule::Min)
        };
        w.colliders.insert(fl(ColliderBuilder::cuboid(0.4, 0.005)
            .translation(Vector::new(0.5, y0 - ROLLER_RADIUS_M - 0.005))));
        let top = strand_top();
        let face = 0.35;
        let with_stop = std::env::var("NOSTOP").is_err();
        if with_stop {
            w.colliders.insert(fl(ColliderBuilder::cuboid(0.01, 0.0225)
                .translation(Vector::new(face - 0.01, top + 0.0275))));
        }
        let n = 3;
        let boxes: Vec<RigidBodyHandle> = (0..n)
            .map(|k| {
                add_box(
                    &mut w,
                    face + HX + 1e-3 + k as f64 * (2.0 * HX + 1e-3),
                    top + HY + 1e-4,
                    0.2,
                )
            })
            .collect();
        let frames = ((if hz > 1000.0 { 2.0 } else { 6.0 }) * hz) as usize;
        let (mut vmax, mut dmax, mut hist) = (0.0f64, 0.0f64, Vec::new());
        let mut prev: Vec<f64> = boxes.iter().map(|&b| w.bodies[b].translation().y).collect();
        for frame in 0..frames {
            drive.step_world(&mut w, &(), &()).expect("frame");
            let ys: Vec<f64> = boxes.iter().map(|&b| w.bodies[b].translation().y).collect();
            let t = frame as f64 / hz;
            let window = if with_stop {
                t > 1.0
            } else {
                (0.1..0.6).contains(&t)
            };
            if window {
                for (k, &b) in boxes.iter().enumerate() {
                    let vy = w.bodies[b].linvel().y;
                    let d = (ys[k] - prev[k]) * hz;
                    vmax = vmax.max(vy.abs());
                    dmax = dmax.max(d.abs());
                    if k == 0 {
                        hist.push((vy, d, ys[k] - top - HY));
                    }
                }
            }
            prev = ys;
        }
        let crossings = hist
            .windows(2)
            .filter(|p| p[0].0.signum() != p[1].0.signum())
            .count();
        let secs = hist.len() as f64 / hz;
        let rms = (hist.iter().map(|h| h.0 * h.0).sum::<f64>() / hist.len() as f64).sqrt();
        println!(
            "{hz} Hz stop={with_stop} e={e}: max |vy| at frame ends {vmax:.4} m/s (rms {rms:.4}), max |dy/dt| over a frame {dmax:.4} m/s, vy sign changes {:.0}/s",
            crossings as f64 / secs
        );
    }
}
