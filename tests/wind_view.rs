//! The wind debug view (`--debug-view wind`, `render::passes::wind_arrows`): arrows of the wind
//! the grass feels, on a slice above the ground. Seen from straight above, a wind towards +x draws
//! arrows along the picture's rows and one towards +z along its columns; under the fluid wind a
//! collider slows the flow in its lee (shorter arrows), under the analytic field it does not
//! (colliders are not wind there).

mod support;

use std::path::Path;

use support::Picture;

/// Static blades from straight above (+x to the right, +z down the picture).
const ABOVE: [&str; 8] = ["--mode", "static", "--blades", "20000", "--size", "320x180", "--camera", "0,7,0,0,-89"];

/// The pixels where `view` differs from `plain` (the arrows), and of them how many have a changed
/// right-hand neighbour and how many a changed neighbour below.
fn arrow_pixels(plain: &Picture, view: &Picture) -> (usize, usize, usize) {
    let changed = |x: u32, y: u32| plain.pixel(x, y) != view.pixel(x, y);
    let (mut count, mut along_rows, mut along_columns) = (0, 0, 0);
    for y in 0..plain.height - 1 {
        for x in 0..plain.width - 1 {
            if changed(x, y) {
                count += 1;
                along_rows += usize::from(changed(x + 1, y));
                along_columns += usize::from(changed(x, y + 1));
            }
        }
    }
    (count, along_rows, along_columns)
}

fn render(dir: &Path, name: &str, extra: &[&str]) -> Picture {
    let args: Vec<&str> = ABOVE.iter().copied().chain(extra.iter().copied()).collect();
    let path = dir.join(format!("{name}.png"));
    let output = support::render(&args, &path);
    if extra.contains(&"wind") {
        // The pass is timed like every other, with no code of its own for it.
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(stdout.contains("wind arrows "), "{stdout}");
    }
    Picture::load(&path)
}

#[test]
fn the_arrows_point_along_the_wind() {
    let dir = support::scratch("wind-view");
    let plain = render(&dir, "plain", &[]);
    let pixels = (plain.width * plain.height) as usize;
    for (direction, rows) in [("0,0.4", true), ("90,0.4", false)] {
        let view = render(&dir, &format!("wind-{direction}"), &["--wind", direction, "--debug-view", "wind"]);
        let (count, along_rows, along_columns) = arrow_pixels(&plain, &view);
        assert!(count > pixels / 200 && count < pixels / 4, "--wind {direction}: {count} of {pixels} pixels changed");
        let (along, across) = if rows { (along_rows, along_columns) } else { (along_columns, along_rows) };
        // Measured: 1 448 along and 394 across (towards +x), 1 370 and 333 (towards +z).
        assert!(along > 2 * across, "--wind {direction}: {along} neighbours along the wind, {across} across");
    }
}

#[test]
fn under_the_fluid_wind_a_collider_shortens_the_arrows_in_its_lee() {
    let dir = support::scratch("wind-view-collider");
    let plain = render(&dir, "plain", &[]);
    // The arrow pixels: an arrow is as long as the wind is fast.
    let arrows = |field: &str, collider: &[&str]| {
        let mut extra = vec!["--wind", "0,0.4", "--wind-field", field, "--time", "3", "--debug-view", "wind"];
        extra.extend_from_slice(collider);
        arrow_pixels(&plain, &render(&dir, &format!("{field}-{}", collider.len()), &extra)).0
    };
    let collider = ["--collider", "sphere:0,0.5,0,1.2"];
    // Measured: 1 985 arrow pixels without the collider, 1 466 with it.
    let (open, blocked) = (arrows("fluid", &[]), arrows("fluid", &collider));
    assert!(10 * blocked < 9 * open, "fluid: {open} arrow pixels in the open, {blocked} with the collider");
    let (open, blocked) = (arrows("analytic", &[]), arrows("analytic", &collider));
    assert_eq!(open, blocked, "the analytic field's wind ignores colliders");
}
