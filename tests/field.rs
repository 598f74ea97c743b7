//! Camera-following blocks (`--field`, Belyaev §2.1) on lavapipe: the same view 100 km from the
//! origin renders identically, GPU memory does not depend on where the camera is, the drawn
//! terrain lies on the relief (the relief-grid pass, recomputed when the camera crosses blocks),
//! grass reaches
//! the view distance, and bad field input is refused.

mod support;

use ash::vk;
use glam::Vec3;
use meadow::app::{with_device, GpuOptions};
use meadow::imagediff::compare_rgb;
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use support::{meadow, scratch, transcript};

const EXTENT: vk::Extent2D = vk::Extent2D { width: 320, height: 180 };

fn settings(culling: Culling) -> RenderSettings {
    RenderSettings::offscreen(4, culling)
}

/// Each camera's picture (RGBA), cull counts and the allocator's bytes after rendering it.
fn render(culling: Culling, cameras: &[Camera]) -> Vec<(Vec<u8>, CullCounts, u64)> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1);
        // Static blades: the wind's gusts are not periodic in the world, the field is.
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let mut renderer = Renderer::new(device.clone(), &scene, settings(culling), animation)?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut out = Vec::new();
        for camera in cameras {
            let timings = renderer.render_offscreen(&mut target, camera, 0.0)?;
            let bytes = device.allocator().generate_report().total_allocated_bytes;
            out.push((target.pixels().to_vec(), timings.cull.expect("the cull ran"), bytes));
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(out)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

fn camera(x: f32, z: f32) -> Camera {
    let relief = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1)
        .field
        .expect("a field")
        .ground
        .relief()
        .expect("a relief")
        .clone();
    let ground = relief.height(f64::from(x), f64::from(z)) as f32;
    Camera { position: Vec3::new(x, ground + 1.7, z), yaw_deg: 30.0, pitch_deg: -10.0 }
}

#[test]
fn a_view_100_km_away_renders_as_it_does_at_the_origin_with_the_same_memory() {
    // The world repeats every kilometre (`scene::field::WORLD_PERIOD`): 100 km away is the same
    // place, and positions relative to the camera's cell keep every bit of precision.
    let cameras = [camera(1.5, 2.5), camera(100_001.5, 100_002.5), camera(-99_998.5, 2.5)];
    let views = render(Culling::default_for(4), &cameras);
    let (near, near_counts, near_bytes) = &views[0];
    assert!(near_counts.total_drawn() > 10_000, "{}", near_counts.summary());
    for (far, far_counts, far_bytes) in &views[1..] {
        assert_eq!(far_counts, near_counts);
        let (stats, _) = compare_rgb(far, near, 3);
        assert!(stats.within_fraction() >= 0.999, "{:.4} within ±3", stats.within_fraction());
        assert_eq!(far_bytes, near_bytes, "GPU memory moved with the camera");
    }
}

/// The relief-grid pass dispatches only when a clipmap level's window moved, and then fills only
/// the vertices that entered (`passes::ground_fill`): a renderer that drew another place first
/// (36 m away: level 0's window moved), and then the same view twice (the second time without a
/// dispatch), renders what a fresh renderer renders.
#[test]
fn the_relief_grid_follows_the_camera_across_blocks() {
    let culling = Culling::default_for(4);
    let (first, there) = (camera(1.5, 2.5), camera(37.5, -21.5));
    let moved = render(culling, &[first, there, there]);
    let fresh = render(culling, &[there]);
    assert_ne!(moved[0].0, fresh[0].0, "the two views must differ for the test to mean anything");
    for (pixels, counts, _) in &moved[1..] {
        assert_eq!(counts, &fresh[0].1);
        assert!(pixels == &fresh[0].0, "a stale relief grid: the view differs from a fresh renderer's");
    }
}

