//! Parsers for the values of the command line and of the viewer's scripts. Each rejects what the
//! renderer cannot use with a message naming the value; clap turns the `Err` into one `error: …`
//! line and exit code 2, a script into one naming its line.

use glam::{Vec2, Vec3};

use crate::error::quoted;
use crate::render::renderer::{BLADES_PER_INSTANCE_RANGE, SEGMENTS_RANGE};
use crate::scene::Camera;

/// A finite `f32` (Rust's parser accepts "NaN" and "inf": they are refused here).
pub fn finite_f32(text: &str) -> Result<f32, String> {
    let value: f32 = text.trim().parse().map_err(|_| format!("'{text}' is not a number", text = quoted(text)))?;
    if !value.is_finite() {
        return Err(format!("'{text}' is not a finite number", text = quoted(text)));
    }
    Ok(value)
}

/// A finite `f32` above 0.
pub fn positive_f32(text: &str) -> Result<f32, String> {
    let value = finite_f32(text)?;
    if value <= 0.0 {
        return Err(format!("'{text}' must be above 0", text = quoted(text)));
    }
    Ok(value)
}

/// LOD bucket segment counts: `8,4,2,1` (decreasing, each in 1..=16).
pub fn lod_segments(text: &str) -> Result<crate::render::culling::LodSegments, String> {
    let counts = text
        .split(',')
        .map(|s| s.trim().parse::<u32>().map_err(|_| format!("'{s}' is not a whole number of segments", s = quoted(s))))
        .collect::<Result<Vec<u32>, String>>()
        .map_err(|e| if text.trim().is_empty() { "give at least one segment count".into() } else { e })?;
    crate::render::culling::LodSegments::new(&counts)
}

/// `--field`: a side in metres above 0, or `infinite` (`None`).
pub fn field(text: &str) -> Result<crate::render::field_gpu::FieldSize, String> {
    if text.trim() == "infinite" {
        return Ok(crate::render::field_gpu::FieldSize(None));
    }
    let size = finite_f32(text)
        .map_err(|_| format!("'{text}' is neither a size in metres nor 'infinite'", text = quoted(text)))?;
    if size <= 0.0 {
        return Err(format!("a field of {size} m is empty: give a size above 0 or 'infinite'"));
    }
    Ok(crate::render::field_gpu::FieldSize(Some(size)))
}

/// `--density`: blades per square metre, above 0 and at most what a block holds.
pub fn density(text: &str) -> Result<f32, String> {
    let density = positive_f32(text)?;
    let most = crate::scene::field::max_density();
    if density > most {
        return Err(format!(
            "{density} blades/m² is over the {most} a {} m block holds ({} blades)",
            crate::scene::field::BLOCK_SIZE,
            crate::scene::field::MAX_BLOCK_BLADES
        ));
    }
    Ok(density)
}

/// Blade count, at least 1. Device limits are checked once the device is known.
pub fn blade_count(text: &str) -> Result<u32, String> {
    let value: u64 =
        text.trim().parse().map_err(|_| format!("'{text}' is not a whole number of blades", text = quoted(text)))?;
    match value {
        0 => Err("at least 1 blade is needed".into()),
        v if v > u64::from(u32::MAX) => {
            Err(format!("{v} blades is more than a draw call can instance (at most {})", u32::MAX))
        }
        v => Ok(v as u32),
    }
}

/// Segments per blade in `1..=16`.
pub fn segments(text: &str) -> Result<u32, String> {
    let value: u32 =
        text.trim().parse().map_err(|_| format!("'{text}' is not a whole number of segments", text = quoted(text)))?;
    if !SEGMENTS_RANGE.contains(&value) {
        return Err(format!("{value} segments is outside {}..={}", SEGMENTS_RANGE.start(), SEGMENTS_RANGE.end()));
    }
    Ok(value)
}

