//! `chaindrive analyze`'s figures of a recorded run (PNG and SVG), drawn
//! with `crate::analysis::figures`.

use std::path::{Path, PathBuf};

use crate::analysis::figures::{Mark, Plot, Trace, save};
use crate::analysis::paper_probes::{
    ContactExample, RunData, link_force_series, roller_contact_series, segment_force_series,
    spectrum_with_peaks, transverse_series,
};
use crate::analysis::recorded::{AnalyzeOptions, RecordedAnalysis, RecordedRun, RecordedSegment};
use crate::analysis::units::si;

/// Figures drawn: (file stem, caption).
pub(super) type FigureList = Vec<(String, String)>;

/// The single-run figures: the chosen link's force, each segment's average
/// link force, transverse displacement and spectrum, the chosen roller's
/// contact force, and each sprocket's latest complete contact against (49).
/// A figure whose data is absent (channel not recorded, no free link, no
/// complete contact) is not drawn; the report says why. Returns each
/// figure's stem and caption, and the paths written.
pub(super) fn recorded_figures(
    run: &RecordedRun,
    a: &RecordedAnalysis,
    options: &AnalyzeOptions,
    dir: &Path,
) -> anyhow::Result<(FigureList, Vec<PathBuf>)> {
    let d = &run.data;
    let mut out = Vec::new();
    let mut paths = Vec::new();
    let mut emit = |plot: Plot, stem: String| -> anyhow::Result<()> {
        paths.extend(save(&plot, dir, &stem)?);
        out.push((stem, plot.title));
        Ok(())
    };
    if let Some(l) = &a.link {
        let s = link_force_series(d, l.link, a.window_s)?;
        emit(
            time_plot(
                format!("force of link {}", l.link),
                ("link force", "N"),
                d.label.clone(),
                s.points(0.0),
            ),
            format!("link{}_force", l.link),
        )?;
    }
    for seg in &a.segments {
        if options.segment.is_some_and(|s| s != seg.segment) {
            continue;
        }
        segment_figures(d, a, seg, &mut emit)?;
    }
    if let Some(r) = &a.roller {
        let (s, _) = roller_contact_series(d, r.roller, r.window_s)?;
        emit(
            time_plot(
                format!("contact force on roller {}", r.roller),
                ("contact force", "N"),
                d.label.clone(),
                s.points(0.0),
            ),
            format!("roller{}_contact", r.roller),
        )?;
    }
    for (k, b) in a.binder.iter().enumerate() {
        let Some(b) = b else { continue };
        emit(
            binder_plot(k + 1, &b.example),
            format!("sprocket{}_contact_vs_binder", k + 1),
        )?;
    }
    Ok((out, paths))
}

/// A plot of one signal over time, drawn as a line.
fn time_plot(
    title: String,
    (y_label, unit): (&str, &str),
    label: String,
    points: Vec<(f64, f64)>,
) -> Plot {
    Plot {
        title,
        x_label: "t (s)".into(),
        y_label: y_label.into(),
        traces: vec![Trace {
            label,
            points,
            mark: Mark::Line,
            color: 0,
        }],
        notes: Vec::new(),
    }
    .with_y_unit(unit)
}

/// Segment `seg`'s figures, each handed to `emit`: its average link force
/// (where it had a free link), its transverse displacement and the
/// displacement's spectrum (where it has two points or more).
fn segment_figures(
    d: &RunData,
    a: &RecordedAnalysis,
    seg: &RecordedSegment,
    emit: &mut impl FnMut(Plot, String) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let k = seg.segment;
    if seg.mean_link_force_n.is_some() {
        let s = segment_force_series(d, k, a.window_s)?;
        emit(
            time_plot(
                format!("average link force of segment {k}"),
                ("average link force", "N"),
                format!("{} (mean {})", d.label, si(s.mean(), "N")),
                s.points(0.0),
            ),
            format!("segment{k}_force"),
        )?;
    }
    let s = transverse_series(d, k, a.spectrum_window_s)?;
    emit(
        time_plot(
            format!("transverse displacement of the middle of segment {k}"),
            ("displacement", "m"),
            d.label.clone(),
            s.points(0.0),
        ),
        format!("segment{k}_transverse"),
    )?;
    let picked = spectrum_with_peaks(&s, d.signals.rate_hz, [1.0, 200.0], 5, 2.0);
    let spectrum: Vec<(f64, f64)> = picked
        .freq_hz
        .iter()
        .zip(&picked.amplitude)
        .filter(|(f, _)| **f <= 200.0)
        .map(|(f, amp)| (*f, *amp))
        .collect();
    if spectrum.len() >= 2 {
        let mut traces = vec![Trace {
            label: d.label.clone(),
            points: spectrum,
            mark: Mark::Line,
            color: 0,
        }];
        if !picked.peaks.is_empty() {
            traces.push(Trace {
                label: "peaks".into(),
                points: picked.peaks.iter().map(|(f, amp)| (*f, *amp)).collect(),
                mark: Mark::Dots,
                color: 1,
            });
        }
        if seg.string_f1_hz > 0.0 {
            // A vertical line from 0 to the highest peak.
            let top = picked.peaks.iter().map(|p| p.1).fold(0.0, f64::max);
            traces.push(Trace {
                label: format!("moving string f₁ = {:.2} Hz", seg.string_f1_hz),
                points: vec![(seg.string_f1_hz, 0.0), (seg.string_f1_hz, top)],
                mark: Mark::Dashed,
                color: 2,
            });
        }
        emit(
            Plot {
                title: format!("amplitude spectrum of segment {k}'s transverse displacement"),
                x_label: "frequency (Hz)".into(),
                y_label: "amplitude".into(),
                traces,
                notes: picked
                    .peaks
                    .iter()
                    .take(3)
                    .map(|(f, amp)| (*f, *amp, format!("{f:.1} Hz")))
                    .collect(),
            }
            .with_y_unit("m"),
            format!("segment{k}_spectrum"),
        )?;
    }
    Ok(())
}

/// Sprocket `sprocket`'s latest complete contact `ex` against (49).
fn binder_plot(sprocket: usize, ex: &ContactExample) -> Plot {
    Plot {
        title: format!(
            "contact force on a roller bedded on sprocket {sprocket}, and Binder's (49)"
        ),
        x_label: "time since contact start".into(),
        y_label: "contact force".into(),
        traces: vec![
            Trace {
                label: format!("roller {} (simulated)", ex.roller),
                points: ex.simulated.points(ex.t_start_s),
                // A short contact holds few samples: mark each.
                mark: if ex.simulated.t_s.len() <= 60 {
                    Mark::LineDots
                } else {
                    Mark::Line
                },
                color: 0,
            },
            Trace {
                label: format!("(49) (nb = {})", ex.inputs.bedded),
                points: ex.binder_points(),
                mark: Mark::Dots,
                color: 1,
            },
        ],
        notes: Vec::new(),
    }
    .with_y_unit("N")
    .with_x_unit("s")
}
