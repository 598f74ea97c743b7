//! Horizontal grouped bars: one chart ([`bars`]) or a grid of them ([`bar_panels`]).

use std::ops::Range;
use std::path::Path;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{label_count, normalize, tick_formatter, value_text};
use super::canvas::{text_width, Canvas};
use super::check::{check_bars, check_size};
use super::layout::{chart_builder, emptiest_corner, legend, mesh, plot_error, swatch, text_scale};
use super::{render, Scale, FONT, INK, PALETTE};
use crate::error::{Error, Result};

/// Horizontal grouped bars: one row per category (first at the top), one bar per group within it
/// (e.g. category = draw-submission strategy, group = blade count, value = ns per draw). Each bar
/// is labelled with its value; `value_label` names the value axis and its unit. Every group must
/// hold one value per category. A single group with an empty name gets no legend.
pub fn bars(
    path: &Path,
    size: (u32, u32),
    title: &str,
    value_label: &str,
    categories: &[String],
    groups: &[(String, Vec<f64>)],
) -> Result<()> {
    check_bars(categories, groups)?;
    check_size(size, (1, 1))?;
    render(path, size, title, (1, 1), |area| draw_bars(area, "", value_label, categories, groups))
}

/// One chart of a [`bar_panels`] grid: the arguments of [`bars`] with a caption.
#[derive(Clone, Debug)]
pub struct BarPanel {
    /// Caption above the panel.
    pub title: String,
    /// Value axis description, with its unit.
    pub value_label: String,
    /// One row of bars per category, first at the top.
    pub categories: Vec<String>,
    /// One bar per group in every category: (legend name, a value per category).
    pub groups: Vec<(String, Vec<f64>)>,
}

/// A grid of [`bars`] charts, `columns` wide, written to `path` (PNG) of `size` pixels with
/// `title` above the grid.
pub fn bar_panels(path: &Path, size: (u32, u32), title: &str, panels: &[BarPanel], columns: usize) -> Result<()> {
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
        check_bars(&panel.categories, &panel.groups)?;
    }
    render(path, size, title, (rows, columns), |area| {
        for (p, cell) in panels.iter().zip(area.split_evenly((rows, columns))) {
            draw_bars(&cell, &p.title, &p.value_label, &p.categories, &p.groups)?;
        }
        Ok(())
    })
}

