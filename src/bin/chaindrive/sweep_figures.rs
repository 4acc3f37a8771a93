//! `chaindrive sweep`'s figures: the Campbell diagram of the chosen signal,
//! its order cuts at the excitation orders, and the envelopes (each
//! segment's link force, the largest contact force, the largest
//! penetration) against the driver's speed.

use std::path::{Path, PathBuf};

use chaindrive::analysis::figures::{self, Mark, Plot, Trace};
use chaindrive::scene::Scene;
use chaindrive::studies::sweep::campbell::{campbell, describe_signal};
use chaindrive::studies::sweep::{CaseResult, order_cut};

/// What the figures show beyond the cases.
pub(crate) struct FigureSettings<'a> {
    /// The folder they go to.
    pub dir: &'a Path,
    /// The signal of the Campbell diagram and the order cuts.
    pub signal: &'a str,
    /// Upper end of the Campbell diagram's frequency axis, Hz (`None`: its default).
    pub max_hz: Option<f64>,
}

const SPEED: &str = "driver speed (rpm)";

/// Draws the figures of the completed cases `done` (in speed order); returns
/// the stems written and the errors met (a figure that cannot be drawn is
/// reported, the others are still drawn).
pub(crate) fn draw_figures(
    settings: &FigureSettings<'_>,
    scene: &Scene,
    done: &[&CaseResult],
    excitation: &[f64],
) -> Vec<Result<String, String>> {
    let dir = settings.dir;
    let mut out = Vec::new();
    let mut keep = |stem: &str, r: Result<Vec<PathBuf>, figures::FigureError>| {
        out.push(r.map(|_| stem.to_owned()).map_err(|e| e.to_string()));
    };
    let diagram = campbell(scene, done, settings.signal, excitation, settings.max_hz);
    keep(
        "campbell",
        figures::save_campbell(&diagram, dir, "campbell"),
    );
    let rpm: Vec<f64> = done.iter().map(|c| c.rpm).collect();
    let (response, unit) = describe_signal(settings.signal);
    let cuts = Plot {
        title: format!("Order cuts: {response}"),
        x_label: SPEED.to_owned(),
        y_label: "order amplitude".to_owned(),
        traces: excitation
            .iter()
            .enumerate()
            .map(|(i, &k)| Trace {
                label: format!("order {k}"),
                points: rpm
                    .iter()
                    .copied()
                    .zip(order_cut(done, settings.signal, k))
                    .collect(),
                mark: Mark::LineDots,
                color: i,
            })
            .collect(),
        notes: Vec::new(),
    }
    .with_y_unit(unit);
    keep("order_cuts", figures::save(&cuts, dir, "order_cuts"));
    keep(
        "envelope_link_force",
        figures::save(&link_force_envelope(done), dir, "envelope_link_force"),
    );
    let single = |title: &str,
                  y_label: &str,
                  label: &str,
                  value: &dyn Fn(&CaseResult) -> f64,
                  color: usize| Plot {
        title: title.to_owned(),
        x_label: SPEED.to_owned(),
        y_label: y_label.to_owned(),
        traces: vec![Trace {
            label: label.to_owned(),
            points: done.iter().map(|c| (c.rpm, value(c))).collect(),
            mark: Mark::LineDots,
            color,
        }],
        notes: Vec::new(),
    };
    let contact = single(
        "Largest contact force",
        "contact force",
        "largest over the window",
        &|c| c.max_contact_force_n,
        1,
    )
    .with_y_unit("N");
    keep(
        "envelope_contact_force",
        figures::save(&contact, dir, "envelope_contact_force"),
    );
    let penetration = single(
        "Largest penetration",
        "penetration",
        "largest over the window",
        &|c| c.max_penetration_m,
        2,
    )
    .with_y_unit("m");
    keep(
        "envelope_penetration",
        figures::save(&penetration, dir, "envelope_penetration"),
    );
    out
}

/// Each segment's link force against speed: the mean (line with dots) between
/// the smallest and the largest over the window's samples (dashed).
fn link_force_envelope(done: &[&CaseResult]) -> Plot {
    let spans = done.first().map_or(0, |c| c.spans.len());
    let mut traces = Vec::new();
    for k in 0..spans {
        let seg = |f: &dyn Fn(&CaseResult) -> f64| -> Vec<(f64, f64)> {
            done.iter().map(|c| (c.rpm, f(c))).collect()
        };
        traces.push(Trace {
            label: format!("segment {} mean", k + 1),
            points: seg(&|c| c.segment_mean_n.get(k).copied().unwrap_or(f64::NAN)),
            mark: Mark::LineDots,
            color: k,
        });
        traces.push(Trace {
            label: format!("segment {} smallest, largest", k + 1),
            points: seg(&|c| c.segment_range_n.get(k).map_or(f64::NAN, |r| r.1)),
            mark: Mark::Dashed,
            color: k,
        });
        // The same legend entry as the largest.
        traces.push(Trace {
            label: String::new(),
            points: seg(&|c| c.segment_range_n.get(k).map_or(f64::NAN, |r| r.0)),
            mark: Mark::Dashed,
            color: k,
        });
    }
    Plot {
        title: "Link force per segment: mean, smallest and largest over the window".to_owned(),
        x_label: SPEED.to_owned(),
        y_label: "segment link force".to_owned(),
        traces,
        notes: Vec::new(),
    }
    .with_y_unit("N")
}
