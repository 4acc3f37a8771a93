//! Figures (PNG and SVG, `plotters`) of the analysis: line plots with markers
//! and labelled points ([`Plot`]), the paper's Figs. 16–24 from runs
//! ([`paper_figures`]), Campbell diagrams ([`Campbell`]) and bar charts
//! ([`Bars`]).
//!
//! Every figure reads on its own: axis titles carry their units, tick labels
//! carry the digits their spacing needs and no more, a legend's glyph is what
//! the plot draws, and the legend sits in the corner that hides the least.
//!
//! Text is drawn with an embedded font (DejaVu Sans, `assets/fonts`), so
//! PNGs render their labels on machines without system fonts. A figure with
//! no finite point is an error ([`FigureError::Empty`]): nothing is written.
//! Feature `figures`.

use std::path::{Path, PathBuf};
use std::sync::Once;

use plotters::chart::SeriesAnno;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::paper_probes::AnalysisError;
use super::units::Prefix;

mod bars;
mod campbell;
mod paper;

pub(crate) use bars::{BarPanel, Bars, save_bars, value_label};
pub(crate) use campbell::{Campbell, OrderLine, SpanLines, save_campbell};
pub(crate) use paper::{FigureChoice, paper_figures};

const FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
const SIZE: (u32, u32) = (1100, 620);

/// Why a figure was not written.
#[derive(Debug, thiserror::Error)]
pub(crate) enum FigureError {
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
pub(crate) enum Mark {
    /// A line through the points.
    Line,
    /// A line through the points with a dot at each: few points, each one a
    /// result (a speed of a sweep).
    LineDots,
    /// A dashed line through the points (a reference, a predicted value).
    Dashed,
    /// A filled circle at each point.
    Dots,
    /// A cross at each point.
    Crosses,
}

impl Mark {
    /// Whether the points are marked one by one (the x range is padded so
    /// that the outermost ones show whole).
    fn marks_points(self) -> bool {
        matches!(self, Self::LineDots | Self::Dots | Self::Crosses)
    }
}

/// One drawn series.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Trace {
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
pub(crate) struct Plot {
    /// Title.
    pub title: String,
    /// x-axis label, with its unit: `driver speed (rpm)`.
    pub x_label: String,
    /// y-axis label, with its unit.
    pub y_label: String,
    /// Series.
    pub traces: Vec<Trace>,
    /// Labelled points (x, y, text).
    pub notes: Vec<(f64, f64, String)>,
}

impl Plot {
    /// The y values, given in `unit` (an SI unit: "N", "m"), rewritten with
    /// the prefix that puts the largest in [1, 1000), and the unit appended
    /// to the axis title: a link force of 0.2–1.6 kN reads "link force (kN)",
    /// a displacement of 20 µm "displacement (µm)". Notes move with the values.
    pub(crate) fn with_y_unit(mut self, unit: &str) -> Self {
        let largest = self
            .traces
            .iter()
            .flat_map(|t| finite(&t.points))
            .map(|p| p.1.abs())
            .fold(0.0, f64::max);
        let p = Prefix::of(largest);
        for t in &mut self.traces {
            t.points.iter_mut().for_each(|q| q.1 = p.scale(q.1));
        }
        self.notes.iter_mut().for_each(|n| n.1 = p.scale(n.1));
        self.y_label = format!("{} ({})", self.y_label, p.unit(unit));
        self
    }

