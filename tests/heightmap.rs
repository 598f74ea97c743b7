//! Heightmaps (issue #35 item 1, `scene::heightmap`, `render::ground::HeightmapGround`): a known
//! 16-bit map gives known heights on the CPU, a block field on it fills every clipmap level with
//! the map's heights at the levels' world vertices (read back from the GPU near the origin and
//! 100 km out, on lavapipe with validation and synchronization validation), its roots stand on
//! the drawn ground, a stored field on it samples it; and bad maps and values are refused in one
//! line, exit 2, before anything is written.

#[path = "support/map_files.rs"]
mod map_files;
#[path = "support/roots.rs"]
mod roots;
mod support;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ash::vk;
use glam::{DVec2, I64Vec2, UVec2, UVec3, Vec3};
use map_files::{ihdr, png, refused, render_cli};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::camera_grid;
use meadow::render::culling::Culling;
use meadow::render::field_gpu::Origin;
use meadow::render::ground_clipmap::{self, Clipmap, CELLS, PERIOD_HALF_METRES};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::heightmap::{Heightmap, TerrainScale};
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use support::{scratch, transcript};

const SCALE: TerrainScale = TerrainScale { x: 1000.0, y: 40.0, z: 1000.0 };
const SIDE: u32 = 65;

/// A 65 × 65 16-bit map: a ramp along x, a bump, ripples along z.
fn texels() -> Vec<u16> {
    (0..SIDE * SIDE)
        .map(|i| {
            let (x, z) = (f64::from(i % SIDE), f64::from(i / SIDE));
            let bump = (-((x - 40.0).powi(2) + (z - 20.0).powi(2)) / 60.0).exp();
            (x * 400.0 + 30_000.0 * bump + 2_000.0 * (z * 0.7).sin() + 2_000.0) as u16
        })
        .collect()
}

/// Write `texels` (`width` × `height`, 16-bit grey) as a PNG at `path`.
fn save16(path: &Path, texels: &[u16], width: u32, height: u32) {
    let bytes: Vec<u8> = texels.iter().flat_map(|v| v.to_ne_bytes()).collect();
    image::save_buffer(path, &bytes, width, height, image::ColorType::L16).expect("saved");
}

/// The map written in a scratch directory of test `name`'s own.
fn map_file(name: &str) -> PathBuf {
    let path = scratch(&format!("heightmap-map-{name}")).join("map.png");
    save16(&path, &texels(), SIDE, SIDE);
    path
}

#[test]
fn a_known_map_gives_known_heights_on_the_cpu() {
    let map = Heightmap::load(&map_file("cpu"), SCALE).expect("loaded");
    assert_eq!((map.width, map.height, map.bits), (SIDE, SIDE, 16));
    assert_eq!(map.texels, texels(), "the file's texels, as written");
    let spacing = SCALE.x / f64::from(SIDE - 1);
    for (x, z) in [(0u32, 0u32), (40, 20), (64, 64), (7, 51)] {
        let world = DVec2::new(f64::from(x), f64::from(z)) * spacing - DVec2::splat(SCALE.x / 2.0);
        let expected = f64::from(texels()[(z * SIDE + x) as usize]) / 65_535.0 * SCALE.y;
        assert!((map.height_at(world.x, world.y) - expected).abs() < 1e-9, "texel ({x}, {z})");
    }
    // Half-way between texels: bilinear; past the edge: mirrored.
    let mid = map.height_at(-500.0 + 0.5 * spacing, -500.0);
    let t = texels();
    assert!((mid - 0.5 * (f64::from(t[0]) + f64::from(t[1])) / 65_535.0 * SCALE.y).abs() < 1e-9);
    assert!((map.height_at(510.0, 3.0) - map.height_at(490.0, 3.0)).abs() < 1e-12);
    // A stored field on the map samples it at its grid's vertices.
    let scene = Scene::generate_on_map(5_000, &map, 1);
    let terrain = &scene.terrain;
    let n = terrain.cells + 1;
    for (x, z) in [(0, 0), (terrain.cells / 3, terrain.cells), (terrain.cells, terrain.cells / 2)] {
        let at = DVec2::new(f64::from(x), f64::from(z)) * f64::from(terrain.cell_size()) + f64::from(terrain.origin());
        let h = terrain.heights[(z * n + x) as usize];
        assert!((f64::from(h) - map.height_at(at.x, at.y)).abs() < 1e-4, "vertex ({x}, {z})");
    }
    assert!(scene
        .blades
        .iter()
        .all(|b| (b.position[1] - terrain.height_at(b.position[0], b.position[2])).abs() < 0.02));
}

