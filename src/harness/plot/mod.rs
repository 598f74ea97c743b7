//! PNG charts for the benchmark commands (`meadow bench`, `meadow overhead`, `meadow timing`).
//!
//! Three chart kinds, each a single call that validates its input, renders with `plotters` into an
//! in-memory RGB buffer and writes the PNG atomically (temp file beside the target, then rename,
//! via [`crate::app::write_png`]):
//! - [`line_panels`]: a grid of line + marker panels (e.g. frame time against blade count),
//! - [`histogram`]: a distribution with its median, p95 and p99 marked,
//! - [`bars`]: horizontal grouped bars (e.g. ns per draw for each draw-submission strategy).
//!
//! Text uses the embedded DejaVu Sans (`assets/fonts`), so nothing depends on system fonts. Bad
//! data (empty, NaN/∞, non-positive values on a log axis, zero size) is [`Error::BadInput`] and
//! writes no file; degenerate ranges (one point, all-equal values) are padded, never a panic.

use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::chart::MeshStyle;
use plotters::coord::combinators::WithKeyPoints;
use plotters::coord::ranged1d::{AsRangedCoord, DefaultFormatting, KeyPointHint, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::register_font;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendTextStyle, DrawingErrorKind};

use crate::error::{Error, Result};

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
    if categories.is_empty() || groups.is_empty() {
        return Err(Error::bad_input("bars: need at least one category and one group"));
    }
    for (name, values) in groups {
        if values.len() != categories.len() {
            let (got, want) = (values.len(), categories.len());
            return Err(Error::bad_input(format!("bars: group `{name}` has {got} values for {want} categories")));
        }
        check_values(&format!("bars: group `{name}`"), values.iter().copied(), Scale::Linear)?;
    }
    check_size(size, (1, 1))?;
    let (n, g) = (categories.len(), groups.len());
    let (min, max) =
        groups.iter().flat_map(|(_, v)| v.iter().copied()).fold((0.0f64, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    // Zero stays on the axis; the far side of each sign gets room for the value labels.
    let room = 0.18 * (max - min);
    let x = if max > min {
        min - if min < 0.0 { room } else { 0.0 }..max + if max > 0.0 { room } else { 0.0 }
    } else {
        0.0..1.0
    };
    let y = Categories(n).range();
    let band = 0.8 / g as f64;
    let show_legend = g > 1 || !groups[0].0.is_empty();
    render(path, size, title, (1, 1), |area| {
        let s = text_scale(area);
        let mut builder = chart_builder(area, "", s, 0.0);
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
            let rows: Vec<(f64, f64)> = values
                .iter()
                .enumerate()
                .map(|(i, &v)| (v, (n - 1 - i) as f64 + 0.4 - band * (j as f64 + 0.5)))
                .collect();
            for &(v, c) in &rows {
                let (y0, y1) =
                    (normalize(c - band * 0.5, &y, Scale::Linear), normalize(c + band * 0.5, &y, Scale::Linear));
                occupied.extend(
                    (0..=8).flat_map(|k| [y0, y1].map(|yy| (normalize(v * f64::from(k) / 8.0, &x, Scale::Linear), yy))),
                );
                let end = normalize(v, &x, Scale::Linear) + (if v < 0.0 { -0.08 } else { 0.08 });
                occupied.push((end, 0.5 * (y0 + y1)));
            }
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
                    EmptyElement::at((v, c))
                        + Text::new(value_text(v, 1e4), (dx, 0), text.pos(Pos::new(h, VPos::Center)))
                }))
                .map_err(plot_error)?;
        }
        if show_legend {
            let names: Vec<String> = groups.iter().map(|(name, _)| name.clone()).collect();
            let corner = emptiest_corner(&occupied, (w, h), s, &names);
            legend(&mut chart, corner, s)?;
        }
        Ok(())
    })
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