/// Blades per instance in `1..=1024`.
pub fn blades_per_instance(text: &str) -> Result<u32, String> {
    let value: u32 = text.trim().parse().map_err(|_| format!("'{text}' is not a whole number", text = quoted(text)))?;
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
        .ok_or_else(|| format!("'{text}' is not WIDTHxHEIGHT (e.g. 1280x720)", text = quoted(text)))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{text}' is not WIDTHxHEIGHT (e.g. 1280x720)", text = quoted(text)))
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
        return Err(format!("'{text}' is not X,Y,Z,YAW_DEG,PITCH_DEG (five numbers)", text = quoted(text)));
    }
    let values = parts.iter().map(|p| finite_f32(p)).collect::<Result<Vec<_>, _>>()?;
    if values[4].abs() > 89.0 {
        return Err(format!("pitch {}° is outside -89..=89", values[4]));
    }
    Ok(Camera { position: Vec3::new(values[0], values[1], values[2]), yaw_deg: values[3], pitch_deg: values[4] })
}

/// `--camera`: `X,Y,Z,YAW_DEG,PITCH_DEG` (`camera`) or a preset's name (`scene::camera::CAMERA_PRESETS`).
pub fn camera_choice(text: &str) -> Result<crate::scene::CameraChoice, String> {
    use crate::scene::camera::CAMERA_PRESETS;
    match text.trim() {
        "landscape" => Ok(crate::scene::CameraChoice::Landscape),
        word if !word.contains(',') && word.parse::<f32>().is_err() => Err(format!(
            "unknown camera preset '{text}': give {} or X,Y,Z,YAW_DEG,PITCH_DEG",
            CAMERA_PRESETS.join(", "),
            text = quoted(text)
        )),
        _ => camera(text).map(crate::scene::CameraChoice::At),
    }
}

/// `--view-distance`: metres above 0, at most `render::limits::MAX_VIEW_DISTANCE`.
pub fn view_distance(text: &str) -> Result<f32, String> {
    let metres = positive_f32(text)?;
    let most = crate::render::limits::MAX_VIEW_DISTANCE;
    if metres > most {
        return Err(format!("a view distance of {metres} m is over the {most} m the ground reaches"));
    }
    Ok(metres)
}

/// `--terrain-scale X,Y,Z`: the heightmap's extent in x and z and the height of white, each a
/// finite number of metres above 0.
pub fn terrain_scale(text: &str) -> Result<crate::scene::heightmap::TerrainScale, String> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 3 {
        return Err(format!("'{text}' is not X,Y,Z (three lengths in metres)", text = quoted(text)));
    }
    let values = parts.iter().map(|p| positive_f32(p)).collect::<Result<Vec<_>, _>>()?;
    let [x, y, z] = [0, 1, 2].map(|i| f64::from(values[i]));
    Ok(crate::scene::heightmap::TerrainScale { x, y, z })
}

/// `--slope-limit`: degrees of slope, finite, from 0 to 90.
pub fn slope_limit(text: &str) -> Result<f32, String> {
    let degrees = finite_f32(text)?;
    if !(0.0..=90.0).contains(&degrees) {
        return Err(format!("a slope limit of {degrees}° is outside 0..=90"));
    }
    Ok(degrees)
}

/// `--flowers`: flowers per square metre, finite, positive, at most `scene::flowers::MOST_PER_M2`.
pub fn flowers(text: &str) -> Result<crate::scene::flowers::Flowers, String> {
    crate::scene::flowers::Flowers::new(finite_f32(text)?)
}

/// `--clumps`: a clump size in metres, finite, within `scene::clumps::SIZE_RANGE_M`.
pub fn clumps(text: &str) -> Result<crate::scene::clumps::Clumps, String> {
    let size_m = finite_f32(text)?;
    let (lo, hi) = crate::scene::clumps::SIZE_RANGE_M;
    if !(lo..=hi).contains(&size_m) {
        return Err(format!("clumps of {size_m} m: give {lo} to {hi} m"));
    }
    Ok(crate::scene::clumps::Clumps { size_m })
}

/// The fastest `timing --fly`: a frame's step stays well inside a block field's cells.
pub const MAX_FLY_SPEED: f32 = 1000.0;

/// `timing --fly`: a speed in m/s above 0, at most `MAX_FLY_SPEED`.
pub fn fly_speed(text: &str) -> Result<f32, String> {
    let speed = positive_f32(text)?;
    if speed > MAX_FLY_SPEED {
        return Err(format!("a flight at {speed} m/s is over the {MAX_FLY_SPEED} m/s a run may fly"));
    }
    Ok(speed)
}