#[test]
fn the_drawn_terrain_follows_the_relief() {
    // The relief-grid pass evaluates the relief on the GPU at the terrain grid's vertices (every
    // 2 m, at even world coordinates here); at a vertex on a hill, the drawn terrain lies where
    // the CPU's relief says. Looking up from 0.3 m under it, the terrain (drawn without face
    // culling) hides the sky; from 0.8 m over it, above the tallest blade, the sky shows. A
    // terrain drawn anywhere else (flat, or a grid shifted by a cell) shows the sky from under it.
    let relief = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1)
        .field
        .expect("a field")
        .ground
        .relief()
        .expect("a relief")
        .clone();
    let hill = (0..40)
        .flat_map(|i| (0..40).map(move |j| (2.0 * i as f32, 2.0 * j as f32)))
        .find(|&(x, z)| relief.height(f64::from(x), f64::from(z)) > 0.5)
        .expect("a vertex on a hill");
    let ground = relief.height(f64::from(hill.0), f64::from(hill.1)) as f32;
    let looking_up =
        |dy: f32| Camera { position: Vec3::new(hill.0, ground + dy, hill.1), yaw_deg: 0.0, pitch_deg: 80.0 };
    let views = render(Culling::default_for(4), &[looking_up(-0.3), looking_up(0.8)]);
    let centre = |rgba: &[u8]| -> Vec<[u8; 3]> {
        let (w, h) = (EXTENT.width as usize, EXTENT.height as usize);
        let rows = h / 2 - 10..h / 2 + 10;
        rows.flat_map(|y| (w / 2 - 10..w / 2 + 10).map(move |x| (y * w + x) * 4))
            .map(|i| [rgba[i], rgba[i + 1], rgba[i + 2]])
            .collect()
    };
    let (under, over) = (centre(&views[0].0), centre(&views[1].0));
    let sky = over[0];
    assert!(over.iter().all(|&p| p == sky), "from over the hill the sky fills the centre");
    assert!(under.iter().all(|&p| p != sky), "from under the hill ({ground:.2} m) the terrain hides the sky");
}

#[test]
fn grass_reaches_the_view_distance() {
    // Between 120 and 150 m there is grass: the longer view draws more blades.
    let cameras = [Camera { pitch_deg: 0.0, ..camera(0.5, 0.5) }];
    let short = render(Culling { view_distance: 120.0, ..Culling::default_for(4) }, &cameras);
    let long = render(Culling::default_for(4), &cameras);
    let (short, long) = (short[0].1.total_drawn(), long[0].1.total_drawn());
    assert!(long > short + 1000, "150 m: {long} blades, 120 m: {short}");
}

/// `meadow render ARGS` refused with exit 2 and one line naming `expect`.
fn refused(args: &[&str], expect: &str) {
    let dir = scratch("field-bad");
    let output = meadow()
        .arg("render")
        .args(args)
        .args(["--device", support::DEVICE, "--out"])
        .arg(dir.join("x.png"))
        .output()
        .expect("run meadow");
    assert_eq!(output.status.code(), Some(2), "{args:?}: {}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: ") && stderr.contains(expect), "{args:?}: {stderr}");
    assert!(!dir.join("x.png").exists());
}

#[test]
fn bad_field_input_is_refused() {
    refused(&["--field", "0"], "empty");
    refused(&["--field", "-5"], "empty");
    refused(&["--field", "wide"], "'wide'");
    refused(&["--field", "infinite", "--density", "0"], "above 0");
    refused(&["--field", "infinite", "--density", "5000"], "4096");
    refused(&["--field", "infinite", "--blades", "1000"], "--blades");
    refused(&["--blades", "1000", "--density", "100"], "--field");
    refused(&["--field", "infinite", "--brute-force"], "--brute-force");
    refused(&["--field", "infinite", "--view-distance", "1000", "--blade-distance", "600"], "--blade-distance 600");
    refused(&["--field", "infinite", "--view-distance", "NaN"], "NaN");
}

