//! Axes of the charts: value ranges, log-axis ticks and the formatting of tick and value labels.

use std::ops::Range;

use plotters::coord::combinators::WithKeyPoints;
use plotters::prelude::*;

use super::Scale;

/// Axis range covering `values` with a 5 % margin; a degenerate span is widened (to ±10 % of the
/// value on a linear axis, to at least a factor of two on a log axis).
pub(super) fn axis_range(values: impl Iterator<Item = f64>, scale: Scale) -> Range<f64> {
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
pub(super) fn log_axis(range: &Range<f64>) -> WithKeyPoints<LogCoord<f64>> {
    let (bold, light) = log_ticks(range);
    range.clone().log_scale().with_key_points(bold).with_light_points(light)
}

/// Labelled and light grid values of a log axis. Labels are picked greedily by priority — powers
/// of ten (every `stride`-th on a long axis), then 2× and 5×, then the other integer multiples; on
/// an axis shorter than a decade, evenly spaced 1-2-5 steps instead — each kept only if it is far
/// enough (about a tenth of the axis) from those already kept. Light lines sit at the integer
/// multiples (up to six decades) or the powers of ten (up to forty).
pub(super) fn log_ticks(range: &Range<f64>) -> (Vec<f64>, Vec<f64>) {
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
pub(super) fn tick_formatter(range: &Range<f64>, scale: Scale) -> impl Fn(&f64) -> String {
    let span = range.end - range.start;
    move |&v| match scale {
        Scale::Log => value_text(v, 1e3),
        Scale::Linear if v.abs() < span * 1e-9 => "0".into(), // tick arithmetic leaves 1e-17 residues
        Scale::Linear => number(v, 1e4, |div| (1.0 - (span / div).log10().floor()).clamp(0.0, 9.0) as usize),
    }
}

/// A data value (bar, percentile, log tick) with four significant digits; SI suffixes from
/// `si_from` up, exponent notation below 0.001.
pub(super) fn value_text(v: f64, si_from: f64) -> String {
    if v != 0.0 && v.abs() < 1e-3 {
        return scientific(v);
    }
    number(v, si_from, |div| (3.0 - (v.abs() / div).log10().floor()).clamp(0.0, 6.0) as usize)
}

/// `v` in fixed notation with `decimals(divisor)` decimals (trailing zeros trimmed), with an SI
/// suffix (`12.5k`, `2M`) from `si_from` up and exponent notation from 10¹⁵.
pub(super) fn number(v: f64, si_from: f64, decimals: impl Fn(f64) -> usize) -> String {
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
pub(super) fn scientific(v: f64) -> String {
    let s = format!("{v:.2e}");
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    format!("{}e{exponent}", trim_zeros(mantissa))
}

/// `"2.500"` → `"2.5"`, `"3.000"` → `"3"`; integers unchanged.
pub(super) fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// Tick labels to ask for along `pixels`, about one per `spacing` pixels.
pub(super) fn label_count(pixels: u32, spacing: u32) -> usize {
    (pixels / spacing).clamp(3, 10) as usize
}

/// Position of `v` across `range` in 0..1 (log10 space on a log axis).
pub(super) fn normalize(v: f64, range: &Range<f64>, scale: Scale) -> f64 {
    match scale {
        Scale::Linear => (v - range.start) / (range.end - range.start),
        Scale::Log => (v / range.start).log10() / (range.end / range.start).log10(),
    }
}