/// A frame read back: its camera, the clipmap's texels, the visible list and the cull's draws.
type Frame = (Camera, Vec<[f32; 4]>, Vec<[u32; 2]>, Vec<u32>);

/// One renderer over a block field on the map: the clipmap read back after each camera.
fn render(scene: &Scene, cameras: &[Camera]) -> Vec<Frame> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 320, height: 180 })?;
        let mut frames = Vec::new();
        for camera in cameras {
            renderer.render_offscreen(&mut target, camera, 0.0)?;
            let (visible, draws) = renderer.read_visible_list()?;
            frames.push((*camera, renderer.read_ground()?, visible, draws));
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(frames)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// The map's height at a world vertex in half-metres on the world's period (centred on the
/// world's origin, as `heightmap_fill.comp` places it).
fn map_at(map: &Heightmap, at: I64Vec2) -> f64 {
    let half = PERIOD_HALF_METRES / 2;
    let centred = I64Vec2::select(at.cmpge(I64Vec2::splat(half)), at - I64Vec2::splat(PERIOD_HALF_METRES), at);
    let world = centred.as_dvec2() * 0.5;
    map.height_at(world.x, world.y)
}

#[test]
fn a_block_field_on_the_map_fills_every_level_with_its_heights_and_stands_on_them() {
    let map = Arc::new(Heightmap::load(&map_file("gpu"), SCALE).expect("loaded"));
    let scene = Scene::blocks_on_map(FieldSpec { size: None, density: 400.0 }, Arc::clone(&map), 1);
    let camera = |x: f32, z: f32| {
        let ground = map.height_at(f64::from(x), f64::from(z)) as f32;
        Camera { position: Vec3::new(x, ground + 1.7, z), yaw_deg: 30.0, pitch_deg: -10.0 }
    };
    // Near the origin (on the bump), and 100 km out (50 of the map's mirrored periods).
    let frames = render(&scene, &[camera(180.5, -300.5), camera(100_180.5, -100_300.5)]);
    let culling = Culling::default_for(4);
    let clipmap = Clipmap::for_view(culling.view_distance, culling.blade_range());
    let dims = clipmap.shape().dims;
    for (camera, grid, _, _) in &frames {
        let cell = Origin::under(camera).cell;
        let windows = clipmap.windows(cell);
        let (mut worst, mut worst_slope, mut lowest, mut highest) = (0.0f64, 0.0f64, f64::MAX, f64::MIN);
        for level in 0..clipmap.levels {
            let step_hm = (2.0 * clipmap.step(level)) as i64;
            let first = windows[level as usize];
            let base = ground_clipmap::grid_window(first).rem_euclid(dims.as_i64vec3()).as_uvec3();
            for z in (0..=CELLS).step_by(3) {
                for x in (0..=CELLS).step_by(3) {
                    let slot = level * dims.x * dims.z + camera_grid::slot(UVec3::new(x, 0, z), base, dims);
                    let t = grid[slot as usize];
                    let at = ((first + UVec2::new(x, z).as_i64vec2()) * step_hm)
                        .rem_euclid(I64Vec2::splat(PERIOD_HALF_METRES));
                    let h = map_at(&map, at);
                    worst = worst.max((f64::from(t[0]) - h).abs());
                    // The slope by central differences over a tenth of a metre.
                    let d = |dx: i64, dz: i64| map_at(&map, at + I64Vec2::new(dx, dz));
                    let slope = DVec2::new(d(1, 0) - d(-1, 0), d(0, 1) - d(0, -1));
                    worst_slope =
                        worst_slope.max((f64::from(t[2]) - slope.x).abs().max((f64::from(t[3]) - slope.y).abs()));
                    (lowest, highest) = (lowest.min(h), highest.max(h));
                }
            }
        }
        let at = camera.position;
        assert!(worst <= 1e-3, "camera at {at}: a texel {worst} m off the map");
        // A 1 m central difference straddles a texel edge at most once: a loose check of the sign
        // and size of the stored slope.
        assert!(worst_slope <= 0.2, "camera at {at}: a slope {worst_slope} off the map's");
        assert!(highest - lowest > 20.0, "camera at {at}: the levels cover {lowest}..{highest} m of the map");
    }
    // The two views, a whole number of the map's periods apart, hold the same texels.
    assert!(frames[0].1 == frames[1].1, "the map 100 km out differs from the map at the origin");
    // The cull's roots stand on the drawn ground (sunk 1 cm), on the bump's slopes too, within
    // 1 mm and the root's packing: a half float of its height above the camera
    // (`visible_scale`), whose step at 8 m is 4 mm, an angle of at most 1/2048 of the ground's
    // slope seen from the camera.
    let blades_per_instance = RenderSettings::offscreen(4, culling).blades_per_instance;
    for (camera, _, visible, draws) in &frames {
        let cell = Origin::under(camera).cell;
        let eye = camera.position.y;
        let placed = roots::roots(&scene, (visible, draws), (cell, eye), blades_per_instance);
        let ground = |at: I64Vec2| map_at(&map, at);
        let (mut worst, mut near) = (0.0f64, 0);
        for &(p, root) in &placed {
            let off = (root - (clipmap.drawn_height_of(&ground, cell, p) - 0.01)).abs();
            let above = (root - f64::from(eye)).abs().max(1e-3);
            let half_step = 2f64.powi(above.log2().floor() as i32 - 11);
            worst = worst.max(off - half_step);
            near += usize::from(above < 4.0 && off <= 2e-3);
        }
        assert!(
            placed.len() > 10_000 && near > 100,
            "{} roots, {near} within 2 mm of the ground and 4 m of the eye's height",
            placed.len()
        );
        assert!(worst <= 1e-3, "a root {worst} m past its packing's step off the drawn ground");
    }
}

#[test]
fn bad_maps_and_values_are_refused_in_one_line() {
    let dir = scratch("heightmap-files");
    let file = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("written");
        path.to_string_lossy().into_owned()
    };
    let good = map_file("bad");
    let good_bytes = std::fs::read(&good).expect("read");
    let text = file("text.png", b"not a png at all");
    let truncated = file("truncated.png", &good_bytes[..good_bytes.len() / 2]);
    let empty = file("empty.png", &png(ihdr(0, 0, 8, 0), None, &[]));
    let huge = file("huge.png", &png(ihdr(100_000, 100_000, 8, 0), None, &[0, 1, 2]));
    let one = dir.join("one.png");
    image::save_buffer(&one, &[7], 1, 1, image::ColorType::L8).expect("saved");
    let colour = dir.join("colour.png");
    image::save_buffer(&colour, &[10, 20, 30, 10, 10, 10, 5, 5, 5, 1, 2, 3], 2, 2, image::ColorType::Rgb8)
        .expect("saved");
    // Palette images, 2 × 2 at 8 bits an index: a palette of red and green, and one of greys.
    let indices = [0, 0, 1, 0, 1, 0];
    let red_green = file("palette.png", &png(ihdr(2, 2, 8, 3), Some(&[255, 0, 0, 0, 255, 0]), &indices));
    let greys = file("greys.png", &png(ihdr(2, 2, 8, 3), Some(&[10, 10, 10, 200, 200, 200]), &indices));
    let missing = dir.join("missing.png").to_string_lossy().into_owned();
    let fifo = dir.join("fifo.png");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(made.success());
    let (one, colour, fifo, dir_text) = (
        one.to_string_lossy().into_owned(),
        colour.to_string_lossy().into_owned(),
        fifo.to_string_lossy().into_owned(),
        dir.to_string_lossy().into_owned(),
    );
    for (case, path, why) in [
        ("text", &text, "not a PNG"),
        ("truncated", &truncated, "--heightmap"),
        ("empty", &empty, "--heightmap"),
        ("huge", &huge, "at most 16384 a side"),
        ("one", &one, "2 × 2 at least"),
        ("colour", &colour, "colour"),
        ("palette", &red_green, "colour"),
        ("missing", &missing, "cannot read it"),
        ("directory", &dir_text, "not a file"),
        ("fifo", &fifo, "not a file"),
    ] {
        refused(case, &["--heightmap", path], why);
    }
    // A palette of greys is grey.
    let (output, written) = render_cli("greys", &["--heightmap", &greys]);
    assert!(output.status.success() && written, "{}", transcript(&output));
    let good = good.to_string_lossy().into_owned();
    for (case, args, why) in [
        ("scale-zero", vec!["--heightmap", &good, "--terrain-scale", "0,10,100"], "above 0"),
        ("scale-negative", vec!["--heightmap", &good, "--terrain-scale", "100,-1,100"], "above 0"),
        ("scale-nan", vec!["--heightmap", &good, "--terrain-scale", "NaN,1,1"], "finite"),
        ("scale-alone", vec!["--terrain-scale", "100,10,100"], "--heightmap"),
        ("relief", vec!["--heightmap", &good, "--relief", "hills", "--field", "40"], "--heightmap"),
        ("period", vec!["--heightmap", &good, "--terrain-scale", "3000,10,1000", "--field", "infinite"], "divide"),
        ("field-square", vec!["--heightmap", &good, "--terrain-scale", "100,10,100", "--field", "40"], "square"),
    ] {
        refused(case, &args, why);
    }
}
