//! The catalogue rating (docs/design-checks.md, “Rating”) against published
//! numbers: entries of the ANSI horsepower tables as printed, the standard's
//! minimum tensile strength 12,500 p² lbf, and a speed typed ten times too
//! high, whose warnings name the chain speed and the strength.

use crate::analysis::design::rating::{
    self, ChainClass, HP_W, RatingSettings, link_plate_limited_hp, roller_bushing_limited_hp,
};
use crate::analysis::{RunSummary, Signals};
use crate::scene::designations::{DESIGNATIONS, find};
use crate::scene::{Overrides, Scene};
use crate::sim::{SampleRate, Simulation};

const INCH_M: f64 = 0.0254;

/// The table's rating of `name` at `teeth` and `rpm`, hp: the smaller of
/// the two limits at the designation's pitch.
fn table_hp(name: &str, teeth: f64, rpm: f64) -> f64 {
    let d = find(name).unwrap_or_else(|| panic!("{name} in the table"));
    let class = ChainClass::of(Some(d.name));
    let p_in = d.pitch_m / INCH_M;
    link_plate_limited_hp(class, teeth, rpm, p_in)
        .min(roller_bushing_limited_hp(class, teeth, rpm, p_in))
}

/// Horsepower-table entries as printed (single strand, small sprocket's
/// teeth and rpm, hp), typed in from:
/// - ANSI 40, 35 and 41: Engineers Edge, "Horsepower Ratings for ANSI
///   Roller Chains" tables for 1/2" standard No. 40, 3/8" No. 35 and 1/2"
///   lightweight No. 41;
/// - ANSI 25: AmesWeb, "Horsepower Ratings ANSI Roller Chain No 25 Table",
///   only its roller–bushing limited entries (that table's lower-speed
///   entries lie 9–43 % above the link-plate formula; docs/design-checks.md).
///
/// Both link-plate limited entries (low speeds) and roller–bushing limited
/// ones (the highest columns, where the ratings fall with speed) are here.
#[rustfmt::skip]
const TABLE: &[(&str, f64, f64, f64)] = &[
    ("ANSI 40", 17.0, 1000.0, 5.48), ("ANSI 40", 11.0, 1800.0, 4.66),
    ("ANSI 40", 18.0, 1600.0, 8.89), ("ANSI 40", 12.0, 1800.0, 5.31),
    ("ANSI 40", 14.0,  700.0, 3.22), ("ANSI 40", 16.0, 1400.0, 6.94),
    ("ANSI 40", 13.0,  900.0, 3.73),
    ("ANSI 35", 11.0, 2500.0, 3.30), ("ANSI 35", 11.0, 3000.0, 2.94),
    ("ANSI 35", 17.0, 1200.0, 2.73), ("ANSI 35", 17.0, 3000.0, 5.64),
    ("ANSI 35", 17.0, 3500.0, 4.48), ("ANSI 35", 21.0, 2500.0, 6.63),
    ("ANSI 35", 15.0, 1500.0, 2.91),
    ("ANSI 41", 17.0, 1000.0, 3.01), ("ANSI 41", 17.0, 1200.0, 3.29),
    ("ANSI 41", 17.0, 1400.0, 2.61), ("ANSI 41", 20.0, 1000.0, 3.59),
    ("ANSI 41", 23.0,  700.0, 3.03),
    ("ANSI 25", 11.0, 4000.0, 1.38), ("ANSI 25", 17.0, 4500.0, 2.22),
    ("ANSI 25", 20.0, 4500.0, 2.83),
];

#[test]
fn ratings_match_the_published_ansi_horsepower_tables_within_1_percent() {
    for &(name, teeth, rpm, printed) in TABLE {
        let ours = table_hp(name, teeth, rpm);
        assert!(
            (ours / printed - 1.0).abs() < 0.01,
            "{name}, {teeth} teeth, {rpm} rpm: ours {ours:.3} hp, table {printed} hp"
        );
    }
}

