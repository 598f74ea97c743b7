//! Validation of chart input: image sizes and the values of panels, before anything is drawn.

use super::{Panel, Scale, MAX_MAGNITUDE, MAX_SIDE, MIN_PANEL};
use crate::error::{Error, Result};

/// Reject a zero, oversized or too-small-for-its-grid image.
pub(super) fn check_size(size: (u32, u32), (rows, columns): (usize, usize)) -> Result<()> {
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
pub(super) fn check_panel(panel: &Panel) -> Result<()> {
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
pub(super) fn check_values(context: &str, values: impl Iterator<Item = f64>, scale: Scale) -> Result<()> {
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

/// Reject bars without categories or groups, or a group without one finite value per category.
pub(super) fn check_bars(categories: &[String], groups: &[(String, Vec<f64>)]) -> Result<()> {
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
    Ok(())
}
