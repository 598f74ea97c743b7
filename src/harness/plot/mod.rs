//! PNG charts for the benchmark commands (`meadow bench`, `meadow overhead`, `meadow timing`).
//!
//! Three chart kinds, each a single call that validates its input, renders with `plotters` into an
//! in-memory RGB buffer and writes the PNG atomically (temp file beside the target, then rename,
//! via [`crate::app::write_png`]):
//! - [`line_panels`]: a grid of line + marker panels (e.g. frame time against blade count),
//! - [`histogram`]: a distribution with its median, p95 and p99 marked,
//! - [`bars`]: horizontal grouped bars (e.g. ns per draw for each draw-submission strategy), and
//!   [`bar_panels`], a grid of them.
//!
//! Text uses the embedded DejaVu Sans (`assets/fonts`), so nothing depends on system fonts. Bad
//! data (empty, NaN/∞, non-positive values on a log axis, zero size) is [`Error::BadInput`] and
//! writes no file; degenerate ranges (one point, all-equal values) are padded, never a panic.

mod axis;
mod bars;
mod canvas;
mod check;
mod layout;

use std::ops::Range;
use std::path::Path;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

pub use bars::{bar_panels, bars, BarPanel};

use crate::error::{Error, Result};
use axis::{axis_range, label_count, log_axis, normalize, tick_formatter, value_text};
use canvas::{font, Canvas};
use check::{check_panel, check_size, check_values};
use layout::{chart_builder, emptiest_corner, legend, mesh, plot_error, stroke, swatch, text_scale, tick_width};

/// One named line of a [`Panel`]: `(x, y)` points, connected in the given order.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Data points, drawn as markers joined by a line.
    pub points: Vec<(f64, f64)>,
}

/// How an axis maps values to pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Evenly spaced values.
    Linear,
    /// Base-10 logarithmic; every value on the axis must be positive.
    Log,
}

/// One chart of a [`line_panels`] grid.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Caption above the panel.
    pub title: String,
    /// X axis description, with its unit (e.g. `"blades"`).
    pub x_label: String,
    /// Y axis description, with its unit (e.g. `"GPU time (ms)"`).
    pub y_label: String,
    /// X axis scale.
    pub x_scale: Scale,
    /// Y axis scale.
    pub y_scale: Scale,
    /// The lines, each in its own palette colour and marker shape.
    pub series: Vec<Series>,
}

/// Series colours (Tableau 10): distinct from each other and from the grey grid.
const PALETTE: [RGBColor; 10] = [
    RGBColor(0x4e, 0x79, 0xa7),
    RGBColor(0xf2, 0x8e, 0x2b),
    RGBColor(0xe1, 0x57, 0x59),
    RGBColor(0x59, 0xa1, 0x4f),
    RGBColor(0xb0, 0x7a, 0xa1),
    RGBColor(0x76, 0xb7, 0xb2),
    RGBColor(0xed, 0xc9, 0x48),
    RGBColor(0x9c, 0x75, 0x5f),
    RGBColor(0xff, 0x9d, 0xa7),
    RGBColor(0xba, 0xb0, 0xac),
];
const INK: RGBColor = RGBColor(0x22, 0x22, 0x22);
/// Font family name the embedded font is registered under (plotters' default family).
const FONT: &str = "sans-serif";
/// Smallest panel that still fits its labels, and the largest image side accepted.
const MIN_PANEL: (u32, u32) = (240, 180);
const MAX_SIDE: u32 = 8192;
/// Values beyond this magnitude break plotters' tick arithmetic; they are rejected as bad input.
const MAX_MAGNITUDE: f64 = 1e100;

/// A grid of line + marker panels, `columns` wide, one legend per panel (in its emptiest corner),
/// written to `path` (PNG) of `size` pixels with `title` above the grid.
pub fn line_panels(path: &Path, size: (u32, u32), title: &str, panels: &[Panel], columns: usize) -> Result<()> {
    if panels.is_empty() {
        return Err(Error::bad_input("plot: no panels to draw"));
    }
    if columns == 0 {
        return Err(Error::bad_input("plot: columns must be at least 1"));
    }
    let columns = columns.min(panels.len());
    let rows = panels.len().div_ceil(columns);
    check_size(size, (rows, columns))?;
    for panel in panels {
        check_panel(panel)?;
    }
    render(path, size, title, (rows, columns), |area| {
        for (panel, cell) in panels.iter().zip(area.split_evenly((rows, columns))) {
            let x = axis_range(panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)), panel.x_scale);
            let y = axis_range(panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)), panel.y_scale);
            match (panel.x_scale, panel.y_scale) {
                (Scale::Linear, Scale::Linear) => draw_panel(&cell, panel, x.clone(), y.clone(), x, y),
                (Scale::Linear, Scale::Log) => draw_panel(&cell, panel, x.clone(), log_axis(&y), x, y),
                (Scale::Log, Scale::Linear) => draw_panel(&cell, panel, log_axis(&x), y.clone(), x, y),
                (Scale::Log, Scale::Log) => draw_panel(&cell, panel, log_axis(&x), log_axis(&y), x, y),
            }?;
        }
        Ok(())
    })
}