    /// As [`Plot::with_y_unit`], for x: a contact of 8 ms reads "(ms)".
    pub(crate) fn with_x_unit(mut self, unit: &str) -> Self {
        let largest = self
            .traces
            .iter()
            .flat_map(|t| finite(&t.points))
            .map(|p| p.0.abs())
            .fold(0.0, f64::max);
        let p = Prefix::of(largest);
        for t in &mut self.traces {
            t.points.iter_mut().for_each(|q| q.0 = p.scale(q.0));
        }
        self.notes.iter_mut().for_each(|n| n.0 = p.scale(n.0));
        self.x_label = format!("{} ({})", self.x_label, p.unit(unit));
        self
    }
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

/// A tick label: the value with the digits that tell it from its
/// neighbours (at most six decimals, trailing zeros dropped), never `-0`.
pub(crate) fn tick(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

fn finite(points: &[(f64, f64)]) -> impl Iterator<Item = (f64, f64)> + '_ {
    points
        .iter()
        .copied()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
}

fn bounds(plot: &Plot) -> Option<((f64, f64), (f64, f64))> {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    let mut any = false;
    for (x, y) in plot.traces.iter().flat_map(|t| finite(&t.points)) {
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
    } else if plot.traces.iter().any(|t| t.mark.marks_points()) {
        // Room for the outermost markers.
        let pad = 0.02 * (x1 - x0);
        (x0, x1) = (x0 - pad, x1 + pad);
    }
    let pad = if y1 > y0 {
        0.06 * (y1 - y0)
    } else {
        0.5 * y0.abs().max(1.0)
    };
    Some(((x0, x1), (y0 - pad, y1 + pad)))
}

/// The corner of the plot whose legend box (estimated from the labels'
/// length and count) covers the fewest drawn points, lines sampled along
/// their segments; the upper right on a tie.
fn legend_corner(plot: &Plot, x: (f64, f64), y: (f64, f64)) -> SeriesLabelPosition {
    let (width_px, height_px) = (f64::from(SIZE.0) - 140.0, f64::from(SIZE.1) - 120.0);
    let labels = plot.traces.iter().filter(|t| !t.label.is_empty());
    let chars = labels
        .clone()
        .map(|t| t.label.chars().count())
        .max()
        .unwrap_or(0);
    let fw = ((40.0 + 7.5 * chars as f64) / width_px).min(1.0);
    let fh = ((10.0 + 19.0 * labels.count() as f64) / height_px).min(1.0);
    let unit = |(px, py): (f64, f64)| ((px - x.0) / (x.1 - x.0), (py - y.0) / (y.1 - y.0));
    let mut samples: Vec<(f64, f64)> = Vec::new();
    for t in &plot.traces {
        let pts: Vec<(f64, f64)> = finite(&t.points).map(unit).collect();
        samples.extend(&pts);
        if matches!(t.mark, Mark::Line | Mark::LineDots | Mark::Dashed) {
            for w in pts.windows(2) {
                samples.extend((1..8).map(|i| {
                    let s = f64::from(i) / 8.0;
                    (
                        w[0].0 + s * (w[1].0 - w[0].0),
                        w[0].1 + s * (w[1].1 - w[0].1),
                    )
                }));
            }
        }
    }
    samples.extend(
        plot.notes
            .iter()
            .filter(|n| n.0.is_finite() && n.1.is_finite())
            .map(|n| unit((n.0, n.1))),
    );
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let covered = |right: bool, upper: bool| {
        samples
            .iter()
            .filter(|(u, v)| {
                let in_x = if right { *u > 1.0 - fw } else { *u < fw };
                let in_y = if upper { *v > 1.0 - fh } else { *v < fh };
                in_x && in_y
            })
            .count()
    };
    corners
        .into_iter()
        .min_by_key(|&(_, right, upper)| covered(right, upper))
        .map_or(SeriesLabelPosition::UpperRight, |c| c.0)
}

/// Labels a drawn series in the legend with the glyph of its mark: what
/// the plot draws, 20 px wide.
fn legend<'a, DB: DrawingBackend + 'a>(
    anno: &mut SeriesAnno<'a, DB>,
    mark: Mark,
    c: RGBColor,
    label: String,
) {
    let stroke = c.stroke_width(2);
    let anno = anno.label(label);
    match mark {
        Mark::Line => {
            anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], stroke))
        }
        Mark::Dashed => anno.legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(0, 0), (7, 0)], stroke)
                + PathElement::new(vec![(12, 0), (20, 0)], stroke)
        }),
        Mark::LineDots => anno.legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(0, 0), (20, 0)], stroke)
                + Circle::new((10, 0), 4, c.filled())
        }),
        Mark::Dots => anno.legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled())),
        Mark::Crosses => anno.legend(move |(x, y)| Cross::new((x + 10, y), 5, stroke)),
    };
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
        // Room for the last x tick label, centred on the axis's end.
        .margin_right(40)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(&plot.x_label)
        .y_desc(&plot.y_label)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.12))
        .draw()
        .map_err(e)?;
    for t in &plot.traces {
        let c = color(t.color);
        let pts: Vec<(f64, f64)> = finite(&t.points).collect();
        // Dense signals in a thin line; a few results in a line that shows.
        let width = if pts.len() > 200 { 1 } else { 2 };
        let anno = match t.mark {
            Mark::Line => chart.draw_series(LineSeries::new(pts, c.stroke_width(width))),
            Mark::Dashed => chart.draw_series(DashedLineSeries::new(pts, 8, 5, c.stroke_width(2))),
            Mark::LineDots => {
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
                    .map_err(e)?;
                chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 4, c.filled())))
            }
            Mark::Dots => chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 4, c.filled()))),
            Mark::Crosses => {
                chart.draw_series(pts.into_iter().map(|p| Cross::new(p, 5, c.stroke_width(2))))
            }
        }
        .map_err(e)?;
        // A trace with no label shares the legend entry of the one before.
        if !t.label.is_empty() {
            legend(anno, t.mark, c, t.label.clone());
        }
    }
    // A note too close to one already written is left out: overlapping
    // labels read as neither.
    let mut written: Vec<(f64, f64)> = Vec::new();
    for (x, y, text) in &plot.notes {
        let (u, v) = ((x - x0) / (x1 - x0), (y - y0) / (y1 - y0));
        if written
            .iter()
            .any(|(a, b)| (u - a).abs() < 0.08 && (v - b).abs() < 0.05)
        {
            continue;
        }
        if x.is_finite() && y.is_finite() {
            written.push((u, v));
            // Beside the point, a little above it.
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((*x, *y))
                        + Text::new(text.clone(), (7, -16), ("sans-serif", 13)),
                ))
                .map_err(e)?;
        }
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.5))
        .position(legend_corner(plot, (x0, x1), (y0, y1)))
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

