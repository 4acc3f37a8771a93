//! Campbell diagrams: the order amplitudes of one response at each swept
//! speed as markers (frequency against the driver's speed; colour and size
//! grow with the amplitude, on a scale beside the plot), over the excitation
//! orders' lines (each labelled `k×` at its end) and each span's predicted
//! natural frequencies (a colour per span, a line style per mode).
//!
//! Unless told otherwise the frequency axis ends a little above the highest
//! order line that is not a meshing order (at the top speed) and the spans'
//! transverse modes: the band where speed harmonics, load tables and strand
//! resonances meet. The meshing orders and axial modes above it are named
//! beside the plot, not drawn. What this module does not do: choose the
//! orders and modes (the sweep does) or compute anything from a run.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{Drawing, FigureError, tick, write_png_svg};
use crate::analysis::units::si;

const SIZE: (u32, u32) = (1280, 720);
/// Width of the panel beside the plot that holds the scales and the legend, px.
const PANEL_PX: u32 = 340;

/// Markers below this fraction of the largest drawn amplitude are left out;
/// the colour scale spans from it to 1 (logarithmic).
pub(super) const SMALLEST_DRAWN: f64 = 0.01;

/// A Campbell diagram.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Campbell {
    /// Title.
    pub title: String,
    /// What the markers measure, in words: `segment 1 link force`.
    pub response: String,
    /// Its SI unit: `N`, `m`, `rad/s`.
    pub unit: String,
    /// Markers (driver rpm, frequency in Hz, amplitude in `unit`).
    pub points: Vec<(f64, f64, f64)>,
    /// The excitation orders' lines.
    pub orders: Vec<OrderLine>,
    /// Each span's predicted natural frequencies.
    pub spans: Vec<SpanLines>,
    /// Upper end of the frequency axis, Hz; `None`: [`Campbell::default_max_hz`].
    pub max_hz: Option<f64>,
}

/// An excitation order's line: frequency = order × driver revolutions per second.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct OrderLine {
    /// Cycles per driver revolution.
    pub order: f64,
    /// A meshing order (a multiple of the driver's tooth count).
    pub meshing: bool,
    /// (driver rpm, Hz).
    pub points: Vec<(f64, f64)>,
}

impl OrderLine {
    /// `2×`, `0.5×`; `20× mesh` for a meshing order.
    pub(crate) fn label(&self) -> String {
        let k = tick(self.order);
        if self.meshing {
            format!("{k}× mesh")
        } else {
            format!("{k}×")
        }
    }
}

/// One span's predicted natural frequencies against the driver's speed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SpanLines {
    /// `span 1: crankshaft → exhaust camshaft`.
    pub label: String,
    /// Transverse modes 1, 2, …: (driver rpm, Hz) each.
    pub transverse: Vec<Vec<(f64, f64)>>,
    /// The first axial mode: (driver rpm, Hz).
    pub axial: Vec<(f64, f64)>,
}

fn finite_y(points: &[(f64, f64)]) -> impl Iterator<Item = f64> + '_ {
    points
        .iter()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .map(|p| p.1)
}

/// The speed at which a line of (rpm, Hz) points first rises above `top`,
/// interpolated between the last point at or below it and the first above;
/// `None` where no point is at or below it before (a line wholly above).
fn leaves_at(points: &[(f64, f64)], top: f64) -> Option<f64> {
    let finite = points.iter().filter(|p| p.0.is_finite() && p.1.is_finite());
    let mut below: Option<(f64, f64)> = None;
    for &(x, y) in finite {
        if y <= top {
            below = Some((x, y));
        } else if let Some((x0, y0)) = below {
            return Some(x0 + (x - x0) * (top - y0) / (y - y0));
        }
    }
    None
}

/// The smallest of 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 × 10ᵏ at or above `v` (> 0).
fn nice_ceil(v: f64) -> f64 {
    let scale = 10f64.powf(v.log10().floor());
    [1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0]
        .into_iter()
        .map(|m| m * scale)
        .find(|&c| c >= v * (1.0 - 1e-12))
        .unwrap_or(10.0 * scale)
}

