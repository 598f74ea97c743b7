//! Where grass grows (issue #35 items 2 and 3, `scene::cover`): on lavapipe with validation and
//! synchronization validation, a block field's cull leaves a steep ramp bare under
//! `--slope-limit` and keeps every blade of the flat ground beside it; a covering map of 0 draws
//! no blade there and visits none of its tiles; a gradient map seen from above, the distance LOD
//! off, draws counts that follow it band by band; a stored field is scattered under the rules, and
//! brute force draws it as the cull does; and bad cover maps and values are refused in one line.

#[path = "support/map_files.rs"]
mod map_files;
#[path = "support/roots.rs"]
mod roots;
mod support;

use std::sync::Arc;

use ash::vk;
use glam::{DVec2, Vec3};
use map_files::{ihdr, png, refused, render_cli};
use meadow::app::{with_device, GpuOptions};
use meadow::imagediff::compare_rgb;
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::field_gpu::Origin;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::cover::{Cover, CoverMap, MapPlacement};
use meadow::scene::field::FieldSpec;
use meadow::scene::heightmap::{Heightmap, TerrainScale};
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use support::{scratch, transcript, Picture};

/// The ramp map's extent: 64 texels of 3.9 m, white 125 m up.
const RAMP: TerrainScale = TerrainScale { x: 250.0, y: 125.0, z: 250.0 };

/// A 65 × 65 map, flat for x ≤ 0 and rising at 45° past it (a texel's rise is its spacing).
fn ramp_map() -> Heightmap {
    let side = 65;
    let texels = (0..side * side).map(|i: u32| ((i % side).saturating_sub(32) * 2048).min(65_535) as u16).collect();
    Heightmap { width: side, height: side, texels, bits: 16, scale: RAMP, mirrored: true }
}

/// What a frame drew: its camera, the roots of its blade buckets (x, z) and its cull counts.
type Frame = (Camera, Vec<DVec2>, CullCounts);

