//! The motorcycle chains 520, 525 and 530: their rows against the numbers
//! their sources print (typed in here, not read from the table), the single
//! strand, the fields a scene must give where a row has no value, and the
//! rating they get (the ANSI 50's, whose pitch and roller they share).

use crate::analysis::design::{fatigue, rating};
use crate::scene::Scene;
use crate::scene::designations::{find, lookup};

fn scene_text(file: &str) -> String {
    let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).expect("the scene file exists")
}

/// The three rows against their sources, typed in millimetres: the pitch
/// 5/8 in = 15.875 mm (the first digit, eighths of an inch), the roller
/// 10.16 mm (Wemoto's "Motorcycle Chain Dimensions" table prints 10.16 for
/// 520, 525 and 530), the inner widths of Tsubaki's "The Complete Guide to
/// Chain", Table 1.9 (6.35, 7.95, 9.53 mm), and the 520's inner plate
/// height 15.0 mm of the D.I.D 520MXV (Suzuki RMX450Z service manual, drive
/// train service data, standard value). Nothing else was read: those values
/// are absent and their sources say so.
#[test]
fn motorcycle_rows_match_their_sources() {
    let typed = [
        // name  P mm    d1 mm  b1 mm  h2 mm (None: not read)
        ("520", 15.875, 10.16, 6.35, Some(15.0)),
        ("525", 15.875, 10.16, 7.95, None),
        ("530", 15.875, 10.16, 9.53, None),
    ];
    for (name, p, d1, b1, h2) in typed {
        let d = find(name).unwrap_or_else(|| panic!("{name} in the table"));
        assert_eq!(d.name, name);
        assert!((d.pitch_m * 1e3 - p).abs() < 1e-9, "{name} pitch");
        assert!((d.roller_diameter_m * 1e3 - d1).abs() < 1e-9, "{name} d1");
        assert!((d.inner_width_m * 1e3 - b1).abs() < 1e-9, "{name} b1");
        match (d.plate_depth_m, h2) {
            (Some(h), Some(typed)) => assert!((h * 1e3 - typed).abs() < 1e-9, "{name} h2"),
            (None, None) => {}
            (got, _) => panic!("{name} plate depth {got:?}"),
        }
        assert!(d.sources.dimensions.contains("Tsubaki"), "{name}");
        assert!(d.sources.dimensions.contains("Wemoto"), "{name}");
        for (value, source) in [
            (d.pin_diameter_m, d.sources.pin_and_plate_depth),
            (d.plate_thickness_m, d.sources.plate_thickness),
            (d.mass_per_m_kg, d.sources.mass),
            (d.tensile_strength_n, d.sources.strength),
        ] {
            assert!(value.is_none(), "{name}: {value:?}");
            assert!(source.contains("none read"), "{name}: {source}");
        }
        assert!(d.stiffness_n_m().is_none() && d.roller_mass_kg().is_none());
    }
    assert!(
        find("520")
            .expect("520")
            .sources
            .pin_and_plate_depth
            .contains("D.I.D 520MXV")
    );
}

/// A motorcycle chain is a single strand: "520-2" is refused saying so and
/// what to write; "520-1" is the 520. A motorcycle number with an ANSI
/// prefix is no chain and the error says to drop it.
#[test]
fn a_motorcycle_chain_is_a_single_strand_only() {
    let e = lookup("520-2").expect_err("two strands");
    assert!(
        e.contains("motorcycle") && e.contains("single strand only") && e.contains("\"520\""),
        "{e}"
    );
    assert_eq!(lookup("520-1").expect("one strand").single.name, "520");
    assert_eq!(lookup(" 530 ").expect("blanks").single.name, "530");
    let e = lookup("ANSI 530").expect_err("no such ANSI chain");
    assert!(e.contains("no ANSI or ISO 606 prefix"), "{e}");
    let text = scene_text("moto_520_15_45.toml").replace("\"520\"", "\"525-2\"");
    let err = Scene::from_toml(&text).expect_err("525-2").to_string();
    assert!(
        err.contains("chain.designation") && err.contains("single strand only"),
        "{err}"
    );
}

