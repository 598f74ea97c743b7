//! Chart layout shared by every chart kind: text scale, strokes, label areas, the mesh and the
//! legend (placed in the emptiest corner).

use std::ops::Range;

use plotters::chart::MeshStyle;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{log_ticks, tick_formatter};
use super::canvas::text_width;
use super::{Scale, FONT, INK};
use crate::error::{Error, Result};

/// The legend corner covering the fewest `occupied` points (normalised 0..1, y up), for a legend
/// of `labels` in a plot of `plot_px` pixels at scale `s`.
pub(super) fn emptiest_corner(
    occupied: &[(f64, f64)],
    plot_px: (u32, u32),
    s: f64,
    labels: &[String],
) -> SeriesLabelPosition {
    let font = 13.0 * s;
    let legend_w = text_width(labels.iter().map(String::as_str), font) + f64::from(swatch(s)) + 30.0 * s;
    let legend_h = labels.len() as f64 * font * 1.5 + 20.0 * s;
    let w = (legend_w / f64::from(plot_px.0.max(1))).min(1.0);
    let h = (legend_h / f64::from(plot_px.1.max(1))).min(1.0);
    let corners = [
        (SeriesLabelPosition::UpperLeft, 0.0, 1.0 - h),
        (SeriesLabelPosition::UpperRight, 1.0 - w, 1.0 - h),
        (SeriesLabelPosition::LowerRight, 1.0 - w, 0.0),
        (SeriesLabelPosition::LowerLeft, 0.0, 0.0),
    ];
    let covered = |x0: f64, y0: f64| {
        occupied
            .iter()
            .filter(|&&(x, y)| x >= x0 - 0.02 && x <= x0 + w + 0.02 && y >= y0 - 0.02 && y <= y0 + h + 0.02)
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperLeft);
    for (position, x0, y0) in corners {
        let n = covered(x0, y0);
        if n < best.0 {
            best = (n, position);
        }
    }
    best.1
}

/// Text and stroke scale for an area: 1.0 at a 380-pixel short side.
pub(super) fn text_scale<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> f64 {
    let (w, h) = area.dim_in_pixel();
    (f64::from(w.min(h)) / 380.0).clamp(0.75, 2.5)
}

/// Width of a legend swatch (line, bar) at scale `s`.
pub(super) fn swatch(s: f64) -> i32 {
    (22.0 * s).round() as i32
}

/// A stroke width of `w` pixels at scale `s`, at least one pixel.
pub(super) fn stroke(s: f64, w: f64) -> u32 {
    (w * s).round().max(1.0) as u32
}

/// Chart layout shared by all kinds: caption, margins and label areas sized for scale `s`.
/// `y_ticks_px` is the width of the longest y tick label, which sets the width of the y label area.
pub(super) fn chart_builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    s: f64,
    y_ticks_px: f64,
) -> ChartBuilder<'a, 'b, DB> {
    let mut builder = ChartBuilder::on(area);
    if !caption.is_empty() {
        builder.caption(caption, (FONT, 15.0 * s).into_font().color(&INK));
    }
    let y_area = y_ticks_px + 26.0 * s;
    builder.margin(8.0 * s).margin_right(24.0 * s).x_label_area_size(44.0 * s).y_label_area_size(y_area);
    builder
}

/// Pixel width of the longest tick label of an axis at scale `s` (estimated from the ends of a
/// linear axis).
pub(super) fn tick_width(range: &Range<f64>, scale: Scale, s: f64) -> f64 {
    let values = match scale {
        Scale::Linear => vec![range.start, range.end, 0.5 * (range.start + range.end)],
        Scale::Log => log_ticks(range).0,
    };
    let format = tick_formatter(range, scale);
    let labels: Vec<String> = values.iter().map(format).collect();
    text_width(labels.iter().map(String::as_str), 12.0 * s)
}

/// Grid, axes, tick labels and axis descriptions in the shared style.
pub(super) fn mesh<'a, 'b, DB, X, Y>(
    chart: &'b mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    s: f64,
    x_desc: &str,
    y_desc: &str,
    fmt_x: &'b dyn Fn(&f64) -> String,
    fmt_y: &'b dyn Fn(&f64) -> String,
) -> MeshStyle<'a, 'b, X, Y, DB>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .label_style((FONT, 12.0 * s).into_font().color(&INK))
        .axis_desc_style((FONT, 14.0 * s).into_font().color(&INK))
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(BLACK.mix(0.04))
        .axis_style(INK.mix(0.8))
        .max_light_lines(1)
        .x_label_formatter(fmt_x)
        .y_label_formatter(fmt_y);
    mesh
}

/// Draw the series legend at `corner` on a translucent white box.
pub(super) fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    corner: SeriesLabelPosition,
    s: f64,
) -> Result<()> {
    chart
        .configure_series_labels()
        .position(corner)
        .margin(10.0 * s)
        .legend_area_size(f64::from(swatch(s)) + 8.0 * s)
        .label_font((FONT, 13.0 * s).into_font().color(&INK))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .draw()
        .map_err(plot_error)
}

/// A plotters drawing failure as a runtime error.
pub(super) fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Plot(format!("drawing failed: {e}"))
}