/// ASME B29.1's minimum ultimate tensile strength of a standard
/// single-strand chain is 12,500 p² lbf (p in inches); the designation
/// table's ANSI rows (typed from the printed dimension table) agree to the
/// rounding of the printed figures. No. 41, a lightweight chain, is not of
/// the standard series.
#[test]
fn ansi_tensile_strengths_are_12500_p_squared_lbf() {
    const LBF_N: f64 = 4.448_221_615_260_5;
    let mut checked = 0;
    for d in DESIGNATIONS.iter().filter(|d| d.name.starts_with("ANSI")) {
        // No. 41 is lightweight; the heavy rows are a maker's catalogue's.
        if d.name == "ANSI 41" || d.name.ends_with('H') {
            continue;
        }
        let p_in = d.pitch_m / INCH_M;
        let standard_n = 12_500.0 * p_in * p_in * LBF_N;
        approx::assert_relative_eq!(
            d.tensile_strength_n.expect("a strength"),
            standard_n,
            max_relative = 2e-3
        );
        checked += 1;
    }
    assert_eq!(checked, 13);
}

/// A scene with ANSI 40 on a 17-tooth driver at 1000 rpm: the ANSI 40
/// table's 5.48 hp, divided by the service factor.
fn ansi40_scene() -> Scene {
    let text = include_str!("../../tests/data/designation_16b.toml")
        .replace("\"ISO 606 16B-1\"", "\"ANSI 40\"")
        .replace("teeth = 19", "teeth = 17")
        .replace("speed_rpm = 100.0", "speed_rpm = 1000.0");
    Scene::from_toml(&text).expect("valid scene")
}