/// The embedded DejaVu Sans, parsed once and registered with plotters as its `sans-serif` family
/// (so plotters' own text metrics agree with [`Canvas`], which does the drawing).
fn font() -> Result<&'static FontRef<'static>> {
    static FONT_REF: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    static DEJAVU: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
    FONT_REF
        .get_or_init(|| {
            register_font(FONT, FontStyle::Normal, DEJAVU).ok()?;
            FontRef::try_from_slice(DEJAVU).ok()
        })
        .as_ref()
        .ok_or_else(|| Error::Plot("the embedded DejaVu Sans font failed to load".into()))
}

/// A [`BitMapBackend`] whose text is laid out and rasterised here with `ab_glyph`: plotters
/// 0.3.7's own `ab_glyph` text path drops glyph side bearings and misplaces the baseline, which
/// gives uneven letter spacing and clips top-anchored text.
struct Canvas<'a> {
    inner: BitMapBackend<'a>,
    font: &'static FontRef<'static>,
}

type CanvasResult<T = ()> =
    std::result::Result<T, DrawingErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

impl DrawingBackend for Canvas<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> CanvasResult {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> CanvasResult {
        self.inner.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> CanvasResult {
        self.inner.draw_pixel(point, color)
    }
    fn draw_line<S: plotters_backend::BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> CanvasResult {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: plotters_backend::BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        style: &S,
        fill: bool,
    ) -> CanvasResult {
        self.inner.draw_rect(a, b, style, fill)
    }
    fn blit_bitmap(&mut self, pos: BackendCoord, size: (u32, u32), src: &[u8]) -> CanvasResult {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<T: BackendTextStyle>(&self, text: &str, style: &T) -> CanvasResult<(u32, u32)> {
        let (w, h) = measure(self.font, text, style.size());
        Ok((w.ceil() as u32, h.ceil() as u32))
    }

    fn draw_text<T: BackendTextStyle>(&mut self, text: &str, style: &T, pos: BackendCoord) -> CanvasResult {
        let (colour, transform, anchor) = (style.color(), style.transform(), style.anchor());
        let (w, h) = measure(self.font, text, style.size());
        let font = self.font.as_scaled(style.size() as f32);
        // Box origin relative to the anchor, whole pixels so glyph edges stay crisp.
        let x0 = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => (-w / 2.0).round(),
            HPos::Right => -w.round(),
        };
        let y0 = match anchor.v_pos {
            VPos::Top => 0.0,
            VPos::Center => (-h / 2.0).round(),
            VPos::Bottom => -h.round(),
        };
        let (mut pen, baseline) = (x0, y0 + font.ascent().round());
        let mut prev = None;
        let mut result = Ok(());
        for c in text.chars() {
            let id = font.glyph_id(c);
            pen += prev.map_or(0.0, |p| font.kern(p, id));
            prev = Some(id);
            let glyph = id.with_scale_and_position(font.scale(), ab_glyph::point(pen, baseline));
            pen += font.h_advance(id);
            let Some(outline) = font.outline_glyph(glyph) else { continue };
            let min = outline.px_bounds().min;
            outline.draw(|gx, gy, coverage| {
                if result.is_ok() && coverage > 0.0 {
                    let (dx, dy) = transform.transform(min.x as i32 + gx as i32, min.y as i32 + gy as i32);
                    let alpha = colour.alpha * f64::from(coverage.min(1.0));
                    result = self.inner.draw_pixel((pos.0 + dx, pos.1 + dy), BackendColor { alpha, rgb: colour.rgb });
                }
            });
        }
        result
    }
}

/// Width of `text` and the font's line height (ascent − descent) at `size` pixels.
fn measure(font: &FontRef<'static>, text: &str, size: f64) -> (f32, f32) {
    let font = font.as_scaled(size as f32);
    let mut prev = None;
    let width = text.chars().fold(0.0, |w, c| {
        let id = font.glyph_id(c);
        let kern = prev.map_or(0.0, |p| font.kern(p, id));
        prev = Some(id);
        w + kern + font.h_advance(id)
    });
    (width, font.ascent() - font.descent())
}

/// Pixel width of the widest of `texts` at `size` pixels (for sizing label areas and legends).
fn text_width<'t>(texts: impl IntoIterator<Item = &'t str>, size: f64) -> f64 {
    let width = |t: &str| font().map_or(0.6 * size * t.chars().count() as f64, |f| f64::from(measure(f, t, size).0));
    texts.into_iter().map(width).fold(0.0, f64::max)
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

/// Reject a zero, oversized or too-small-for-its-grid image.
fn check_size(size: (u32, u32), (rows, columns): (usize, usize)) -> Result<()> {
    let (w, h) = size;
    if w == 0 || h == 0 {
        return Err(Error::bad_input(format!("plot: image size must be non-zero, got {w}x{h}")));
    }
    if w > MAX_SIDE || h > MAX_SIDE {
        return Err(Error::bad_input(format!("plot: image size {w}x{h} exceeds {MAX_SIDE} pixels a side")));
    }
    let (cw, ch) = (u64::from(w) / columns as u64, u64::from(h) / rows as u64);
    if cw < u64::from(MIN_PANEL.0) || ch < u64::from(MIN_PANEL.1) {
        let (mw, mh) = MIN_PANEL;
        return Err(Error::bad_input(format!(
            "plot: {w}x{h} is too small for {rows}x{columns} panels (each needs at least {mw}x{mh})"
        )));
    }
    Ok(())
}

/// Reject a panel with no series or points, or with values its axes cannot show.
fn check_panel(panel: &Panel) -> Result<()> {
    let title = &panel.title;
    if panel.series.is_empty() {
        return Err(Error::bad_input(format!("plot: panel `{title}` has no series")));
    }
    for series in &panel.series {
        let label = &series.label;
        if series.points.is_empty() {
            return Err(Error::bad_input(format!("plot: panel `{title}`: series `{label}` has no points")));
        }
        check_values(
            &format!("plot: panel `{title}`: series `{label}`: x"),
            series.points.iter().map(|p| p.0),
            panel.x_scale,
        )?;
        check_values(
            &format!("plot: panel `{title}`: series `{label}`: y"),
            series.points.iter().map(|p| p.1),
            panel.y_scale,
        )?;
    }
    Ok(())
}

/// Every value must be finite, of plottable magnitude, and positive on a log axis.
fn check_values(context: &str, values: impl Iterator<Item = f64>, scale: Scale) -> Result<()> {
    for v in values {
        if !v.is_finite() {
            return Err(Error::bad_input(format!("{context}: value {v} is not finite")));
        }
        if v.abs() > MAX_MAGNITUDE {
            return Err(Error::bad_input(format!("{context}: value {v:e} is beyond ±{MAX_MAGNITUDE:e}")));
        }
        if scale == Scale::Log && v <= 0.0 {
            return Err(Error::bad_input(format!(
                "{context}: value {v} on a log axis (log axes need positive values)"
            )));
        }
    }
    Ok(())
}

/// Axis range covering `values` with a 5 % margin; a degenerate span is widened (to ±10 % of the
/// value on a linear axis, to at least a factor of two on a log axis).
fn axis_range(values: impl Iterator<Item = f64>, scale: Scale) -> Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        return 0.0..1.0;
    }
    match scale {
        Scale::Linear if hi - lo <= 1e-9 * lo.abs().max(hi.abs()) => {
            let mid = 0.5 * (lo + hi);
            let pad = if mid == 0.0 { 1.0 } else { mid.abs() * 0.1 };
            mid - pad..mid + pad
        }
        Scale::Linear => lo - 0.05 * (hi - lo)..hi + 0.05 * (hi - lo),
        Scale::Log => {
            let (l0, l1) = (lo.log10(), hi.log10());
            let pad = (0.05 * (l1 - l0)).max(0.15 - 0.5 * (l1 - l0));
            10f64.powf(l0 - pad)..10f64.powf(l1 + pad)
        }
    }
}