/// One renderer over `scene` with `culling`: each camera's drawn roots and counts.
fn render(scene: &Scene, culling: Culling, cameras: &[Camera]) -> Vec<Frame> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, culling);
        let per_instance = settings.blades_per_instance;
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 320, height: 180 })?;
        let mut frames = Vec::new();
        for camera in cameras {
            let timings = renderer.render_offscreen(&mut target, camera, 0.0)?;
            let (visible, draws) = renderer.read_visible_list()?;
            let origin = (Origin::under(camera).cell, camera.position.y);
            let placed = roots::roots(scene, (&visible, &draws), origin, per_instance);
            let counts = timings.cull.expect("the cull ran");
            frames.push((*camera, placed.into_iter().map(|(p, _)| p).collect(), counts));
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(frames)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// Looking straight down from `height` m above (x, z).
fn above(x: f32, z: f32, height: f32) -> Camera {
    Camera { position: Vec3::new(x, height, z), yaw_deg: 0.0, pitch_deg: -89.0 }
}

#[test]
fn the_slope_limit_leaves_a_steep_ramp_bare_and_flat_ground_covered() {
    let spec = FieldSpec { size: None, density: 100.0 };
    let plain = Scene::blocks_on_map(spec, Arc::new(ramp_map()), 1);
    let limited = plain.clone().with_cover(Cover { slope_limit_deg: Some(30.0), map: None }, 0, 1);
    let cameras = [above(0.0, 0.0, 70.0)];
    let count = |frame: &Frame| {
        let flat = frame.1.iter().filter(|p| p.x < -8.0).count();
        let steep = frame.1.iter().filter(|p| p.x > 8.0).count();
        (flat, steep)
    };
    let (plain_flat, plain_steep) = count(&render(&plain, Culling::default_for(4), &cameras)[0]);
    let (flat, steep) = count(&render(&limited, Culling::default_for(4), &cameras)[0]);
    assert!(plain_flat > 2_000 && plain_steep > 2_000, "without a limit: {plain_flat} flat, {plain_steep} steep");
    assert_eq!(steep, 0, "blades on the 45° ramp under a 30° limit");
    assert_eq!(flat, plain_flat, "the flat ground lost blades to the slope limit");
}

/// A map of `grass` (`width` × `height`, row by row) over `RAMP`'s extent, mirrored.
fn cover_map(width: u32, height: u32, grass: Vec<u8>) -> Cover {
    let placement = MapPlacement { x: RAMP.x, z: RAMP.z, mirrored: true };
    let flowers = grass.clone();
    Cover { slope_limit_deg: None, map: Some(Arc::new(CoverMap { width, height, grass, flowers, placement })) }
}

#[test]
fn a_covering_map_of_zero_draws_no_blade_there_and_visits_none_of_its_tiles() {
    // Flat ground, bare for x < 0: a map of 64 × 1 texels, 0 then 255 (the edge between texels
    // 31 and 32, at x = −1.98 m; bilinear to x = +1.98 m).
    let flat = Heightmap { texels: vec![0; 65 * 65], ..ramp_map() };
    let spec = FieldSpec { size: None, density: 100.0 };
    let full = Scene::blocks_on_map(spec, Arc::new(flat), 1);
    let grass = (0..64).map(|x| if x < 32 { 0 } else { 255 }).collect();
    let split = full.clone().with_cover(cover_map(64, 1, grass), 0, 1);
    let cameras = [above(0.0, 0.0, 40.0)];
    let (_, full_roots, full_counts) = render(&full, Culling::default_for(4), &cameras).remove(0);
    let (_, roots, counts) = render(&split, Culling::default_for(4), &cameras).remove(0);
    let bare = roots.iter().filter(|p| p.x < -2.0).count();
    let covered = |r: &[DVec2]| r.iter().filter(|p| p.x > 2.0).count();
    assert!(full_roots.iter().filter(|p| p.x < -2.0).count() > 2_000, "{}", full_counts.summary());
    assert_eq!(bare, 0, "blades drawn where the map is 0");
    assert_eq!(covered(&roots), covered(&full_roots), "the covered half lost blades");
    // The bare half's tiles are not visited: about half the tiles and their blades.
    let (tiles, visited) = (counts.tiles_visible as f64, counts.after_tiles as f64);
    let (full_tiles, full_visited) = (full_counts.tiles_visible as f64, full_counts.after_tiles as f64);
    assert!(tiles < 0.6 * full_tiles, "{tiles} of {full_tiles} tiles visited");
    assert!(visited < 0.6 * full_visited, "{visited} of {full_visited} candidates visited");
}

#[test]
fn a_gradient_map_seen_from_above_draws_counts_that_follow_it() {
    // Density rising along x from 0 at x = −125 m to 1 at +125 m (256 texels), seen from 60 m
    // above x = 0 with the distance LOD off: each band of x holds the blades the full field draws
    // there, each times the density at its root, within 5 %.
    let flat = Heightmap { texels: vec![0; 65 * 65], ..ramp_map() };
    let spec = FieldSpec { size: None, density: 60.0 };
    let full = Scene::blocks_on_map(spec, Arc::new(flat), 1);
    let cover = cover_map(256, 1, (0..=255).collect());
    let thinned = full.clone().with_cover(cover.clone(), 0, 1);
    let no_lod = Culling { density: false, segment_lod: false, ..Culling::default_for(4) };
    let cameras = [above(0.0, 0.0, 60.0)];
    let (_, full_roots, _) = render(&full, no_lod, &cameras).remove(0);
    let (_, roots, _) = render(&thinned, no_lod, &cameras).remove(0);
    let map = cover.map.as_ref().expect("a map");
    let (lo, hi) = full_roots.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p.x), hi.max(p.x)));
    let bands = 6;
    let band = |x: f64| (((x - lo) / (hi - lo) * f64::from(bands)) as usize).min(bands as usize - 1);
    let (mut expected, mut drawn) = (vec![0.0f64; bands as usize], vec![0usize; bands as usize]);
    for p in &full_roots {
        expected[band(p.x)] += f64::from(map.density_at(p.x, p.y));
    }
    for p in &roots {
        drawn[band(p.x)] += 1;
    }
    let checked: Vec<_> = (0..bands as usize).filter(|&b| drawn[b] >= 2_000).collect();
    assert!(checked.len() >= 3, "bands of 2 000 blades or more: {drawn:?}");
    for b in checked {
        let off = (drawn[b] as f64 - expected[b]) / expected[b];
        assert!(off.abs() <= 0.05, "band {b}: {} drawn against {:.0} expected ({drawn:?})", drawn[b], expected[b]);
    }
    assert!(drawn[0] * 2 < drawn[bands as usize - 1], "the counts do not rise with the map: {drawn:?}");
}

