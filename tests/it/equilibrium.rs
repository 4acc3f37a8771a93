//! The static equilibrium: drives that used to fail settle, and infeasible
//! requests name their cause with the closed-form threshold.

use chaindrive::scene::Scene;
use chaindrive::sim::{EquilibriumError, SimError, Simulation};

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