/// `--fog`: a density per metre, finite and at least 0 (0: no fog).
pub fn fog(text: &str) -> Result<f32, String> {
    let density = finite_f32(text)?;
    if density < 0.0 {
        return Err(format!("a fog density of {density} per metre is negative: give 0 (no fog) or more"));
    }
    Ok(density)
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
        assert_eq!(camera_choice("landscape"), Ok(crate::scene::CameraChoice::Landscape));
        assert!(camera_choice("panorama").is_err_and(|e| e.contains("unknown camera preset")));
        assert!(camera_choice("1,2,3,45,-10").is_ok() && camera_choice("1,2").is_err() && camera_choice("5").is_err());
        assert!(view_distance("10000").is_ok() && view_distance("10001").is_err() && view_distance("0").is_err());
        assert!(fog("-0.1").is_err() && fog("NaN").is_err() && fog("0") == Ok(0.0));
    }
}

/// Comma-separated finite numbers, `count` of them (or any count in `counts`).
fn numbers(text: &str, counts: &[usize], shape: &str) -> Result<Vec<f32>, String> {
    let parts: Vec<&str> = text.split(',').collect();
    if !counts.contains(&parts.len()) {
        return Err(format!("'{text}' is not {shape}", text = quoted(text)));
    }
    parts.iter().map(|p| finite_f32(p)).collect()
}

/// `DIR_DEG,STRENGTH`: direction the wind blows towards (degrees from +x towards +z), strength ≥ 0.
pub fn wind(text: &str) -> Result<(f32, f32), String> {
    let v = numbers(text, &[2], "DIR_DEG,STRENGTH")?;
    if v[1] < 0.0 {
        return Err(format!("wind strength {} is negative", v[1]));
    }
    Ok((v[0], v[1]))
}

/// `X,Z,POWER,SIGMA[,VX,VZ][,HEIGHT]`: a point source (eq. 4.1), optionally moving at (VX, VZ)
/// m/s, at HEIGHT metres above the ground (where the fluid wind injects it; 0.5 by default):
/// five numbers give the height, six the motion, seven both.
pub fn source(text: &str) -> Result<crate::wind::PointSource, String> {
    let v = numbers(text, &[4, 5, 6, 7], "X,Z,POWER,SIGMA[,VX,VZ][,HEIGHT]")?;
    if !(0.0..=16.0).contains(&v[3]) {
        return Err(format!("source sigma {} is outside 0..=16 (σ of eq. 4.1; negative is meaningless)", v[3]));
    }
    if !(0.0..=1000.0).contains(&v[2]) {
        return Err(format!("source power {} is outside 0..=1000", v[2]));
    }
    let velocity = if v.len() >= 6 { Vec2::new(v[4], v[5]) } else { Vec2::ZERO };
    let height = match v.len() {
        5 => v[4],
        7 => v[6],
        _ => crate::wind::DEFAULT_SOURCE_HEIGHT,
    };
    if !(0.0..=1000.0).contains(&height) {
        return Err(format!("source height {height} is outside 0..=1000 m above the ground"));
    }
    Ok(crate::wind::PointSource { position: Vec2::new(v[0], v[1]), power: v[2], sigma: v[3], velocity, height })
}

/// `NX,NY,NZ`: the fluid wind's cells per axis (at least `wind::MIN_FLUID_CELLS` each; the
/// device's 3-D image limit and the memory budget are checked when the device is known).
pub fn fluid_grid(text: &str) -> Result<[u32; 3], String> {
    let v = numbers(text, &[3], "NX,NY,NZ")?;
    let min = crate::wind::MIN_FLUID_CELLS as f32;
    if let Some(n) = v.iter().find(|n| !(n.fract() == 0.0 && **n >= min && **n <= 65536.0)) {
        return Err(format!("fluid grid '{}': {n} cells is not a whole number in {min}..=65536", quoted(text)));
    }
    Ok([v[0] as u32, v[1] as u32, v[2] as u32])
}

/// `DXZ,DY`: the fluid wind's cell width and height in metres, each above 0.
pub fn fluid_cell(text: &str) -> Result<[f32; 2], String> {
    let v = numbers(text, &[2], "DXZ,DY")?;
    if let Some(c) = v.iter().find(|c| !(c.is_finite() && **c > 0.0 && **c <= 1000.0)) {
        return Err(format!("fluid cell '{}': {c} m is not a length in (0, 1000]", quoted(text)));
    }
    Ok([v[0], v[1]])
}