#[test]
fn a_camera_past_the_block_index_is_refused_and_one_inside_it_draws() {
    // 2³¹ cells of 4 m end at 8.59e9 m: past `scene::field::MAX_DISTANCE` (8e9 m) a camera is
    // refused with one line before any work (it once drew nothing, and exited 0).
    refused(&["--field", "infinite", "--camera", "1e10,1.7,0,0,0"], "8e9 m from the origin");
    refused(&["--field", "infinite", "--camera", "0,1.7,-8.1e9,0,0"], "8e9 m from the origin");
    // At 8e9 m (whole kilometres: the same place, the world repeats) the view draws what it
    // draws at the origin.
    let dir = scratch("field-far");
    let drawn = |x: &str| -> String {
        let output = meadow()
            .args(["render", "--validation", "--device", support::DEVICE, "--size", "160x90", "--mode", "static"])
            .args(["--field", "infinite", "--camera", &format!("{x},1.7,0,30,-10"), "--out"])
            .arg(dir.join("far.png"))
            .output()
            .expect("run meadow");
        support::assert_clean(&output);
        let stdout = String::from_utf8_lossy(&output.stdout).to_string();
        let cull = stdout.lines().find(|l| l.starts_with("cull:")).expect("a cull line");
        cull.split("drawn ").nth(1).expect("drawn").split(' ').next().expect("count").to_string()
    };
    let (near, far) = (drawn("0"), drawn("8e9"));
    assert!(near.parse::<u64>().expect("a count") > 1000, "{near} blades drawn at the origin");
    assert_eq!(far, near, "blades drawn at 8e9 m and at the origin");
}

#[test]
fn a_bounded_field_ends_where_its_size_says() {
    // Standing 10 m outside a 20 m field looking at it: grass, but less than the unbounded field.
    let dir = scratch("field-bounded");
    let run = |field: &str| -> String {
        let output = meadow()
            .args(["render", "--validation", "--device", support::DEVICE, "--size", "160x90", "--mode", "static"])
            .args(["--field", field, "--camera", "0,3,20,0,-15", "--out"])
            .arg(dir.join(format!("{field}.png")))
            .output()
            .expect("run meadow");
        support::assert_clean(&output);
        let stdout = String::from_utf8_lossy(&output.stdout).to_string();
        stdout.lines().find(|l| l.starts_with("cull:")).expect("a cull line").to_string()
    };
    let drawn = |line: &str| -> u64 {
        line.split("drawn ").nth(1).and_then(|s| s.split(' ').next()).and_then(|s| s.parse().ok()).expect("drawn")
    };
    let (bounded, unbounded) = (drawn(&run("20")), drawn(&run("infinite")));
    assert!(bounded > 0 && bounded * 2 < unbounded, "20 m field: {bounded}, unbounded: {unbounded}");
}

#[test]
fn a_longer_view_distance_set_live_needs_a_new_renderer_for_its_rings() {
    // A rebuild keeps the cull's buffers, which hold the rings of the distance the field was
    // uploaded with: a rebuild for a longer one is refused (`Renderer::fits_upload`; the viewer
    // then makes a new renderer), and the renderer keeps drawing its rings. The control:
    // uploaded with the longer distance, the frame has more rings.
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1);
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let with_distance = |view_distance: f32| {
            let mut culling = Culling::default_for(4);
            culling.view_distance = view_distance;
            settings(culling)
        };
        let camera = camera(0.0, 0.0);
        let rings = |renderer: &Renderer| renderer.frame_uniforms(&camera, 0.0, EXTENT).cull_tiles.y;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut renderer = Renderer::new(device.clone(), &scene, with_distance(40.0), animation.clone())?;
        let uploaded = rings(&renderer);
        let refused = renderer.rebuild(&scene, with_distance(300.0), animation.clone()).err().map(|e| e.to_string());
        assert!(refused.as_deref().is_some_and(|e| e.contains("a new renderer")), "{refused:?}");
        let live = rings(&renderer);
        let drawn: u32 =
            renderer.render_offscreen(&mut target, &camera, 0.0)?.cull.expect("the cull ran").drawn.iter().sum();
        drop(renderer);
        let control = rings(&Renderer::new(device.clone(), &scene, with_distance(300.0), animation)?);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok((uploaded, live, drawn, control))
    });
    assert_eq!(messages, Some(0), "validation messages");
    let (uploaded, live, drawn, control) = result.expect("rendered");
    assert_eq!(live, uploaded, "the renderer keeps its rings");
    assert!(control > uploaded, "uploaded for 300 m: {control} rings against {uploaded}");
    assert!(drawn > 0);
}
