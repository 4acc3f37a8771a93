//! Chains by designation: the table against dimensions typed in from the
//! standards (not read from the table), the fields a designation fills and
//! the ones a scene overrides, and a typo's error.

use crate::scene::Scene;
use crate::scene::designations::{DESIGNATIONS, find, lookup, transverse_pitch_m};

const INCH_M: f64 = 0.0254;

/// A value the row must have (every row but the motorcycle chains').
fn known(value: Option<f64>) -> f64 {
    value.expect("the row has the value")
}

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
        } else if d.is_motorcycle() {
            // A motorcycle number's first digit: 520 is 5/8 in.
            let eighths: f64 = d.name[..1].parse().expect("a digit");
            eighths / 8.0 * INCH_M
        } else {
            // A heavy chain ("80H") has its standard chain's pitch.
            let number = d.name.trim_start_matches("ANSI ").trim_end_matches('H');
            let eighths: f64 = number[..number.len() - 1].parse().expect("a number");
            eighths / 8.0 * INCH_M
        };
        approx::assert_relative_eq!(d.pitch_m, expected, max_relative = 1e-12);
    }
}

/// ANSI rows against ASME B29.1's dimension table as printed by Engineers
/// Edge ("Roller Chain Dimensions per ASME/ANSI B29.1M") and AmesWeb, in
/// inches: pitch, roller diameter, width, pin diameter, link plate
/// thickness, minimum ultimate tensile strength (lbf); and the weight per
/// foot (lb/ft) of the "Standard Roller Chain Dimensions" table. Typed in
/// here, converted here (1 in = 25.4 mm, 1 lbf = 4.448 222 N, 1 lb/ft =
/// 1.488 164 kg/m); to the printed digits.
#[test]
fn ansi_rows_match_asme_b29_1() {
    let typed = [
        // name        P      Dr     W      Dp     LPT    MUTS     lb/ft
        ("ANSI 40", 0.500, 0.312, 0.312, 0.156, 0.060, 3125.0, 0.41),
        ("ANSI 60", 0.750, 0.469, 0.500, 0.234, 0.094, 7030.0, 1.00),
        ("ANSI 80", 1.000, 0.625, 0.625, 0.312, 0.125, 12500.0, 1.69),
        ("ANSI 160", 2.000, 1.125, 1.250, 0.562, 0.250, 50000.0, 6.43),
        (
            "ANSI 240", 3.000, 1.875, 1.875, 0.937, 0.375, 112500.0, 16.90,
        ),
    ];
    for (name, p, dr, w, dp, lpt, muts, wt) in typed {
        let d = find(name).unwrap_or_else(|| panic!("{name} in the table"));
        let inch = |m: f64| m / INCH_M;
        assert!((inch(d.pitch_m) - p).abs() < 5e-4, "{name} pitch");
        assert!((inch(d.roller_diameter_m) - dr).abs() < 5e-4, "{name} Dr");
        assert!((inch(d.inner_width_m) - w).abs() < 5e-4, "{name} W");
        assert!(
            (inch(known(d.pin_diameter_m)) - dp).abs() < 5e-4,
            "{name} Dp"
        );
        assert!(
            (inch(known(d.plate_thickness_m)) - lpt).abs() < 5e-4,
            "{name} LPT"
        );
        assert!(
            (known(d.tensile_strength_n) / 4.448_222 - muts).abs() < 1.0,
            "{name} MUTS"
        );
        assert!(
            (known(d.mass_per_m_kg) / 1.488_164 - wt).abs() < 5e-3,
            "{name} weight"
        );
        assert!(d.sources.dimensions.contains("B29.1"), "{name}");
    }
}

