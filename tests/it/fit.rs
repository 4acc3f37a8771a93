//! A drive that fits: the nearest roller count always lays out, `fit` moves
//! a sprocket until the chain fits exactly, `check` suggests only what it
//! then accepts, and a tensioner takes up the chain by itself.

fn text(file: &str) -> String {
    let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).expect("the scene file exists")
}

/// Regression: after the tensioner has moved until the pretension is
/// reached, the path is longer than the unstretched chain by the links'
/// stretch (T₀/K = 300 N / 5e7 N/m = 6 µm per link; `check` reported
/// 1.0 mm over the chain). `check` called that a misfit and pointed to
/// `fit`; it now prints the tensioner's final position and no misfit notice.
#[cfg(feature = "cli")]
#[test]
fn a_tensioners_stretch_is_not_called_a_misfit() {
    use crate::common::{chaindrive, stderr};
    let path = format!(
        "{}/tests/data/idler_tensioner_3.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let out = chaindrive(&["check", &path]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("tensioner \"idler\": centre"), "{text}");
    assert!(!err.contains("notice: the chain is"), "{err}");
}

/// Regression: `run` printed the layout's message twice (once as the
/// error, once as its source). It is printed once, and `check` on the same
/// scene offers no count (none fits: each is listed with why) but the move,
/// which `fit` then makes:
/// the fitted scene lays out with strand links of one pitch.
#[cfg(feature = "cli")]
#[test]
fn run_says_it_once_and_check_offers_the_move() {
    use crate::common::{chaindrive, stderr};
    let dir = tempfile::tempdir().expect("a temporary folder");
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        text("flat_20_40_0508.toml").replace("rollers = 110", "rollers = 111"),
    )
    .expect("written");
    let s = scene.to_str().expect("utf-8");
    let out = chaindrive(&["run", s, "--duration", "0.01"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert_eq!(err.matches("needs 110.25 pitches").count(), 1, "{err}");
    let out = chaindrive(&["check", s]);
    let err = stderr(&out);
    assert!(!out.status.success());
    assert!(err.contains("no roller count fits"), "{err}");
    assert!(
        !err.contains("rollers fits as the sprockets stand"),
        "{err}"
    );
    // One answer: the layout's message offered "the nearest count is 110
    // rollers" before the list refused 110. Only the list names counts.
    assert!(!err.contains("nearest count"), "{err}");
    assert!(
        err.contains("  110 rollers: the chain is 0.0032 m"),
        "{err}"
    );
    assert!(err.contains("chaindrive fit"), "{err}");
    let fitted = dir.path().join("f.toml");
    let out = chaindrive(&[
        "fit",
        s,
        "--move",
        "driven",
        "--rollers",
        "110",
        "--out",
        fitted.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let fitted_text = std::fs::read_to_string(&fitted).expect("written");
    // The user's file is kept but for the two values.
    assert!(fitted_text.starts_with("# The 20T/40T drive"));
    assert!(fitted_text.contains("rollers = 110\n"));
    // `check` notes a layout that takes up more than 1 µm of misfit.
    let check = chaindrive(&["check", fitted.to_str().expect("utf-8")]);
    assert!(check.status.success(), "{}", stderr(&check));
    assert!(
        !stderr(&check).contains("notice: the chain is"),
        "{}",
        stderr(&check)
    );
}
