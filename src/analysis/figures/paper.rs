//! The paper's Figs. 16–24 drawn from runs of the drive: link and segment
//! forces, transverse displacements and their spectra, a roller's contact
//! force and contacts against Binder's (49).

use std::path::Path;

use super::{FigureError, Mark, Plot, Trace, save};
use crate::analysis::paper_probes::{
    AnalysisError, RunData, binder_comparison, link_force_series, roller_contact_series,
    segment_force_series, spectrum_with_peaks, transverse_series,
};
use crate::analysis::units::si;

/// Which series of the runs a figure shows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct FigureChoice {
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
pub(crate) fn paper_figures(
    runs: &[&RunData],
    choice: FigureChoice,
    dir: &Path,
) -> Result<Vec<(String, String)>, FigureError> {
    let mut out = Vec::new();
    let Some(first) = runs.first() else {
        return Err(FigureError::Empty("paper figures".to_owned()));
    };
    let mut keep = |plot: Plot, stem: String| -> Result<(), FigureError> {
        save(&plot, dir, &stem)?;
        out.push((stem, plot.title));
        Ok(())
    };
    let segments = first.summary.strands.len();
    let stem = "fig16_link_force";
    keep(link_figure(runs, choice.link, stem)?, stem.to_owned())?;
    let stem = "fig17_segment1_force";
    keep(segment1_figure(runs, stem)?, stem.to_owned())?;
    for (seg, fig_t, fig_f) in [(1usize, 18, 20), (segments.min(4), 19, 21)] {
        let stem = format!("fig{fig_t}_segment{seg}_transverse");
        let (plot, spectra) = transverse_figures(runs, seg, [fig_t, fig_f], &stem)?;
        keep(plot, stem)?;
        keep(spectra, format!("fig{fig_f}_segment{seg}_spectrum"))?;
    }
    let stem = "fig22_roller_contact";
    keep(roller_figure(runs, choice.roller, stem)?, stem.to_owned())?;
    for k in 1..=first.facts.teeth.len() {
        let stem = format!("fig23_24_sprocket{k}_contact_vs_binder");
        let plot = binder_figure(runs, k, &stem)?;
        keep(plot, stem)?;
    }
    Ok(out)
}

/// The error of figure `stem` whose data cannot be cut.
fn cut_error(stem: &str) -> impl Fn(AnalysisError) -> FigureError {
    let stem = stem.to_owned();
    move |source: AnalysisError| FigureError::Analysis {
        stem: stem.clone(),
        source,
    }
}

/// Fig. 16: one link over the last second.
fn link_figure(runs: &[&RunData], link: usize, stem: &str) -> Result<Plot, FigureError> {
    let mut plot = Plot {
        title: format!("Fig. 16: force of link {} over the last second", link),
        x_label: "t (s)".into(),
        y_label: "link force".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let s = link_force_series(r, link, r.summary.window_s).map_err(cut_error(stem))?;
        plot.traces.push(Trace {
            label: r.label.clone(),
            points: s.points(0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    Ok(plot.with_y_unit("N"))
}

/// Fig. 17: segment 1's average link force over the last second.
fn segment1_figure(runs: &[&RunData], stem: &str) -> Result<Plot, FigureError> {
    let mut plot = Plot {
        title: "Fig. 17: average link force of segment 1 over the last second".into(),
        x_label: "t (s)".into(),
        y_label: "average link force".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let s = segment_force_series(r, 1, r.summary.window_s).map_err(cut_error(stem))?;
        plot.traces.push(Trace {
            label: format!("{} (mean {})", r.label, si(s.mean(), "N")),
            points: s.points(0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    Ok(plot.with_y_unit("N"))
}

/// Figs. 18–21 (`figs`: the displacement's number and the spectrum's):
/// segment `seg`'s transverse displacement and its spectrum.
fn transverse_figures(
    runs: &[&RunData],
    seg: usize,
    figs: [usize; 2],
    stem: &str,
) -> Result<(Plot, Plot), FigureError> {
    let [fig_t, fig_f] = figs;
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
        let s = transverse_series(r, seg, r.spectrum_window_s()).map_err(cut_error(stem))?;
        plot.traces.push(Trace {
            label: r.label.clone(),
            points: s.points(0.0),
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
    Ok((plot.with_y_unit("m"), spectra.with_y_unit("m")))
}

/// Fig. 22: one roller's contact force through a chain circuit.
fn roller_figure(runs: &[&RunData], roller: usize, stem: &str) -> Result<Plot, FigureError> {
    let mut plot = Plot {
        title: format!(
            "Fig. 22: contact force on roller {} through a chain circuit",
            roller
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
        let (s, _) = roller_contact_series(r, roller, [from, end]).map_err(cut_error(stem))?;
        plot.traces.push(Trace {
            label: r.label.clone(),
            points: s.points(0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    Ok(plot.with_y_unit("N"))
}

/// Figs. 23–24: on sprocket `k`, the latest complete contact against (49).
fn binder_figure(runs: &[&RunData], k: usize, stem: &str) -> Result<Plot, FigureError> {
    let mut plot = Plot {
        title: format!(
            "Figs. 23–24: contact force on a roller bedded on sprocket {k}, and Binder's (49)"
        ),
        x_label: "time since contact start".into(),
        y_label: "contact force".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let b = binder_comparison(r, k, r.steady_window_s()).map_err(cut_error(stem))?;
        let ex = &b.example;
        plot.traces.push(Trace {
            label: format!("{} roller {}", r.label, ex.roller),
            points: ex.simulated.points(ex.t_start_s),
            mark: Mark::Line,
            color: i,
        });
        plot.traces.push(Trace {
            label: format!("(49), {} (nb = {})", r.label, ex.inputs.bedded),
            points: ex.binder_points(),
            mark: Mark::Dots,
            color: i,
        });
    }
    Ok(plot.with_y_unit("N").with_x_unit("s"))
}
