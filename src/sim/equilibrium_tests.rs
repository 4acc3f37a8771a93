//! The static equilibrium: drives that used to fail settle, and infeasible
//! requests name their cause with the closed-form threshold.

use crate::scene::Scene;
use crate::sim::statics::BeyondSeatingArc;
use crate::sim::{EquilibriumError, SimError, Simulation};

fn scene(file: &str) -> Scene {
    let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("the scene file exists");
    Scene::from_toml(&text).expect("a valid scene")
}

fn equilibrium_error(scene: &Scene) -> EquilibriumError {
    match Simulation::new(scene) {
        Err(SimError::Equilibrium(e)) => e,
        Err(e) => panic!("expected an equilibrium error, got {e}"),
        Ok(sim) => panic!("expected no equilibrium, got {:?}", sim.equilibrium),
    }
}

/// Pitch radius R = P / (2 sin(π/N)).
fn pitch_radius_m(pitch_m: f64, teeth: u32) -> f64 {
    pitch_m / (2.0 * (std::f64::consts::PI / f64::from(teeth)).sin())
}

/// Regression: without gravity and with the real profile, the first
/// relaxation left the chain slack (T(l₀) flat), the secant step shortened
/// every link by 1.7 mm and the next relaxation blew up. It settles now at
/// the pretension (within the scene's tolerance, 10⁻³), with the rollers at
/// rest: the largest roller force below 10⁻³ of the pretension.
#[test]
fn flat_real_profile_drive_with_load_settles() {
    let scene = scene("flat_30_30_real.toml");
    let sim = Simulation::new(&scene).expect("a static equilibrium");
    let target = scene.chain().pretension_n;
    approx::assert_relative_eq!(sim.equilibrium.tension_n, target, max_relative = 1e-3);
    assert!(
        sim.equilibrium.force_residual < 1e-3,
        "{:?}",
        sim.equilibrium
    );
}

/// A 60/30 drive whose chain is about 0.23 pitch shorter than the path
/// through the seated rollers: at 3000 N its 40 free links take up only
/// 40 T/K = 40 · 3000 / 815e6 m = 0.147 mm.
#[test]
fn too_short_chain_is_named() {
    let scene = scene("short_60_30.toml");
    let EquilibriumError::ChainTooShort {
        short_pitches,
        free_links,
        allowed_m,
        ..
    } = equilibrium_error(&scene)
    else {
        panic!("expected ChainTooShort");
    };
    assert_eq!(free_links, 40);
    approx::assert_relative_eq!(allowed_m, 40.0 * 3000.0 / 815e6, max_relative = 1e-12);
    assert!((0.2..0.26).contains(&short_pitches), "{short_pitches}");
}

/// 15T driver, 45T driven with M = −400 N·m, T₀ = 200 N, equal strands
/// (20 links each): the slack strand carries T₀ − |M| / (2R), R the 45T
/// pitch radius (0.6372 m), so the limit is 2 R T₀ = 254.9 N·m and the
/// least pretension |M| / (2R) = 313.9 N.
#[test]
fn load_beyond_pretension_is_named() {
    let scene = scene("overload_15_45.toml");
    let r = pitch_radius_m(scene.chain().pitch_m, 45);
    let EquilibriumError::LoadBeyondPretension {
        limit_n_m,
        needed_n,
        sprocket,
        ..
    } = equilibrium_error(&scene)
    else {
        panic!("expected LoadBeyondPretension");
    };
    assert_eq!(sprocket, "driven");
    approx::assert_relative_eq!(limit_n_m, 2.0 * r * 200.0, max_relative = 1e-9);
    approx::assert_relative_eq!(needed_n, 400.0 / (2.0 * r), max_relative = 1e-9);
}

