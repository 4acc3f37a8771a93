//! Figures and reports an engineer reads: a timing drive's Campbell diagram
//! shows the band where its cam orders and strand modes meet (not the
//! meshing band), and `analyze`'s report writes small amplitudes with the
//! digits that show them.

use crate::analysis::figures::save_campbell;
use crate::analysis::orders::OrderSet;
use crate::scene::{Overrides, Scene};
use crate::studies::sweep::campbell::campbell;
use crate::studies::sweep::{
    CaseOutcome, SweepSettings, completed, default_orders, excitation_orders, on_order_grid,
    run_sweep,
};
use std::path::Path;

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