/// B-series rows against the Ametric catalogue table "Standard Metric
/// Roller Chain (DIN 8180/8187 and BS 228)": pitch, inner width b₁, roller
/// diameter d₁ (mm, printed to two decimals, 9.525 and 15.875 as 9.52 and
/// 15.87), weight (kg/m) and, for 06B and 08B, breaking strength (N).
#[test]
fn iso_rows_match_the_ametric_catalogue() {
    let typed = [
        // name           P      b1     d1     kg/m   N (0: not printed)
        ("ISO 606 06B-1", 9.52, 5.72, 6.35, 0.41, 9000.0),
        ("ISO 606 08B-1", 12.70, 7.75, 8.51, 0.70, 18000.0),
        ("ISO 606 10B-1", 15.87, 9.65, 10.16, 0.91, 0.0),
        ("ISO 606 16B-1", 25.40, 17.02, 15.88, 2.68, 0.0),
        ("ISO 606 32B-1", 50.80, 30.99, 29.21, 10.5, 0.0),
        ("ISO 606 48B-1", 76.20, 45.72, 48.26, 25.0, 0.0),
    ];
    for (name, p, b1, d1, q, f) in typed {
        let d = find(name).unwrap_or_else(|| panic!("{name} in the table"));
        assert!((d.pitch_m * 1e3 - p).abs() < 0.01, "{name} pitch");
        assert!((d.inner_width_m * 1e3 - b1).abs() < 0.005, "{name} b1");
        assert!((d.roller_diameter_m * 1e3 - d1).abs() < 0.005, "{name} d1");
        assert!((known(d.mass_per_m_kg) - q).abs() < 0.005, "{name} mass");
        if f > 0.0 {
            assert!(
                (known(d.tensile_strength_n) - f).abs() < 1.0,
                "{name} strength"
            );
        }
        assert!(d.sources.dimensions.contains("Ametric"), "{name}");
        assert!(d.sources.mass.contains("Ametric"), "{name}");
    }
}

/// What no source was found for says so: every B-series plate thickness
/// and pin diameter, and the 56B to 72B masses.
#[test]
fn unchecked_values_are_marked_as_estimates() {
    for d in DESIGNATIONS.iter().filter(|d| d.name.starts_with("ISO")) {
        assert!(d.sources.plate_thickness.contains("estimate"), "{}", d.name);
        assert!(
            d.sources.pin_and_plate_depth.contains("estimate"),
            "{}",
            d.name
        );
    }
    for name in ["56B", "64B", "72B"] {
        assert!(find(name).expect(name).sources.mass.contains("estimate"));
    }
    for d in DESIGNATIONS.iter().filter(|d| d.name.starts_with("ANSI")) {
        assert!(
            !format!("{:?}", d.sources).contains("estimate"),
            "{}",
            d.name
        );
    }
}

