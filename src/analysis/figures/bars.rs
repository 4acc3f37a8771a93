//! Bar charts: one bar per named item (a duty cycle's operating points), in
//! panels stacked one above the other that share the items, each with its
//! value written over its bar and an optional reference line.
//!
//! It draws what it is given; what the bars mean is the caller's.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FigureError, SIZE, color, register_font};

/// One panel of a [`Bars`] figure.
#[derive(Clone, Debug, PartialEq)]
pub struct BarPanel {
    /// y-axis title, with its unit.
    pub y_label: String,
    /// One value per item (`None`: no bar, "n/a" written).
    pub values: Vec<Option<f64>>,
    /// Decimals of a value written over its bar.
    pub decimals: usize,
    /// Written after each value (" %").
    pub suffix: String,
    /// A dashed horizontal reference line (e.g. a safety factor of 1; say
    /// what it is in `y_label`).
    pub reference: Option<f64>,
    /// Colour index into the palette.
    pub color: usize,
}

/// A figure of bar panels over the same items.
#[derive(Clone, Debug, PartialEq)]
pub struct Bars {
    /// Title.
    pub title: String,
    /// The items' names, left to right.
    pub items: Vec<String>,
    /// The panels, top to bottom.
    pub panels: Vec<BarPanel>,
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    items: &[String],
    panel: &BarPanel,
    caption: Option<&str>,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let n = items.len().max(1);
    let largest = panel
        .values
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .chain(panel.reference)
        .fold(0.0, f64::max);
    let top = if largest > 0.0 { 1.2 * largest } else { 1.0 };
    let mut builder = ChartBuilder::on(area);
    if let Some(c) = caption {
        builder.caption(c, ("sans-serif", 22));
    }
    let mut chart = builder
        .margin(14)
        .margin_right(30)
        .x_label_area_size(36)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.5..(n as f64 - 0.5), 0.0..top)
        .map_err(e)?;
    let name = |v: &f64| {
        let i = v.round();
        if (v - i).abs() < 1e-6 && i >= 0.0 {
            items.get(i as usize).cloned().unwrap_or_default()
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .y_desc(&panel.y_label)
        .x_labels(n)
        .x_label_formatter(&name)
        .y_label_formatter(&|v| super::tick(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .disable_x_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.12))
        .draw()
        .map_err(e)?;
    let c = color(panel.color);
    for (i, v) in panel.values.iter().enumerate() {
        let x = i as f64;
        let text = match v {
            Some(v) if v.is_finite() => {
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(x - 0.3, 0.0), (x + 0.3, *v)],
                        c.mix(0.8).filled(),
                    )))
                    .map_err(e)?;
                value_label(*v, panel.decimals, &panel.suffix)
            }
            _ => "n/a".to_owned(),
        };
        let y = v.filter(|v| v.is_finite()).unwrap_or(0.0);
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((x, y)) + Text::new(text, (-18, -20), ("sans-serif", 14)),
            ))
            .map_err(e)?;
    }
    if let Some(r) = panel.reference {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(-0.5, r), (n as f64 - 0.5, r)],
                8,
                5,
                BLACK.stroke_width(1),
            ))
            .map_err(e)?;
    }
    Ok(())
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, bars: &Bars) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((bars.panels.len().max(1), 1));
    for (k, (area, panel)) in areas.iter().zip(&bars.panels).enumerate() {
        let caption = (k == 0).then_some(bars.title.as_str());
        draw_panel(area, &bars.items, panel, caption)?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Writes `bars` as `dir/stem.png` and `dir/stem.svg`; returns the paths.
///
/// # Errors
/// A figure without items, or one that cannot be drawn or written.
pub fn save_bars(bars: &Bars, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, FigureError> {
    if bars.items.is_empty() || bars.panels.is_empty() {
        return Err(FigureError::Empty(stem.to_owned()));
    }
    register_font();
    let height = SIZE.1 / 2 * u32::try_from(bars.panels.len()).unwrap_or(1).max(2);
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let fail = |message: String| FigureError::Draw {
        stem: stem.to_owned(),
        message,
    };
    draw(
        BitMapBackend::new(&png, (SIZE.0, height)).into_drawing_area(),
        bars,
    )
    .map_err(fail)?;
    draw(
        SVGBackend::new(&svg, (SIZE.0, height)).into_drawing_area(),
        bars,
    )
    .map_err(fail)?;
    Ok(vec![png, svg])
}

/// The text written over a bar: `v` with `decimals` decimals and `suffix`,
/// or with as many more as show a positive value's two significant digits
/// (0.006 is "0.0060", not "0.0", which reads as none); beyond twelve
/// decimals in scientific notation.
pub(crate) fn value_label(v: f64, decimals: usize, suffix: &str) -> String {
    let needed = if v > 0.0 && v.is_finite() {
        // Two significant digits: the first is at 10^floor(log10 v).
        (1.0 - v.log10().floor()).max(0.0) as usize
    } else {
        0
    };
    if needed > 12 {
        format!("{v:.1e}{suffix}")
    } else {
        let d = decimals.max(needed);
        format!("{v:.d$}{suffix}")
    }
}

#[cfg(test)]
mod tests {
    use super::value_label;

    /// A damage share of 0.006 % written over its bar must not read "0.0 %"
    /// (no damage) beside another point's 99.9 %: a positive value keeps two
    /// significant digits however many decimals the panel asks for; zero
    /// stays zero and a large value keeps the panel's decimals.
    #[test]
    fn a_small_positive_value_is_not_written_as_zero() {
        assert_eq!(value_label(0.005_958, 1, " %"), "0.0060 %");
        assert_eq!(value_label(0.068_87, 1, " %"), "0.069 %");
        assert_eq!(value_label(99.925, 1, " %"), "99.9 %");
        assert_eq!(value_label(0.0, 1, " %"), "0.0 %");
        assert_eq!(value_label(0.85, 2, ""), "0.85");
        assert_eq!(value_label(3.0e-9, 1, ""), "0.0000000030");
        assert_eq!(value_label(2.0e-20, 1, " %"), "2.0e-20 %");
    }
}
