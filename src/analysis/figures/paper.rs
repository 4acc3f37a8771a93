//! The paper's Figs. 16–24 drawn from runs of the drive: link and segment
//! forces, transverse displacements and their spectra, a roller's contact
//! force and contacts against Binder's (49).

use std::path::Path;

use super::{FigureError, Mark, Plot, Trace, save};
use crate::analysis::study::{
    AnalysisError, RunData, Series, binder_comparison, link_force_series, roller_contact_series,
    segment_force_series, spectrum_with_peaks, transverse_series,
};
use crate::analysis::units::si;

/// A series' points (time since `t0`, value), in SI units.
fn points(s: &Series, t0: f64) -> Vec<(f64, f64)> {
    s.t_s
        .iter()
        .zip(&s.value)
        .map(|(t, v)| (t - t0, *v))
        .collect()
}

/// Which series of the runs a figure shows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FigureChoice {
    /// Link of Fig. 16 (0-based).
    pub link: usize,
    /// Roller of Fig. 22 (0-based).
    pub roller: usize,
}

/// Draws Figs. 16–24 for `runs` (overlaid, one colour each) into `dir`;
/// returns each figure's stem and caption. Every figure is checked before
/// anything is drawn for it; a figure whose data cannot be cut (unknown
/// index, window outside the run) is an error, and figures already written
/// stay.
pub fn paper_figures(
    runs: &[&RunData],
    choice: FigureChoice,
    dir: &Path,
) -> Result<Vec<(String, String)>, FigureError> {
    let mut out = Vec::new();
    let Some(first) = runs.first() else {
        return Err(FigureError::Empty("paper figures".to_owned()));
    };
    let an = |stem: &str| {
        let stem = stem.to_owned();
        move |source: AnalysisError| FigureError::Analysis { stem, source }
    };
    let last_second = |r: &RunData| r.summary.window_s;
    let segments = first.summary.strands.len();

    // Fig. 16: one link over the last second.
    let stem = "fig16_link_force";
    let mut plot = Plot {
        title: format!(
            "Fig. 16: force of link {} over the last second",
            choice.link
        ),
        x_label: "t (s)".into(),
        y_label: "link force".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let s = link_force_series(r, choice.link, last_second(r)).map_err(an(stem))?;
        plot.traces.push(Trace {
            label: r.label.clone(),
            points: points(&s, 0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    let plot = plot.with_y_unit("N");
    save(&plot, dir, stem)?;
    out.push((stem.to_owned(), plot.title.clone()));

    // Fig. 17: segment 1's average link force over the last second.
    let stem = "fig17_segment1_force";
    let mut plot = Plot {
        title: "Fig. 17: average link force of segment 1 over the last second".into(),
        x_label: "t (s)".into(),
        y_label: "average link force".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let s = segment_force_series(r, 1, last_second(r)).map_err(an(stem))?;
        plot.traces.push(Trace {
            label: format!("{} (mean {})", r.label, si(s.mean(), "N")),
            points: points(&s, 0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    let plot = plot.with_y_unit("N");
    save(&plot, dir, stem)?;
    out.push((stem.to_owned(), plot.title.clone()));

    // Figs. 18–21: transverse displacement of segments 1 and 4 and their spectra.
    for (seg, fig_t, fig_f) in [(1usize, 18, 20), (segments.min(4), 19, 21)] {
        let stem = format!("fig{fig_t}_segment{seg}_transverse");
        let mut plot = Plot {
            title: format!("Fig. {fig_t}: transverse displacement of the middle of segment {seg}"),
            x_label: "t (s)".into(),
            y_label: "displacement".into(),
            ..Plot::default()
        };
        let mut spectra = Plot {
            title: format!(
                "Fig. {fig_f}: amplitude spectrum of segment {seg}'s transverse displacement (dots: peaks)"
            ),
            x_label: "frequency (Hz)".into(),
            y_label: "amplitude".into(),
            ..Plot::default()
        };
        for (i, r) in runs.iter().enumerate() {
            let s = transverse_series(r, seg, r.spectrum_window_s()).map_err(an(&stem))?;
            plot.traces.push(Trace {
                label: r.label.clone(),
                points: points(&s, 0.0),
                mark: Mark::Line,
                color: i,
            });
            let picked = spectrum_with_peaks(&s, r.summary.sample_rate_hz, [1.0, 200.0], 5, 2.0);
            spectra.traces.push(Trace {
                label: r.label.clone(),
                points: picked
                    .freq_hz
                    .iter()
                    .zip(&picked.amplitude)
                    .filter(|(f, _)| **f <= 200.0)
                    .map(|(f, a)| (*f, *a))
                    .collect(),
                mark: Mark::Line,
                color: i,
            });
            spectra.traces.push(Trace {
                // The run's colour says whose; one legend entry per run.
                label: String::new(),
                points: picked.peaks.iter().map(|(f, a)| (*f, *a)).collect(),
                mark: Mark::Dots,
                color: i,
            });
            for (f, a) in picked.peaks.iter().take(3) {
                spectra.notes.push((*f, *a, format!("{f:.1} Hz")));
            }
        }
        let plot = plot.with_y_unit("m");
        save(&plot, dir, &stem)?;
        out.push((stem, plot.title.clone()));
        let stem = format!("fig{fig_f}_segment{seg}_spectrum");
        let spectra = spectra.with_y_unit("m");
        save(&spectra, dir, &stem)?;
        out.push((stem, spectra.title.clone()));
    }

    // Fig. 22: one roller's contact force through a chain circuit.
    let stem = "fig22_roller_contact";
    let mut plot = Plot {
        title: format!(
            "Fig. 22: contact force on roller {} through a chain circuit",
            choice.roller
        ),
        x_label: "t (s)".into(),
        y_label: "contact force".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let end = r.summary.window_s[1];
        let v = r
            .summary
            .sprockets
            .first()
            .map_or(0.0, |s| s.mean_speed_rad_s.abs())
            * r.facts.pitch_radius_m.first().copied().unwrap_or(0.0);
        let circuit = if v > 0.0 {
            r.probes.rollers() as f64 * r.facts.pitch_m / v
        } else {
            1.0
        };
        let from = (end - circuit).max(r.probes.t_s.first().copied().unwrap_or(0.0));
        let (s, _) = roller_contact_series(r, choice.roller, [from, end]).map_err(an(stem))?;
        plot.traces.push(Trace {
            label: r.label.clone(),
            points: points(&s, 0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    let plot = plot.with_y_unit("N");
    save(&plot, dir, stem)?;
    out.push((stem.to_owned(), plot.title.clone()));

    // Figs. 23–24: per sprocket, the latest complete contact against (49).
    for k in 1..=first.facts.teeth.len() {
        let stem = format!("fig23_24_sprocket{k}_contact_vs_binder");
        let mut plot = Plot {
            title: format!(
                "Figs. 23–24: contact force on a roller bedded on sprocket {k}, and Binder's (49)"
            ),
            x_label: "time since contact start".into(),
            y_label: "contact force".into(),
            ..Plot::default()
        };
        for (i, r) in runs.iter().enumerate() {
            let b = binder_comparison(r, k, r.steady_window_s()).map_err(an(&stem))?;
            let ex = &b.example;
            plot.traces.push(Trace {
                label: format!("{} roller {}", r.label, ex.roller),
                points: points(&ex.simulated, ex.t_start_s),
                mark: Mark::Line,
                color: i,
            });
            plot.traces.push(Trace {
                label: format!("(49), {} (nb = {})", r.label, ex.inputs.bedded),
                points: ex
                    .binder_t_s
                    .iter()
                    .zip(&ex.binder_n)
                    .map(|(t, f)| (t - ex.t_start_s, *f))
                    .collect(),
                mark: Mark::Dots,
                color: i,
            });
        }
        let plot = plot.with_y_unit("N").with_x_unit("s");
        save(&plot, dir, &stem)?;
        out.push((stem, plot.title.clone()));
    }
    Ok(out)
}
