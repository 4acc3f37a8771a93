//! Chains by designation: the table against dimensions typed in from the
//! standards (not read from the table), the fields a designation fills and
//! the ones a scene overrides, and a typo's error.

use chaindrive::scene::Scene;
use chaindrive::scene::designations::{DESIGNATIONS, find};

const INCH_M: f64 = 0.0254;

fn scene_text(file: &str) -> String {
    let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).expect("the scene file exists")
}

/// The pitch follows from the name in both families: an ISO 606 B-series
/// number is the pitch in sixteenths of an inch (16B: 16/16 in = 25.4 mm;
/// 05B is the exception, a metric 8.00 mm),
/// an ANSI number's leading digits are the pitch in eighths of an inch
/// (80: 8/8 in; 25: 2/8 in; the trailing 0, 1 or 5 is the kind). Exact.
#[test]
fn every_pitch_follows_from_its_name() {
    for d in DESIGNATIONS {
        let expected = if let Some(rest) = d.name.strip_prefix("ISO 606 ") {
            let n: f64 = rest.trim_end_matches("B-1").parse().expect("a number");
            if n == 5.0 { 8.0e-3 } else { n / 16.0 * INCH_M }
        } else {
            let number = d.name.trim_start_matches("ANSI ");
            let eighths: f64 = number[..number.len() - 1].parse().expect("a number");
            eighths / 8.0 * INCH_M
        };
        approx::assert_relative_eq!(d.pitch_m, expected, max_relative = 1e-12);
    }
}

/// Pitch P, roller diameter d₁ and pin diameter d₂ (mm) of a handful of
/// sizes, typed in from ISO 606:2004 Table 1 (B series) and ASME B29.1
/// (ANSI), to the standards' two decimals.
#[test]
fn dimensions_match_the_standards() {
    let typed = [
        ("ISO 606 05B-1", 8.00, 5.00, 2.31),
        ("ISO 606 08B-1", 12.70, 8.51, 4.45),
        ("ISO 606 16B-1", 25.40, 15.88, 8.28),
        ("ISO 606 24B-1", 38.10, 25.40, 14.63),
        ("ISO 606 48B-1", 76.20, 48.26, 29.24),
        ("ISO 606 72B-1", 114.30, 72.39, 44.48),
        ("ANSI 40", 12.70, 7.92, 3.96),
        ("ANSI 60", 19.05, 11.91, 5.94),
        ("ANSI 80", 25.40, 15.88, 7.92),
        ("ANSI 120", 38.10, 22.23, 11.10),
        ("ANSI 240", 76.20, 47.63, 23.81),
    ];
    for (name, p, d1, d2) in typed {
        let d = find(name).unwrap_or_else(|| panic!("{name} in the table"));
        assert!((d.pitch_m * 1e3 - p).abs() < 0.005, "{name} pitch");
        assert!((d.roller_diameter_m * 1e3 - d1).abs() < 0.005, "{name} d1");
        assert!((d.pin_diameter_m * 1e3 - d2).abs() < 0.005, "{name} d2");
    }
}

/// Both families are covered from end to end: ISO 606 05B to 72B and
/// ANSI 25 to 240; every row is a physical chain (pin inside the roller,
/// roller inside the pitch, pin inside the plate) with a positive mass and
/// stiffness, and its sources named.
#[test]
fn the_table_covers_both_families() {
    for name in [
        "05B", "06B", "08B", "10B", "12B", "16B", "20B", "24B", "28B", "32B", "40B", "48B", "56B",
        "64B", "72B", "ANSI 25", "ANSI 35", "ANSI 40", "ANSI 41", "ANSI 50", "ANSI 60", "ANSI 80",
        "ANSI 100", "ANSI 120", "ANSI 140", "ANSI 160", "ANSI 180", "ANSI 200", "ANSI 240",
    ] {
        assert!(find(name).is_some(), "{name}");
    }
    for d in DESIGNATIONS {
        assert!(d.pin_diameter_m < d.roller_diameter_m, "{}", d.name);
        assert!(d.roller_diameter_m < d.pitch_m, "{}", d.name);
        assert!(d.pin_diameter_m < d.plate_depth_m, "{}", d.name);
        assert!(
            d.mass_per_m_kg > 0.0 && d.stiffness_n_m() > 0.0,
            "{}",
            d.name
        );
        assert!(!d.dimension_source.is_empty() && !d.mass_source.is_empty());
    }
}

