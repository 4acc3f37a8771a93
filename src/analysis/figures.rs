//! Figures (PNG and SVG, `plotters`) of the analysis: line plots with markers
//! and labelled points, and the paper's Figs. 16–24 from runs.
//!
//! Text is drawn with an embedded font (DejaVu Sans, `assets/fonts`), so
//! PNGs render their labels on machines without system fonts. A figure with
//! no finite point is an error ([`FigureError::Empty`]): nothing is written.
//! Feature `figures`.

use std::path::{Path, PathBuf};
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::study::{
    AnalysisError, RunData, Series, binder_comparison, link_force_series, roller_contact_series,
    segment_force_series, spectrum_with_peaks, transverse_series,
};

const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
const SIZE: (u32, u32) = (1100, 620);

/// Why a figure was not written.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// Nothing finite to draw.
    #[error("figure {0}: no finite data to draw")]
    Empty(String),
    /// The data could not be cut from the run.
    #[error("figure {stem}: {source}")]
    Analysis {
        /// The figure.
        stem: String,
        /// Why.
        source: AnalysisError,
    },
    /// Drawing or writing failed.
    #[error("figure {stem}: {message}")]
    Draw {
        /// The figure.
        stem: String,
        /// Why.
        message: String,
    },
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A line through the points.
    Line,
    /// A filled circle at each point.
    Dots,
    /// A cross at each point.
    Crosses,
}

/// One drawn series.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// Legend text.
    pub label: String,
    /// Points (x, y); non-finite ones are skipped.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub mark: Mark,
    /// Colour index into the palette.
    pub color: usize,
}

/// A line plot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plot {
    /// Title.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Series.
    pub traces: Vec<Trace>,
    /// Labelled points (x, y, text).
    pub notes: Vec<(f64, f64, String)>,
}

/// The palette: circular, real, real with the same rest length, then more.
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(0, 0, 0),
];

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is embedded; a failure here would show as missing text, not a crash.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

