//! Parsers for command-line values. Each rejects what the renderer cannot use with a message
//! naming the value; clap turns the `Err` into one `error: …` line and exit code 2.

use glam::Vec3;

use crate::render::renderer::{BLADES_PER_INSTANCE_RANGE, SEGMENTS_RANGE};
use crate::scene::Camera;

/// A finite `f32` (Rust's parser accepts "NaN" and "inf": they are refused here).
pub fn finite_f32(text: &str) -> Result<f32, String> {
    let value: f32 = text.trim().parse().map_err(|_| format!("'{text}' is not a number"))?;
    if !value.is_finite() {
        return Err(format!("'{text}' is not a finite number"));
    }
    Ok(value)
}

/// Blade count, at least 1. Device limits are checked once the device is known.
pub fn blade_count(text: &str) -> Result<u32, String> {
    let value: u64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a whole number of blades"))?;
    match value {
        0 => Err("at least 1 blade is needed".into()),
        v if v > u64::from(u32::MAX) => Err(format!(
            "{v} blades is more than a draw call can instance (at most {})",
            u32::MAX
        )),
        v => Ok(v as u32),
    }
}

/// Segments per blade in `1..=16`.
pub fn segments(text: &str) -> Result<u32, String> {
    let value: u32 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a whole number of segments"))?;
    if !SEGMENTS_RANGE.contains(&value) {
        return Err(format!(
            "{value} segments is outside {}..={}",
            SEGMENTS_RANGE.start(),
            SEGMENTS_RANGE.end()
        ));
    }
    Ok(value)
}

/// Blades per instance in `1..=1024`.
pub fn blades_per_instance(text: &str) -> Result<u32, String> {
    let value: u32 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a whole number"))?;
    if !BLADES_PER_INSTANCE_RANGE.contains(&value) {
        return Err(format!(
            "{value} blades per instance is outside {}..={}",
            BLADES_PER_INSTANCE_RANGE.start(),
            BLADES_PER_INSTANCE_RANGE.end()
        ));
    }
    Ok(value)
}

/// `WIDTHxHEIGHT`, both at least 1. The device's maximum is checked later.
pub fn size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .trim()
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}' is not WIDTHxHEIGHT (e.g. 1280x720)"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{text}' is not WIDTHxHEIGHT (e.g. 1280x720)"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if w == 0 || h == 0 {
        return Err(format!("size {w}x{h} is empty: width and height must be at least 1"));
    }
    Ok((w, h))
}

/// `X,Y,Z,YAW_DEG,PITCH_DEG`, all finite; pitch within ±89° so the view is defined.
pub fn camera(text: &str) -> Result<Camera, String> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 5 {
        return Err(format!("'{text}' is not X,Y,Z,YAW_DEG,PITCH_DEG (five numbers)"));
    }
    let values = parts.iter().map(|p| finite_f32(p)).collect::<Result<Vec<_>, _>>()?;
    if values[4].abs() > 89.0 {
        return Err(format!("pitch {}° is outside -89..=89", values[4]));
    }
    Ok(Camera {
        position: Vec3::new(values[0], values[1], values[2]),
        yaw_deg: values[3],
        pitch_deg: values[4],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_nan_inf_zero_and_ranges() {
        assert!(finite_f32("NaN").is_err());
        assert!(finite_f32("inf").is_err());
        assert!(finite_f32("-infinity").is_err());
        assert_eq!(finite_f32("1.5"), Ok(1.5));
        assert!(blade_count("0").is_err());
        assert!(blade_count("99999999999").is_err());
        assert_eq!(blade_count("40000"), Ok(40_000));
        assert!(segments("0").is_err() && segments("17").is_err());
        assert_eq!(segments("16"), Ok(16));
        assert!(size("0x0").is_err() && size("1280").is_err() && size("axb").is_err());
        assert_eq!(size("1280x720"), Ok((1280, 720)));
        assert!(camera("0,1,2,3").is_err() && camera("0,NaN,2,3,4").is_err() && camera("0,1,2,3,90").is_err());
        assert_eq!(camera("1,2,3,45,-10").map(|c| c.yaw_deg), Ok(45.0));
    }
}
