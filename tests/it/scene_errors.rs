//! Bad scenes end in errors that name the field and the reason; valid ones
//! run reproducibly.

use chaindrive::model::DriveModel;
use chaindrive::scene::{L60MC_TOML, Scene};

/// The error text of a scene variant: parse/validation errors, else layout errors.
fn error_of(text: &str) -> String {
    match Scene::from_toml(text) {
        Err(e) => e.to_string(),
        Ok(scene) => match DriveModel::build(&scene) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("scene accepted:\n{text}"),
        },
    }
}

/// The paper's scene with its `k`-th sprocket block removed.
fn without_sprocket(k: usize) -> String {
    let blocks: Vec<&str> = L60MC_TOML.split("[[sprockets]]").collect();
    let mut out = blocks[0].to_owned();
    for (i, b) in blocks[1..].iter().enumerate() {
        if i != k {
            out.push_str("[[sprockets]]");
            out.push_str(b);
        }
    }
    out
}

#[test]
fn each_bad_input_names_its_field() {
    let cases: Vec<(String, &str, &str)> = vec![
        (
            L60MC_TOML.replace("law = \"lankarani_nikravesh\"", "law = \"flores\""),
            "contact.restitution",
            "must be > 0 with law \"flores\"",
        ),
        (
            L60MC_TOML.replace("law = \"lankarani_nikravesh\"", "law = \"stiff\""),
            "contact.law",
            "allowed: \"lankarani_nikravesh\", \"hunt_crossley\", \"flores\", \"gonthier\"",
        ),
        (
            L60MC_TOML
                .replace("stepping = \"substepped\"", "stepping = \"rapier\"")
                .replace("integrator = \"velocity_verlet\"", "integrator = \"rk4\""),
            "solver.integrator",
            "needs stepping = \"substepped\"",
        ),
        (
            L60MC_TOML.replace("dt_s = 1e-5", "dt_s = 1e-5\ntolerance = 2.0"),
            "solver.tolerance",
            "below 1",
        ),
        (
            L60MC_TOML.replace("mass_kg = 850.0", "mass_kg = nan"),
            "sprockets[0].mass_kg",
            "finite",
        ),
        (
            L60MC_TOML.replace("mass_kg = 183.0", "mass_kg = 0.0"),
            "sprockets[2].mass_kg",
            "> 0",
        ),
        (
            L60MC_TOML.replace("stiffness_n_m = 815e6", "stiffness_n_m = -1.0"),
            "chain.stiffness_n_m",
            "> 0",
        ),
        (
            L60MC_TOML.replace("pitch_m = 0.0889", "pitch_m = 0.0"),
            "chain.pitch_m",
            "> 0",
        ),
        (
            L60MC_TOML.replace("teeth = 60", "teeth = 0"),
            "sprockets[0].teeth",
            "must lie in",
        ),
        (
            L60MC_TOML.replace("restitution = 0.0 ", "restitution = -0.2 "),
            "contact.restitution",
            "[0, 1]",
        ),
        (
            L60MC_TOML.replace("wrap = \"cw\"", "wrap = \"sideways\""),
            "sprockets[1].wrap",
            "allowed",
        ),
        (
            L60MC_TOML.replace("speed_rpm = 120.0", "speed_rpm = inf"),
            "sprockets[0].speed_rpm",
            "finite",
        ),
        (
            L60MC_TOML.replace("center_m = [-0.5560, 2.2020]", "center_m = [0.2, 2.3]"),
            "sprockets[3].center_m",
            "overlaps",
        ),
        (
            L60MC_TOML.replace("rollers = 122", "rollers = 118"),
            "chain.rollers",
            "too short",
        ),
        (
            L60MC_TOML.replace("rollers = 122", "rollers = 126"),
            "chain.rollers",
            "too long",
        ),
        (
            L60MC_TOML.replacen("role = \"free\"", "role = \"driver\"\nspeed_rpm = 10.0", 1),
            "sprockets",
            "at most one",
        ),
        // A wrap sense the path cannot honour with this chain: the lengths no longer fit.
        (
            L60MC_TOML.replacen(
                "wrap = \"ccw\"\nrole = \"free\"",
                "wrap = \"cw\"\nrole = \"free\"",
                1,
            ),
            "chain.rollers",
            "chain",
        ),
        (
            without_sprocket(1).replace("[[sprockets]]", "[[sprocket]]"),
            "sprocket",
            "unknown field",
        ),
        (L60MC_TOML.replace("teeth = 60\n", ""), "teeth", "missing"),
        (
            L60MC_TOML.replace("duration_s = 10.0", "duration_s = \"ten\""),
            "duration_s",
            "invalid type",
        ),
    ];
    for (text, path, reason) in &cases {
        let msg = error_of(text);
        assert!(msg.contains(path), "expected {path} in: {msg}");
        assert!(msg.contains(reason), "expected '{reason}' in: {msg}");
    }
}