/// A scene naming "520" without the values its row lacks gets one error per
/// missing field, each naming the field and the designation; the row's
/// pitch and roller radius are filled.
#[test]
fn a_motorcycle_scene_names_the_fields_its_row_lacks() {
    let full = scene_text("moto_520_15_45.toml");
    let text = full
        .replace("roller_mass_kg = 0.0145\n", "")
        .replace("stiffness_n_m = 1.76e8\n", "");
    let err = Scene::from_toml(&text).expect_err("no mass").to_string();
    for field in ["chain.roller_mass_kg", "chain.stiffness_n_m"] {
        assert!(err.contains(field), "{field}: {err}");
    }
    assert!(err.contains("\"520\" has no published value"), "{err}");
    assert!(
        !err.contains("chain.pitch_m") && !err.contains("NaN"),
        "{err}"
    );
    let scene = Scene::from_toml(&full).expect("a valid scene");
    let chain = scene.chain();
    assert_eq!((chain.designation, chain.strands), (Some("520"), 1));
    approx::assert_relative_eq!(chain.pitch_m, 0.015875, max_relative = 1e-12);
    approx::assert_relative_eq!(chain.roller_radius_m, 5.08e-3, max_relative = 1e-12);
    assert_eq!(chain.pin_radius_m, None);
    assert_eq!(chain.tensile_strength_n, Some(36_500.0));
    // The wear check needs the pin and the bushing the row has not.
    let err = Scene::from_toml(&format!("{full}\n[checks]\nwear = true\n"))
        .expect_err("no bearing area")
        .to_string();
    assert!(
        err.contains("checks.wear") && err.contains("chain.bushing_length_m"),
        "{err}"
    );
}

/// Without chain.tensile_strength_n a 520 drive is rated (the rating needs
/// the pitch only) but has no safety factors and no fatigue check, and both
/// notes name the field; a strength that is not positive is refused at its
/// path.
#[test]
fn a_motorcycle_chain_without_a_strength_says_which_field_gives_it() {
    let text = scene_text("moto_520_15_45.toml").replace("tensile_strength_n = 36500.0\n", "");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let r =
        rating::of_scene(&scene, rating::RatingSettings::default(), Some(1000.0)).expect("rated");
    assert!(r.tensile_strength_n.is_none());
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("chain.tensile_strength_n") && n.contains("520")),
        "{:?}",
        r.notes
    );
    let e = fatigue::curve_of_scene(&scene).expect_err("no strength");
    assert!(e.contains("chain.tensile_strength_n"), "{e}");
    let text = scene_text("moto_520_15_45.toml").replace("36500.0", "-1.0");
    let err = Scene::from_toml(&text).expect_err("negative").to_string();
    assert!(err.contains("chain.tensile_strength_n"), "{err}");
}

/// The written strength overrides a designation's: an ANSI 80 scene given
/// 100 kN is checked against 100 kN, not the table's 12,500 lbf.
#[test]
fn a_written_tensile_strength_overrides_the_designation() {
    let text = scene_text("designation_16b.toml").replace(
        "designation = \"ISO 606 16B-1\"",
        "designation = \"ANSI 80\"\ntensile_strength_n = 100e3",
    );
    let scene = Scene::from_toml(&text).expect("a valid scene");
    assert_eq!(scene.chain().tensile_strength_n, Some(100e3));
    let (curve, _) = fatigue::curve_of_scene(&scene).expect("a curve");
    assert_eq!(curve.tensile_strength_n, 100e3);
}

/// The 520, 525 and 530 are rated as the ANSI 50: the same scene named
/// "ANSI 50" gets the same limits H₁ and H₂ (the formulas take the pitch,
/// teeth and speed, and the 520's pitch is the ANSI 50's), and the basis
/// says so, with the 520's inner width against the ANSI 50's.
#[test]
fn a_motorcycle_chain_is_rated_as_the_ansi_50() {
    let settings = rating::RatingSettings::default();
    let text = scene_text("moto_520_15_45.toml");
    let moto = Scene::from_toml(&text).expect("520");
    let ansi = Scene::from_toml(&text.replace("\"520\"", "\"ANSI 50\"")).expect("ANSI 50");
    let m = rating::of_scene(&moto, settings, Some(1000.0)).expect("rated");
    let a = rating::of_scene(&ansi, settings, Some(1000.0)).expect("rated");
    assert_eq!(m.link_plate_limited_power_w, a.link_plate_limited_power_w);
    assert_eq!(
        m.roller_bushing_limited_power_w,
        a.roller_bushing_limited_power_w
    );
    assert_eq!(m.designation.as_deref(), Some("520"));
    assert!(
        m.basis.contains("ANSI 50") && m.basis.contains("6.35 mm"),
        "{}",
        m.basis
    );
    // The written strength reaches the safety factors' denominator.
    assert_eq!(m.tensile_strength_n, Some(36_500.0));
}