#[test]
fn a_scene_is_rated_at_its_smallest_sprocket_with_the_service_factor() {
    let settings = RatingSettings {
        service_factor: 1.5,
    };
    let r = rating::of_scene(&ansi40_scene(), settings, Some(2000.0)).expect("rated");
    approx::assert_relative_eq!(r.rated_power_w, 5.48 * HP_W, max_relative = 0.01);
    approx::assert_relative_eq!(r.design_power_w, 5.48 * HP_W / 1.5, max_relative = 0.01);
    assert_eq!(r.limited_by, "link_plate");
    // Chain speed N P n / 60 = 17 × 0.0127 m × 1000 / 60 = 3.598 m/s: bath
    // lubrication (type B: 1.52 to 11.7 m/s for No. 40).
    approx::assert_relative_eq!(
        r.chain_speed_m_s,
        17.0 * 0.0127 * 1000.0 / 60.0,
        max_relative = 1e-12
    );
    assert_eq!(r.lubrication, rating::Lubrication::B);
    // 1 − cos(π/17) = 0.017 026; 17 teeth at 1000 rpm pass at 283.3 Hz, and
    // the driven sprocket's 38 teeth at the same rate.
    approx::assert_relative_eq!(r.polygonal_speed_variation, 0.017_026, max_relative = 1e-3);
    approx::assert_relative_eq!(
        r.tooth_frequency_hz[0],
        17_000.0 / 60.0,
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(
        r.tooth_frequency_hz[1],
        17_000.0 / 60.0,
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(r.margin.expect("a power"), r.design_power_w / 2000.0);
    // ANSI 40's minimum tensile strength: 12,500 × 0.5² lbf = 13.90 kN.
    approx::assert_relative_eq!(
        r.tensile_strength_n.expect("a strength"),
        13_900.7,
        max_relative = 1e-3
    );
}

#[test]
fn a_bad_service_factor_is_an_error_not_a_rating() {
    let settings = RatingSettings {
        service_factor: f64::NAN,
    };
    let e = rating::of_scene(&ansi40_scene(), settings, None).expect_err("refused");
    assert!(e.to_string().contains("service factor"), "{e}");
}

/// The summary of `text` run for `duration_s` (statistics over the whole run).
fn run(text: &str, duration_s: f64) -> RunSummary {
    let scene = Scene::from_toml_with(
        text,
        &Overrides {
            duration_s: Some(duration_s),
            ..Overrides::default()
        },
    )
    .expect("valid scene");
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let sampling = SampleRate::new(10_000.0, scene.solver().dt_s).expect("a whole number of steps");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, 0.0);
    let out = sim
        .run(duration_s, sampling.every, &mut signals, None)
        .expect("run");
    RunSummary::of_run_over(&sim, &out, &signals, 0.0, duration_s)
}

const MOTO_10B: &str = include_str!("../../tests/data/user_moto_10b_free_arm.toml");

/// The motorcycle drive (ISO 606 10B-1, 22.2 kN, 15-tooth driver) with its
/// speed typed as 40000 rpm instead of 4000: 15 × 15.875 mm × 40000 / 60 =
/// 159 m/s at full speed, whose centrifugal tension alone, m v² with
/// m = 0.91 kg/m, is 23 kN, above the strength. The warnings name the chain
/// speed and the tensile strength.
#[test]
fn a_speed_typed_ten_times_too_high_is_flagged_by_chain_speed_and_strength() {
    let typo = MOTO_10B.replace("speed_rpm = 3000.0", "speed_rpm = 40000.0");
    assert_ne!(typo, MOTO_10B);
    let s = run(&typo, 0.1);
    let r = s.rating.as_ref().expect("a rating block");
    assert!(r.chain_speed_m_s > 50.0, "{}", r.chain_speed_m_s);
    let speed = s
        .warnings
        .iter()
        .find(|w| w.starts_with("chain speed"))
        .unwrap_or_else(|| panic!("no chain-speed warning: {:?}", s.warnings));
    assert!(speed.contains("m/s"), "{speed}");
    let force = s
        .warnings
        .iter()
        .find(|w| w.starts_with("link force"))
        .unwrap_or_else(|| panic!("no link-force warning: {:?}", s.warnings));
    assert!(force.contains("tensile strength of 22.2 kN"), "{force}");
    assert!(force.contains("chain speed"), "{force}");
    assert!(r.static_safety_factor.expect("a strength") < 6.0);
}

/// The same drive as written, at 3000 rpm (11.9 m/s): no chain-speed or
/// link-force warning, safety factors above 6.
#[test]
fn the_drive_as_written_has_no_speed_or_strength_warning() {
    let s = run(MOTO_10B, 0.1);
    let r = s.rating.as_ref().expect("a rating block");
    assert!(
        !s.warnings
            .iter()
            .any(|w| w.starts_with("chain speed") || w.starts_with("link force")),
        "{:?}",
        s.warnings
    );
    assert!(r.static_safety_factor.expect("a strength") > 6.0, "{r:?}");
    assert!(
        r.mean_static_safety_factor.expect("a strength")
            > r.static_safety_factor.expect("a strength")
    );
}

/// A chain without a designation is rated by its pitch as a guide: a
/// margin below 1 is reported in the block, not flagged.
#[test]
fn a_chain_without_designation_is_rated_but_its_margin_not_flagged() {
    let text = MOTO_10B.replace("designation = \"ISO 606 10B-1\"\n", "pitch_m = 0.015875\nroller_radius_m = 0.00508\nroller_mass_kg = 0.0144\nstiffness_n_m = 2.0e8\npin_radius_m = 0.00254\n");
    let scene = Scene::from_toml(&text).expect("valid scene");
    let r = rating::of_scene(&scene, RatingSettings::default(), Some(1e5)).expect("rated");
    assert!(r.designation.is_none() && r.tensile_strength_n.is_none());
    assert!(r.margin.expect("a power") < 1.0);
    assert!(
        r.notes.iter().any(|n| n.contains("chain.designation")),
        "{:?}",
        r.notes
    );
}
