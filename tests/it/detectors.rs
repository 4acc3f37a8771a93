//! Blow-up detectors that detect numerical blow-up and not hard working
//! points; `solver.dt_s = "auto"`; the summary's warnings.

/// The README's first command, `cargo run --release -- run`: the paper's
/// drive as it comes, 10 s; a newcomer sees no warning.
#[cfg(feature = "cli")]
#[test]
fn the_first_command_prints_no_warning() {
    let out = crate::common::chaindrive(&["run", "--quiet"]);
    assert!(out.status.success(), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("warning"), "{stderr}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("velocity_verlet"));
}