/// A histogram of `values` in `bins` equal-width bins over their range, with the median, p95 and
/// p99 marked as vertical lines (legend entries give their values); `x_label` names the quantity
/// and unit. The title gets the sample count appended.
pub fn histogram(path: &Path, size: (u32, u32), title: &str, x_label: &str, values: &[f64], bins: usize) -> Result<()> {
    if values.is_empty() {
        return Err(Error::bad_input("histogram: no values to draw"));
    }
    if !(1..=10_000).contains(&bins) {
        return Err(Error::bad_input(format!("histogram: bins must be in 1..=10000, got {bins}")));
    }
    check_values("histogram", values.iter().copied(), Scale::Linear)?;
    check_size(size, (1, 1))?;
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let (lo, hi) = (sorted[0], sorted[sorted.len() - 1]);
    let (span, width) = if hi > lo {
        (lo..hi, (hi - lo) / bins as f64)
    } else {
        // All values equal: a padded span, shifted so the value sits mid-bin.
        let padded = axis_range([lo, hi].into_iter(), Scale::Linear);
        let width = (padded.end - padded.start) / bins as f64;
        let start = lo - width * ((bins / 2) as f64 + 0.5);
        (start..start + width * bins as f64, width)
    };
    let mut counts = vec![0u32; bins];
    for v in &sorted {
        let bin = ((v - span.start) / width).floor().clamp(0.0, bins as f64 - 1.0) as usize;
        counts[bin] += 1;
    }
    let top = f64::from(counts.iter().copied().max().unwrap_or(1)) * 1.15;
    let x = axis_range([span.start, span.end].into_iter(), Scale::Linear);
    let y = 0.0..top;
    let marks = [("median", 0.5, INK), ("p95", 0.95, PALETTE[1]), ("p99", 0.99, PALETTE[2])];
    let title = format!("{title} (n = {})", values.len());
    render(path, size, &title, (1, 1), |area| {
        let s = text_scale(area);
        let mut chart = chart_builder(area, "", s, tick_width(&y, Scale::Linear, s))
            .build_cartesian_2d(x.clone(), y.clone())
            .map_err(plot_error)?;
        let (fmt_x, fmt_y) = (tick_formatter(&x, Scale::Linear), tick_formatter(&y, Scale::Linear));
        let (w, h) = chart.plotting_area().dim_in_pixel();
        let labels = (label_count(w, 90), label_count(h, 45));
        mesh(&mut chart, s, x_label, "count", &fmt_x, &fmt_y)
            .x_labels(labels.0)
            .y_labels(labels.1)
            .draw()
            .map_err(plot_error)?;
        let (fill, edge) = (PALETTE[0].mix(0.75).filled(), PALETTE[0].stroke_width(1));
        let bar = |i: usize, c: u32| {
            [(span.start + width * i as f64, 0.0), (span.start + width * (i + 1) as f64, f64::from(c))]
        };
        let filled = counts.iter().enumerate().filter(|(_, &c)| c > 0);
        chart.draw_series(filled.clone().map(|(i, &c)| Rectangle::new(bar(i, c), fill))).map_err(plot_error)?;
        chart.draw_series(filled.map(|(i, &c)| Rectangle::new(bar(i, c), edge))).map_err(plot_error)?;
        let mut occupied: Vec<(f64, f64)> = Vec::new();
        for (i, &c) in counts.iter().enumerate() {
            let xc = normalize(span.start + width * (i as f64 + 0.5), &x, Scale::Linear);
            occupied.extend((0..=4).map(|k| (xc, f64::from(c) * f64::from(k) / 4.0 / top)));
        }
        let (mut labels, swatch) = (Vec::new(), swatch(s));
        for (name, q, colour) in marks {
            let v = quantile(&sorted, q);
            let xv = normalize(v, &x, Scale::Linear);
            occupied.extend((0..=8).map(|k| (xv, f64::from(k) / 8.0)));
            let style = colour.stroke_width(stroke(s, 2.0));
            let label = format!("{name} {}", value_text(v, 1e4));
            labels.push(label.clone());
            chart
                .draw_series(LineSeries::new([(v, 0.0), (v, top)], style))
                .map_err(plot_error)?
                .label(label)
                .legend(move |(lx, ly)| PathElement::new([(lx, ly), (lx + swatch, ly)], style));
        }
        let corner = emptiest_corner(&occupied, (w, h), s, &labels);
        legend(&mut chart, corner, s)
    })
}

