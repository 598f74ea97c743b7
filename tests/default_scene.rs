//! What `meadow render` draws when no flag names a scene (issue #37, item 6), on lavapipe with
//! validation and synchronization validation: the landscape, an unbounded field from the
//! landscape camera with the far field to 2 km, under a fog that leaves a surface 1 km away at
//! least 30 % of its colour; `--brute-force`, `--mode floor`, `--submission` and `--debug-view
//! bounds` keep the stored 100 000-blade field; a block field ends in haze at its view distance;
//! a blade distance over the default view distance is refused in one line.

mod support;

use meadow::scene::camera::{rows_below_horizon, FOV_Y_DEG, LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG};
use support::{scratch, Picture};

/// `meadow render --validation ARGS`: its standard output and picture.
fn render(name: &str, args: &[&str]) -> (String, Picture) {
    let out = scratch(&format!("default-scene-{name}")).join("out.png");
    let output = support::render(args, &out);
    (String::from_utf8_lossy(&output.stdout).to_string(), Picture::load(&out))
}

/// The line of `stdout` that starts with `prefix`.
fn line<'a>(stdout: &'a str, prefix: &str) -> &'a str {
    stdout.lines().find(|l| l.starts_with(prefix)).unwrap_or_else(|| panic!("no `{prefix}` line:\n{stdout}"))
}

/// The exact sRGB decoding of an 8-bit level, to linear light.
fn linear(level: u8) -> f64 {
    let c = f64::from(level) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The mean linear green of `picture` over `rows` and the middle `columns` columns, minus the
/// sky's (the top row's).
fn green_over_sky(picture: &Picture, rows: std::ops::RangeInclusive<u32>, columns: u32) -> f64 {
    let sky = linear(picture.pixel(picture.width / 2, 0)[1]);
    let x0 = (picture.width - columns) / 2;
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in rows {
        for x in x0..x0 + columns {
            sum += linear(picture.pixel(x, y)[1]) - sky;
            n += 1.0;
        }
    }
    sum / n
}

#[test]
fn with_no_flags_render_draws_the_landscape_and_its_fog_lets_1_km_show() {
    let (stdout, foggy) = render("landscape", &[]);
    assert!(line(&stdout, "scene: ").starts_with("scene: an unbounded field"), "{stdout}");
    let far = line(&stdout, "far field: ");
    assert!(far.contains("m to 2000 m") && !far.starts_with("far field: 0 plants"), "{far}");

    // The same view without fog: in linear light the fog mixes the surface towards the sky by the
    // transmittance, so at the rows of 1 km (± 100 m) the fogged picture keeps that share of the
    // unfogged one's difference from the sky: e^-1 = 0.37 at 0.001 per metre, 0.33–0.41 over
    // the band; the old default's 0.012 kept 6e-6.
    let (_, clear) = render("landscape-no-fog", &["--fog", "0"]);
    let rows = clear.height as f32;
    let horizon =
        0.5 * rows - 0.5 * rows / (0.5 * FOV_Y_DEG.to_radians()).tan() * (-LANDSCAPE_PITCH_DEG).to_radians().tan();
    let row =
        |d: f32| (horizon + rows_below_horizon(LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG, d, clear.height)).round() as u32;
    let band = row(1100.0)..=row(900.0);
    let kept = green_over_sky(&foggy, band.clone(), 200) / green_over_sky(&clear, band.clone(), 200);
    assert!((0.3..=0.45).contains(&kept), "at 1 km (rows {band:?}) the fog keeps {kept:.3} of the colour");
}

#[test]
fn the_reference_paths_keep_the_stored_field_without_blades() {
    let stored: [&[&str]; 4] =
        [&["--brute-force"], &["--mode", "floor"], &["--submission", "instanced"], &["--debug-view", "bounds"]];
    for args in stored {
        let (stdout, _) = render("stored", &[args, &["--size", "160x90"]].concat());
        let scene = line(&stdout, "scene: ");
        assert!(scene.starts_with("scene: 100000 blades"), "{args:?}: {scene}");
        assert!(!stdout.contains("far field: "), "{args:?}: {stdout}");
    }
    // --blades alone is the stored field too, through the cull.
    let (stdout, _) = render("blades", &["--blades", "2000", "--size", "160x90"]);
    assert!(line(&stdout, "scene: ").starts_with("scene: 2000 blades"), "{stdout}");
}

#[test]
fn a_blade_distance_over_the_default_view_distance_is_refused() {
    for (args, why) in [
        (&["--blades", "500", "--blade-distance", "300"][..], "over the view distance, 150 m by default"),
        (&["--blade-distance", "2500"], "over the view distance, 2000 m by default"),
    ] {
        let out = scratch("default-scene-bad").join("never.png");
        let output = support::meadow().arg("render").args(args).arg("--out").arg(&out).output().expect("run meadow");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: ") && stderr.contains(why), "{args:?}: {stderr}");
        assert!(!out.exists());
    }
}

#[test]
fn a_block_field_ends_in_haze_at_its_view_distance() {
    // No fog, the landscape camera, no far field: a block field's ground, blades and flowers
    // fade into the sky's colour over the last fifth of the view distance (`horizon_haze`), so
    // at 150 m the field ends in haze and not at a line. Against the same view to 300 m (the
    // blades still to 150 m, so the same blades), the rows of 142–148 m keep 5 % of their
    // difference from the sky (measured; the haze there is 0.07–0.27) and the rows of 90–110 m
    // all of it (1.000). Without the haze the edge kept all of it and ended at a line.
    let base = ["--field", "infinite", "--camera", "landscape", "--fog", "0", "--far-field", "off", "--flowers", "20"];
    let (_, hazy) = render("haze-150", &[&base[..], &["--view-distance", "150"]].concat());
    let (_, clear) = render("haze-300", &[&base[..], &["--view-distance", "300"]].concat());
    let rows = clear.height as f32;
    let horizon =
        0.5 * rows - 0.5 * rows / (0.5 * FOV_Y_DEG.to_radians()).tan() * (-LANDSCAPE_PITCH_DEG).to_radians().tan();
    let row =
        |d: f32| (horizon + rows_below_horizon(LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG, d, clear.height)).round() as u32;
    let kept = |near: f32, far: f32| {
        let band = row(far)..=row(near);
        green_over_sky(&hazy, band.clone(), 400) / green_over_sky(&clear, band, 400)
    };
    let (edge, inside) = (kept(142.0, 148.0), kept(90.0, 110.0));
    assert!(edge < 0.4, "at 142–148 m the haze keeps {edge:.3} of the colour");
    assert!((0.97..=1.03).contains(&inside), "at 90–110 m the haze keeps {inside:.3} of the colour");
}