/// Draw checked bars into `area`, with `caption` above them unless it is empty.
fn draw_bars(
    area: &DrawingArea<Canvas, Shift>,
    caption: &str,
    value_label: &str,
    categories: &[String],
    groups: &[(String, Vec<f64>)],
) -> Result<()> {
    let (n, g) = (categories.len(), groups.len());
    let x = bar_range(groups);
    let y = Categories(n).range();
    let band = 0.8 / g as f64;
    let show_legend = g > 1 || !groups[0].0.is_empty();
    let s = text_scale(area);
    let mut builder = chart_builder(area, caption, s, 0.0);
    // The category labels sit beside the bars, so their area fits the longest name.
    let names = text_width(categories.iter().map(String::as_str), 12.0 * s);
    builder.set_label_area_size(LabelAreaPosition::Left, names + 16.0 * s);
    let mut chart = builder.build_cartesian_2d(x.clone(), Categories(n)).map_err(plot_error)?;
    let fmt_x = tick_formatter(&x, Scale::Linear);
    let fmt_y = |v: &f64| categories.get(Categories::index(n, *v)).cloned().unwrap_or_default();
    let (w, h) = chart.plotting_area().dim_in_pixel();
    let x_labels = label_count(w, 90);
    mesh(&mut chart, s, value_label, "", &fmt_x, &fmt_y)
        .disable_y_mesh()
        .x_labels(x_labels)
        .y_labels(n)
        .draw()
        .map_err(plot_error)?;
    let bar_px = f64::from(h) / n as f64 * band;
    let text = TextStyle::from((FONT, (11.0 * s).min(bar_px * 0.85).max(8.0)).into_font()).color(&INK);
    let swatch = swatch(s);
    let mut occupied = Vec::new();
    for (j, (name, values)) in groups.iter().enumerate() {
        let colour = PALETTE[j % PALETTE.len()];
        let rows: Vec<(f64, f64)> =
            values.iter().enumerate().map(|(i, &v)| (v, (n - 1 - i) as f64 + 0.4 - band * (j as f64 + 0.5))).collect();
        occupied.extend(bar_footprint(&rows, band, &x, &y));
        let series = chart
            .draw_series(
                rows.iter()
                    .map(|&(v, c)| Rectangle::new([(0.0, c - band * 0.42), (v, c + band * 0.42)], colour.filled())),
            )
            .map_err(plot_error)?;
        if show_legend {
            series.label(name.clone()).legend(move |(lx, ly)| {
                Rectangle::new([(lx, ly - swatch / 4), (lx + swatch, ly + swatch / 4)], colour.filled())
            });
        }
        chart
            .draw_series(rows.iter().map(|&(v, c)| {
                let (dx, h) = if v < 0.0 { (-4, HPos::Right) } else { (4, HPos::Left) };
                EmptyElement::at((v, c)) + Text::new(value_text(v, 1e4), (dx, 0), text.pos(Pos::new(h, VPos::Center)))
            }))
            .map_err(plot_error)?;
    }
    if show_legend {
        let names: Vec<String> = groups.iter().map(|(name, _)| name.clone()).collect();
        let corner = emptiest_corner(&occupied, (w, h), s, &names);
        legend(&mut chart, corner, s)?;
    }
    Ok(())
}

/// The value axis of [`bars`]: zero stays on it, and the far side of each sign gets room for
/// the value labels.
fn bar_range(groups: &[(String, Vec<f64>)]) -> Range<f64> {
    let (min, max) =
        groups.iter().flat_map(|(_, v)| v.iter().copied()).fold((0.0f64, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let room = 0.18 * (max - min);
    if max > min {
        min - if min < 0.0 { room } else { 0.0 }..max + if max > 0.0 { room } else { 0.0 }
    } else {
        0.0..1.0
    }
}

/// The points (normalised 0..1) covered by bars `(value, centre)` of height `band` and by their
/// value labels, for placing the legend of [`bars`].
fn bar_footprint(rows: &[(f64, f64)], band: f64, x: &Range<f64>, y: &Range<f64>) -> Vec<(f64, f64)> {
    let mut occupied = Vec::new();
    for &(v, c) in rows {
        let (y0, y1) = (normalize(c - band * 0.5, y, Scale::Linear), normalize(c + band * 0.5, y, Scale::Linear));
        occupied
            .extend((0..=8).flat_map(|k| [y0, y1].map(|yy| (normalize(v * f64::from(k) / 8.0, x, Scale::Linear), yy))));
        let end = normalize(v, x, Scale::Linear) + (if v < 0.0 { -0.08 } else { 0.08 });
        occupied.push((end, 0.5 * (y0 + y1)));
    }
    occupied
}

/// The category axis of [`bars`]: category `i` of `n` sits at value `n - 1 - i` (first on top),
/// with one key point (label) per category.
struct Categories(usize);

impl Categories {
    /// Category index of an axis value.
    fn index(n: usize, v: f64) -> usize {
        (n as f64 - 1.0 - v).round().max(0.0) as usize
    }
}

impl Ranged for Categories {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let t = (value + 0.5) / self.0 as f64;
        limit.0 + (f64::from(limit.1 - limit.0) * t).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let step = self.0.div_ceil(hint.max_num_points().max(1)).max(1);
        (0..self.0).step_by(step).map(|i| i as f64).collect()
    }

    fn range(&self) -> Range<f64> {
        -0.5..self.0 as f64 - 0.5
    }
}
