//! The analysis: spectra of synthetic signals, Binder's formulas against
//! values computed by hand, and `chaindrive reproduce` end to end.

#[cfg(feature = "cli")]
use crate::common::{chaindrive, stderr};
use approx::assert_abs_diff_eq;

#[cfg(feature = "cli")]
#[test]
fn reproduce_writes_report_summaries_and_figures() {
    let dir = tempfile::tempdir().expect("tmp");
    let out = dir.path().join("study");
    let o = chaindrive(&[
        "reproduce",
        "--out",
        out.to_str().expect("utf-8"),
        "--duration",
        "1.5",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = crate::common::read_json(&out.join("summary.json"));
    for key in ["circular", "real", "real_same_rest_length"] {
        let s = &summary[key];
        assert!(
            s["segments"].as_array().is_some_and(|a| a.len() == 4),
            "{key}"
        );
        assert!(
            s["static_tension_n"].as_f64().is_some_and(f64::is_finite),
            "{key}"
        );
    }
    // The same rest length as the circular run, hence a lower static tension
    // (docs/model.md, “The real profile and the rest length”).
    let rest = |k: &str| summary[k]["rest_length_m"].as_f64().expect("rest");
    assert_abs_diff_eq!(
        rest("circular"),
        rest("real_same_rest_length"),
        epsilon = 1e-12
    );
    let tension = |k: &str| summary[k]["static_tension_n"].as_f64().expect("tension");
    assert!(tension("real_same_rest_length") < tension("circular") - 1000.0);

    let report = std::fs::read_to_string(out.join("report.md")).expect("report");
    assert!(
        report.contains(
            "| quantity | run | paper | ours | theory | ours vs paper | ours vs theory |"
        )
    );
    assert!(report.contains("segment 1 mean link force"));
    assert!(report.contains("sprocket 1 contact force vs (49)"));
    assert!(
        !report.contains("NaN") && !report.contains("inf "),
        "{report}"
    );
    assert!(!summary.to_string().contains("null"));
    for stem in [
        "fig16_link_force",
        "fig17_segment1_force",
        "fig18_segment1_transverse",
        "fig19_segment4_transverse",
        "fig20_segment1_spectrum",
        "fig21_segment4_spectrum",
        "fig22_roller_contact",
        "fig23_24_sprocket1_contact_vs_binder",
    ] {
        let png = std::fs::read(out.join(format!("{stem}.png"))).expect(stem);
        assert!(png.starts_with(b"\x89PNG"), "{stem}");
        let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).expect(stem);
        // Text is drawn (embedded font): the SVG holds the axis label.
        assert!(svg.contains("<text") && svg.contains("Fig"), "{stem}");
        assert!(report.contains(&format!("{stem}.png")), "{stem}");
    }
    // The PNG has text pixels: an embedded font renders on font-less machines.
    // (Checked indirectly: a PNG with a caption is larger than a bare grid would be.)
    let png = std::fs::metadata(out.join("fig16_link_force.png")).expect("png");
    assert!(png.len() > 10_000);
}

#[cfg(feature = "cli")]
#[test]
fn reproduce_rejects_bad_indices_and_durations_before_running() {
    let dir = tempfile::tempdir().expect("tmp");
    let out = dir.path().join("bad");
    let path = out.to_str().expect("utf-8");
    for (args, needle) in [
        (vec!["--roller", "122"], "unknown roller 122"),
        (vec!["--link", "500"], "unknown link 500"),
        (vec!["--duration", "0"], "--duration"),
        // 1/(3000 Hz · 1e-5 s) is no whole number of the scene's steps.
        (vec!["--rate", "3000"], "--rate"),
    ] {
        let mut all = vec!["reproduce", "--out", path];
        all.extend(args);
        let o = chaindrive(&all);
        assert!(!o.status.success());
        let err = stderr(&o);
        assert!(err.contains(needle), "{err}");
        assert!(!out.join("report.md").exists() && !out.join("fig16_link_force.png").exists());
    }
}
