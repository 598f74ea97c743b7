//! The viewer's overlay (issue 12) under Xvfb, with validation and synchronization validation:
//! scripted clicks and drags on its controls (pointer events through egui's input) change the
//! viewer; a screenshot with the overlay differs from one without only inside its panels; F1
//! hides it; the capture button writes a trace whose spans nest in their frames.

mod support;

use std::path::Path;
use std::process::Output;

use support::xvfb::Xvfb;
use support::{assert_clean, meadow, scratch, transcript, Picture};

/// `meadow view --validation` under an Xvfb of its own, at 1280x720 with `args`, in `dir`.
fn view(dir: &Path, args: &[&str]) -> Output {
    view_scaled(dir, args, "1")
}

/// `view` with winit's X11 scale factor (the display's DPI scale) set to `scale`.
fn view_scaled(dir: &Path, args: &[&str], scale: &str) -> Output {
    let xvfb = Xvfb::start("1280x1024x24");
    xvfb.on(&mut meadow())
        .env("WINIT_X11_SCALE_FACTOR", scale)
        .args(["view", "--validation", "--device", support::DEVICE, "--blades", "3000", "--size", "1280x720"])
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run meadow")
}

/// `meadow view --validation` of the landscape (no scene flag) at 1280x720, running `script`.
fn xvfb_landscape(dir: &Path, script: &str) -> Output {
    let xvfb = Xvfb::start("1280x1024x24");
    xvfb.on(&mut meadow())
        .env("WINIT_X11_SCALE_FACTOR", "1")
        .args(["view", "--validation", "--device", support::DEVICE, "--size", "1280x720", "--script", script])
        .current_dir(dir)
        .output()
        .expect("run meadow")
}

fn script(dir: &Path, name: &str, lines: &str) -> String {
    std::fs::write(dir.join(name), lines).expect("write script");
    name.to_string()
}

#[test]
fn a_dragged_distance_applies_when_the_drag_ends_and_a_longer_one_makes_a_new_renderer() {
    // The landscape (blades to 150 m, the view to 2 km): the blade distance slider dragged to its
    // end (504 m) applies when the drag ends, and, past the cull's rings uploaded at start,
    // through a new renderer (`Renderer::fits_upload`); then the view distance dragged a little
    // way shorter rebuilds the passes alone. Before, the sliders sprang back while dragged and a
    // drag applied nothing. Validation and synchronization validation stay clean.
    let dir = scratch("ui-distances");
    let s = script(&dir, "distances.txt", "5 ui-drag 400 blade distance m\n25 ui-drag -10 view distance m\n45 quit\n");
    let output = xvfb_landscape(&dir, &s);
    assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    let field = |line: &str, name: &str| -> Option<f32> { line.split(name).nth(1)?.split(',').next()?.parse().ok() };
    let applied: Vec<(f32, f32)> = stdout
        .lines()
        .filter(|l| l.starts_with("culling Culling {"))
        .filter_map(|l| Some((field(l, "view_distance: ")?, field(l, "blade_distance: ")?)))
        .collect();
    assert_eq!(applied.len(), 2, "{}", transcript(&output));
    assert_eq!(applied[0], (2000.0, 504.0), "the blade distance's drag: {}", transcript(&output));
    assert!((100.0..2000.0).contains(&applied[1].0), "the view distance's drag: {}", transcript(&output));
    let replaced = stdout.lines().filter(|l| l.contains("longer than the scene was uploaded for")).count();
    assert_eq!(replaced, 1, "one new renderer, for the blade distance: {}", transcript(&output));
}

