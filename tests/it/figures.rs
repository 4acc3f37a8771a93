//! Figures and reports an engineer reads: a timing drive's Campbell diagram
//! shows the band where its cam orders and strand modes meet (not the
//! meshing band), and `analyze`'s report writes small amplitudes with the
//! digits that show them.

use std::path::Path;

use chaindrive::analysis::figures::save_campbell;
use chaindrive::analysis::orders::OrderSet;
use chaindrive::scene::{Overrides, Scene};
use chaindrive::studies::sweep::campbell::campbell;
use chaindrive::studies::sweep::{
    CaseOutcome, SweepSettings, completed, default_orders, excitation_orders, on_order_grid,
    run_sweep,
};

use crate::common::{chaindrive_in, read_json, stderr};

fn timing_excited() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/timing-excited.toml");
    Scene::from_path_with(&path, &Overrides::default())
        .expect("readable")
        .expect("valid scene")
}

/// `assets/timing-excited.toml`: a 20-tooth crank with speed harmonics of
/// orders 2 and 4, and two 40-tooth cams whose four-lobe torque tables are
/// order 4 of the cam, order 2 of the crank. At 3000 rpm (50 rev/s) the
/// highest of these is order 4 at 4 × 50 = 200 Hz; the meshing order 20 is
/// at 20 × 50 = 1000 Hz. The diagram's frequency axis must reach 200 Hz and
/// every span's predicted transverse mode, and end below 1000 Hz (the old
/// axis ran to the largest analysed order, 80 × 50 = 4000 Hz).
#[test]
fn a_timing_drives_campbell_diagram_shows_its_cam_orders_and_strand_modes_not_the_meshing_band() {
    let scene = timing_excited();
    let orders: OrderSet = default_orders(&scene).expect("orders");
    let settings = SweepSettings {
        rpm: vec![1000.0, 3000.0],
        settle_s: 0.1,
        window_s: 0.25,
        jobs: 2,
        orders,
    };
    let cases = run_sweep(&scene, &settings, None, &|_| {}).expect("sweep");
    assert!(
        cases.iter().all(|c| matches!(c, CaseOutcome::Done(_))),
        "a case failed: {cases:?}"
    );
    let done = completed(&cases);
    let (excitation, _) = on_order_grid(&excitation_orders(&scene), &orders);
    let diagram = campbell(&scene, &done, "seg1_link_force_n", &excitation, None);
    let top = diagram.top_hz();
    let highest_mode = done
        .iter()
        .flat_map(|c| c.spans.iter().flat_map(|s| s.transverse_hz.iter().copied()))
        .fold(0.0, f64::max);
    assert!(
        top >= 200.0,
        "order 4 at 3000 rpm (200 Hz) above the axis's {top} Hz"
    );
    assert!(
        top >= highest_mode,
        "a transverse mode at {highest_mode} Hz above the axis's {top} Hz"
    );
    assert!(
        top < 1000.0,
        "the axis runs into the meshing band: {top} Hz"
    );
    // And it does not waste the figure: at most twice what it must show.
    assert!(top <= 2.0 * highest_mode.max(200.0), "{top} Hz");
    // The meshing orders are named beside the plot; each order line is labelled.
    let tmp = tempfile::tempdir().expect("tempdir");
    let paths = save_campbell(&diagram, tmp.path(), "campbell").expect("drawn");
    let svg = std::fs::read_to_string(&paths[1]).expect("svg");
    for text in [
        "1×",
        "2×",
        "4×",
        "20× mesh",
        "40× mesh",
        "span 1: crankshaft → exhaust",
    ] {
        assert!(svg.contains(text), "{text:?} not in the diagram");
    }
    // An asked axis is kept.
    let asked = campbell(
        &scene,
        &done,
        "seg1_link_force_n",
        &excitation,
        Some(2500.0),
    );
    assert_eq!(asked.top_hz(), 2500.0);
}

#[test]
fn sweep_refuses_a_frequency_axis_that_ends_at_or_below_zero() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for bad in ["0", "-5", "nan"] {
        let o = chaindrive_in(
            tmp.path(),
            &[
                "sweep",
                "--rpm",
                "300:400:100",
                "--max-freq",
                bad,
                "--out",
                "s",
            ],
        );
        let err = stderr(&o);
        assert!(!o.status.success(), "--max-freq {bad} accepted");
        assert!(err.contains("--max-freq"), "{bad}: {err}");
        assert!(
            !tmp.path().join("s").exists(),
            "--max-freq {bad} ran the sweep"
        );
    }
}

/// A written amplitude: "3.50 µm" → 3.5e-6 m; `None` for anything else.
fn metres(cell: &str) -> Option<f64> {
    let (number, unit) = cell.trim().split_once(' ')?;
    let factor = match unit {
        "nm" => 1e-9,
        "µm" => 1e-6,
        "mm" => 1e-3,
        "m" => 1.0,
        _ => return None,
    };
    number.parse::<f64>().ok().map(|v| v * factor)
}

/// The guided drive (`tests/data/guide_30_30.toml`): a guide holds segment
/// 1, whose transverse amplitude is a few µm, while segment 2 swings by
/// millimetres. Every amplitude the report writes, the strand's and its
/// spectral peaks', must read back as the analysis's own number to three
/// significant digits (the old report wrote "0.004" and "0.00 mm").
#[test]
fn analyze_writes_small_transverse_amplitudes_with_the_digits_that_show_them() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/guide_30_30.toml");
    let scene = scene.to_str().expect("utf-8 path");
    let run = chaindrive_in(
        dir,
        &[
            "run",
            scene,
            "--duration",
            "1",
            "--record",
            "g.mcap",
            "--quiet",
        ],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let o = chaindrive_in(dir, &["analyze", "g.mcap", "--out", "a"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let analysis = read_json(&dir.join("a/analysis.json"));
    let report = std::fs::read_to_string(dir.join("a/report.md")).expect("report");
    let segments = analysis["segments"].as_array().expect("segments");
    let mut smallest = f64::INFINITY;
    for s in segments {
        let k = s["segment"].as_u64().expect("segment number");
        let row = report
            .lines()
            .find(|l| l.starts_with(&format!("| {k} | ")) && l.contains(" Hz ("))
            .unwrap_or_else(|| panic!("no row for segment {k} in\n{report}"));
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        // | segment | length | mean | p2p | amplitude | peak | string | vs | (52) | transverse amplitude | peaks |
        let written = metres(cells[10]).unwrap_or_else(|| panic!("{:?} in {row}", cells[10]));
        let amplitude = s["transverse_amplitude_m"].as_f64().expect("amplitude");
        assert!(
            (written - amplitude).abs() <= 5e-3 * amplitude,
            "segment {k}: wrote {} for {amplitude} m",
            cells[10]
        );
        smallest = smallest.min(amplitude);
        let peaks = s["peaks"].as_array().expect("peaks");
        for (p, text) in peaks.iter().zip(cells[11].split("), ")) {
            let a = p[1].as_f64().expect("peak amplitude");
            let cell = text
                .split_once('(')
                .map(|(_, c)| c.trim_end_matches(')'))
                .unwrap_or("");
            let written = metres(cell).unwrap_or_else(|| panic!("{cell:?} in {row}"));
            assert!(
                (written - a).abs() <= 5e-3 * a,
                "segment {k}: peak written {cell} for {a} m"
            );
            smallest = smallest.min(a);
        }
    }
    // The check meant something: an amplitude under 5 µm ("0.00 mm" at two decimals).
    assert!(smallest < 5e-6, "smallest amplitude {smallest} m");
}
