//! Structural checks on a render: what any picture of a meadow must show, independent of goldens.

mod support;

use support::Picture;

fn is_grass([r, g, b]: [u8; 3]) -> bool {
    g > r && g > b && g >= 20
}

fn is_sky([r, g, b]: [u8; 3]) -> bool {
    b > g && g > r && b > 150
}

fn luminance(p: [u8; 3]) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

#[test]
fn default_view_is_sky_above_grass_with_vertical_blades() {
    let dir = support::scratch("structure");
    let path = dir.join("structure.png");
    // Static blades: the default wind bends them, which is the keyframe tests' business.
    let output = support::render(&["--blades", "20000", "--size", "320x180", "--mode", "static"], &path);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("triangles: ") && stdout.contains("gpu: ") && stdout.contains("device: llvmpipe"));
    let p = Picture::load(&path);
    assert_eq!((p.width, p.height), (320, 180));

    // Sky: the top tenth of the picture.
    let top: Vec<_> = (0..p.height / 10).flat_map(|y| (0..p.width).map(move |x| (x, y))).collect();
    let sky = top.iter().filter(|(x, y)| is_sky(p.pixel(*x, *y))).count();
    assert!(sky as f64 > 0.95 * top.len() as f64, "sky in the top tenth: {sky}/{}", top.len());

    // Grass dominates the lower 40 %.
    let lower: Vec<_> = (p.height * 6 / 10..p.height).flat_map(|y| (0..p.width).map(move |x| (x, y))).collect();
    let grass = lower.iter().filter(|(x, y)| is_grass(p.pixel(*x, *y))).count();
    assert!(grass as f64 > 0.9 * lower.len() as f64, "grass in the lower 40 %: {grass}/{}", lower.len());

    // Blades are thin vertical features: across a row the brightness changes much more than
    // along a column.
    let (mut dx, mut dy, mut n) = (0.0, 0.0, 0.0);
    for y in p.height * 6 / 10..p.height - 1 {
        for x in 0..p.width - 1 {
            let l = luminance(p.pixel(x, y));
            dx += (luminance(p.pixel(x + 1, y)) - l).abs();
            dy += (luminance(p.pixel(x, y + 1)) - l).abs();
            n += 1.0;
        }
    }
    // Measured on lavapipe: about 20 per pixel across rows and a ratio of 1.4; bare ground or
    // blurred grass gives a few units and a ratio near 1.
    assert!(dx / n > 8.0, "mean horizontal gradient {:.1}: no blade detail", dx / n);
    assert!(dx > 1.25 * dy, "horizontal gradient {dx:.0} vs vertical {dy:.0}: no vertical blade structure");
}

#[test]
fn blade_count_and_segments_change_the_triangle_count() {
    let dir = support::scratch("triangles");
    let args = ["--brute-force", "--blades", "3000", "--segments", "3", "--size", "64x64"];
    let output = support::render(&args, &dir.join("t.png"));
    let stdout = String::from_utf8_lossy(&output.stdout);
    // 3000 blades × 3 segments × 2 triangles: brute force draws every blade (culled, the line
    // counts what the cull drew).
    assert!(stdout.contains("(18000 blades + "), "{stdout}");
}

/// Yellow to red: the cluster-bounds lines (`shaders/debug/cluster_bounds.vert`), never grass or sky.
fn is_bounds_line([r, g, b]: [u8; 3]) -> bool {
    r > 180 && b < 90 && r > g
}

#[test]
fn cluster_bounds_view_draws_the_grid_and_reports_its_pass() {
    let dir = support::scratch("bounds");
    let args = ["--blades", "5000", "--size", "320x180", "--mode", "static"];
    support::render(&args, &dir.join("plain.png"));
    let with_bounds: Vec<&str> = args.iter().copied().chain(["--debug-view", "bounds"]).collect();
    let output = support::render(&with_bounds, &dir.join("bounds.png"));
    // The new pass is timed like every other, with no code of its own for it.
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("cluster bounds "), "{stdout}");
    let (plain, bounds) = (Picture::load(&dir.join("plain.png")), Picture::load(&dir.join("bounds.png")));
    let pixels: Vec<_> = (0..plain.height).flat_map(|y| (0..plain.width).map(move |x| (x, y))).collect();
    let lines = |p: &Picture| pixels.iter().filter(|(x, y)| is_bounds_line(p.pixel(*x, *y))).count();
    assert_eq!(lines(&plain), 0, "no line colour without the view");
    // Measured: about 4 % of a 320x180 picture at the default view (a 9 m field of 1 m clusters).
    assert!(lines(&bounds) > pixels.len() / 100, "only {} line pixels", lines(&bounds));
    // Everything else is the plain picture.
    let other = pixels.iter().filter(|(x, y)| !is_bounds_line(bounds.pixel(*x, *y)));
    let changed = other.filter(|(x, y)| plain.pixel(*x, *y) != bounds.pixel(*x, *y)).count();
    assert!(changed < pixels.len() / 50, "{changed} pixels changed besides the lines");
}