#[test]
fn clicks_and_drags_on_the_controls_change_the_viewer() {
    let dir = scratch("ui-controls");
    let s = script(
        &dir,
        "controls.txt",
        "5 ui-click GPU culling\n10 ui-drag 60 wind strength\n15 ui-click uniform\n20 ui-click gusts\n\
         22 ui-click GPU culling\n25 ui-click occlusion\n28 ui-click 3 in flight\n31 ui-click Immediate\n\
         34 ui-click frame budget\n36 ui-click add a calm area here\n39 ui-click remove calm #0\n45 quit\n",
    );
    let output = view(&dir, &["--script", &s]);
    assert_clean(&output);
    // Each control changed what its key changes, in order (the lines the viewer prints when a
    // control changes something; the help printed at start names them too, hence whole lines).
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = |start: &str, has: &str| stdout.lines().position(|l| l.starts_with(start) && l.contains(has));
    let culling = line("mode Texture,", ", brute force");
    let wind = line("wind strength 0.", "deg");
    let mode = line("mode Uniform,", "");
    let gusts = line("gusts off", "");
    assert!(culling.is_some() && wind.is_some() && mode.is_some() && gusts.is_some(), "{}", transcript(&output));
    assert!(culling < wind && wind < mode && mode < gusts, "{}", transcript(&output));
    // The culling panel's own tests, frames in flight (a new renderer), the present mode (a new
    // swapchain) and the frame budget.
    let occlusion = line("culling Culling { enabled: true,", "occlusion: false");
    let in_flight = line("3 frames in flight", "");
    let present = line("present mode Immediate", "");
    let budget = line("frame budget 50 ms", "");
    assert!(
        gusts < occlusion && occlusion < in_flight && in_flight < present && present < budget,
        "{}",
        transcript(&output)
    );
    assert!(budget.is_some(), "{}", transcript(&output));
    // The calm areas' list: one added under the camera, then removed.
    let (added, removed) = (line("calm area ", " to "), line("calm area #0 removed", ""));
    assert!(budget < added && added < removed, "{}", transcript(&output));
    // The control: the same frames without the clicks change nothing.
    let s = script(&dir, "idle.txt", "30 quit\n");
    let idle = view(&dir, &["--script", &s]);
    assert_clean(&idle);
    let stdout = String::from_utf8_lossy(&idle.stdout);
    let changed = ["mode ", "wind strength", "gusts ", "culling ", "present mode", "frame budget", "calm area"];
    assert!(!stdout.lines().any(|l| changed.iter().any(|c| l.starts_with(c))), "{}", transcript(&idle));
    // A control that is not there, and the overlay turned off: one line, exit 2.
    for (args, said) in [
        (vec!["--script", "nope.txt"], "no control 'warp drive' on screen (shown: "),
        (vec!["--script", "nope.txt", "--no-ui"], "need the overlay shown"),
    ] {
        script(&dir, "nope.txt", "3 ui-click warp drive\n9 quit\n");
        let output = view(&dir, &args);
        assert_eq!(output.status.code(), Some(2), "{}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.starts_with("error: --script: ") && stderr.contains(said), "{stderr}");
    }
}

/// The panels' rectangles (pixels) the viewer printed for its screenshot.
fn panels(output: &Output) -> Vec<[u32; 4]> {
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("overlay panels in the screenshot: "))
        .unwrap_or_else(|| panic!("{}", transcript(output)));
    line.split(' ')
        .map(|r| {
            let v: Vec<u32> = r.split(',').map(|n| n.parse().expect("pixel")).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
}

#[test]
fn a_screenshot_with_the_overlay_differs_from_one_without_only_inside_its_panels() {
    // Time frozen, no frame budget: the scene is the same frame in both runs.
    let dir = scratch("ui-screenshot");
    let s = script(&dir, "frozen.txt", "0 pause\n0 time 2.0\n20 screenshot shot.png\n21 quit\n");
    std::fs::create_dir_all(dir.join("plain")).expect("dir");
    std::fs::create_dir_all(dir.join("ui")).expect("dir");
    std::fs::copy(dir.join(&s), dir.join("plain").join(&s)).expect("copy");
    std::fs::copy(dir.join(&s), dir.join("ui").join(&s)).expect("copy");
    let plain = view(&dir.join("plain"), &["--script", &s]);
    assert_clean(&plain);
    let with_ui = view(&dir.join("ui"), &["--script", &s, "--screenshot-ui"]);
    assert_clean(&with_ui);
    let rects = panels(&with_ui);
    assert_eq!(rects.len(), 3, "the controls, timing and view panels: {rects:?}");
    let (a, b) = (Picture::load(&dir.join("plain/shot.png")), Picture::load(&dir.join("ui/shot.png")));
    assert_eq!((a.width, a.height), (b.width, b.height));
    let inside = |x: u32, y: u32| rects.iter().any(|r| x >= r[0] && x < r[2] && y >= r[1] && y < r[3]);
    let (mut changed_inside, mut pixels_inside) = (0u64, 0u64);
    for y in 0..a.height {
        for x in 0..a.width {
            let i = 3 * (y * a.width + x) as usize;
            let same = a.rgb[i..i + 3] == b.rgb[i..i + 3];
            if inside(x, y) {
                pixels_inside += 1;
                changed_inside += u64::from(!same);
            } else {
                assert!(same, "pixel {x},{y} outside the panels {rects:?} changed");
            }
        }
    }
    assert!(changed_inside * 2 > pixels_inside, "{changed_inside} of {pixels_inside} panel pixels changed");
    // F1 hides the overlay: the screenshot is the plain one again.
    std::fs::create_dir_all(dir.join("hidden")).expect("dir");
    let s2 =
        script(&dir.join("hidden"), "hidden.txt", "0 pause\n0 time 2.0\n5 press f1\n20 screenshot shot.png\n21 quit\n");
    let hidden = view(&dir.join("hidden"), &["--script", &s2, "--screenshot-ui"]);
    assert_clean(&hidden);
    let c = Picture::load(&dir.join("hidden/shot.png"));
    assert!(a.rgb == c.rgb, "F1 did not hide the overlay");
}

#[test]
fn renderer_replacements_keep_the_overlay_s_texture_copies_validation_clean() {
    // `]` 13 times, one a frame: a new renderer (and scene) each time, to which the viewer
    // resends egui's font whole, patched in the same frame with the new blade count's glyphs.
    // Those copies into one texture once raced (7 SYNC-HAZARD-WRITE-AFTER-WRITE in this run);
    // now a texture's pending copies never overlap (`render::overlay::textures::queue`).
    let dir = scratch("ui-replace");
    let presses: String = (1..=13).map(|frame| format!("{} press ]\n", frame + 1)).collect();
    let s = script(&dir, "double.txt", &format!("{presses}20 quit\n"));
    let xvfb = Xvfb::start("1280x1024x24");
    let output = xvfb
        .on(&mut meadow())
        .args(["view", "--validation", "--device", support::DEVICE, "--blades", "1", "--size", "640x360"])
        .args(["--script", &s])
        .current_dir(&dir)
        .output()
        .expect("run meadow");
    assert_clean(&output);
    // Each press replaced the renderer: 2, 4, ... 8192 blades.
    let stdout = String::from_utf8_lossy(&output.stdout);
    let replaced = (1..=13).filter(|n| stdout.contains(&format!(" segments, {} blades,", 1u32 << n))).count();
    assert_eq!(replaced, 13, "{}", transcript(&output));
}

#[test]
fn the_capture_button_writes_a_trace_whose_spans_nest_in_their_frames() {
    let dir = scratch("ui-capture");
    std::fs::create_dir_all(dir.join("captures")).expect("dir");
    let s = script(&dir, "capture.txt", "5 ui-click capture\n90 quit\n");
    let output = view(&dir, &["--script", &s, "--capture-dir", "captures"]);
    assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("capturing 60 frames") && stdout.contains("wrote captures/meadow-capture-1.json"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(dir.join("captures/meadow-capture-1.json")).expect("the trace");
    let doc: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let events = doc["traceEvents"].as_array().expect("traceEvents");
    let spans = |pid: u64, pick: &dyn Fn(&str) -> bool| -> Vec<(String, f64, f64, String)> {
        events
            .iter()
            .filter(|e| e["ph"] == "X" && e["pid"] == pid && pick(e["name"].as_str().unwrap_or("")))
            .map(|e| {
                let ts = e["ts"].as_f64().expect("ts");
                let frame = e["args"]["frame"].as_str().unwrap_or(e["name"].as_str().unwrap_or("")).to_string();
                (e["name"].as_str().unwrap_or("").to_string(), ts, ts + e["dur"].as_f64().expect("dur"), frame)
            })
            .collect()
    };
    let frames = spans(2, &|n| n.starts_with("frame "));
    assert_eq!(frames.len(), 60, "GPU frames in the trace");
    let passes = spans(2, &|n| !n.starts_with("frame "));
    assert!(passes.iter().any(|p| p.0 == "overlay") && passes.iter().any(|p| p.0 == "blades"), "{passes:?}");
    // Every pass lies inside its frame's span (to a microsecond of rounding).
    for (name, start, end, frame) in &passes {
        let (_, f0, f1, _) = frames.iter().find(|f| &f.0 == frame).unwrap_or_else(|| panic!("{frame} of {name}"));
        assert!(*start >= f0 - 1.0 && *end <= f1 + 1.0, "{name} [{start}, {end}] outside {frame} [{f0}, {f1}]");
    }
    // The CPU side: a record span per frame.
    assert_eq!(spans(1, &|n| n == "record").len(), 60);
    // Without --capture-dir the panel says how to get one; a capture dir that is not a directory
    // is refused before anything opens.
    let output = view(&dir, &["--frames", "2", "--capture-dir", "capture.txt"]);
    assert_eq!(output.status.code(), Some(2), "{}", transcript(&output));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--capture-dir capture.txt: not a directory"));
}

#[test]
fn the_overlay_follows_the_display_scale_factor() {
    // At a scale factor of 2 (a high-DPI display), egui draws the same panels at twice the
    // pixels: each panel twice as wide, the scene untouched outside them.
    let dir = scratch("ui-scale");
    let s = script(&dir, "shot.txt", "0 pause\n10 screenshot shot.png\n11 quit\n");
    let one = view_scaled(&dir, &["--script", &s, "--screenshot-ui"], "1");
    assert_clean(&one);
    let two = view_scaled(&dir, &["--script", &s, "--screenshot-ui"], "2");
    assert_clean(&two);
    let (a, b) = (panels(&one), panels(&two));
    let width = |r: &[u32; 4]| f64::from(r[2] - r[0]);
    let ratio = width(&b[0]) / width(&a[0]);
    assert!((ratio - 2.0).abs() < 0.05, "the controls panel is {ratio:.3} times as wide: {a:?} then {b:?}");
}