#[test]
fn a_stored_field_is_scattered_under_the_rules_and_brute_force_draws_it_alike() {
    let map = ramp_map();
    let plain = Scene::generate_on_map(20_000, &map, 3);
    let rules = Cover { slope_limit_deg: Some(30.0), ..cover_map(2, 1, vec![255, 0]) };
    let covered = plain.clone().with_cover(rules.clone(), 20_000, 3);
    let terrain = &covered.terrain;
    let x_of = |s: &Scene| s.blades.iter().map(|b| f64::from(b.position[0])).collect::<Vec<_>>();
    // The field is 7 m a side over the map's centre. The ramp (x > 1 m, past the terrain cell
    // that bends at x = 0) is bare by its slope; the map thins the flat ground (x < −1 m) to
    // about half (255 at x = −125 m, 0 at +125 m), blade by blade as the density at its root.
    let (plain_x, x) = (x_of(&plain), x_of(&covered));
    assert!(x.iter().all(|&x| x < 1.0), "a blade on the ramp");
    let flat_plain: Vec<f64> = plain_x.iter().copied().filter(|&x| x < -1.0).collect();
    let expected: f64 = flat_plain.iter().map(|&x| f64::from(rules.density(x, 0.0, glam::Vec2::ZERO))).sum();
    let kept = x.iter().filter(|&&x| x < -1.0).count() as f64;
    assert!(plain_x.iter().filter(|&&x| x > 1.0).count() > 2_000, "no blade on the ramp to begin with");
    assert!(
        flat_plain.len() > 2_000 && (kept - expected).abs() <= 0.05 * expected,
        "{kept} kept, {expected:.0} expected"
    );
    assert!(covered
        .blades
        .iter()
        .all(|b| (b.position[1] - terrain.height_at(b.position[0], b.position[2])).abs() < 0.02));
    // Brute force and the cull (the frustum alone) draw the same picture of it.
    let dir = scratch("cover-stored");
    image::save_buffer(dir.join("ramp.png"), &ramp_bytes(&map), 65, 65, image::ColorType::L16).expect("map");
    image::save_buffer(dir.join("cover.png"), &[255, 0], 2, 1, image::ColorType::L8).expect("cover");
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let (ramp, cover) = (at("ramp.png"), at("cover.png"));
    let base = [
        "--blades",
        "20000",
        "--seed",
        "3",
        "--heightmap",
        &ramp,
        "--terrain-scale",
        "250,125,250",
        "--size",
        "320x180",
    ];
    let shot = |extra: &[&str], name: &str| {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        support::render(&args, &dir.join(name));
        Picture::load(&dir.join(name))
    };
    let rules = ["--cover", &cover, "--slope-limit", "30"];
    let culled = shot(&[&rules[..], &["--cull", "frustum", "--lod", "none"]].concat(), "culled.png");
    let brute = shot(&[&rules[..], &["--brute-force"]].concat(), "brute.png");
    let (stats, _) = compare_rgb(&culled.rgb, &brute.rgb, 3);
    assert!(stats.within_fraction() >= 0.999, "{:.4} within ±3", stats.within_fraction());
    // And the rules changed the picture.
    let plain = shot(&["--brute-force"], "plain.png");
    let (stats, _) = compare_rgb(&plain.rgb, &brute.rgb, 3);
    assert!(stats.within_fraction() < 0.9, "the cover rules left {:.4} of the picture", stats.within_fraction());
}

/// The ramp map's texels as a 16-bit PNG's native-order bytes.
fn ramp_bytes(map: &Heightmap) -> Vec<u8> {
    map.texels.iter().flat_map(|t| t.to_ne_bytes()).collect()
}

