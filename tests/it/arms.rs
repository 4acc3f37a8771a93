//! Tensioner arms that take up the chain, through the binary: `check` warns
//! where the chain's fit, not the arm, sets the static tension and lists
//! what fits; `run`'s summary names what set it; `check` accepts the chain
//! the arm takes up and prints where it laid the arm.

fn path(file: &str) -> String {
    format!("{}/{file}", env!("CARGO_MANIFEST_DIR"))
}

fn text(file: &str) -> String {
    std::fs::read_to_string(path(file)).expect("the scene file exists")
}

/// The timing drive of `tests/data/user_timing_06b_arm.toml`: 101 rollers
/// (06B-1, P = 9.525 mm) on a path that needs 100 with straight strands,
/// a hydraulic arm with 25 mm of travel on the slack strand.
const ONE_LINK_LONG: &str = "tests/data/user_timing_06b_arm.toml";

/// `assets/timing-drive.toml` with both cams 2.3 mm higher: the 112
/// rollers (08B-1, P = 12.7 mm, K = 1e8 N/m) are 4.26 mm short of the path
/// with straight strands, within the half pitch the free links take up.
fn short_timing_drive() -> String {
    let t = text("assets/timing-drive.toml");
    assert_eq!(t.matches("0.370638]").count(), 2);
    t.replace("0.370638]", "0.372938]")
}

/// The same drives through the binary: `check` warns (not a notice) and
/// lists what fits; `run`'s summary names what set the tension; `check`
/// accepts the chain the arm takes up and prints where it laid the arm.
#[cfg(feature = "cli")]
#[test]
fn check_and_the_summary_name_what_sets_the_tension() {
    use crate::common::{chaindrive, read_json, stderr};
    let dir = tempfile::tempdir().expect("a temporary folder");
    let short = dir.path().join("short.toml");
    std::fs::write(&short, short_timing_drive()).expect("written");
    let short = short.to_str().expect("utf-8");
    let out = chaindrive(&["check", short]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: the static tension") && err.contains("not by the tensioner arms"),
        "{err}"
    );
    assert!(!err.contains("notice: the chain is"), "{err}");
    assert!(
        err.contains("no roller count fits as the sprockets stand"),
        "{err}"
    );
    let summary = dir.path().join("s.json");
    let out = chaindrive(&[
        "run",
        short,
        "--duration",
        "0.002",
        "--summary",
        summary.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let s = read_json(&summary);
    assert_eq!(s["static_tension_set_by"], "chain_misfit");
    let warned = s["warnings"].as_array().expect("warnings").iter().any(|w| {
        w.as_str()
            .is_some_and(|w| w.contains("not by the tensioner arms"))
    });
    assert!(warned, "{}", s["warnings"]);
    let out = chaindrive(&["check", &path(ONE_LINK_LONG)]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(!err.contains("too long"), "{err}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("tensioner \"slack arm\": laid turned by"),
        "{text}"
    );
}