/// Writes `plot` as `dir/stem.png` and `dir/stem.svg`; returns the paths.
/// An empty plot writes nothing and is an error.
pub(crate) fn save(plot: &Plot, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, FigureError> {
    if bounds(plot).is_none() {
        return Err(FigureError::Empty(stem.to_owned()));
    }
    write_png_svg(plot, dir, stem)
}

/// A figure drawn the same way into any plotters backend.
pub(crate) trait Drawing {
    /// Draws the figure on `root`; the error is plotters' message.
    fn draw_on<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static;

    /// The canvas it is drawn on, pixels (width, height).
    fn size(&self) -> (u32, u32) {
        SIZE
    }
}

impl Drawing for Plot {
    fn draw_on<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        draw(root, self)
    }
}

/// Writes `figure` as `dir/stem.png` and `dir/stem.svg`, both of the
/// figure's size; returns the paths.
pub(crate) fn write_png_svg(
    figure: &impl Drawing,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, FigureError> {
    register_font();
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let fail = |message: String| FigureError::Draw {
        stem: stem.to_owned(),
        message,
    };
    figure
        .draw_on(BitMapBackend::new(&png, figure.size()).into_drawing_area())
        .map_err(fail)?;
    figure
        .draw_on(SVGBackend::new(&svg, figure.size()).into_drawing_area())
        .map_err(fail)?;
    Ok(vec![png, svg])
}