impl Campbell {
    /// The frequency axis's upper end when none is asked for: 10 % above the
    /// highest of the non-meshing order lines and the spans' transverse
    /// modes, rounded up to a round number. With neither, the highest of
    /// every line and marker.
    pub(crate) fn default_max_hz(&self) -> f64 {
        let band = self
            .orders
            .iter()
            .filter(|o| !o.meshing)
            .flat_map(|o| finite_y(&o.points))
            .chain(
                self.spans
                    .iter()
                    .flat_map(|s| s.transverse.iter().flat_map(|m| finite_y(m))),
            )
            .fold(0.0f64, f64::max);
        let wanted = if band > 0.0 {
            band
        } else {
            self.orders
                .iter()
                .flat_map(|o| finite_y(&o.points))
                .chain(self.spans.iter().flat_map(|s| finite_y(&s.axial)))
                .chain(self.points.iter().map(|p| p.1).filter(|f| f.is_finite()))
                .fold(0.0f64, f64::max)
        };
        if wanted > 0.0 {
            nice_ceil(1.1 * wanted)
        } else {
            1.0
        }
    }

    /// The frequency axis's upper end: `max_hz`, or the default.
    pub(crate) fn top_hz(&self) -> f64 {
        self.max_hz
            .filter(|f| *f > 0.0 && f.is_finite())
            .unwrap_or_else(|| self.default_max_hz())
    }

    /// What lies above the frequency axis and is not drawn, in words; empty
    /// when everything shows.
    pub(crate) fn above_range(&self) -> Vec<String> {
        let top = self.top_hz();
        let mut out = Vec::new();
        // A line wholly above is not drawn; one that leaves the axis is drawn
        // up to where it leaves, which the note gives.
        let (mut above, mut cut) = (Vec::new(), Vec::new());
        for o in &self.orders {
            if !finite_y(&o.points).any(|f| f > top) {
                continue;
            }
            match leaves_at(&o.points, top) {
                Some(rpm) => cut.push(format!("{} above {rpm:.0} rpm", o.label())),
                None => above.push(o.label()),
            }
        }
        if !above.is_empty() {
            out.push(format!("order lines {}", above.join(", ")));
        }
        if !cut.is_empty() {
            out.push(format!("order lines {}", cut.join(", ")));
        }
        let range = |values: &mut dyn Iterator<Item = f64>| {
            values
                .filter(|f| *f > top)
                .fold(None, |acc: Option<(f64, f64)>, f| {
                    Some(acc.map_or((f, f), |(a, b)| (a.min(f), b.max(f))))
                })
        };
        let transverse = range(
            &mut self
                .spans
                .iter()
                .flat_map(|s| s.transverse.iter().flat_map(|m| finite_y(m))),
        );
        let axial = range(&mut self.spans.iter().flat_map(|s| finite_y(&s.axial)));
        for (what, r) in [("transverse modes", transverse), ("axial modes", axial)] {
            match r {
                Some((a, b)) if b - a > 0.005 * b => {
                    out.push(format!("{what} at {}–{}", si(a, "Hz"), si(b, "Hz")));
                }
                Some((a, _)) => out.push(format!("{what} at {}", si(a, "Hz"))),
                None => {}
            }
        }
        let largest = self.largest_drawn();
        let hidden = self
            .points
            .iter()
            .filter(|p| p.1 > top && p.2 >= SMALLEST_DRAWN * largest && p.0.is_finite())
            .count();
        if hidden > 0 {
            out.push(format!("{hidden} markers (order amplitudes)"));
        }
        out
    }

    /// The largest amplitude among the markers within the frequency axis.
    fn largest_drawn(&self) -> f64 {
        let top = self.top_hz();
        self.points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite() && p.1 <= top)
            .map(|p| p.2)
            .filter(|a| a.is_finite())
            .fold(0.0f64, f64::max)
    }
}

/// The parts of a polyline at or below `top`: each segment that crosses it
/// is cut there; non-finite points split the line.
pub(crate) fn clip_below(points: &[(f64, f64)], top: f64) -> Vec<Vec<(f64, f64)>> {
    let mut parts = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let mut previous: Option<(f64, f64)> = None;
    for &p in points {
        if !(p.0.is_finite() && p.1.is_finite()) {
            parts.push(std::mem::take(&mut current));
            previous = None;
            continue;
        }
        if let Some(q) = previous {
            // Where the segment q → p crosses `top`, if it does.
            if (q.1 - top) * (p.1 - top) < 0.0 {
                let w = (top - q.1) / (p.1 - q.1);
                current.push((q.0 + w * (p.0 - q.0), top));
                if p.1 > top {
                    parts.push(std::mem::take(&mut current));
                }
            }
        }
        if p.1 <= top {
            current.push(p);
        }
        previous = Some(p);
    }
    parts.push(current);
    parts.retain(|part| part.len() >= 2);
    parts
}