#[test]
fn fewer_than_two_sprockets() {
    let mut text = without_sprocket(3);
    for k in [2, 1] {
        let blocks: Vec<&str> = text.split("[[sprockets]]").collect();
        text = blocks[..=k].join("[[sprockets]]");
    }
    let msg = error_of(&text);
    assert!(
        msg.contains("sprockets: a drive needs at least 2 sprockets"),
        "{msg}"
    );
}

#[test]
fn more_than_64_sprockets() {
    // The contact generator's reach sets are 64-bit masks: a 65th sprocket is
    // refused by name, not dropped.
    let blocks: Vec<&str> = L60MC_TOML.split("[[sprockets]]").collect();
    let mut text = L60MC_TOML.to_string();
    for _ in 0..61 {
        text.push_str("[[sprockets]]");
        text.push_str(blocks[2]);
    }
    assert_eq!(text.matches("[[sprockets]]").count(), 65);
    let msg = error_of(&text);
    assert!(
        msg.contains("sprockets: a drive has at most 64 sprockets, got 65"),
        "{msg}"
    );
}

#[test]
fn all_errors_are_reported_at_once() {
    let text = L60MC_TOML
        .replace("roller_mass_kg = 3.01", "roller_mass_kg = -3.01")
        .replace("mass_kg = 759.0", "mass_kg = -1.0")
        .replace("dt_s = 1e-5", "dt_s = 0.0");
    let err = Scene::from_toml(&text).expect_err("invalid");
    let lines = err.lines();
    assert!(lines.len() >= 4, "{lines:?}"); // roller mass, two sprocket masses, dt
    assert!(
        lines
            .iter()
            .any(|l| l.ends_with("solver.dt_s: must be > 0, got 0") && l.contains(":8: ")),
        "{lines:?}"
    );
}

#[test]
fn two_runs_give_identical_summaries() {
    let run = || {
        let mut s = crate::common::run_summary(0.6, 1000.0);
        s.wall_s = 0.0;
        s.ns_per_step = 0.0;
        serde_json::to_string(&s).expect("json")
    };
    assert_eq!(run(), run());
}

/// Regression: a roller too large for the real profile's seating curve was
/// blamed on `sprockets[0].profile: seating diameter …`, a field not in the
/// file. ASA B29.1: the seating diameter is Dt = 1.005 Dr + 0.003 in and must
/// be below the pitch P, so for P = 0.0889 m the largest roller radius is
/// r < (P − 0.003 in) / 2.01 = (0.0889 − 7.62e-5) / 2.01 = 0.0441909 m.
/// r = 0.0443 m passes the overlap check (2r = 0.0886 m < P) and fails this one;
/// r = 0.0441 m passes both.
#[test]
fn a_roller_too_large_for_the_real_profile_names_the_chain_fields() {
    let big = L60MC_TOML
        .replace("roller_radius_m = 0.027", "roller_radius_m = 0.0443")
        .replace("profile = \"circular\"", "profile = \"real\"");
    assert!(
        big.contains("profile = \"real\""),
        "the scene names its profile"
    );
    let Err(e) = Scene::from_toml(&big) else {
        panic!("a roller too large for the real profile was accepted");
    };
    let text = e.to_string();
    assert!(text.contains("chain.roller_radius_m"), "{text}");
    assert!(text.contains("chain.pitch_m = 0.0889 m"), "{text}");
    assert!(text.contains("roller_radius_m < 0.044191 m"), "{text}");
    assert!(!text.contains("seating diameter 0."), "{text}");
    // The bound is the profile construction's own: just below it the
    // construction does not refuse the roller, just above it does.
    use chaindrive::geometry::asa::{AsaError, AsaProfile};
    let refused = |r: f64| {
        matches!(
            AsaProfile::new(50, 0.0889, 2.0 * r),
            Err(AsaError::RollerTooBig { .. })
        )
    };
    let max_radius_m = (0.0889 - 7.62e-5) / 2.01;
    assert!(refused(max_radius_m * (1.0 + 1e-9)));
    assert!(!refused(max_radius_m * (1.0 - 1e-9)));
    let small = big.replace("roller_radius_m = 0.0443", "roller_radius_m = 0.0441");
    if let Err(e) = Scene::from_toml(&small) {
        assert!(!e.to_string().contains("real tooth profile"), "{e}");
    }
    // The circular profile has no seating curve: only the overlap check applies.
    let circular = L60MC_TOML.replace("roller_radius_m = 0.027", "roller_radius_m = 0.0443");
    if let Err(e) = Scene::from_toml(&circular) {
        assert!(!e.to_string().contains("real tooth profile"), "{e}");
    }
}