/// The over-loaded 15T/45T drive with its load ramped in over 0.5 s
/// (`load_ramp_s`): the static equilibrium carries no load, so it settles
/// although |M| = 400 N·m > 2 R T₀ = 254.9 N·m, and the load and the driver
/// then rise together. 0.3 s of the run (30 000 steps) end without a blow-up
/// and with the loaded sprocket turning no faster than the driver's chain
/// speed allows: |ω₄₅| R₄₅ ≤ 2 ω₁₅ R₁₅ at 10 rpm (a bound, not a fit: the
/// strands' stretch lets the driven sprocket lag or surge, never reverse
/// the chain beyond twice the drive's speed).
#[test]
fn ramped_overload_settles_and_runs() {
    let scene = scene("overload_15_45_ramped.toml");
    let mut sim = Simulation::new(&scene).expect("a static equilibrium with no load");
    let pitch = scene.chain().pitch_m;
    let (r15, r45) = (pitch_radius_m(pitch, 15), pitch_radius_m(pitch, 45));
    approx::assert_relative_eq!(
        sim.equilibrium.tension_n,
        scene.chain().pretension_n,
        max_relative = scene.equilibrium().tension_tolerance
    );
    sim.run(0.3, u64::MAX, &mut crate::sim::NoObserver, None)
        .expect("no blow-up while the load ramps in");
    let omega = &sim.state.omega;
    assert!(omega.iter().all(|w| w.is_finite()), "{omega:?}");
    let driver_chain_speed = 10.0 * std::f64::consts::TAU / 60.0 * r15;
    assert!(
        omega[1].abs() * r45 <= 2.0 * driver_chain_speed,
        "driven chain speed {} m/s, driver's {driver_chain_speed} m/s",
        omega[1].abs() * r45
    );
}