/// Marker colour at `r` ∈ [0, 1] of the logarithmic amplitude scale: pale
/// blue (small) through purple to red (the largest).
fn heat(r: f64) -> RGBColor {
    const STOPS: [(f64, (f64, f64, f64)); 4] = [
        (0.0, (190.0, 210.0, 235.0)),
        (0.35, (90.0, 150.0, 210.0)),
        (0.7, (135.0, 60.0, 170.0)),
        (1.0, (215.0, 25.0, 28.0)),
    ];
    let r = if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let i = STOPS.iter().rposition(|s| s.0 <= r).unwrap_or(0).min(2);
    let (r0, a) = STOPS[i];
    let (r1, b) = STOPS[i + 1];
    let w = (r - r0) / (r1 - r0);
    let mix = |x: f64, y: f64| (x + w * (y - x)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Where an amplitude sits on the logarithmic scale: 0 at
/// [`SMALLEST_DRAWN`] of the largest, 1 at the largest.
fn scale_position(amplitude: f64, largest: f64) -> f64 {
    let smallest = SMALLEST_DRAWN.log10();
    ((amplitude / largest).log10() - smallest) / -smallest
}

/// Marker radius, px, at scale position `r`.
fn radius(r: f64) -> i32 {
    (3.0 + 8.0 * r.clamp(0.0, 1.0)).round() as i32
}

/// Span colours: none of the markers' blues, purples and reds.
const SPAN_COLORS: [RGBColor; 6] = [
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(188, 189, 34),
    RGBColor(227, 119, 194),
];

const ORDER_GREY: RGBColor = RGBColor(95, 95, 95);

/// How a span mode's line is dashed: (dash, gap) in px; `None`: solid.
fn dashes(mode: usize) -> Option<(u32, u32)> {
    match mode {
        0 => None,
        1 => Some((10, 6)),
        _ => Some((3, 4)),
    }
}

/// The axial mode's dashes.
const AXIAL_DASHES: (u32, u32) = (18, 5);

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
        .chain(c.orders.iter().flat_map(|o| o.points.iter().map(|p| p.0)))
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
    let top = c.top_hz();
    root.fill(&WHITE).map_err(e)?;
    let (plot_area, panel) = root.split_horizontally(SIZE.0 - PANEL_PX);
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(&c.title, ("sans-serif", 20))
        .margin(14)
        .margin_right(8)
        .x_label_area_size(48)
        .y_label_area_size(72)
        // Room on the right for the order lines' labels.
        .build_cartesian_2d((x0 - 0.03 * (x1 - x0))..(x1 + 0.11 * (x1 - x0)), 0.0..top)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("driver speed (rpm)")
        .y_desc("frequency (Hz)")
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.1))
        .draw()
        .map_err(e)?;
    // Span modes, behind everything; the earlier spans' lines wider, so that
    // a span whose frequencies equal a later one's (a symmetric drive) shows
    // as a rim around it.
    for (k, span) in c.spans.iter().enumerate() {
        let col = SPAN_COLORS[k % SPAN_COLORS.len()];
        let wider = (c.spans.len() - 1 - k).min(2) as u32;
        let lines = span
            .transverse
            .iter()
            .enumerate()
            .map(|(n, m)| (m, dashes(n), 2 + wider))
            .chain(std::iter::once((
                &span.axial,
                Some(AXIAL_DASHES),
                1 + wider,
            )));
        for (points, dash, width) in lines {
            for part in clip_below(points, top) {
                let style = col.stroke_width(width);
                match dash {
                    None => chart.draw_series(LineSeries::new(part, style)),
                    Some((d, g)) => chart.draw_series(DashedLineSeries::new(part, d, g, style)),
                }
                .map_err(e)?;
            }
        }
    }
    // Order lines, labelled at their end or where they leave the top.
    let label_font = |pos: Pos| ("sans-serif", 14).into_font().color(&ORDER_GREY).pos(pos);
    for o in &c.orders {
        let width = if o.meshing { 2 } else { 1 };
        let parts = clip_below(&o.points, top);
        for part in &parts {
            chart
                .draw_series(LineSeries::new(
                    part.iter().copied(),
                    ORDER_GREY.stroke_width(width),
                ))
                .map_err(e)?;
        }
        let Some(&end) = parts.last().and_then(|p| p.last()) else {
            continue;
        };
        // Where it leaves the top: just below the edge, right of the line
        // (the line runs up to the right, so nothing of it is there); at the
        // top speed: clear of the largest marker.
        let (offset, pos) = if end.1 >= top * (1.0 - 1e-9) {
            ((5, 4), Pos::new(HPos::Left, VPos::Top))
        } else {
            ((radius(1.0) + 4, 0), Pos::new(HPos::Left, VPos::Center))
        };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at(end) + Text::new(o.label(), offset, label_font(pos)),
            ))
            .map_err(e)?;
    }
    // Markers, the largest last (on top).
    let largest = c.largest_drawn();
    if largest > 0.0 {
        let mut pts: Vec<(f64, f64, f64)> = c
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite() && p.1 <= top)
            .filter(|p| p.2.is_finite() && p.2 >= SMALLEST_DRAWN * largest)
            .collect();
        pts.sort_by(|a, b| a.2.total_cmp(&b.2));
        chart
            .draw_series(pts.into_iter().map(|(x, y, a)| {
                let r = scale_position(a, largest);
                EmptyElement::at((x, y))
                    + Circle::new((0, 0), radius(r), heat(r).filled())
                    + Circle::new((0, 0), radius(r), BLACK.mix(0.45).stroke_width(1))
            }))
            .map_err(e)?;
    }
    draw_panel(&panel, c, largest).map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