/// A log axis over `range` with its own grid (see [`log_ticks`]); plotters' own log ticks leave a
/// range without a power of ten unlabelled and crowd long ranges with light lines.
fn log_axis(range: &Range<f64>) -> WithKeyPoints<LogCoord<f64>> {
    let (bold, light) = log_ticks(range);
    range.clone().log_scale().with_key_points(bold).with_light_points(light)
}

/// Labelled and light grid values of a log axis. Labels are picked greedily by priority — powers
/// of ten (every `stride`-th on a long axis), then 2× and 5×, then the other integer multiples; on
/// an axis shorter than a decade, evenly spaced 1-2-5 steps instead — each kept only if it is far
/// enough (about a tenth of the axis) from those already kept. Light lines sit at the integer
/// multiples (up to six decades) or the powers of ten (up to forty).
fn log_ticks(range: &Range<f64>) -> (Vec<f64>, Vec<f64>) {
    let (l0, l1) = (range.start.log10(), range.end.log10());
    let decades = l1 - l0;
    // Values m/10 · 10^k inside the range, for mantissas m (in tenths, 10..=90) passing `keep`.
    let values = |keep: &dyn Fn(i32, u32) -> bool| -> Vec<f64> {
        (l0.floor() as i32..=l1.ceil() as i32)
            .flat_map(|k| (10..=90).filter(move |&m| keep(k, m)).map(move |m| f64::from(m) / 10.0 * 10f64.powi(k)))
            .filter(|v| range.contains(v))
            .collect()
    };
    let stride = (0.1 * decades).ceil().max(1.0) as i32;
    let mut classes = vec![values(&|k, m| m == 10 && k % stride == 0)];
    if decades < 1.0 {
        let raw = (range.end - range.start) / 8.0;
        let p = 10f64.powf(raw.log10().floor());
        let step = p * [1.0, 2.0, 5.0, 10.0].into_iter().find(|&m| raw <= m * p).unwrap_or(10.0);
        classes.push(
            ((range.start / step).ceil() as i64..=(range.end / step).floor() as i64).map(|i| i as f64 * step).collect(),
        );
    } else {
        classes.push(values(&|_, m| m == 20 || m == 50));
        classes.push(values(&|_, m| m % 10 == 0));
    }
    // Evenly spaced short-axis steps may sit closer; their labels are short.
    let gap = decades * if decades < 1.0 { 0.07 } else { 0.1 };
    let mut bold: Vec<f64> = Vec::new();
    for v in classes.into_iter().flatten() {
        if bold.iter().all(|b| (b.log10() - v.log10()).abs() >= gap) {
            bold.push(v);
        }
    }
    bold.sort_by(f64::total_cmp);
    let light = match decades {
        d if d <= 6.0 => values(&|_, m| m % 10 == 0),
        d if d <= 40.0 => values(&|_, m| m == 10),
        _ => Vec::new(),
    };
    (bold, light)
}

