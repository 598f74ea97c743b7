//! The view to the horizon (#30 items 3 and 4): `--view-distance 5000` from the landscape camera
//! under a light fog renders validation-clean with the ground seen out to 5 km, while the blades
//! keep their 150 m range; the picture and the counts are the same on every run and llvmpipe
//! thread count; and on a 16-bit depth buffer, whose near plane moves out with the view
//! distance (`scene::camera::near_plane`), hills 10 km away hide each other as on a float one.

mod support;

use meadow::scene::camera::{rows_below_horizon, FOV_Y_DEG, LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG};
use support::Picture;

const ROWS: u32 = 720;

/// `--field infinite` from the landscape camera, static blades.
const LANDSCAPE: &[&str] = &["--field", "infinite", "--camera", "landscape", "--mode", "static", "--size", "1280x720"];
/// A fog of 0.0002 per metre: at 4 km a surface keeps 45 % of its colour (the default 0.012 would
/// keep 1e-21, and a test of far ground could not fail).
const LIGHT_FOG: &[&str] = &["--fog", "0.0002"];

/// What one run printed and drew.
struct Run {
    stdout: String,
    picture: Picture,
    png: Vec<u8>,
    cull: String,
    triangles: String,
}

fn run(name: &str, view_distance: &str, env: &[(&str, &str)], extra: &[&str]) -> Run {
    let out = support::scratch(&format!("horizon-{name}")).join("view.png");
    let output = support::meadow()
        .envs(env.iter().copied())
        .args(["render", "--validation", "--device", support::DEVICE, "--view-distance", view_distance])
        .args(LANDSCAPE)
        .args(extra)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run meadow");
    support::assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout).to_string();
    let line = |start: &str| stdout.lines().find(|l| l.starts_with(start)).unwrap_or_default().to_string();
    let png = std::fs::read(&out).expect("png");
    let (cull, triangles) = (line("cull:"), line("triangles:"));
    Run { stdout, picture: Picture::load(&out), png, cull, triangles }
}

/// The horizon's row (flat ground infinitely far) in a picture `ROWS` high from the landscape camera.
fn horizon_row() -> f32 {
    let focal = 0.5 * ROWS as f32 / (0.5 * FOV_Y_DEG.to_radians()).tan();
    0.5 * ROWS as f32 - focal * (-LANDSCAPE_PITCH_DEG).to_radians().tan()
}

/// The row where flat ground `distance` metres ahead lies.
fn row_at(distance: f32) -> f32 {
    horizon_row() + rows_below_horizon(LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG, distance, ROWS)
}

/// The share of row `y`'s pixels that are not the sky's colour (the top-left pixel's).
fn ground_share(picture: &Picture, y: u32) -> f64 {
    let sky = picture.pixel(0, 0);
    let ground =
        (0..picture.width).filter(|&x| picture.pixel(x, y).iter().zip(sky).any(|(&p, s)| p.abs_diff(s) > 2)).count();
    ground as f64 / f64::from(picture.width)
}

/// Rows between 4 km and 1.5 km ahead (half a row of margin for the relief's ±1.5 m).
fn far_rows() -> std::ops::RangeInclusive<u32> {
    (row_at(4000.0) + 0.5).ceil() as u32..=(row_at(1500.0) - 1.5).floor() as u32
}

#[test]
fn the_ground_reaches_5_km_from_the_landscape_camera_the_same_on_every_thread_count() {
    let rows = far_rows();
    assert!(rows.clone().count() >= 3, "{rows:?}");
    let far = run("far", "5000", &[("LP_NUM_THREADS", "4")], LIGHT_FOG);
    let sky = far.picture.pixel(0, 0);
    assert!(sky[2] > sky[0] + 40, "the top-left pixel is not the sky: {sky:?}");
    for y in rows.clone() {
        let share = ground_share(&far.picture, y);
        assert!(share > 0.95, "row {y} ({:.0} px below the horizon): {share:.3} ground", y as f32 - horizon_row());
    }
    // The control: with the ground to 1 km (its grid's edge at 1.28 km), those rows are sky, so
    // the test sees where the ground ends.
    let near = run("near", "1000", &[("LP_NUM_THREADS", "4")], LIGHT_FOG);
    for y in rows {
        let share = ground_share(&near.picture, y);
        assert!(share < 0.05, "row {y} at a 1 km view distance: {share:.3} ground");
    }
    // The blade rings are sized by the blades' 150 m range, not by the view distance: the same
    // candidates (ring slots times the block's blades) at 1 km and at 5 km.
    let considered = |r: &Run| r.cull.split(" considered").next().map(str::to_string);
    assert!(considered(&far).is_some() && considered(&far) == considered(&near), "{}\n{}", far.cull, near.cull);
    // Bit-identical on one thread and again on four.
    for (name, threads) in [("far-1", "1"), ("far-4", "4")] {
        let again = run(name, "5000", &[("LP_NUM_THREADS", threads)], LIGHT_FOG);
        assert_eq!((&again.cull, &again.triangles), (&far.cull, &far.triangles), "{threads} threads");
        assert!(again.png == far.png, "the picture with {threads} threads differs");
    }
}

#[test]
fn on_a_16_bit_depth_buffer_far_hills_hide_each_other_as_on_a_float_one() {
    // lavapipe attaches D32_SFLOAT; hidden with the 24-bit format, the renderer falls back to
    // D16_UNORM. Hills 10 km out, seen over each other near the horizon, are ordered by depth:
    // with the 0.05 m near plane every surface past 3.3 km stored less than one depth step and
    // farther hills drew over nearer ones (27 % of the pixels of rows 260..300 moved by more than
    // 3 levels from the float picture, mean 6.1); with the near plane derived from the view
    // distance, 2.3 % (mean 0.24).
    let hills = ["--relief", "hills", "--fog", "0.0001"];
    let float = run("d32", "10000", &[], &hills);
    let hide = [("MEADOW_HIDE", "format:D32_SFLOAT,format:X8_D24_UNORM_PACK32")];
    let fixed = run("d16", "10000", &hide, &hills);
    assert!(fixed.stdout.contains("depth in D16_UNORM instead"), "{}", fixed.stdout);
    assert!(!float.stdout.contains("D16_UNORM"), "{}", float.stdout);
    let top = horizon_row() as u32 - 12;
    let (mut moved, mut pixels) = (0u32, 0u32);
    for y in top..top + 40 {
        for x in 0..float.picture.width {
            let (a, b) = (float.picture.pixel(x, y), fixed.picture.pixel(x, y));
            moved += u32::from(a.iter().zip(b).any(|(&p, q)| p.abs_diff(q) > 3));
            pixels += 1;
        }
    }
    let share = f64::from(moved) / f64::from(pixels);
    assert!(share < 0.08, "D16: {:.1} % of the far rows moved from the float picture", 100.0 * share);
}