/// `text` cut into lines of at most `width` characters at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(l) if l.chars().count() + 1 + word.chars().count() <= width => {
                l.push(' ');
                l.push_str(word);
            }
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

/// A column of text and samples drawn top-down on the panel.
struct Column<'a, DB: DrawingBackend> {
    panel: &'a DrawingArea<DB, Shift>,
    /// Top of the next line, px.
    y: i32,
}

impl<DB: DrawingBackend> Column<'_, DB> {
    /// One line of text at `x`, px.
    fn text(
        &mut self,
        text: &str,
        font: &TextStyle,
        x: i32,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        self.panel
            .draw(&Text::new(text.to_owned(), (x, self.y), font.clone()))?;
        self.y += 21;
        Ok(())
    }

    /// `text` wrapped at `width` characters; lines after the first at `x + indent`.
    fn wrapped(
        &mut self,
        text: &str,
        width: usize,
        font: &TextStyle,
        x: i32,
        indent: i32,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        for (j, l) in wrap(text, width).into_iter().enumerate() {
            self.text(&l, font, if j == 0 { x } else { x + indent })?;
        }
        Ok(())
    }

    /// A line sample (solid or dashed) left of the next line of text.
    fn sample(
        &self,
        style: ShapeStyle,
        dash: Option<(u32, u32)>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let points = vec![(12, self.y + 8), (44, self.y + 8)];
        match dash {
            None => self.panel.draw(&PathElement::new(points, style)),
            Some((d, g)) => self
                .panel
                .draw(&DashedPathElement::new(points, d, g, style)),
        }
    }
}