/// Tick label formatter for an axis over `range`: enough decimals to tell the ticks apart.
fn tick_formatter(range: &Range<f64>, scale: Scale) -> impl Fn(&f64) -> String {
    let span = range.end - range.start;
    move |&v| match scale {
        Scale::Log => value_text(v, 1e3),
        Scale::Linear if v.abs() < span * 1e-9 => "0".into(), // tick arithmetic leaves 1e-17 residues
        Scale::Linear => number(v, 1e4, |div| (1.0 - (span / div).log10().floor()).clamp(0.0, 9.0) as usize),
    }
}

/// A data value (bar, percentile, log tick) with four significant digits; SI suffixes from
/// `si_from` up, exponent notation below 0.001.
fn value_text(v: f64, si_from: f64) -> String {
    if v != 0.0 && v.abs() < 1e-3 {
        return scientific(v);
    }
    number(v, si_from, |div| (3.0 - (v.abs() / div).log10().floor()).clamp(0.0, 6.0) as usize)
}

/// `v` in fixed notation with `decimals(divisor)` decimals (trailing zeros trimmed), with an SI
/// suffix (`12.5k`, `2M`) from `si_from` up and exponent notation from 10¹⁵.
fn number(v: f64, si_from: f64, decimals: impl Fn(f64) -> usize) -> String {
    let a = v.abs();
    let (div, suffix) = match a {
        _ if a >= 1e15 => return scientific(v),
        _ if a < si_from => (1.0, ""),
        _ if a >= 1e12 => (1e12, "T"),
        _ if a >= 1e9 => (1e9, "G"),
        _ if a >= 1e6 => (1e6, "M"),
        _ => (1e3, "k"),
    };
    let d = decimals(div);
    format!("{}{suffix}", trim_zeros(&format!("{:.d$}", v / div)))
}