/// `X0,Z0,X1,Z1` with X0 < X1 and Z0 < Z1.
pub fn calm(text: &str) -> Result<crate::wind::CalmArea, String> {
    let v = numbers(text, &[4], "X0,Z0,X1,Z1")?;
    if v[0] >= v[2] || v[1] >= v[3] {
        return Err(format!("calm area '{text}' is inverted or empty: need X0 < X1 and Z0 < Z1", text = quoted(text)));
    }
    Ok(crate::wind::CalmArea { min: Vec2::new(v[0], v[1]), max: Vec2::new(v[2], v[3]) })
}

/// `sphere:X,Y,Z,R[,VX,VY,VZ]` or `ellipsoid:X,Y,Z,RX,RY,RZ[,VX,VY,VZ]`: radii > 0, an optional
/// velocity in m/s (finite, as every number).
pub fn collider(text: &str) -> Result<crate::wind::Collider, String> {
    const SHAPES: &str = "sphere:X,Y,Z,R[,VX,VY,VZ] or ellipsoid:X,Y,Z,RX,RY,RZ[,VX,VY,VZ]";
    let (kind, rest) = text.split_once(':').ok_or_else(|| format!("'{text}' is not {SHAPES}", text = quoted(text)))?;
    let (v, radii_end) = match kind {
        "sphere" => (numbers(rest, &[4, 7], "sphere:X,Y,Z,R[,VX,VY,VZ]")?, 4),
        "ellipsoid" => (numbers(rest, &[6, 9], "ellipsoid:X,Y,Z,RX,RY,RZ[,VX,VY,VZ]")?, 6),
        other => return Err(format!("unknown collider '{other}': use sphere or ellipsoid", other = quoted(other))),
    };
    let radii = match radii_end {
        4 => glam::Vec3::splat(v[3]),
        _ => glam::Vec3::new(v[3], v[4], v[5]),
    };
    if radii.min_element() <= 0.0 {
        return Err(format!("collider radius in '{text}' must be positive", text = quoted(text)));
    }
    let velocity = v.get(radii_end..).filter(|v| v.len() == 3).map_or(glam::Vec3::ZERO, glam::Vec3::from_slice);
    Ok(crate::wind::Collider { center: glam::Vec3::new(v[0], v[1], v[2]), radii, velocity })
}

/// Keyframe poses over the full circle, 8..=1 000 000.
pub fn poses(text: &str) -> Result<u32, String> {
    let value: u32 =
        text.trim().parse().map_err(|_| format!("'{text}' is not a whole number of poses", text = quoted(text)))?;
    if !(8..=1_000_000).contains(&value) {
        return Err(format!("{value} poses is outside 8..=1000000"));
    }
    Ok(value)
}

/// Cluster edge in metres, 0.05..=1000.
pub fn cluster_size(text: &str) -> Result<f32, String> {
    let value = finite_f32(text)?;
    if !(0.05..=1000.0).contains(&value) {
        return Err(format!("cluster size {value} m is outside 0.05..=1000"));
    }
    Ok(value)
}

/// A fixed time step (`--dt`): seconds as a number or a fraction `A/B`, above 0 and at most 1/15 s.
pub fn dt(text: &str) -> Result<f64, String> {
    let number = |t: &str| -> Result<f64, String> {
        t.trim().parse::<f64>().map_err(|_| format!("'{text}' is not a number or a fraction", text = quoted(text)))
    };
    let value = match text.split_once('/') {
        Some((a, b)) => number(a)? / number(b)?,
        None => number(text)?,
    };
    let max = crate::render::animation::clock::MAX_DT;
    if !value.is_finite() {
        return Err(format!("time step '{text}' is not a finite number", text = quoted(text)));
    }
    if value <= 0.0 {
        return Err(format!("time step '{text}' must be above 0", text = quoted(text)));
    }
    if value > max + 1e-12 {
        return Err(format!("time step '{text}' is over 1/15 s (the longest step)", text = quoted(text)));
    }
    Ok(value)
}

/// Simulation time in seconds, finite and ≥ 0.
pub fn time(text: &str) -> Result<f32, String> {
    let value = finite_f32(text)?;
    if value < 0.0 {
        return Err(format!("time {value} is negative"));
    }
    Ok(value)
}