/// The panel beside the plot: the amplitude scale, the order lines, the
/// spans' colours and the modes' line styles, and what lies above the axis.
fn draw_panel<DB: DrawingBackend>(
    panel: &DrawingArea<DB, Shift>,
    c: &Campbell,
    largest: f64,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let h = TextStyle::from(("sans-serif", 16).into_font());
    let b = TextStyle::from(("sans-serif", 14).into_font());
    let small = ("sans-serif", 13).into_font().color(&RGBColor(90, 90, 90));
    let mut col = Column { panel, y: 48 };
    col.text("Order amplitude", &h, 10)?;
    col.wrapped(
        &format!("of the {} at each speed", c.response),
        42,
        &small,
        10,
        0,
    )?;
    col.y += 8;
    if largest > 0.0 {
        for i in 0..5 {
            let a = largest * 10f64.powf(-0.5 * f64::from(i));
            let r = scale_position(a, largest);
            let centre = (30, col.y + 8);
            panel.draw(&Circle::new(centre, radius(r), heat(r).filled()))?;
            panel.draw(&Circle::new(
                centre,
                radius(r),
                BLACK.mix(0.45).stroke_width(1),
            ))?;
            col.text(&si(a, &c.unit), &b, 55)?;
            col.y += 6;
        }
        col.text(
            &format!(
                "below {} % of the largest: not drawn",
                100.0 * SMALLEST_DRAWN
            ),
            &small,
            10,
        )?;
    } else {
        col.text("no response to draw", &small, 10)?;
    }
    col.y += 14;
    col.text("Excitation orders", &h, 10)?;
    col.sample(ORDER_GREY.stroke_width(1), None)?;
    col.text("k× : k per driver revolution", &b, 55)?;
    col.sample(ORDER_GREY.stroke_width(2), None)?;
    col.text("meshing: driver's teeth × k", &b, 55)?;
    if !c.spans.is_empty() {
        col.y += 14;
        col.text("Span natural frequencies", &h, 10)?;
        for (k, span) in c.spans.iter().enumerate() {
            col.sample(SPAN_COLORS[k % SPAN_COLORS.len()].stroke_width(4), None)?;
            col.wrapped(&span.label, 34, &b, 55, 10)?;
        }
        col.y += 6;
        let modes = c
            .spans
            .iter()
            .map(|s| s.transverse.len())
            .max()
            .unwrap_or(0);
        for n in 0..modes.min(3) {
            col.sample(BLACK.mix(0.7).stroke_width(2), dashes(n))?;
            let name = if n == 2 && modes > 3 {
                "transverse modes 3 and up".to_owned()
            } else {
                format!("transverse mode {}", n + 1)
            };
            col.text(&name, &b, 55)?;
        }
        col.sample(BLACK.mix(0.7).stroke_width(1), Some(AXIAL_DASHES))?;
        col.text("axial mode 1", &b, 55)?;
    }
    let above = c.above_range();
    if !above.is_empty() {
        col.y += 14;
        col.text(
            &format!("Above {}, not drawn:", si(c.top_hz(), "Hz")),
            &h,
            10,
        )?;
        for item in above {
            col.wrapped(&item, 42, &small, 10, 12)?;
        }
    }
    Ok(())
}

/// Writes `campbell` as `dir/stem.png` and `dir/stem.svg`; returns the
/// paths. A diagram with no finite point is an error.
pub(crate) fn save_campbell(
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
    write_png_svg(campbell, dir, stem)
}