/// Render into an RGB buffer (white background, optional `title` above) and write it as PNG.
/// The title is sized relative to the cells of a `grid` (rows, columns) of charts.
fn render(
    path: &Path,
    size: (u32, u32),
    title: &str,
    grid: (usize, usize),
    draw: impl FnOnce(&DrawingArea<Canvas, Shift>) -> Result<()>,
) -> Result<()> {
    let font = font()?;
    let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = Canvas { inner: BitMapBackend::with_buffer(&mut rgb, size), font }.into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let area = if title.is_empty() {
            root.clone()
        } else {
            let cell = (size.0 / grid.1 as u32).min(size.1 / grid.0 as u32);
            let px = (20.0 * (f64::from(cell) / 380.0).clamp(0.75, 2.5)).max(f64::from(size.0.min(size.1)) / 30.0);
            root.margin(px * 0.4, 0.0, 0.0, 0.0)
                .titled(title, (FONT, px).into_font().color(&INK))
                .map_err(plot_error)?
        };
        draw(&area)?;
        root.present().map_err(plot_error)?;
    }
    let rgba: Vec<u8> = rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    crate::app::write_png(path, size, &rgba)
}

/// Draw one [`Panel`] into `cell` with the given axis specs; `xr`/`yr` are their value ranges.
fn draw_panel<X, Y>(
    cell: &DrawingArea<Canvas, Shift>,
    panel: &Panel,
    x: X,
    y: Y,
    xr: Range<f64>,
    yr: Range<f64>,
) -> Result<()>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let s = text_scale(cell);
    let mut chart = chart_builder(cell, &panel.title, s, tick_width(&yr, panel.y_scale, s))
        .build_cartesian_2d(x, y)
        .map_err(plot_error)?;
    let (fmt_x, fmt_y) = (tick_formatter(&xr, panel.x_scale), tick_formatter(&yr, panel.y_scale));
    let (w, h) = chart.plotting_area().dim_in_pixel();
    let labels = (label_count(w, 90), label_count(h, 45));
    mesh(&mut chart, s, &panel.x_label, &panel.y_label, &fmt_x, &fmt_y)
        .x_labels(labels.0)
        .y_labels(labels.1)
        .draw()
        .map_err(plot_error)?;
    let (r, sw) = ((3.5 * s).round() as i32, swatch(s));
    let mut occupied = Vec::new();
    for (i, series) in panel.series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let (line, fill) = (colour.stroke_width(stroke(s, 2.0)), colour.filled());
        let pts = &series.points;
        chart.draw_series(LineSeries::new(pts.iter().copied(), line)).map_err(plot_error)?;
        // Marker shapes cycle with the palette so series stay distinguishable without colour.
        macro_rules! markers {
            ($make:expr) => {{
                let make = $make;
                chart
                    .draw_series(pts.iter().map(|&p| EmptyElement::at(p) + make((0, 0))))
                    .map_err(plot_error)?
                    .label(series.label.clone())
                    .legend(move |(lx, ly)| {
                        EmptyElement::at((lx, ly)) + PathElement::new([(0, 0), (sw, 0)], line) + make((sw / 2, 0))
                    });
            }};
        }
        match i % 3 {
            0 => markers!(move |c| Circle::new(c, r, fill)),
            1 => markers!(move |(cx, cy): (i32, i32)| Rectangle::new(
                [(cx - r + 1, cy - r + 1), (cx + r - 1, cy + r - 1)],
                fill
            )),
            _ => markers!(move |c| TriangleMarker::new(c, r + 1, fill)),
        }
        let norm: Vec<(f64, f64)> = pts
            .iter()
            .map(|&(px, py)| (normalize(px, &xr, panel.x_scale), normalize(py, &yr, panel.y_scale)))
            .collect();
        occupied.extend(norm.iter().copied());
        for w in norm.windows(2) {
            occupied.extend((1..8).map(|k| {
                let t = f64::from(k) / 8.0;
                (w[0].0 + (w[1].0 - w[0].0) * t, w[0].1 + (w[1].1 - w[0].1) * t)
            }));
        }
    }
    let labels: Vec<String> = panel.series.iter().map(|s| s.label.clone()).collect();
    let corner = emptiest_corner(&occupied, (w, h), s, &labels);
    legend(&mut chart, corner, s)
}

/// Quantile `q` (0..=1) of sorted values, linearly interpolated between order statistics.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let pos = q * (sorted.len() - 1) as f64;
    let (i, frac) = (pos.floor() as usize, pos.fract());
    let next = sorted[(i + 1).min(sorted.len() - 1)];
    sorted[i] + (next - sorted[i]) * frac
}