#[test]
fn bad_cover_maps_and_values_are_refused_in_one_line() {
    let dir = scratch("cover-files");
    let file = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("written");
        path.to_string_lossy().into_owned()
    };
    let good_path = dir.join("good.png");
    image::save_buffer(&good_path, &[0, 255, 255, 0], 2, 2, image::ColorType::L8).expect("saved");
    let good_bytes = std::fs::read(&good_path).expect("read");
    let text = file("text.png", b"not a png at all");
    let truncated = file("truncated.png", &good_bytes[..good_bytes.len() / 2]);
    let empty = file("empty.png", &png(ihdr(0, 0, 8, 0), None, &[]));
    let huge = file("huge.png", &png(ihdr(100_000, 100_000, 8, 0), None, &[0, 1, 2]));
    let missing = dir.join("missing.png").to_string_lossy().into_owned();
    let fifo = dir.join("fifo.png");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo").success());
    let (fifo, dir_text) = (fifo.to_string_lossy().into_owned(), dir.to_string_lossy().into_owned());
    let scale = ["--terrain-scale", "1000,1,1000"];
    for (case, path, why) in [
        ("cover-text", &text, "not a PNG"),
        ("cover-truncated", &truncated, "--cover"),
        ("cover-empty", &empty, "--cover"),
        ("cover-huge", &huge, "at most 16384 a side"),
        ("cover-missing", &missing, "cannot read it"),
        ("cover-directory", &dir_text, "not a file"),
        ("cover-fifo", &fifo, "not a file"),
    ] {
        refused(case, &[&scale[..], &["--cover", path]].concat(), why);
    }
    let good = good_path.to_string_lossy().into_owned();
    refused("cover-alone", &["--cover", &good], "--heightmap or --terrain-scale");
    for (case, limit, why) in [
        ("slope-negative", "-1", "outside 0..=90"),
        ("slope-over", "91", "outside 0..=90"),
        ("slope-nan", "NaN", "finite"),
    ] {
        refused(case, &["--slope-limit", limit], why);
    }
    // Valid: a 1 × 1 map (a uniform density) and a palette map (expanded; its red is read).
    let one = dir.join("one.png");
    image::save_buffer(&one, &[128], 1, 1, image::ColorType::L8).expect("saved");
    let palette = file("palette.png", &png(ihdr(2, 2, 8, 3), Some(&[255, 0, 0, 0, 255, 0]), &[0, 0, 1, 0, 1, 0]));
    for (case, path) in [("cover-one", one.to_string_lossy().into_owned()), ("cover-palette", palette)] {
        let (output, written) = render_cli(case, &[&scale[..], &["--cover", &path]].concat());
        assert!(output.status.success() && written, "{case}: {}", transcript(&output));
    }
}

#[test]
fn the_cover_view_colours_bare_ground_red_and_covered_ground_green() {
    // A split map over the procedural relief seen from above (bare for x < 0: the picture's left
    // half): `--debug-view cover` draws the cover unlit, red where bare and green where full.
    let dir = scratch("cover-view");
    let mut split = vec![0u8; 64];
    split[32..].fill(255);
    image::save_buffer(dir.join("split.png"), &split, 64, 1, image::ColorType::L8).expect("map");
    let map = dir.join("split.png").to_string_lossy().into_owned();
    let args = [
        "--field",
        "infinite",
        "--density",
        "40",
        "--terrain-scale",
        "200,1,200",
        "--cover",
        &map,
        "--camera",
        "0,30,0,0,-89",
        "--fog",
        "0",
        "--size",
        "160x90",
    ];
    let shot = |extra: &[&str], name: &str| {
        support::render(&[&args[..], extra].concat(), &dir.join(name));
        Picture::load(&dir.join(name))
    };
    // The mean red and green of the columns from `from` to `to` (fractions of the width).
    let mean = |p: &Picture, from: f32, to: f32| {
        let (mut r, mut g, mut n) = (0.0, 0.0, 0.0);
        for y in 0..p.height {
            for x in (from * p.width as f32) as u32..(to * p.width as f32) as u32 {
                let [pr, pg, _] = p.pixel(x, y);
                (r, g, n) = (r + f64::from(pr), g + f64::from(pg), n + 1.0);
            }
        }
        (r / n, g / n)
    };
    let view = shot(&["--debug-view", "cover"], "cover.png");
    let ((lr, lg), (rr, rg)) = (mean(&view, 0.05, 0.4), mean(&view, 0.6, 0.95));
    assert!(lr > 3.0 * lg, "the bare half: red {lr:.0}, green {lg:.0}");
    assert!(rg > 2.0 * rr, "the covered half: red {rr:.0}, green {rg:.0}");
    // Shaded, the bare earth is not that red.
    let shaded = shot(&[], "shaded.png");
    let (sr, sg) = mean(&shaded, 0.05, 0.4);
    assert!(sr < 2.0 * sg, "the shaded bare half: red {sr:.0}, green {sg:.0}");
}
