//! Inserting a drive into a rapier world: the cost of the static
//! equilibrium for the examples' drives (a measurement, printed, not
//! asserted), and a settled drive inserted again without settling anew.

use std::time::Instant;

use chaindrive::prelude::*;
use rapier2d_f64::prelude::*;

/// A body turning about a fixed axle at `(x, y)`, of rotational inertia
/// `inertia_kg_m2`.
fn axle(x: f64, y: f64, inertia_kg_m2: f64) -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic()
        .translation(Vector::new(x, y))
        .lock_translations()
        .additional_mass_properties(MassProperties::new(Vector::ZERO, 1.0, inertia_kg_m2))
}

fn asset(name: &str) -> Scene {
    let path = format!("{}/assets/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("asset");
    Scene::from_toml(&text).expect("valid asset")
}

/// The drives the examples and the co-simulation tests insert: a name, the
/// scene, and the bodies to mount (sprocket index, body) in a fresh world.
type Case = (&'static str, Scene, Vec<(usize, RigidBodyBuilder)>);

fn cases() -> Vec<Case> {
    let conveyor = asset("conveyor.toml");
    vec![
        (
            "conveyor, head on a motor body (examples conveyor, motor_joint)",
            conveyor.clone(),
            vec![(0, axle(0.0, 0.0, 0.05))],
        ),
        (
            "conveyor, head kinematic, tail on a carriage (example tensioner_carriage)",
            conveyor.clone(),
            vec![
                (0, RigidBodyBuilder::kinematic_velocity_based()),
                (1, axle(1.016, 0.0, 0.01)),
            ],
        ),
        ("conveyor, no mounts", conveyor, Vec::new()),
        (
            "bicycle, crank and wheel on bodies (example bicycle)",
            asset("bicycle.toml"),
            vec![(0, axle(0.0, 0.0, 0.02)), (1, axle(-0.4143, 0.03, 10.0))],
        ),
        (
            "paper drive, no mounts (example paper_in_scene)",
            Scene::l60mc(),
            Vec::new(),
        ),
    ]
}

/// Inserts `case` into a fresh world; the seconds it took.
fn insert(case: &Case) -> (ChainDrive, PhysicsWorld, f64) {
    let (_, scene, mounts) = case;
    let mut world = PhysicsWorld::default();
    let mut builder = ChainDrive::builder(scene);
    for (k, body) in mounts {
        let h = world.bodies.insert(body.clone());
        builder = builder.mount(*k, h);
    }
    let started = Instant::now();
    let drive = builder.build(&mut world).expect("inserted");
    (drive, world, started.elapsed().as_secs_f64())
}

#[test]
#[ignore = "a measurement: cargo test --release --test it insertion_times -- --ignored --nocapture"]
fn insertion_times() {
    for case in cases() {
        let (drive, _, seconds) = insert(&case);
        let eq = drive.equilibrium();
        println!(
            "{:<75} {seconds:>7.3} s  tension {:>8.2} N  residual {:.1e}",
            case.0, eq.tension_n, eq.force_residual
        );
    }
}

/// Mean link force K (d − l₀) over the links whose both rollers lie in the
/// box `x_m` × `y_m`, from the roller positions alone, N.
fn strand_mean_n(drive: &ChainDrive, x_m: (f64, f64), y_m: (f64, f64)) -> f64 {
    let s = drive.state();
    let k = drive.scene().chain().stiffness_n_m;
    let l0 = drive.equilibrium().rest_length_m;
    let n = s.x.len();
    let inside = |i: usize| (x_m.0..x_m.1).contains(&s.x[i]) && (y_m.0..y_m.1).contains(&s.y[i]);
    let forces: Vec<f64> = (0..n)
        .filter(|&i| inside(i) && inside((i + 1) % n))
        .map(|i| {
            let j = (i + 1) % n;
            k * ((s.x[j] - s.x[i]).hypot(s.y[j] - s.y[i]) - l0)
        })
        .collect();
    assert!(forces.len() > 10, "{} links in the box", forces.len());
    forces.iter().sum::<f64>() / forces.len() as f64
}

#[test]
fn a_conveyor_on_a_motor_body_settles_with_its_load_reacted_at_the_motor() {
    // assets/conveyor.toml: every sprocket free, the head on the user's
    // motor body, a load of −0.5 N·m on the tail. Before, no sprocket was
    // held for the solve and the relaxation ran its course (10 s, residual
    // 3e-5 of the pretension); now the motor's sprocket is held at rest for
    // the solve and Newton settles it to 1e-7.
    let case = &cases()[0];
    let (drive, _, _) = insert(case);
    let eq = drive.equilibrium();
    assert!(
        eq.force_residual <= 1e-7,
        "residual {:e}",
        eq.force_residual
    );
    // Hand values: the free strands' mean is the pretension (500 N, the
    // rule's tolerance 1 %). The tail with its wrap at rest: about its
    // centre the strands' pull R (T_upper − T_lower) balances the load
    // (−0.5 N·m) and the wrap's weight, taken as a half circle of chain at
    // the pitch radius R = p / (2 sin(π/20)) = 81.18 mm on the tail's outer
    // side: mass π R m_r / p = 0.201 kg at 2R/π, a moment of −0.1015 N·m.
    // So the strands differ by (0.5 + 0.1015) / R = 7.41 N. Within 8 %:
    // the seated rollers sit inside the pitch circle and the strands reach
    // it over a few links, which the half circle ignores. (The sag changes
    // a strand's tension by w·sag ≈ 7.7 N/m · 2 mm alike in both strands.)
    let upper = strand_mean_n(&drive, (0.2, 0.8), (0.05, 0.2));
    let lower = strand_mean_n(&drive, (0.2, 0.8), (-0.2, -0.05));
    let r = 0.0254 / (2.0 * (std::f64::consts::PI / 20.0).sin());
    let rho_kg_m = 0.02 / 0.0254;
    let wrap_moment = std::f64::consts::PI * r * rho_kg_m * 9.81 * 2.0 * r / std::f64::consts::PI;
    let want = (0.5 + wrap_moment) / r;
    assert!(
        ((0.5 * (upper + lower) - 500.0) / 500.0).abs() < 0.01,
        "strands {upper} N and {lower} N"
    );
    assert!(
        ((upper - lower) - want).abs() < 0.08 * want,
        "strands differ by {} N, the load and the wrap at rest make {want} N",
        upper - lower
    );
}

#[test]
fn a_settled_drive_is_inserted_again_at_its_settled_state_and_runs() {
    let case = &cases()[0];
    let (mut drive, mut world, _) = insert(case);
    let settled = drive.state().clone();
    let equilibrium = drive.equilibrium().clone();
    let head = drive.sprocket(0).expect("sprocket 0");
    let motor = drive.sprocket_body(head);
    world.bodies[motor].add_torque(1.0, true);
    for _ in 0..10 {
        drive.step_world(&mut world, &(), &()).expect("frame");
    }
    assert_ne!(drive.state().x, settled.x, "the drive did not move");
    // The same world after `remove`, and a fresh world.
    let scene = case.1.clone();
    let again = |world: &mut PhysicsWorld, motor| {
        ChainDrive::builder(&scene)
            .mount(0, motor)
            .settled_from(&drive)
            .build(world)
            .expect("inserted again")
    };
    let mut fresh = PhysicsWorld::default();
    let fresh_motor = fresh.bodies.insert(case.2[0].1.clone());
    let mut copy = again(&mut fresh, fresh_motor);
    assert_eq!(copy.state(), &settled);
    assert_eq!(copy.equilibrium(), &equilibrium);
    let old = ChainDrive::builder(&scene).settled_from(&drive);
    drive.remove(&mut world);
    world.bodies[motor].set_angvel(0.0, true);
    let back = old.mount(0, motor).build(&mut world).expect("after remove");
    assert_eq!(back.state(), &settled);
    fresh.bodies[fresh_motor].add_torque(1.0, true);
    for _ in 0..30 {
        copy.step_world(&mut fresh, &(), &())
            .expect("the copy runs");
    }
    assert!(copy.sprocket_speed(head) > 0.0, "the copy did not turn");
}

#[test]
fn settling_from_a_drive_of_another_scene_is_refused() {
    let (drive, _, _) = insert(&cases()[0]);
    let mut world = PhysicsWorld::default();
    let err = ChainDrive::builder(&Scene::l60mc())
        .settled_from(&drive)
        .build(&mut world)
        .err()
        .expect("refused");
    assert!(err.to_string().contains("settled_from"), "{err}");
    assert_eq!(world.bodies.len(), 0, "nothing added on an error");
}

#[test]
fn more_mounts_than_sprockets_is_named_not_a_panic() {
    let mut world = PhysicsWorld::default();
    let motor = world.bodies.insert(axle(0.0, 0.0, 0.05));
    let err = ChainDrive::insert(
        &asset("conveyor.toml"),
        &[None, None, Some(motor)],
        &mut world.bodies,
        &mut world.colliders,
    )
    .err()
    .expect("refused");
    assert!(err.to_string().contains("mounts"), "{err}");
}

/// The drive's kinetic energy: the rollers' and the free sprockets' (the
/// kinematic driver's is the motor's), J.
fn kinetic_energy_j(drive: &ChainDrive) -> (f64, f64) {
    let (m, s) = (drive.model(), drive.state());
    let rollers: f64 =
        s.vx.iter()
            .zip(&s.vy)
            .map(|(vx, vy)| 0.5 * m.roller_mass_kg * (vx * vx + vy * vy))
            .sum();
    let sprockets: f64 = m
        .sprockets
        .iter()
        .zip(&s.omega)
        .filter(|(sp, _)| sp.speed_law.is_none() && sp.inv_inertia > 0.0)
        .map(|(sp, w)| 0.5 * w * w / sp.inv_inertia)
        .sum();
    (rollers, sprockets)
}

/// What a run of the first second of a drive shows: the tail's speed off
/// ω_d·z_d/z_t in frame 1 and at most over the second (fractions), the
/// kinetic energies (rollers, tail) at the start and after the second, J,
/// and the closed forms of those energies, J.
struct FirstSecond {
    first: f64,
    worst: f64,
    start_j: (f64, f64),
    end_j: (f64, f64),
    want_j: (f64, f64),
}

/// A two-sprocket drive (60 and 30 teeth, 300 rollers, 60 rpm, ramp
/// 0.5 s) built moving or not, run for 60 frames. The closed forms assume
/// an inextensible chain of equal pitches p seated on the pitch circles
/// R = p / (2 sin(π/z)): every roller at the chain speed v = ω_d·R_d, the
/// tail (its teeth passing at the driver's rate) at ω_t = ω_d·z_d/z_t, so
/// the energies are ½·n·m·v² and ½·J_t·ω_t².
fn first_second(moving: bool) -> FirstSecond {
    let mut spec = chaindrive::scene::DriveSpec::new(300, 2).expect("spec");
    spec.speed_rpm = 60.0;
    spec.ramp_s = 0.5;
    let scene = spec.scene().expect("scene");
    let omega_d = 60.0 * std::f64::consts::TAU / 60.0;
    let tail_want = omega_d * 60.0 / 30.0;
    let pitch_m = spec.chain.pitch_m.expect("pitch");
    let v = omega_d * pitch_m / (2.0 * (std::f64::consts::PI / 60.0).sin());
    let mut world = PhysicsWorld::default();
    let builder = ChainDrive::builder(&scene);
    let builder = if moving {
        builder.start_moving()
    } else {
        builder
    };
    let mut drive = builder.build(&mut world).expect("drive builds");
    let (driver, tail) = (drive.sprocket(0).expect("0"), drive.sprocket(1).expect("1"));
    let model = drive.model();
    let want_j = (
        0.5 * 300.0 * model.roller_mass_kg * v * v,
        0.5 * tail_want * tail_want / model.sprockets[1].inv_inertia,
    );
    let start_j = kinetic_energy_j(&drive);
    let (mut first, mut worst) = (f64::NAN, 0.0f64);
    for frame in 0..60 {
        drive.step_world(&mut world, &(), &()).expect("frame");
        let off = drive.sprocket_speed(tail) / tail_want - 1.0;
        if frame == 0 {
            first = off;
            if moving {
                assert!(
                    (drive.sprocket_speed(driver) - omega_d).abs() < 1e-9,
                    "the driver at its speed from the start"
                );
            }
        }
        worst = worst.max(off.abs());
    }
    FirstSecond {
        first,
        worst,
        start_j,
        end_j: kinetic_energy_j(&drive),
        want_j,
    }
}

/// `ChainDriveBuilder::start_moving` against the closed forms of
/// [`first_second`]: the tail within 2 % of ω_d·z_d/z_t in every frame of
/// the first second (the polygonal action alone moves it by up to
/// 1/cos(π/30) − 1 = 0.55 %), the energies within 1 % at the start and
/// after the second; the same drive ramped from rest is nowhere near its
/// speed in its first frame.
#[test]
fn a_drive_started_moving_turns_its_tail_at_the_teeth_ratio_from_the_first_frame() {
    let r = first_second(true);
    println!(
        "started moving: tail {:+.3} % in frame 1, at most {:.3} % off in 1 s; chain energy \
         {:.4} J at the start, {:.4} J after 1 s (closed form {:.4} J); tail {:.4} J, {:.4} J \
         ({:.4} J)",
        100.0 * r.first,
        100.0 * r.worst,
        r.start_j.0,
        r.end_j.0,
        r.want_j.0,
        r.start_j.1,
        r.end_j.1,
        r.want_j.1
    );
    assert!(
        r.worst < 0.02,
        "tail off its speed by {:.2} %",
        100.0 * r.worst
    );
    for (got, want, what) in [
        (r.start_j.0, r.want_j.0, "chain at the start"),
        (r.end_j.0, r.want_j.0, "chain after 1 s"),
        (r.start_j.1, r.want_j.1, "tail at the start"),
    ] {
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "{what}: {got} J, closed form {want} J"
        );
    }
    let ramped = first_second(false);
    println!(
        "ramped from rest: tail {:+.1} % in frame 1, chain energy {} J at the start",
        100.0 * ramped.first,
        ramped.start_j.0
    );
    assert!(ramped.first < -0.5 && ramped.start_j.0 == 0.0);
}