/// `v` as `1.5e-5`: up to three significant digits.
fn scientific(v: f64) -> String {
    let s = format!("{v:.2e}");
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    format!("{}e{exponent}", trim_zeros(mantissa))
}

/// `"2.500"` → `"2.5"`, `"3.000"` → `"3"`; integers unchanged.
fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// Tick labels to ask for along `pixels`, about one per `spacing` pixels.
fn label_count(pixels: u32, spacing: u32) -> usize {
    (pixels / spacing).clamp(3, 10) as usize
}

/// Position of `v` across `range` in 0..1 (log10 space on a log axis).
fn normalize(v: f64, range: &Range<f64>, scale: Scale) -> f64 {
    match scale {
        Scale::Linear => (v - range.start) / (range.end - range.start),
        Scale::Log => (v / range.start).log10() / (range.end / range.start).log10(),
    }
}

/// The legend corner covering the fewest `occupied` points (normalised 0..1, y up), for a legend
/// of `labels` in a plot of `plot_px` pixels at scale `s`.
fn emptiest_corner(occupied: &[(f64, f64)], plot_px: (u32, u32), s: f64, labels: &[String]) -> SeriesLabelPosition {
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

/// Quantile `q` (0..=1) of sorted values, linearly interpolated between order statistics.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let pos = q * (sorted.len() - 1) as f64;
    let (i, frac) = (pos.floor() as usize, pos.fract());
    let next = sorted[(i + 1).min(sorted.len() - 1)];
    sorted[i] + (next - sorted[i]) * frac
}

/// Text and stroke scale for an area: 1.0 at a 380-pixel short side.
fn text_scale<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> f64 {
    let (w, h) = area.dim_in_pixel();
    (f64::from(w.min(h)) / 380.0).clamp(0.75, 2.5)
}

/// Width of a legend swatch (line, bar) at scale `s`.
fn swatch(s: f64) -> i32 {
    (22.0 * s).round() as i32
}

/// A stroke width of `w` pixels at scale `s`, at least one pixel.
fn stroke(s: f64, w: f64) -> u32 {
    (w * s).round().max(1.0) as u32
}

/// Chart layout shared by all kinds: caption, margins and label areas sized for scale `s`.
/// `y_ticks_px` is the width of the longest y tick label, which sets the width of the y label area.
fn chart_builder<'a, 'b, DB: DrawingBackend>(
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
fn tick_width(range: &Range<f64>, scale: Scale, s: f64) -> f64 {
    let values = match scale {
        Scale::Linear => vec![range.start, range.end, 0.5 * (range.start + range.end)],
        Scale::Log => log_ticks(range).0,
    };
    let format = tick_formatter(range, scale);
    let labels: Vec<String> = values.iter().map(format).collect();
    text_width(labels.iter().map(String::as_str), 12.0 * s)
}

/// Grid, axes, tick labels and axis descriptions in the shared style.
fn mesh<'a, 'b, DB, X, Y>(
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
fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
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
fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Plot(format!("drawing failed: {e}"))
}
