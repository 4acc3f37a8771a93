//! `chaindrive analyze` on recordings written by the real binary: its
//! numbers against the run's own `--summary` (the same samples, the same
//! windows: the last second, and the ramp's end + 0.5 s to the end for
//! spectra, `src/analysis/summary.rs`), and its refusals of bad input.

use std::path::Path;

use approx::abs_diff_eq;

use crate::common::{chaindrive_in, read_json, stderr};

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// `a` within `rel` of `b`, relative to `b`.
fn close(a: f64, b: f64, rel: f64) -> bool {
    abs_diff_eq!(a, b, epsilon = rel * b.abs().max(1e-12))
}

/// Fails with a clear message, non-zero exit, and writes no output directory.
fn refused(dir: &Path, args: &[&str], out: &str, expect: &[&str]) {
    let o = chaindrive_in(dir, args);
    let err = stderr(&o);
    assert!(!o.status.success(), "{args:?} succeeded");
    for e in expect {
        assert!(err.contains(e), "{args:?}: {e:?} not in {err}");
    }
    assert!(!dir.join(out).exists(), "{args:?} wrote {out}");
}

#[test]
fn analyze_agrees_with_the_runs_summary_and_refuses_bad_indices_and_windows() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path();
    // 2 s: the summary's spectrum window (ramp end 1 s + 0.5 s to the end) holds 0.5 s.
    let run = chaindrive_in(
        dir,
        &[
            "run",
            "--duration",
            "2",
            "--record",
            "x.mcap",
            "--summary",
            "s.json",
            "--quiet",
        ],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let o = chaindrive_in(dir, &["analyze", "x.mcap", "--out", "d"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.join("d");
    for name in [
        "report.md",
        "analysis.json",
        "link0_force.png",
        "link0_force.svg",
        "roller0_contact.png",
        "segment1_force.png",
        "segment4_transverse.svg",
        "segment4_spectrum.png",
        "sprocket1_contact_vs_binder.png",
    ] {
        let p = out.join(name);
        assert!(
            p.metadata().map(|m| m.len() > 0).unwrap_or(false),
            "{name} missing or empty"
        );
    }
    let summary = read_json(&dir.join("s.json"));
    let analysis = read_json(&out.join("analysis.json"));
    let report = std::fs::read_to_string(out.join("report.md")).expect("report");
    // The paper's drive keeps its mesh: the recording lists no jump or ride.
    assert!(
        report.contains("**Mesh:** the recording lists no tooth jump and no roller riding a tip."),
        "the report's mesh line"
    );
    assert_eq!(analysis["tooth_jumps"], serde_json::json!([]));
    assert_eq!(analysis["window_s"], summary["window_s"]);
    assert_eq!(analysis["spectrum_window_s"], summary["spectrum_window_s"]);
    assert!(close(
        f(&analysis["static_tension_n"]),
        f(&summary["static_tension_n"]),
        1e-9
    ));
    let segs = summary["segments"].as_array().expect("segments");
    assert_eq!(segs.len(), 4);
    for (s, a) in segs
        .iter()
        .zip(analysis["segments"].as_array().expect("segments"))
    {
        let k = &s["segment"];
        assert_eq!(&a["segment"], k);
        // The samples' statistics are the run's samples'.
        for field in ["link_force_p2p_n", "transverse_peak_hz"] {
            let (x, y) = (f(&a[field]), f(&s[field]));
            assert!(close(x, y, 1e-6), "segment {k} {field}: {x} vs {y}");
        }
        // The recording's mean is its samples', the run's is every step's:
        // they agree within the mean's standard error (batch means), and
        // the string frequency (∝ √mean) within half that, relatively.
        let (x, y) = (f(&a["mean_link_force_n"]), f(&s["mean_link_force_n"]));
        let se = f(&s["mean_link_force_se_n"]);
        assert!((x - y).abs() < se, "segment {k}: {x} vs {y}, SE {se}");
        let (fa, fs) = (f(&a["string_f1_hz"]), f(&s["string_f1_hz"]));
        assert!(close(fa, fs, se / y), "segment {k}: {fa} vs {fs} Hz");
        // The report's segment table shows the recording's mean, to 0.1 N.
        let row = format!(
            "| {k} | {:.4} | {:.1} |",
            f(&a["length_m"]),
            f(&a["mean_link_force_n"])
        );
        assert!(report.contains(&row), "{row} not in the report");
    }
    for (s, a) in summary["sprockets"]
        .as_array()
        .expect("sprockets")
        .iter()
        .zip(analysis["sprockets"].as_array().expect("sprockets"))
    {
        let (x, y) = (f(&a["speed_p2p_rad_s"]), f(&s["speed_p2p_rad_s"]));
        assert!(close(x, y, 1e-6), "sprocket {}: {x} vs {y}", s["sprocket"]);
        // A smooth speed's samples meet its mean to 10⁻⁴ (the moments, which
        // jump at every impact, are the samples' in the recording's summary
        // and every step's in the run's: not compared).
        let (x, y) = (f(&a["mean_speed_rad_s"]), f(&s["mean_speed_rad_s"]));
        assert!(close(x, y, 1e-4), "sprocket {}: {x} vs {y}", s["sprocket"]);
        let row = format!(
            "| {} | {} | {:.4} |",
            s["sprocket"],
            a["teeth"],
            f(&a["mean_speed_rad_s"])
        );
        assert!(report.contains(&row), "{row} not in the report");
    }
    // Sprocket 1 (60 teeth, 1 s at steady speed) has complete contacts to compare with (49).
    assert!(
        analysis["sprockets"][0]["binder"]["contacts"]
            .as_u64()
            .unwrap_or(0)
            > 0
    );
    assert!(!report.contains("NaN"));

    let unknown = "unknown roller 500: the chain has rollers 0 to 121";
    refused(
        dir,
        &["analyze", "x.mcap", "--out", "e", "--roller", "500"],
        "e",
        &[unknown],
    );
    refused(
        dir,
        &["analyze", "x.mcap", "--out", "e", "--link", "122"],
        "e",
        &["unknown link 122"],
    );
    refused(
        dir,
        &["analyze", "x.mcap", "--out", "e", "--segment", "9"],
        "e",
        &["unknown segment 9: the drive has segments 1 to 4"],
    );
    refused(
        dir,
        &["analyze", "x.mcap", "--out", "e", "--window", "5,6"],
        "e",
        &["window [5, 6] s is outside the run's samples [0, 2"],
    );
    refused(
        dir,
        &["analyze", "x.mcap", "--out", "e", "--window", "1,0.5"],
        "e",
        &["--window"],
    );
}

#[test]
fn analyze_names_missing_channels_and_rejects_files_that_are_not_mcap() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path();
    let record = |file: &str, channels: &str| {
        let o = chaindrive_in(
            dir,
            &[
                "run",
                "--duration",
                "0.3",
                "--record",
                file,
                "--record-channels",
                channels,
                "--quiet",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
    };
    record("sprockets.mcap", "sprockets");
    refused(
        dir,
        &["analyze", "sprockets.mcap", "--out", "e"],
        "e",
        &[
            "lacks channel(s) /segments",
            "it has: /sprockets",
            "--record-channels",
        ],
    );
    // Signals without links and contacts: the segment and sprocket analysis
    // runs, and says what it left out; asking for a link is an error.
    record("signals.mcap", "sprockets,segments");
    refused(
        dir,
        &["analyze", "signals.mcap", "--out", "e", "--link", "3"],
        "e",
        &[
            "lacks channel(s) /links needed for link 3's force",
            "/segments, /sprockets",
        ],
    );
    refused(
        dir,
        &["analyze", "signals.mcap", "--out", "e", "--roller", "3"],
        "e",
        &["lacks channel(s) /contacts, /rollers"],
    );
    let o = chaindrive_in(dir, &["analyze", "signals.mcap", "--out", "ok"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("contact forces: not recorded"));
    let report = std::fs::read_to_string(dir.join("ok/report.md")).expect("report");
    assert!(report.contains("not recorded: needs /contacts, /rollers"));
    assert!(!dir.join("ok/link0_force.png").exists());
    assert!(dir.join("ok/segment1_force.png").exists());

    std::fs::write(dir.join("scene.mcap"), "name = \"not a recording\"\n").expect("write");
    refused(
        dir,
        &["analyze", "scene.mcap", "--out", "e"],
        "e",
        &["scene.mcap is not a readable MCAP recording", "name = "],
    );
    refused(
        dir,
        &["analyze", "absent.mcap", "--out", "e"],
        "e",
        &["cannot read absent.mcap"],
    );
}

#[test]
fn a_failed_analysis_leaves_the_outputs_of_an_earlier_one_alone() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path();
    let run = chaindrive_in(
        dir,
        &["run", "--duration", "0.3", "--record", "x.mcap", "--quiet"],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let ok = chaindrive_in(dir, &["analyze", "x.mcap", "--out", "d"]);
    assert!(ok.status.success(), "{}", stderr(&ok));
    let read_all = || {
        let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir.join("d"))
            .expect("d")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.is_file())
            .map(|p| {
                let name = p.file_name().expect("name").to_string_lossy().into_owned();
                (name, std::fs::read(&p).expect("readable"))
            })
            .collect();
        files.sort();
        files
    };
    let before = read_all();
    assert!(
        before.iter().any(|(n, _)| n == "link0_force.png"),
        "{before:?}"
    );
    // A second analysis (another window, so other figures) that cannot write
    // one of its figures: a directory stands where segment 4's spectrum goes.
    let blocked = dir.join("d/segment4_spectrum.png");
    std::fs::remove_file(&blocked).expect("remove");
    std::fs::create_dir(&blocked).expect("directory in the way");
    let before: Vec<_> = before
        .into_iter()
        .filter(|(n, _)| n != "segment4_spectrum.png")
        .collect();
    let failed = chaindrive_in(
        dir,
        &["analyze", "x.mcap", "--out", "d", "--window", "0.1,0.3"],
    );
    assert!(!failed.status.success(), "the blocked figure was written");
    assert!(
        stderr(&failed).contains("segment4_spectrum"),
        "{}",
        stderr(&failed)
    );
    // Every file of the earlier analysis is still there, unchanged, and
    // nothing of the failed one is left beside them.
    let after = read_all();
    let names = |v: &[(String, Vec<u8>)]| v.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
    assert_eq!(names(&after), names(&before));
    for ((name, a), (_, b)) in after.iter().zip(&before) {
        assert!(a == b, "{name} changed");
    }
    assert_eq!(
        std::fs::read_dir(dir.join("d")).expect("d").count(),
        after.len() + 1,
        "only the blocking directory besides the earlier files"
    );
}

/// A recording of a scene whose load table is a file beside it holds the
/// table: `analyze` reads it from any working directory, and after the file
/// is gone, the table the run used: the file's text, attached under the
/// name the scene gives it.
#[cfg(feature = "record")]
#[test]
fn a_recording_holds_the_load_table_its_scene_read() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path();
    let (scenes, elsewhere) = (dir.join("scenes"), dir.join("elsewhere"));
    for d in [&scenes, &elsewhere] {
        std::fs::create_dir(d).expect("dir");
    }
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    for name in ["timing-excited.toml", "cam-torque.csv"] {
        std::fs::copy(assets.join(name), scenes.join(name)).expect("copied");
    }
    // Run from `dir`: the scene names its table relative to its own folder.
    let run = chaindrive_in(
        dir,
        &[
            "run",
            "scenes/timing-excited.toml",
            "--duration",
            "0.05",
            "--record",
            "x.mcap",
            "--quiet",
        ],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let analyze = |out: &str| {
        let o = chaindrive_in(&elsewhere, &["analyze", "../x.mcap", "--out", out]);
        assert!(o.status.success(), "analyze ({out}): {}", stderr(&o));
    };
    analyze("from_another_folder");
    std::fs::remove_file(scenes.join("cam-torque.csv")).expect("removed");
    analyze("without_the_file");
    let csv = std::fs::read(assets.join("cam-torque.csv")).expect("table");
    let top = crate::common::mcap_top_level(&dir.join("x.mcap"));
    let tables: Vec<_> = top
        .attachments
        .iter()
        .filter(|a| a.1 == "text/csv")
        .map(|a| (a.0.as_str(), a.2.as_slice()))
        .collect();
    assert_eq!(tables, [("cam-torque.csv", csv.as_slice())]);
}