/// The 1-based line of the first line of `text` that starts with `start`.
fn line_of(text: &str, start: &str) -> usize {
    text.lines()
        .position(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("no line starts with {start}"))
        + 1
}

/// Two unknown fields in two tables are both named with their lines (serde
/// alone stops at the first), and an out-of-range value beside them too.
#[test]
fn every_unknown_field_is_named_with_the_bad_values() {
    let text = L60MC_TOML
        .replace("rollers = 122", "rollers = 122\nroller_count = 3")
        .replace("exponent = 1.5", "exponent = 1.5\nstiffnes = 2e9")
        .replace("dt_s = 1e-5", "dt_s = -1.0");
    let lines = Scene::from_toml(&text).expect_err("invalid").lines();
    let expect = [
        format!(
            "{}:1: chain.roller_count: unknown field, expected one of `rollers`",
            line_of(&text, "roller_count")
        ),
        format!(
            "{}:1: contact.stiffnes: unknown field, expected one of `law`",
            line_of(&text, "stiffnes ")
        ),
        format!(
            "{}:8: solver.dt_s: must be > 0, got -1",
            line_of(&text, "dt_s")
        ),
    ];
    assert_eq!(lines.len(), expect.len(), "{lines:#?}");
    for (line, start) in lines.iter().zip(&expect) {
        assert!(
            line.starts_with(start.as_str()),
            "{line}\nexpected: {start}…"
        );
    }
}

/// Missing and mistyped fields are all named, each once, in the order of
/// the file: a missing field at its table's header, a mistyped one at its
/// value; the values are not checked while the shape is wrong.
#[test]
fn every_missing_or_mistyped_field_is_named() {
    let text = L60MC_TOML
        .replacen("teeth = 60\n", "", 1)
        .replace("duration_s = 10.0", "duration_s = \"ten\"")
        .replace("center_m = [0.0, 0.0]", "center_m = 0.0")
        .replace("pretension_n = 21000.0", "pretension_n = -1.0\nfoo = 1");
    let lines = Scene::from_toml(&text).expect_err("invalid").lines();
    let first = line_of(&text, "[[sprockets]]");
    let expect = [
        format!("{}:1: chain.foo: unknown field", line_of(&text, "foo")),
        format!("{first}:1: sprockets[0].teeth: missing field: it is required here"),
        format!(
            "{}:12: sprockets[0].center_m: invalid type:",
            line_of(&text, "center_m = 0.0")
        ),
        format!(
            "{}:14: solver.duration_s: invalid type: string \"ten\", expected f64",
            line_of(&text, "duration_s")
        ),
    ];
    assert_eq!(lines.len(), expect.len(), "{lines:#?}");
    for (line, start) in lines.iter().zip(&expect) {
        assert!(
            line.starts_with(start.as_str()),
            "{line}\nexpected: {start}…"
        );
    }
}

/// A scene without `[contact]` is told what the section needs: it has no
/// defaults for the stiffness and the restitution.
#[test]
fn a_missing_contact_section_says_what_it_needs() {
    let start = L60MC_TOML.find("[contact]").expect("section");
    let end = start + L60MC_TOML[start..].find("[[sprockets]]").expect("next");
    let text = format!("{}{}", &L60MC_TOML[..start], &L60MC_TOML[end..]);
    let lines = Scene::from_toml(&text).expect_err("invalid").lines();
    assert_eq!(lines.len(), 1, "{lines:?}");
    for needle in [
        "contact: missing field",
        "stiffness",
        "restitution",
        "no defaults",
    ] {
        assert!(lines[0].contains(needle), "{needle} not in {}", lines[0]);
    }
}