/// The Verlet blades' stiffness k_s or the inertial chains' k/J (`--stiffness`, 1/s²), in
/// `verlet::STIFFNESS_RANGE`.
pub fn stiffness(text: &str) -> Result<f32, String> {
    let value = finite_f32(text)?;
    let (lo, hi) = crate::render::animation::verlet::STIFFNESS_RANGE;
    if !(lo..=hi).contains(&value) {
        return Err(format!("stiffness {value} is outside {lo}..={hi} (1/s²)"));
    }
    Ok(value)
}

/// The Verlet blades' drag rate k_a or the inertial chains' damper d/J (`--damping`, 1/s), in
/// `verlet::DAMPING_RANGE`.
pub fn damping(text: &str) -> Result<f32, String> {
    let value = finite_f32(text)?;
    let (lo, hi) = crate::render::animation::verlet::DAMPING_RANGE;
    if !(lo..=hi).contains(&value) {
        return Err(format!("damping {value} is outside {lo}..={hi} (1/s)"));
    }
    Ok(value)
}

#[cfg(test)]
mod animation_tests {
    use super::*;

    #[test]
    fn animation_values_are_checked() {
        assert!(wind("30,NaN").is_err() && wind("30,-1").is_err());
        assert_eq!(dt("1/60"), Ok(1.0 / 60.0));
        assert_eq!(dt("0.05"), Ok(0.05));
        assert_eq!(dt("1/15"), Ok(1.0 / 15.0));
        for bad in ["0", "-0.01", "NaN", "0.1", "1/0", "inf", "x", "1/x"] {
            assert!(dt(bad).is_err(), "{bad}");
        }
        assert_eq!(wind("30,0.5"), Ok((30.0, 0.5)));
        assert!(source("0,0,1,-1").is_err() && source("0,0,1").is_err());
        assert_eq!(source("1,2,0.5,2,0.1,0").map(|s| s.velocity.x), Ok(0.1));
        assert!(calm("1,0,0,1").is_err() && calm("0,0,1,1").is_ok());
        assert!(collider("sphere:0,0,0,0").is_err() && collider("cube:0,0,0,1").is_err());
        assert!(collider("ellipsoid:0,0.2,0,0.3,0.2,0.5").is_ok());
        let moving = collider("sphere:1,0.3,2,0.3,1.5,0,-0.5").expect("a moving sphere");
        assert_eq!(moving.velocity, glam::Vec3::new(1.5, 0.0, -0.5));
        assert_eq!(moving.center_at(2.0), glam::Vec3::new(4.0, 0.3, 1.0));
        let ellipsoid = collider("ellipsoid:0,0.2,0,0.3,0.2,0.5,0,0,1").expect("a moving ellipsoid");
        assert_eq!((ellipsoid.radii, ellipsoid.velocity), (glam::Vec3::new(0.3, 0.2, 0.5), glam::Vec3::Z));
        for bad in [
            "sphere:0,0,0,NaN",
            "sphere:0,0,0,-1",
            "sphere:0,0,0,1,NaN,0,0",
            "sphere:0,0,0,1,1",
            "ellipsoid:0,0,0,1,1,1,1",
        ] {
            assert!(collider(bad).is_err(), "{bad}");
        }
        assert!(poses("0").is_err() && poses("1000").is_ok());
        assert!(cluster_size("0").is_err() && cluster_size("inf").is_err());
        assert!(time("-1").is_err() && time("2.5").is_ok());
    }
}

/// A submission strategy of `meadow overhead` (`render::submission::Strategy`).
pub fn strategy(text: &str) -> Result<crate::render::submission::Strategy, String> {
    use crate::render::submission::Strategy;
    Strategy::parse(text.trim()).ok_or_else(|| {
        let names: Vec<&str> = Strategy::ALL.iter().map(|s| s.name()).collect();
        format!("'{}' is not a strategy (one of {})", quoted(text), names.join(", "))
    })
}

/// Clusters (draws) of `meadow overhead`: `1..=1_000_000`.
pub fn clusters(text: &str) -> Result<u32, String> {
    let value: u64 =
        text.trim().parse().map_err(|_| format!("'{text}' is not a whole number of clusters", text = quoted(text)))?;
    match value {
        0 => Err("at least 1 cluster is needed".into()),
        v if v > 1_000_000 => Err(format!("{v} clusters is more than the 1000000 draws meadow records per frame")),
        v => Ok(v as u32),
    }
}