/// With a ramp, the relaxation holds no load: the static tension (and the
/// rest length the pretension rule found) equal those of the same drive
/// with the load removed, to 1e-9 relative (the same computation, so in
/// practice to the bit).
#[test]
fn ramped_load_equilibrium_is_the_unloaded_one() {
    let ramped = scene("overload_15_45_ramped.toml");
    let path = format!(
        "{}/tests/data/overload_15_45_ramped.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).expect("the scene file exists");
    let unloaded_text = text
        .replace("load_torque_n_m = -400.0\n", "")
        .replace("load_ramp_s = 0.5\n", "");
    assert_ne!(text, unloaded_text);
    let unloaded = Scene::from_toml(&unloaded_text).expect("a valid scene");
    let a = Simulation::new(&ramped).expect("settles").equilibrium;
    let b = Simulation::new(&unloaded).expect("settles").equilibrium;
    approx::assert_relative_eq!(a.tension_n, b.tension_n, max_relative = 1e-9);
    approx::assert_relative_eq!(a.rest_length_m, b.rest_length_m, max_relative = 1e-9);
}

/// `load_ramp_s` must be finite and ≥ 0, and is allowed only with a load.
#[test]
fn bad_load_ramp_names_its_field() {
    let path = format!(
        "{}/tests/data/overload_15_45_ramped.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).expect("the scene file exists");
    let cases = [
        (
            text.replace("load_ramp_s = 0.5", "load_ramp_s = -0.1"),
            ">= 0",
        ),
        (
            text.replace("load_ramp_s = 0.5", "load_ramp_s = nan"),
            "finite",
        ),
        (
            text.replace("load_torque_n_m = -400.0\n", ""),
            "only on a sprocket with a load_torque_n_m",
        ),
    ];
    for (bad, reason) in &cases {
        let msg = Scene::from_toml(bad).expect_err("rejected").to_string();
        assert!(msg.contains("sprockets[1].load_ramp_s"), "{msg}");
        assert!(msg.contains(reason), "expected '{reason}' in: {msg}");
    }
    let on_driver = text.replace(
        "ramp_s = 0.5\n[[sprockets]]",
        "ramp_s = 0.5\nload_ramp_s = 0.1\n[[sprockets]]",
    );
    assert_ne!(on_driver, text);
    let msg = Scene::from_toml(&on_driver)
        .expect_err("rejected")
        .to_string();
    assert!(msg.contains("sprockets[0].load_ramp_s"), "{msg}");
}

/// The load law M(t) = M t / t_L before t_L, M after, by hand for
/// M = −400 N·m, t_L = 0.5 s; without a ramp the full load from t = 0.
#[test]
fn load_ramp_is_linear_then_constant() {
    let (model, ..) =
        crate::model::DriveModel::build(&scene("overload_15_45_ramped.toml")).expect("builds");
    let sp = &model.sprockets[1];
    for (t_s, expected) in [
        (0.0, 0.0),
        (0.125, -100.0),
        (0.25, -200.0),
        (0.5, -400.0),
        (3.0, -400.0),
    ] {
        approx::assert_relative_eq!(sp.load_torque_at(t_s), expected, epsilon = 1e-12);
    }
    assert_eq!(sp.load_at_rest_n_m(), 0.0);
    let (model, ..) =
        crate::model::DriveModel::build(&scene("overload_15_45.toml")).expect("builds");
    let sp = &model.sprockets[1];
    assert_eq!(sp.load_torque_at(0.0), -400.0);
    assert_eq!(sp.load_at_rest_n_m(), -400.0);
}

#[test]
fn a_user_torque_is_not_ramped() {
    // A co-simulation's user torque on a mounted sprocket (here 30 N·m) acts
    // in full from t = 0; only the scene's load (−400 N·m over 0.5 s) ramps:
    // M t / t_L + U.
    let (mut model, ..) =
        crate::model::DriveModel::build(&scene("overload_15_45_ramped.toml")).expect("builds");
    let sp = &mut model.sprockets[1];
    sp.user_torque_n_m = 30.0;
    for (t_s, expected) in [(0.0, 30.0), (0.25, -170.0), (0.5, -370.0), (2.0, -370.0)] {
        approx::assert_relative_eq!(sp.load_torque_at(t_s), expected, epsilon = 1e-12);
    }
}

/// A back-side idler with a small load settles, and each loaded sprocket's
/// torque balance holds on the relaxed chain: the strands either side of a
/// sprocket of pitch radius R with load M differ by |M| / R (the lever arm
/// swings between R cos(π/z) and R as the rollers seat: 1.7 % for z = 17,
/// 0.2 % for z = 45; tolerance 3 %).
#[test]
fn back_side_idler_with_a_load_settles_and_balances_its_torque() {
    let scene = scene("backside_idler_520.toml");
    let sim = Simulation::new(&scene).expect("a static equilibrium");
    approx::assert_relative_eq!(sim.equilibrium.tension_n, 600.0, max_relative = 1e-3);
    assert!(
        sim.equilibrium.force_residual < 1e-6,
        "{:?}",
        sim.equilibrium
    );
    let t: Vec<f64> =
        crate::test_support::strand_means(&sim.model, &sim.state, sim.forces.output())
            .into_iter()
            .map(|m| m.expect("a free strand"))
            .collect();
    // Strand k leaves sprocket k: wheel (1) between strands 0 and 1, idler (2) between 1 and 2.
    let pitch = scene.chain().pitch_m;
    for (teeth, load, before, after) in [(45, 50.0, 0, 1), (17, 5.0, 1, 2)] {
        let r = pitch_radius_m(pitch, teeth);
        approx::assert_relative_eq!((t[after] - t[before]).abs(), load / r, max_relative = 0.03);
    }
}

/// The 6 m sagging conveyor (`tests/data/conveyor_sag_6m.toml`: 520
/// rollers, 1500 N, −100 N·m on the tail) settles with the real profile,
/// and with the circular profile at other loads on the tail: every roller's
/// force below 10⁻⁶ of the pretension and the static tension within the
/// scene's tolerance. (With the circular profile at −100 N·m the roller
/// leaving the tail rests on the rim of its seating half circle, where the
/// contact force is discontinuous, and the drive starts *not settled*:
/// docs/model.md, “Pretension and static equilibrium”.)
#[test]
fn sagging_conveyor_settles_with_either_profile_away_from_the_seating_rim() {
    let path = format!(
        "{}/tests/data/conveyor_sag_6m.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).expect("the scene file exists");
    let real = text.replace(
        "gravity_m_s2 = [0.0, -9.81]",
        "gravity_m_s2 = [0.0, -9.81]\nprofile = \"real\"",
    );
    let lighter = text.replace("load_torque_n_m = -100.0", "load_torque_n_m = -50.0");
    let reversed = text.replace("load_torque_n_m = -100.0", "load_torque_n_m = 100.0");
    for (label, variant) in [
        ("real profile", real),
        ("circular, -50 N·m", lighter),
        ("circular, +100 N·m", reversed),
    ] {
        assert_ne!(variant, text, "{label}: the scene was not changed");
        let scene = Scene::from_toml(&variant).expect("a valid scene");
        let sim = Simulation::new(&scene).expect("a static equilibrium");
        let target = scene.chain().pretension_n;
        approx::assert_relative_eq!(
            sim.equilibrium.tension_n,
            target,
            max_relative = scene.equilibrium().tension_tolerance
        );
        assert!(
            sim.equilibrium.force_residual <= 1e-6,
            "{label}: {:?}",
            sim.equilibrium
        );
    }
}

/// Regression: the 6 m sagging conveyor as written (circular profile,
/// −100 N·m on the tail) has no smooth rest state, and it ends with an
/// error naming the cause instead of starting *not settled*. The tight
/// lower strand sags about 6 cm over 6.35 m and leaves both sprockets at an
/// angle below the horizontal, so the first free roller at either end of it
/// is pulled outward (its two links meet at an angle that opens away from
/// the sprocket's centre) and along the pitch circle by the tension jump
/// across that sprocket, |M|/R = 100 / 0.0812 ≈ 1232 N on the tail and the
/// same on the held head that reacts it (R = P / (2 sin(π/20)) for
/// P = 25.4 mm). The circular profile holds a roller only up to its seating
/// arc's rim, 90° from the gap's bottom: the cause names a roller at an end
/// of the lower strand, on the sprocket there, on the rim: pulled beyond it
/// (0° < angle < 90°, outward and along components positive), or held on
/// its edge outside the seating circle where the force jumps to zero (the
/// relaxation leaves the roller chattering across the rim, and the state
/// reached catches it on either side). The same drive with the real profile
/// settles (the test above).
#[test]
fn sagging_conveyor_on_the_circular_rim_names_the_cause() {
    let path = format!(
        "{}/tests/data/conveyor_sag_6m.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).expect("the scene file exists");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let sim = Simulation::new(&scene).expect("a run starts from the state reached");
    let Some(
        err @ BeyondSeatingArc {
            roller,
            sprocket,
            beyond_deg,
            outward_n,
            along_n,
            residual,
            ..
        },
    ) = &sim.equilibrium.beyond_seating_arc
    else {
        panic!("expected the seating arc named, got {:?}", sim.equilibrium);
    };
    assert!(sim.equilibrium.force_residual > 1e-3, "{err}");
    match err.edge_depth_m {
        None => {
            assert!(*beyond_deg > 0.0 && *beyond_deg < 90.0, "{err}");
            assert!(*outward_n > 0.0 && *along_n > 0.0, "{err}");
        }
        Some(depth_m) => {
            // Beyond the edge by at most the 10° the check allows, outside
            // the seating circle by less than the roller's radius, pulled
            // back towards the gap.
            assert!((0.0..=10.0).contains(beyond_deg), "{err}");
            assert!(depth_m > 0.0 && depth_m < 7.94e-3, "{err}");
            assert!(*outward_n <= 0.0, "{err}");
        }
    }
    assert!(*residual > 1e-6, "{err}");
    // The roller is at an end of the lower strand, within a few pitches of
    // the wraps' ends on its sprocket: the tail's wrap holds rollers 250–270
    // or so of 520, the head's 510–519 and 0–10.
    match sprocket.as_str() {
        "tail" => assert!((240..=290).contains(roller), "{err}"),
        "head (driver, held)" => assert!(*roller >= 490 || *roller <= 30, "{err}"),
        _ => panic!("{err}"),
    }
    let text = err.to_string();
    assert!(text.contains("profile = \"real\""), "{text}");
}