fn bounds(plot: &Plot) -> Option<((f64, f64), (f64, f64))> {
    let pts = plot
        .traces
        .iter()
        .flat_map(|t| t.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    let mut any = false;
    for &(x, y) in pts {
        any = true;
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !any {
        return None;
    }
    if !(x1 > x0) {
        (x0, x1) = (x0 - 1.0, x1 + 1.0);
    }
    let pad = if y1 > y0 {
        0.06 * (y1 - y0)
    } else {
        0.5 * y0.abs().max(1.0)
    };
    Some(((x0, x1), (y0 - pad, y1 + pad)))
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, plot: &Plot) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let Some(((x0, x1), (y0, y1))) = bounds(plot) else {
        return Err("no finite data".to_owned());
    };
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(&plot.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(&plot.x_label)
        .y_desc(&plot.y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(e)?;
    for t in &plot.traces {
        let c = color(t.color);
        let pts: Vec<(f64, f64)> = t
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .collect();
        let legend = move |(x, y): (i32, i32)| PathElement::new(vec![(x, y), (x + 20, y)], c);
        match t.mark {
            Mark::Line => chart
                .draw_series(LineSeries::new(pts, c.stroke_width(1)))
                .map_err(e)?
                .label(t.label.clone())
                .legend(legend),
            Mark::Dots => chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, c.filled())))
                .map_err(e)?
                .label(t.label.clone())
                .legend(legend),
            Mark::Crosses => chart
                .draw_series(pts.into_iter().map(|p| Cross::new(p, 5, c.stroke_width(2))))
                .map_err(e)?
                .label(t.label.clone())
                .legend(legend),
        };
    }
    for (x, y, text) in &plot.notes {
        if x.is_finite() && y.is_finite() {
            chart
                .draw_series(std::iter::once(Text::new(
                    text.clone(),
                    (*x, *y),
                    ("sans-serif", 13),
                )))
                .map_err(e)?;
        }
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

/// Writes `plot` as `dir/stem.png` and `dir/stem.svg`; returns the paths.
/// An empty plot writes nothing and is an error.
pub fn save(plot: &Plot, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, FigureError> {
    if bounds(plot).is_none() {
        return Err(FigureError::Empty(stem.to_owned()));
    }
    register_font();
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let fail = |message: String| FigureError::Draw {
        stem: stem.to_owned(),
        message,
    };
    draw(BitMapBackend::new(&png, SIZE).into_drawing_area(), plot).map_err(fail)?;
    draw(SVGBackend::new(&svg, SIZE).into_drawing_area(), plot).map_err(fail)?;
    Ok(vec![png, svg])
}

fn points(s: &Series, scale: f64, t0: f64) -> Vec<(f64, f64)> {
    s.t_s
        .iter()
        .zip(&s.value)
        .map(|(t, v)| (t - t0, v * scale))
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
        y_label: "link force (kN)".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let s = link_force_series(r, choice.link, last_second(r)).map_err(an(stem))?;
        plot.traces.push(Trace {
            label: r.label.clone(),
            points: points(&s, 1e-3, 0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    save(&plot, dir, stem)?;
    out.push((stem.to_owned(), plot.title.clone()));

    // Fig. 17: segment 1's average link force over the last second.
    let stem = "fig17_segment1_force";
    let mut plot = Plot {
        title: "Fig. 17: average link force of segment 1 over the last second".into(),
        x_label: "t (s)".into(),
        y_label: "average link force (kN)".into(),
        ..Plot::default()
    };
    for (i, r) in runs.iter().enumerate() {
        let s = segment_force_series(r, 1, last_second(r)).map_err(an(stem))?;
        plot.traces.push(Trace {
            label: format!("{} (mean {:.1} kN)", r.label, s.mean() * 1e-3),
            points: points(&s, 1e-3, 0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    save(&plot, dir, stem)?;
    out.push((stem.to_owned(), plot.title.clone()));

    // Figs. 18–21: transverse displacement of segments 1 and 4 and their spectra.
    for (seg, fig_t, fig_f) in [(1usize, 18, 20), (segments.min(4), 19, 21)] {
        let stem = format!("fig{fig_t}_segment{seg}_transverse");
        let mut plot = Plot {
            title: format!("Fig. {fig_t}: transverse displacement of the middle of segment {seg}"),
            x_label: "t (s)".into(),
            y_label: "displacement (mm)".into(),
            ..Plot::default()
        };
        let mut spectra = Plot {
            title: format!(
                "Fig. {fig_f}: amplitude spectrum of segment {seg}'s transverse displacement"
            ),
            x_label: "frequency (Hz)".into(),
            y_label: "amplitude (mm)".into(),
            ..Plot::default()
        };
        for (i, r) in runs.iter().enumerate() {
            let s = transverse_series(r, seg, r.spectrum_window_s()).map_err(an(&stem))?;
            plot.traces.push(Trace {
                label: r.label.clone(),
                points: points(&s, 1e3, 0.0),
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
                    .map(|(f, a)| (*f, a * 1e3))
                    .collect(),
                mark: Mark::Line,
                color: i,
            });
            spectra.traces.push(Trace {
                label: format!("{} peaks", r.label),
                points: picked.peaks.iter().map(|(f, a)| (*f, a * 1e3)).collect(),
                mark: Mark::Dots,
                color: i,
            });
            for (f, a) in picked.peaks.iter().take(3) {
                spectra
                    .notes
                    .push((*f + 1.5, a * 1e3, format!("{f:.1} Hz")));
            }
        }
        save(&plot, dir, &stem)?;
        out.push((stem, plot.title.clone()));
        let stem = format!("fig{fig_f}_segment{seg}_spectrum");
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
        y_label: "contact force (kN)".into(),
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
            points: points(&s, 1e-3, 0.0),
            mark: Mark::Line,
            color: i,
        });
    }
    save(&plot, dir, stem)?;
    out.push((stem.to_owned(), plot.title.clone()));

    // Figs. 23–24: per sprocket, the latest complete contact against (49).
    for k in 1..=first.facts.teeth.len() {
        let stem = format!("fig23_24_sprocket{k}_contact_vs_binder");
        let mut plot = Plot {
            title: format!(
                "Figs. 23–24: contact force on a roller bedded on sprocket {k}, and Binder's (49)"
            ),
            x_label: "time since contact start (s)".into(),
            y_label: "contact force (kN)".into(),
            ..Plot::default()
        };
        for (i, r) in runs.iter().enumerate() {
            let b = binder_comparison(r, k, r.steady_window_s()).map_err(an(&stem))?;
            let ex = &b.example;
            plot.traces.push(Trace {
                label: format!("{} roller {}", r.label, ex.roller),
                points: points(&ex.simulated, 1e-3, ex.t_start_s),
                mark: Mark::Line,
                color: i,
            });
            plot.traces.push(Trace {
                label: format!("(49), {} (nb = {})", r.label, ex.inputs.bedded),
                points: ex
                    .binder_t_s
                    .iter()
                    .zip(&ex.binder_n)
                    .map(|(t, f)| (t - ex.t_start_s, f * 1e-3))
                    .collect(),
                mark: Mark::Dots,
                color: i,
            });
        }
        save(&plot, dir, &stem)?;
        out.push((stem, plot.title.clone()));
    }
    Ok(out)
}

/// A Campbell diagram: order amplitudes of one signal at each swept speed as
/// markers (frequency against rpm; size and colour grow with the amplitude),
/// over lines (excitation orders, predicted natural frequencies).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Campbell {
    /// Title.
    pub title: String,
    /// Markers (rpm, frequency in Hz, amplitude); amplitudes below 1 % of
    /// the largest are not drawn.
    pub points: Vec<(f64, f64, f64)>,
    /// Lines (rpm, frequency in Hz), drawn first, with their legend.
    pub lines: Vec<Trace>,
    /// Upper end of the frequency axis, Hz.
    pub max_hz: f64,
}

/// Marker colour for an amplitude relative to the largest, from blue (small) to red.
fn heat(relative: f64) -> RGBColor {
    let r = relative.clamp(0.0, 1.0);
    let mix = |a: u8, b: u8| (f64::from(a) + r * (f64::from(b) - f64::from(a))).round() as u8;
    RGBColor(mix(60, 220), mix(90, 30), mix(200, 40))
}

fn draw_campbell<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    c: &Campbell,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in c
        .points
        .iter()
        .map(|p| p.0)
        .chain(c.lines.iter().flat_map(|t| t.points.iter().map(|p| p.0)))
        .filter(|x| x.is_finite())
    {
        x0 = x0.min(x);
        x1 = x1.max(x);
    }
    if !(x1 >= x0) {
        return Err("no finite data".to_owned());
    }
    if !(x1 > x0) {
        (x0, x1) = (x0 - 1.0, x1 + 1.0);
    }
    let pad = 0.03 * (x1 - x0);
    let top = if c.max_hz > 0.0 { c.max_hz } else { 1.0 };
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(&c.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d((x0 - pad)..(x1 + pad), 0.0..top)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("driver speed, rpm")
        .y_desc("frequency, Hz")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(e)?;
    for t in &c.lines {
        let col = color(t.color);
        let pts: Vec<(f64, f64)> = t
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite() && p.1 <= top)
            .collect();
        let style = match t.mark {
            Mark::Line => col.stroke_width(1),
            Mark::Dots | Mark::Crosses => col.stroke_width(2),
        };
        chart
            .draw_series(LineSeries::new(pts, style))
            .map_err(e)?
            .label(t.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col));
    }
    let largest = c
        .points
        .iter()
        .map(|p| p.2)
        .filter(|a| a.is_finite())
        .fold(0.0f64, f64::max);
    if largest > 0.0 {
        let mut pts: Vec<(f64, f64, f64)> = c
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite() && p.1 <= top)
            .filter(|p| p.2.is_finite() && p.2 >= 0.01 * largest)
            .collect();
        // The largest last, on top.
        pts.sort_by(|a, b| a.2.total_cmp(&b.2));
        chart
            .draw_series(pts.into_iter().map(|(x, y, a)| {
                let r = a / largest;
                let size = (2.0 + 9.0 * r.sqrt()).round() as i32;
                Circle::new((x, y), size, heat(r).filled())
            }))
            .map_err(e)?;
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

/// Writes `campbell` as `dir/stem.png` and `dir/stem.svg`; returns the
/// paths. A diagram with no finite point is an error.
pub fn save_campbell(
    campbell: &Campbell,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, FigureError> {
    if !campbell
        .points
        .iter()
        .any(|p| p.0.is_finite() && p.1.is_finite() && p.2.is_finite())
    {
        return Err(FigureError::Empty(stem.to_owned()));
    }
    register_font();
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let fail = |message: String| FigureError::Draw {
        stem: stem.to_owned(),
        message,
    };
    draw_campbell(BitMapBackend::new(&png, SIZE).into_drawing_area(), campbell).map_err(fail)?;
    draw_campbell(SVGBackend::new(&svg, SIZE).into_drawing_area(), campbell).map_err(fail)?;
    Ok(vec![png, svg])
}