/// The stiffness estimate η E A / P with A = 2 t (h₂ − d₂), recomputed by
/// hand for 56B-1 (t = 12 mm, h₂ = 77.85 mm, d₂ = 34.32 mm, P = 88.9 mm,
/// E = 206 GPa, η = 1/3): 2 · 12 · 43.53 mm² = 1044.72 mm²,
/// E A / P = 206e3 · 1044.72 / 88.9 N/mm = 2.4208e9 N/m, η of it 806.9 MN/m
/// — within 1 % of the paper's 815 MN/m for its chain of this size, on
/// which η was calibrated.
#[test]
fn the_stiffness_estimate_is_the_documented_formula() {
    let d = find("56B").expect("56B");
    approx::assert_relative_eq!(d.stiffness_n_m(), 2.4208e9 / 3.0, max_relative = 1e-3);
    approx::assert_relative_eq!(d.stiffness_n_m(), 815e6, max_relative = 0.01);
}

/// A designation fills pitch, roller radius, roller mass (mass per metre
/// times the pitch) and pin radius; the stiffness written in the file wins
/// over the table's.
#[test]
fn a_designation_fills_the_chain_and_written_fields_override() {
    let scene = Scene::from_toml(&scene_text("designation_16b.toml")).expect("a valid scene");
    let chain = scene.chain();
    let d = find("ISO 606 16B-1").expect("16B");
    assert_eq!(chain.designation, Some("ISO 606 16B-1"));
    approx::assert_relative_eq!(chain.pitch_m, 0.0254, max_relative = 1e-12);
    approx::assert_relative_eq!(chain.roller_radius_m, 0.5 * 15.88e-3, max_relative = 1e-12);
    approx::assert_relative_eq!(
        chain.roller_mass_kg,
        d.mass_per_m_kg * 0.0254,
        max_relative = 1e-12
    );
    assert_eq!(chain.stiffness_n_m, 2e8);
    // Without the written stiffness, the table's estimate.
    let text = scene_text("designation_16b.toml").replace("stiffness_n_m = 2e8\n", "");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    approx::assert_relative_eq!(
        scene.chain().stiffness_n_m,
        d.stiffness_n_m(),
        max_relative = 1e-12
    );
    // The pin radius reaches the joint friction.
    let text = scene_text("designation_16b.toml").replace(
        "pretension_n = 1000.0",
        "pretension_n = 1000.0\njoint_friction = 0.1",
    );
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let joints = scene.chain().joint_friction.expect("joint friction on");
    approx::assert_relative_eq!(joints.pin_radius_m, 0.5 * 8.28e-3, max_relative = 1e-12);
}

/// A typo is an error at chain.designation naming the nearest names; a
/// chain with neither a designation nor a pitch names the missing field.
#[test]
fn a_typo_in_the_designation_suggests_the_nearest_names() {
    let text = scene_text("designation_16b.toml").replace("ISO 606 16B-1", "ISO 606 16V-1");
    let err = Scene::from_toml(&text)
        .expect_err("unknown designation")
        .to_string();
    assert!(err.contains("chain.designation"), "{err}");
    assert!(err.contains("\"ISO 606 16B-1\""), "{err}");
    let text = scene_text("designation_16b.toml").replace("designation = \"ISO 606 16B-1\"\n", "");
    let err = Scene::from_toml(&text).expect_err("no pitch").to_string();
    assert!(
        err.contains("chain.pitch_m") && err.contains("chain.designation"),
        "{err}"
    );
    assert!(!err.contains("NaN"), "{err}");
}

/// The drive named by designation lays out, settles and runs briefly.
#[test]
fn a_drive_by_designation_runs() {
    let scene = Scene::from_toml(&scene_text("designation_16b.toml")).expect("a valid scene");
    let mut sim = chaindrive::sim::Simulation::new(&scene).expect("a static equilibrium");
    sim.run(0.02, u64::MAX, &mut chaindrive::sim::NoObserver, None)
        .expect("no blow-up");
}