/// The families are covered from end to end: ISO 606 05B to 72B,
/// ANSI 25 to 240 and the heavy 60H to 240H; every row is a physical chain (pin inside the roller,
/// roller inside the pitch, pin inside the plate) with a positive mass and
/// stiffness, and its sources named.
#[test]
fn the_table_covers_both_families() {
    for name in [
        "05B",
        "06B",
        "08B",
        "10B",
        "12B",
        "16B",
        "20B",
        "24B",
        "28B",
        "32B",
        "40B",
        "48B",
        "56B",
        "64B",
        "72B",
        "ANSI 25",
        "ANSI 35",
        "ANSI 40",
        "ANSI 41",
        "ANSI 50",
        "ANSI 60",
        "ANSI 80",
        "ANSI 100",
        "ANSI 120",
        "ANSI 140",
        "ANSI 160",
        "ANSI 180",
        "ANSI 200",
        "ANSI 240",
        "ANSI 60H",
        "80H",
        "100H",
        "120H",
        "140H",
        "160H",
        "180H",
        "200H",
        "ansi 240h",
    ] {
        assert!(find(name).is_some(), "{name}");
    }
    // The motorcycle rows hold fewer values (their own tests).
    for d in DESIGNATIONS.iter().filter(|d| !d.is_motorcycle()) {
        assert!(known(d.pin_diameter_m) < d.roller_diameter_m, "{}", d.name);
        assert!(d.roller_diameter_m < d.pitch_m, "{}", d.name);
        assert!(
            known(d.pin_diameter_m) < known(d.plate_depth_m),
            "{}",
            d.name
        );
        assert!(
            known(d.mass_per_m_kg) > 0.0 && known(d.stiffness_n_m()) > 0.0,
            "{}",
            d.name
        );
        assert!(!d.sources.dimensions.is_empty() && !d.sources.mass.is_empty());
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
    approx::assert_relative_eq!(
        known(d.stiffness_n_m()),
        2.4208e9 / 3.0,
        max_relative = 1e-3
    );
    approx::assert_relative_eq!(known(d.stiffness_n_m()), 815e6, max_relative = 0.01);
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
        known(d.mass_per_m_kg) * 0.0254,
        max_relative = 1e-12
    );
    assert_eq!(chain.stiffness_n_m, 2e8);
    // Without the written stiffness, the table's estimate.
    let text = scene_text("designation_16b.toml").replace("stiffness_n_m = 2e8\n", "");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    approx::assert_relative_eq!(
        scene.chain().stiffness_n_m,
        known(d.stiffness_n_m()),
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
    let mut sim = crate::sim::Simulation::new(&scene).expect("a static equilibrium");
    sim.run(0.02, u64::MAX, &mut crate::sim::NoObserver, None)
        .expect("no blow-up");
}

/// Multiple strands against the catalogues' printed numbers, typed here:
/// the minimum tensile strength of n strands is n times the single strand's
/// (ASME B29.1's ANSI 80: 12,500 lbf, so 80-2 25,000 lbf; U.S. Tsubaki
/// prints RS50-3 at 14,640 lbs), the mass about n times (PEER's 80-2
/// weighs 3.41 lb/ft on average, 2 × 1.69 = 3.38: within 1.5 %), and the
/// pitch and roller are the single strand's (08A-3 is ANSI 40 in three
/// strands: 1/2 in pitch).
#[test]
fn multi_strand_chains_scale_as_the_catalogues_print() {
    let lbf_n = 4.448_222;
    let c = lookup("ANSI 80-2").expect("80-2");
    assert_eq!((c.single.name, c.strands), ("ANSI 80", 2));
    approx::assert_relative_eq!(
        known(c.tensile_strength_n()),
        25_000.0 * lbf_n,
        max_relative = 1e-6
    );
    approx::assert_relative_eq!(
        known(c.mass_per_m_kg()),
        3.41 * 1.488_164,
        max_relative = 0.015
    );
    assert_eq!(c.name(), "ANSI 80-2");
    let c = lookup("50-3").expect("50-3");
    approx::assert_relative_eq!(
        known(c.tensile_strength_n()),
        14_640.0 * lbf_n,
        max_relative = 1e-6
    );
    let c = lookup("iso 606 08a-3").expect("08A-3");
    assert_eq!((c.single.name, c.strands), ("ANSI 40", 3));
    approx::assert_relative_eq!(c.single.pitch_m, 0.5 * INCH_M, max_relative = 1e-12);
    let c = lookup("ISO 606 16B-2").expect("16B-2");
    assert_eq!(c.name(), "ISO 606 16B-2");
    // Stiffness and the wear check's bearing length: n times.
    approx::assert_relative_eq!(
        known(c.stiffness_n_m()),
        2.0 * known(c.single.stiffness_n_m()),
        max_relative = 1e-12
    );
    // 16B: b1 = 17.02 mm, t = 3.10 mm (the table's estimate): 2 × 23.22 mm.
    approx::assert_relative_eq!(
        known(c.bushing_length_m()),
        2.0 * 23.22e-3,
        max_relative = 1e-9
    );
    // No transverse pitch was read for the B series; 80-2's is 1.153 in (PEER).
    assert!(transverse_pitch_m(c.single).is_none());
    approx::assert_relative_eq!(
        transverse_pitch_m(find("80").expect("80")).expect("published"),
        1.153 * INCH_M,
        max_relative = 1e-12
    );
}

/// A strand count beyond the rating's factors, a multi-strand No. 41 and a
/// name the table does not hold (a motorcycle chain's heavy grade or another
/// size, a heavy chain smaller than 60H) are errors
/// that say what is allowed, and a scene names the field.
#[test]
fn strand_counts_and_families_outside_the_table_are_clear_errors() {
    let e = lookup("80-7").expect_err("7 strands");
    assert!(
        e.contains("1 to 4 strands") && e.contains("\"ANSI 80-4\""),
        "{e}"
    );
    let e = lookup("ANSI 41-2").expect_err("41 is single only");
    assert!(e.contains("single strand only"), "{e}");
    for name in ["520H", "630", "50H", "ANSI 530", "16X"] {
        let e = lookup(name).expect_err(name);
        assert!(
            e.contains("unknown designation") && e.contains("nearest"),
            "{e}"
        );
    }
    // The families not in the table say so, and what to give instead.
    for (name, family) in [
        ("520H", "motorcycle chains are 520, 525 and 530"),
        ("630", "motorcycle chains are 520, 525 and 530"),
        ("50H", "60H to 240H"),
    ] {
        let e = lookup(name).expect_err(name);
        assert!(e.contains(family) && e.contains("chain.pitch_m"), "{e}");
    }
    assert!(!lookup("16X").expect_err("16X").contains("not in the table"));
    assert!(find("80-2").is_none(), "find is single strands only");
    let text = scene_text("designation_16b.toml").replace("ISO 606 16B-1", "80-7");
    let err = Scene::from_toml(&text).expect_err("80-7").to_string();
    assert!(
        err.contains("chain.designation") && err.contains("1 to 4"),
        "{err}"
    );
    assert!(
        !err.contains("chain.pitch_m"),
        "one error, not the fields: {err}"
    );
}

/// A scene naming "ISO 606 16B-2" gets two strands' mass and stiffness, and
/// a rating of 1.7 times one strand's. By hand, the 19-tooth driver at 100
/// rpm, pitch 1 in, standard constants: H₁ = 0.004 · 19^1.08 · 100^0.9 ·
/// 1^2.93 = 6.069 hp, H₂ = 17,000 · 19^1.5 / 100^1.5 = 1,408 hp, so the
/// rating is H₁ = 6.069 hp = 4,525.6 W, and two strands may transmit
/// 1.7 × 4,525.6 = 7,693.6 W; the tensile strength 2 × 60 kN; the fatigue
/// limit 1.7 times the single strand's.
#[test]
fn a_two_strand_designation_reaches_the_rating_and_the_fatigue_check() {
    use crate::analysis::design::{fatigue, rating};
    let single = Scene::from_toml(&scene_text("designation_16b.toml")).expect("16B-1");
    let text = scene_text("designation_16b.toml")
        .replace("ISO 606 16B-1", "ISO 606 16B-2")
        .replace("stiffness_n_m = 2e8\n", "");
    let double = Scene::from_toml(&text).expect("16B-2");
    let chain = double.chain();
    assert_eq!(
        (chain.designation, chain.strands),
        (Some("ISO 606 16B-1"), 2)
    );
    // 16B: 2.68 kg/m (Ametric) × 2 strands × 25.4 mm.
    approx::assert_relative_eq!(
        chain.roller_mass_kg,
        2.0 * 2.68 * 0.0254,
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(
        chain.stiffness_n_m,
        2.0 * known(find("16B").expect("16B").stiffness_n_m()),
        max_relative = 1e-12
    );
    let settings = rating::RatingSettings::default();
    let r = rating::of_scene(&double, settings, Some(1000.0)).expect("rated");
    approx::assert_relative_eq!(r.rated_power_w, 4_525.6, max_relative = 1e-4);
    approx::assert_relative_eq!(r.design_power_w, 7_693.6, max_relative = 1e-4);
    assert_eq!((r.strands, r.strand_factor), (2, 1.7));
    assert_eq!(r.designation.as_deref(), Some("ISO 606 16B-2"));
    approx::assert_relative_eq!(
        r.tensile_strength_n.expect("a strength"),
        120e3,
        max_relative = 1e-12
    );
    let one = rating::of_scene(&single, settings, Some(1000.0)).expect("rated");
    approx::assert_relative_eq!(one.design_power_w, 4_525.6, max_relative = 1e-4);
    let (sn1, _) = fatigue::curve_of_scene(&single).expect("a curve");
    let (sn2, basis) = fatigue::curve_of_scene(&double).expect("a curve");
    approx::assert_relative_eq!(
        sn2.fatigue_limit_n,
        1.7 * sn1.fatigue_limit_n,
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(sn2.tensile_strength_n, 120e3, max_relative = 1e-12);
    assert!(basis.contains("multiple-strand factor 1.7"), "{basis}");
}

/// ANSI heavy rows against the Donghua "Drive Chains 2020" catalogue, heavy
/// duty series simplex table (pp. 244–245), typed here in millimetres, kg/m
/// and kN: pitch P, roller d₁, inner width b₁, pin d₂, inner plate depth h₂,
/// plate thickness T, mass q, minimum tensile strength Q_min. The 80H is
/// checked against a second maker: the Mecha catalogue's 16H1 (ASA 80
/// heavy) weighs 3.10 kg/m and breaks at 56,700 N at least.
#[test]
fn heavy_rows_match_the_donghua_catalogue() {
    let typed = [
        // name        P       d1     b1     d2     h2     T      kg/m   kN
        (
            "ANSI 60H", 19.050, 11.91, 12.57, 5.94, 18.00, 3.25, 1.87, 31.80,
        ),
        (
            "ANSI 80H", 25.400, 15.88, 15.75, 7.92, 24.00, 4.00, 3.10, 56.70,
        ),
        (
            "ANSI 120H",
            38.100,
            22.23,
            25.22,
            11.10,
            35.70,
            5.60,
            6.60,
            127.00,
        ),
        (
            "ANSI 160H",
            50.800,
            28.58,
            31.55,
            14.27,
            47.80,
            7.20,
            10.30,
            226.80,
        ),
        (
            "ANSI 200H",
            63.500,
            39.68,
            37.85,
            19.85,
            60.00,
            9.50,
            19.16,
            353.80,
        ),
        (
            "ANSI 240H",
            76.200,
            47.63,
            47.35,
            23.81,
            72.39,
            12.70,
            30.40,
            510.30,
        ),
    ];
    for (name, p, d1, b1, d2, h2, t, q, f) in typed {
        let d = find(name).unwrap_or_else(|| panic!("{name} in the table"));
        let mm = |m: f64| m * 1e3;
        assert!((mm(d.pitch_m) - p).abs() < 5e-4, "{name} P");
        assert!((mm(d.roller_diameter_m) - d1).abs() < 5e-3, "{name} d1");
        assert!((mm(d.inner_width_m) - b1).abs() < 5e-3, "{name} b1");
        assert!((mm(known(d.pin_diameter_m)) - d2).abs() < 5e-3, "{name} d2");
        assert!((mm(known(d.plate_depth_m)) - h2).abs() < 5e-3, "{name} h2");
        assert!(
            (mm(known(d.plate_thickness_m)) - t).abs() < 5e-3,
            "{name} T"
        );
        assert!((known(d.mass_per_m_kg) - q).abs() < 5e-3, "{name} q");
        assert!(
            (known(d.tensile_strength_n) - f * 1e3).abs() < 1.0,
            "{name} Q"
        );
        assert!(d.sources.dimensions.contains("Donghua"), "{name}");
        assert!(d.sources.strength.contains("Donghua"), "{name}");
    }
    let d = find("80H").expect("80H");
    assert!((known(d.mass_per_m_kg) - 3.10).abs() < 5e-3);
    assert!((known(d.tensile_strength_n) - 56_700.0).abs() < 1.0);
}

/// A heavy chain's plates are the next larger standard size's: B29.1's link
/// plate thickness of ANSI 80, 100, …, 240 (0.125, 0.156, 0.187, 0.219,
/// 0.250, 0.281, 0.312, 0.375 in, typed from the B29.1 table) against the
/// catalogue's 60H to 200H, within 0.08 mm; 240H's 12.70 mm is 0.500 in.
/// Its pitch, roller and pin are its standard chain's (B29.1: 80's roller
/// 0.625 in, pin 0.312 in).
#[test]
fn heavy_plates_are_the_next_larger_sizes() {
    for (heavy, next_lpt_in) in [
        ("60H", 0.125),
        ("80H", 0.156),
        ("100H", 0.187),
        ("120H", 0.219),
        ("140H", 0.250),
        ("160H", 0.281),
        ("180H", 0.312),
        ("200H", 0.375),
        ("240H", 0.500),
    ] {
        let t_mm = known(find(heavy).expect(heavy).plate_thickness_m) * 1e3;
        assert!(
            (t_mm - next_lpt_in * 25.4).abs() < 0.08,
            "{heavy}: {t_mm} mm against {next_lpt_in} in"
        );
    }
    let d = find("80H").expect("80H");
    assert!((d.roller_diameter_m / INCH_M - 0.625).abs() < 5e-4);
    assert!((known(d.pin_diameter_m) / INCH_M - 0.312).abs() < 5e-4);
}

/// The heavy plates' stiffness by hand, 80H (T = 4.00 mm, h₂ = 24.00 mm,
/// d₂ = 7.92 mm, P = 25.4 mm): A = 2 · 4.00 · 16.08 = 128.64 mm², E A / P =
/// 206e3 · 128.64 / 25.4 N/mm = 1.04330e9 N/m, a third of it 3.4777e8 N/m;
/// the standard 80 (t = 3.175 mm, h₂ = 0.95 · 25.4 = 24.13 mm, d₂ = 7.9248
/// mm): A = 102.903 mm², 2.7819e8 N/m. Two strands of 80H: n × 56.70 kN =
/// 113.40 kN, as the catalogue's duplex table prints 80H-2 (and its
/// triplex 80H-3 at 170.1 kN).
#[test]
fn a_heavy_chain_is_stiffer_and_comes_in_strands() {
    approx::assert_relative_eq!(
        known(find("80H").expect("80H").stiffness_n_m()),
        3.4777e8,
        max_relative = 1e-4
    );
    approx::assert_relative_eq!(
        known(find("80").expect("80").stiffness_n_m()),
        2.7819e8,
        max_relative = 1e-4
    );
    let c = lookup("ANSI 80H-2").expect("80H-2");
    assert_eq!((c.single.name, c.strands), ("ANSI 80H", 2));
    assert_eq!(c.name(), "ANSI 80H-2");
    approx::assert_relative_eq!(
        known(c.tensile_strength_n()),
        113_400.0,
        max_relative = 1e-9
    );
    let c = lookup("80h-3").expect("80H-3");
    approx::assert_relative_eq!(
        known(c.tensile_strength_n()),
        170_100.0,
        max_relative = 1e-9
    );
    // The catalogue's multi-strand heavy tables print the standard chain's
    // strand spacing: none is listed for a heavy chain.
    assert!(transverse_pitch_m(c.single).is_none());
}