impl Drawing for Campbell {
    fn draw_on<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        draw_campbell(root, self)
    }

    fn size(&self) -> (u32, u32) {
        SIZE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A drive like an engine's timing drive: orders 1, 2 and 4 and the
    /// meshing orders 20 and 40 from 600 to 3000 rpm; one span whose
    /// transverse modes sit at 50, 100 and 150 Hz and whose axial mode at 1.5 kHz.
    fn timing_like() -> Campbell {
        let rpm = [600.0, 1800.0, 3000.0];
        let line = |k: f64| rpm.iter().map(|&r| (r, k * r / 60.0)).collect::<Vec<_>>();
        let flat = |f: f64| rpm.iter().map(|&r| (r, f)).collect::<Vec<_>>();
        Campbell {
            title: "t".into(),
            response: "segment 1 link force".into(),
            unit: "N".into(),
            points: vec![(600.0, 10.0, 1.0)],
            orders: [
                (1.0, false),
                (2.0, false),
                (4.0, false),
                (20.0, true),
                (40.0, true),
            ]
            .into_iter()
            .map(|(order, meshing)| OrderLine {
                order,
                meshing,
                points: line(order),
            })
            .collect(),
            spans: vec![SpanLines {
                label: "span 1".into(),
                transverse: vec![flat(50.0), flat(100.0), flat(150.0)],
                axial: flat(1500.0),
            }],
            max_hz: None,
        }
    }

    #[test]
    fn the_default_range_covers_the_cam_orders_and_span_modes_but_not_the_meshing_band() {
        let c = timing_like();
        let top = c.default_max_hz();
        // Order 4 at 3000 rpm: 4 × 50 = 200 Hz, the highest of what must show.
        assert!(top >= 200.0, "{top}");
        // Within 25 % of it (10 % margin, rounded up), far below the meshing
        // order at the top speed (20 × 50 = 1000 Hz) and the axial mode.
        assert!(top <= 250.0, "{top}");
        let above = c.above_range().join("; ");
        assert!(
            above.contains("20× mesh") && above.contains("40× mesh"),
            "{above}"
        );
        assert!(above.contains("axial modes at 1.50 kHz"), "{above}");
        assert!(!above.contains("4×,"), "{above}");
    }

    #[test]
    fn a_line_that_leaves_the_axis_is_named_with_the_speed_where_it_leaves() {
        // Order 4 from 600 to 3000 rpm is 40–200 Hz; with the axis ending at
        // 100 Hz it is drawn up to 100 × 60 / 4 = 1500 rpm, which the note
        // gives, while the meshing orders (from 200 Hz) lie wholly above.
        let c = Campbell {
            max_hz: Some(100.0),
            ..timing_like()
        };
        let above = c.above_range();
        assert!(
            above.contains(&"order lines 20× mesh, 40× mesh".to_owned()),
            "{above:?}"
        );
        assert!(
            above.contains(&"order lines 4× above 1500 rpm".to_owned()),
            "{above:?}"
        );
    }

    #[test]
    fn an_asked_range_is_kept() {
        let c = Campbell {
            max_hz: Some(4000.0),
            ..timing_like()
        };
        assert_eq!(c.top_hz(), 4000.0);
        assert!(c.above_range().is_empty(), "{:?}", c.above_range());
    }

    #[test]
    fn lines_are_cut_where_they_leave_the_axis() {
        let parts = clip_below(&[(0.0, 0.0), (1.0, 2.0), (2.0, 0.0)], 1.0);
        assert_eq!(
            parts,
            vec![vec![(0.0, 0.0), (0.5, 1.0)], vec![(1.5, 1.0), (2.0, 0.0)]]
        );
        assert!(clip_below(&[(0.0, 2.0), (1.0, 3.0)], 1.0).is_empty());
        assert_eq!(
            clip_below(&[(0.0, 0.0), (1.0, f64::NAN), (2.0, 0.0), (3.0, 0.5)], 1.0),
            vec![vec![(2.0, 0.0), (3.0, 0.5)]]
        );
    }

    #[test]
    fn round_numbers_round_up() {
        assert_eq!(nice_ceil(220.0), 250.0);
        assert_eq!(nice_ceil(1000.0), 1000.0);
        assert_eq!(nice_ceil(1010.0), 1200.0);
        assert_eq!(nice_ceil(0.09), 0.1);
    }

    #[test]
    fn the_colour_scale_runs_from_the_smallest_drawn_to_the_largest() {
        assert!((scale_position(1.0, 1.0) - 1.0).abs() < 1e-12);
        assert!(scale_position(SMALLEST_DRAWN, 1.0).abs() < 1e-12);
        assert_eq!(heat(1.0), RGBColor(215, 25, 28));
        assert_eq!(heat(0.0), RGBColor(190, 210, 235));
        assert!(radius(1.0) > radius(0.0));
    }

    #[test]
    fn a_campbell_diagram_is_written_as_png_and_svg() {
        let dir = tempfile::tempdir().expect("tempdir");
        let paths = save_campbell(&timing_like(), dir.path(), "c").expect("drawn");
        assert_eq!(paths.len(), 2);
        let svg = std::fs::read_to_string(&paths[1]).expect("svg");
        for text in [
            "4×",
            "20× mesh",
            "driver speed (rpm)",
            "frequency (Hz)",
            "1.00 N",
        ] {
            assert!(svg.contains(text), "{text} not in the SVG");
        }
        // The panel beside the plot lies on the canvas: its heading starts
        // 10 px into the panel, whose PANEL_PX reach the canvas's right
        // edge. (Drawn on a narrower canvas than the diagram's own, the
        // panel was cut at the edge: "span 2: rear → ch".)
        let attr = |tag: &str, name: &str| -> f64 {
            let start = tag.find(&format!("{name}=\"")).expect(name) + name.len() + 2;
            let len = tag[start..].find('"').expect("closing quote");
            tag[start..start + len].parse().expect("a number")
        };
        let width = attr(&svg[..svg.find('>').expect("svg tag")], "width");
        let heading = svg.find("Order amplitude").expect("the panel's heading");
        let tag = &svg[svg[..heading].rfind("<text").expect("its tag")..heading];
        let x = attr(tag, "x");
        assert!(
            x - 10.0 + f64::from(PANEL_PX) <= width,
            "the panel from x = {} px, {PANEL_PX} px wide, on a canvas {width} px wide",
            x - 10.0
        );
    }
}
