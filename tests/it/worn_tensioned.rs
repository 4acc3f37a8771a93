//! Worn and tensioned drives set up from the command line: a tensioner
//! sprocket under the tensioner rule (`pretension_by = "tensioner"`) reaches
//! low pretensions new and worn and takes a worn chain up by the length its
//! strands gained; a load held at rest beyond the pretension is refused by
//! name; a worn chain that sags behind a guide's entry is refused before the
//! run instead of blowing up in it, and so is one that runs over the end
//! of an arm's shoe; a chain that touches no tooth at rest
//! is warned about.

use crate::common::{chaindrive, stderr};
use std::path::{Path, PathBuf};

/// `tests/data/worn_30_30_tensioner.toml` with each `(from, to)` replaced,
/// written into `dir`.
fn variant(dir: &Path, name: &str, pairs: &[(&str, &str)]) -> PathBuf {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/worn_30_30_tensioner.toml");
    let mut text = std::fs::read_to_string(base).expect("scene");
    for (from, to) in pairs {
        assert!(text.contains(from), "{from} in the scene");
        text = text.replace(from, to);
    }
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

/// The static tension, N, and the tensioner's centre x, m, `check` prints.
fn tension_and_centre(scene: &Path) -> (f64, f64) {
    let out = chaindrive(&["check", scene.to_str().expect("utf-8")]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let after = |key: &str| -> f64 {
        let rest = &text[text.find(key).unwrap_or_else(|| panic!("{key} in {text}")) + key.len()..];
        let end = rest.find([' ', ',']).expect("a number's end");
        rest[..end].parse().expect("a number")
    };
    (after("static equilibrium: tension "), after("centre ["))
}

#[test]
fn a_tensioner_sprocket_sets_low_pretensions_on_new_and_worn_chains() {
    // Before: 100–300 N ended in "no free strand link to measure the static
    // tension on" and 500 N in a layout needing 572531 pitches: the first
    // move from the fit did not take up the real profile's seats, the
    // chain stayed slack, and the secant on a flat tension ran away.
    let dir = tempfile::tempdir().expect("temp dir");
    let mut last_x = f64::NEG_INFINITY;
    for t0 in ["100.0", "300.0", "500.0"] {
        let scene = variant(
            dir.path(),
            &format!("new_{t0}.toml"),
            &[("pretension_n = 1000.0", &format!("pretension_n = {t0}"))],
        );
        let (tension, x) = tension_and_centre(&scene);
        let t0: f64 = t0.parse().expect("number");
        // The default equilibrium.tension_tolerance, 1e-3.
        assert!(
            (tension / t0 - 1.0).abs() <= 1e-3,
            "{tension} N against {t0} N"
        );
        // Along +x the path grows: a higher pretension sits further out.
        assert!(x > last_x, "{x} m after {last_x} m");
        last_x = x;
    }
    // Worn by e = 2 % at 500 N, the tensioner takes the chain's gain up.
    // The 111 links gain 111 P e = 56.39 mm; each wrap of 15 pitches keeps
    // at most its own links' gain (its rollers ride out on the flanks), so
    // the two strands, along the centre line, take between the 81 strand
    // links' gain and all of it: a move of 81 P e / 2 = 20.57 mm to
    // 111 P e / 2 = 28.19 mm beyond the new chain's position.
    let worn = variant(
        dir.path(),
        "worn_500.toml",
        &[
            ("pretension_n = 1000.0", "pretension_n = 500.0"),
            ("elongation_pct = 0.0", "elongation_pct = 2.0"),
        ],
    );
    let (tension, x) = tension_and_centre(&worn);
    assert!(
        (tension / 500.0 - 1.0).abs() <= 1e-3,
        "{tension} N against 500 N"
    );
    let moved_m = x - last_x;
    let p_e = 0.0254 * 0.02;
    assert!(
        moved_m > 81.0 * p_e / 2.0 && moved_m < 111.0 * p_e / 2.0,
        "worn take-up {moved_m} m"
    );
}

#[test]
fn a_load_held_at_rest_beyond_the_pretension_is_refused_under_the_tensioner_rule() {
    // Before: "the path through the seated rollers needs 104.02 pitches":
    // the search for a tension the load put out of reach ran away. With the
    // 1500 N·m load held at rest (no load_ramp_s) the strands differ by
    // M / r_p, r_p = P / (2 sin(π/30)) = 0.121494 m, i.e. 12346 N; the
    // pooled mean is the pretension, so the slack strand stays in tension
    // only from about half that, 6173 N (within one link's share, 1/81, of
    // strands one link unequal: 2 %).
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = variant(dir.path(), "held.toml", &[("load_ramp_s = 1.0", "")]);
    let out = chaindrive(&["check", scene.to_str().expect("utf-8")]);
    assert!(!out.status.success(), "a load the pretension cannot hold");
    let err = stderr(&out);
    assert!(err.contains("chain.pretension_n"), "{err}");
    let key = "raise chain.pretension_n to at least ";
    let at = err.find(key).unwrap_or_else(|| panic!("{err}")) + key.len();
    let needed: f64 = err[at..]
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .expect("a number");
    let r_p = 0.0254 / (2.0 * (std::f64::consts::PI / 30.0).sin());
    let hand = 1500.0 / r_p / 2.0;
    assert!(
        (needed / hand - 1.0).abs() < 0.02,
        "{needed} N against {hand} N"
    );
}

#[test]
fn a_worn_chain_sagging_behind_a_guides_entry_is_refused_before_the_run() {
    // Before: user_moto_10b_free_arm.toml worn by 3 % set up, ran, and blew
    // up at t = 0.0083 s (roller 0 6.10 mm into the guide against the
    // 5.08 mm limit). The chain gains 110 × 15.875 mm × 0.03 = 52.4 mm on
    // fixed centres (the arm hangs free), the slack strand sags below the
    // wear strip's 10 mm, 10° entry ramp, and the first roller to reach the
    // ramp's tip meets the strip from behind.
    let err = worn_check_refused("user_moto_10b_free_arm.toml", "3.0");
    for named in ["slack wear strip", "guides.0.start_ramp", "52.4 mm"] {
        assert!(err.contains(named), "{named} in {err}");
    }
    // The depth named lies beyond the limit, the roller radius 5.08 mm.
    let depth = number_after(&err, "meet the face ");
    assert!(depth > 5.08, "{depth} mm");
}

/// `chaindrive check`'s message for `tests/data/NAME` worn by `pct` %
/// (a tensioner-preload drive), which it must refuse.
fn worn_check_refused(name: &str, pct: &str) -> String {
    let dir = tempfile::tempdir().expect("temp dir");
    let base = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let line = format!("elongation_pct = {pct}");
    let text = std::fs::read_to_string(base).expect("scene").replace(
        "\npretension_by = \"tensioner_preload\"\n",
        &format!("\npretension_by = \"tensioner_preload\"\n{line}\n"),
    );
    assert!(text.contains(&line));
    let scene = dir.path().join("worn.toml");
    std::fs::write(&scene, text).expect("write");
    let out = chaindrive(&["check", scene.to_str().expect("utf-8")]);
    assert!(!out.status.success(), "{name} worn {pct} % refused");
    stderr(&out)
}

/// The number written after `key` in `text`.
fn number_after(text: &str, key: &str) -> f64 {
    let at = text.find(key).unwrap_or_else(|| panic!("{text}")) + key.len();
    text[at..]
        .split(' ')
        .next()
        .and_then(|d| d.parse().ok())
        .expect("a number")
}

#[test]
fn a_worn_chain_run_over_the_end_of_an_arms_shoe_is_refused_before_the_run() {
    // Before: user_timing_06b_arm.toml worn by 1 % settled (static tension
    // 2.3 N), ran, and blew up at t = 0.0121 s (roller 12 4.03 mm into
    // the arm's shoe against the 3.175 mm limit, the roller radius). The
    // chain is one link (9.525 mm) longer than its straight path and gains
    // 101 × 9.525 mm × 0.01 = 9.6 mm; the arm's shoe takes up at most
    // 12.10 mm (`check` prints it), so the arm turns in until the strand
    // runs over the shoe's end, and roller 12, resting behind that end,
    // meets the shoe from behind once the chain moves.
    let err = worn_check_refused("user_timing_06b_arm.toml", "1.0");
    for named in [
        "slack arm",
        "tensioners.0",
        "shoe_end_deg",
        "chain.elongation_pct",
        "9.6 mm longer",
        "12.10 mm",
    ] {
        assert!(err.contains(named), "{named} in {err}");
    }
    let depth = number_after(&err, "meet the shoe ");
    assert!(depth > 3.175, "{depth} mm");
}

#[test]
fn a_worn_chain_is_refused_at_the_first_wear_step_that_runs_over_the_shoes_end() {
    // Before: worn by 2 % the same drive was refused only once all its wear
    // steps were settled, the arm turned far beyond the shoe's end (12–15 s
    // of setup). The arm turns further in as the chain gains length, so the
    // first wear step whose rest state runs over the shoe's end settles
    // the refusal. Worn by 0.5 % the drive has a rest state clear of the end
    // (`a_worn_arm_drive_is_lengthened_by_newton_alone`) and worn by 1 % it
    // has none: that step lies between, and the 1 % and 2 % lengthenings,
    // taking steps of one size, meet it at the same wear, within a step.
    let wear_at = |pct: &str| {
        let err = worn_check_refused("user_timing_06b_arm.toml", pct);
        assert!(err.contains("shoe_end_deg"), "{err}");
        let steps = number_after(&err, "lengthened towards it in ");
        let step = number_after(&err, "shoe's end already at step ");
        assert!(step < steps, "{step} of {steps}: {err}");
        let at = number_after(&err, &format!("at step {step} (links "));
        assert!(0.5 < at && at <= 1.0, "{at} % in {err}");
        (at, 1.0 / steps * pct.parse::<f64>().expect("a number"))
    };
    let (one, step_one) = wear_at("1.0");
    let (two, step_two) = wear_at("2.0");
    approx::assert_relative_eq!(step_one, step_two, max_relative = 0.05);
    assert!((one - two).abs() <= 1.01 * step_one, "{one} % and {two} %");
}

#[test]
fn a_chain_that_meshes_with_no_sprocket_at_rest_is_warned_about() {
    // The 30/30 drive on fixed centres, no gravity: worn by 2 % its chain
    // gains 111 × 25.4 mm × 0.02 = 56.4 mm, far more than the 1 kN stretch
    // it had (111 × 1000 N / K, under a millimetre), so at rest it hangs
    // free of every tooth. Before, `check` and the run said nothing of it.
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/worn_30_30_fixed.toml");
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(&base).expect("scene");
    let worn = dir.path().join("worn.toml");
    std::fs::write(
        &worn,
        text.replace("elongation_pct = 0.0", "elongation_pct = 2.0"),
    )
    .expect("write");
    let out = chaindrive(&["check", worn.to_str().expect("utf-8")]);
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("meshes with no sprocket at rest"), "{err}");
    assert!(err.contains("56.4 mm"), "{err}");
    let new = chaindrive(&["check", base.to_str().expect("utf-8")]);
    assert!(new.status.success(), "{}", stderr(&new));
    assert!(
        !stderr(&new).contains("meshes with no sprocket"),
        "{}",
        stderr(&new)
    );
}
