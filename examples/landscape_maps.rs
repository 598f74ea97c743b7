//! Writes the example maps under `assets/landscape/` (issue #35 item 4), so a fresh machine needs
//! no imaging tools: `cargo run --release --example landscape_maps`.
//! - `heightmap.png`: 129 × 129 texels, 16-bit grey, rolling hills with a steep ridge and a
//!   hollow where the pond lies (for `--terrain-scale 200,12,200`: 1.56 m a texel, white 12 m up).
//! - `cover.png`: 128 × 128 texels, RGB: red the grass's density, bare along a winding path
//!   about 4 m wide and over a pond-shaped patch with a soft rim; green the flowers' density
//!   (meadows of it away from the path).
//!
//! Drawn with: `meadow render --field infinite --heightmap assets/landscape/heightmap.png
//! --cover assets/landscape/cover.png --terrain-scale 200,12,200`.
//!
//! `cargo run --release --example landscape_maps -- relief PATH.png [SEED]` writes instead the
//! unbounded field's gentle relief of `SEED` (default 1, `meadow`'s `--seed`) exported as a
//! 16-bit heightmap, 4 001 × 4 001 texels at 0.5 m over 2 km (`Heightmap::from_relief`; too large
//! for the repository), and prints the `--terrain-scale` that draws it as the relief
//! (`meadow bench --preset landscape` compares the two).

use std::f64::consts::TAU;
use std::path::Path;

/// The pond's centre and radii, in the maps' unit square.
const POND: (f64, f64, f64, f64) = (0.68, 0.35, 0.09, 0.06);

/// How far (unit square) `(u, v)` lies inside the pond's ellipse: < 1 inside.
fn pond(u: f64, v: f64) -> f64 {
    let (cu, cv, ru, rv) = POND;
    (((u - cu) / ru).powi(2) + ((v - cv) / rv).powi(2)).sqrt()
}

/// The path's distance (unit square, along u) from `(u, v)`: a sine winding along v.
fn path(u: f64, v: f64) -> f64 {
    (u - (0.3 + 0.08 * (v * TAU * 1.5).sin())).abs()
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn heightmap(dir: &Path) -> Result<(), image::ImageError> {
    let side = 129u32;
    let texels: Vec<u16> = (0..side * side)
        .map(|i| {
            let (u, v) = (f64::from(i % side) / 128.0, f64::from(i / side) / 128.0);
            let hills = 0.35 + 0.15 * (u * TAU).sin() * (v * TAU * 2.0).cos() + 0.1 * ((u + v) * TAU * 3.0).sin();
            let ridge = 0.35 * smoothstep(0.06, 0.0, (v - 0.8 - 0.05 * (u * TAU).sin()).abs());
            let hollow = -0.2 * smoothstep(1.6, 0.6, pond(u, v));
            ((hills + ridge + hollow).clamp(0.0, 1.0) * 65_535.0) as u16
        })
        .collect();
    // `save_buffer` takes 16-bit samples in native order.
    let bytes: Vec<u8> = texels.iter().flat_map(|t| t.to_ne_bytes()).collect();
    image::save_buffer(dir.join("heightmap.png"), &bytes, side, side, image::ColorType::L16)
}

fn cover(dir: &Path) -> Result<(), image::ImageError> {
    let side = 128u32;
    let mut rgb = Vec::with_capacity((side * side * 3) as usize);
    for i in 0..side * side {
        let (u, v) = ((f64::from(i % side) + 0.5) / 128.0, (f64::from(i / side) + 0.5) / 128.0);
        let grass = smoothstep(0.008, 0.016, path(u, v)) * smoothstep(1.0, 1.25, pond(u, v));
        let flowers = grass * smoothstep(0.55, 0.8, (u * TAU * 2.0).sin() * (v * TAU * 3.0).cos());
        rgb.extend([(grass * 255.0).round() as u8, (flowers * 255.0).round() as u8, 0]);
    }
    image::save_buffer(dir.join("cover.png"), &rgb, side, side, image::ColorType::Rgb8)
}

/// `relief PATH [SEED]`: the relief exported (see the module's comment).
fn relief(args: &[String]) -> Result<String, String> {
    let [path, rest @ ..] = args else {
        return Err("relief needs an output PATH.png".into());
    };
    let seed = match rest {
        [] => 1,
        [seed] => seed.parse::<u64>().map_err(|e| format!("seed '{seed}': {e}"))?,
        _ => return Err("relief takes PATH.png and at most a SEED".into()),
    };
    let relief = meadow::scene::field::Relief::of_kind(meadow::scene::field::ReliefKind::Gentle, seed);
    let (map, low) = meadow::scene::heightmap::Heightmap::from_relief(&relief, 2000.0, 0.5);
    let bytes: Vec<u8> = map.texels.iter().flat_map(|t| t.to_ne_bytes()).collect();
    image::save_buffer(path, &bytes, map.width, map.height, image::ColorType::L16)
        .map_err(|e| format!("{path}: {e}"))?;
    Ok(format!(
        "wrote {path}: {} x {} texels; draw it with --field infinite --heightmap {path} --terrain-scale 2000,{},2000 \
         (its ground lies {:.3} m below the relief's)",
        map.width, map.height, map.scale.y, -low
    ))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some((mode, rest)) = args.split_first() {
        let done = match mode.as_str() {
            "relief" => relief(rest),
            _ => Err(format!("unknown mode '{mode}' (none: the example maps; relief PATH.png [SEED])")),
        };
        match done {
            Ok(line) => println!("{line}"),
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(2);
            }
        }
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/landscape");
    let written = std::fs::create_dir_all(&dir).map_err(image::ImageError::IoError).and_then(|()| {
        heightmap(&dir)?;
        cover(&dir)
    });
    if let Err(e) = written {
        eprintln!("error: {}: {e}", dir.display());
        std::process::exit(1);
    }
    println!("wrote {}/heightmap.png and cover.png", dir.display());
}
