//! A user's own drives through guides, tensioner arms, designations and
//! sweeps: a motorcycle's final drive by designation with a wear strip and
//! a spring arm, the same drive flat with a hydraulic arm setting its
//! tension, and a sweep of it with an engine harmonic and a cam-table load.
//! Every expected number is worked by hand from the scene's own inputs.

use crate::scene::designations::find;
use crate::scene::{Overrides, Scene};
#[cfg(feature = "lab")]
use crate::studies::sweep::excitation_orders;

fn data(file: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(file)
}

fn scene(file: &str) -> Scene {
    Scene::from_path_with(&data(file), &Overrides::default())
        .expect("the scene file reads")
        .expect("a valid scene")
}

const INCH_M: f64 = 0.0254;

/// ISO 606's A series is ASME B29.1's chains under metric names (two digits:
/// the pitch in sixteenths of an inch): "ISO 606 10A-1" is ANSI 50, pitch
/// 5/8 in, roller 0.400 in; "16A-1" is ANSI 80, pitch 1 in, roller 0.625 in.
/// Before, 10A-1 was unknown and its nearest names were 10B-1 (another
/// chain, roller 10.16 mm on a B-series plate) and ANSI 100 (twice the
/// pitch). Exact (the table's inch values).
#[test]
fn an_iso_a_series_name_is_its_ansi_chain() {
    for (name, pitch_in, roller_d_in) in [
        ("ISO 606 10A-1", 0.625, 0.400),
        ("16A-1", 1.0, 0.625),
        ("08A", 0.5, 0.312),
    ] {
        let d = find(name).unwrap_or_else(|| panic!("{name} is known"));
        approx::assert_relative_eq!(d.pitch_m, pitch_in * INCH_M, max_relative = 1e-12);
        approx::assert_relative_eq!(
            d.roller_radius_m(),
            roller_d_in / 2.0 * INCH_M,
            max_relative = 1e-12
        );
    }
    // The same in a scene: the motorcycle drive on "ISO 606 10A-1" is on
    // ANSI 50's rollers.
    let text = std::fs::read_to_string(data("user_moto_10b_guide_arm.toml"))
        .expect("the scene file reads")
        .replace("ISO 606 10B-1", "ISO 606 10A-1");
    let s = Scene::from_toml(&text).expect("a valid scene");
    approx::assert_relative_eq!(
        s.chain().roller_radius_m,
        0.2 * INCH_M,
        max_relative = 1e-12
    );
}

/// A typo in the designation is one error at `chain.designation`; the
/// fields the designation would have filled are not reported missing as
/// well (before: four more errors, "chain.pitch_m: is required (or give
/// chain.designation …)", to a user who had given one).
#[test]
fn a_typo_in_the_designation_is_one_error() {
    let text = std::fs::read_to_string(data("user_moto_10b_guide_arm.toml"))
        .expect("the scene file reads")
        .replace("ISO 606 10B-1", "ISO 606 10-B1");
    let err = Scene::from_toml(&text)
        .expect_err("unknown designation")
        .to_string();
    assert!(err.contains("chain.designation"), "{err}");
    assert!(err.contains("\"ISO 606 10B-1\""), "{err}");
    assert!(!err.contains("is required"), "{err}");
    assert!(!err.contains("NaN"), "{err}");
}

/// The orders a sweep overlays and searches for crossings include the
/// scene's own excitation, in orders of the driver: the engine's harmonic
/// (2), the meshing order and twice it (15, 30), the wheel's load harmonic
/// of order 3 (3 × 15/42 = 15/14: the wheel turns 15/42 of a revolution per
/// engine revolution) and the cam table's four lobes (assets/cam-torque.csv:
/// "lobes 90 deg apart", 4 × 15/42 = 10/7). Before, only 1, 2, 15 and 30
/// were searched, whatever the scene's excitation. Exact.
#[cfg(feature = "lab")]
#[test]
fn a_sweep_searches_the_scenes_own_excitation_orders() {
    let orders = excitation_orders(&scene("user_moto_10b_sweep.toml"));
    let expected = [15.0 / 14.0, 10.0 / 7.0, 1.0, 2.0, 15.0, 30.0];
    for k in expected {
        assert!(
            orders.iter().any(|o| (o - k).abs() < 1e-12),
            "order {k} missing from {orders:?}"
        );
    }
    assert_eq!(orders.len(), expected.len(), "{orders:?}");
    assert!(orders.windows(2).all(|w| w[0] < w[1]), "{orders:?}");
}

/// A conveyor whose upper strand lies on a wear strip (lifted 0.2 mm above
/// the sprockets' tangent) settles at rest with the real tooth form as it
/// does without the strip: within 1e-6 of the pretension (found 9.8e-11).
#[test]
fn a_conveyor_on_a_wear_strip_settles_at_rest() {
    let text = std::fs::read_to_string(data("user_conveyor_strips.toml"))
        .expect("the scene file")
        .replace("profile = \"circular\"", "profile = \"real\"");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let sim = crate::sim::Simulation::new(&scene).expect("it settles");
    assert!(
        sim.equilibrium.force_residual < 1e-6,
        "{:?}",
        sim.equilibrium
    );
    let t = sim.equilibrium.tension_n;
    assert!(
        (t - 2000.0).abs() <= 2000.0 * scene.equilibrium().tension_tolerance,
        "{t}"
    );
}
