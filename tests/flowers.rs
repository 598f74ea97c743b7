//! Flowers among the blades (issue #36 item 1, `scene::flowers`, `render::flowers`), on lavapipe
//! with validation and synchronization validation:
//! - the flowers the cull claims are the CPU reference's: the blades it keeps
//!   (`cull_reference::reference_kept`) whose hash falls under the share, every one in the
//!   flowers' buckets and none left in the blades';
//! - a covering map whose green is 0 on one half grows no flower there, and flowers on the other;
//! - the flowers' stems bend the way the wind blows (their pose records read back, turned into
//!   the world), under the keyframes and under Verlet's stateful blades;
//! - bad values and combinations are refused in one line, with nothing written.

#[path = "support/map_files.rs"]
mod map_files;
mod support;

use std::collections::HashSet;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use map_files::refused;
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::poses::recorded_point;
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::render::cull_reference::reference_kept;
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::gpu_constants::{DRAW_FIRST_INSTANCE, DRAW_INSTANCES, DRAW_WORDS};
use meadow::render::uniforms::FrameUniforms;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::cover::{Cover, CoverMap, MapPlacement};
use meadow::scene::flowers::{claimed, flower_hash, Flowers, STORED_KEY};
use meadow::scene::{bezier, Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{GlobalWind, Wind};

const SEGMENTS: u32 = 4;
const EXTENT: vk::Extent2D = vk::Extent2D { width: 160, height: 160 };
const BLADES: u32 = 20_000;
/// Flowers per m²: a quarter of the stored field's 400 blades per m².
const PER_M2: f32 = 100.0;

/// What a frame read back.
struct Frame {
    counts: CullCounts,
    visible: Vec<[u32; 2]>,
    draws: Vec<u32>,
    records: Vec<u32>,
    uniforms: FrameUniforms,
}

/// The cull without the edge-on and occlusion tests (the CPU reference has no depth pyramid,
/// and a flower is never edge-on).
fn culling() -> Culling {
    Culling { orientation: false, occlusion: false, ..Culling::default_for(SEGMENTS) }
}

/// Above the stored field's centre, looking down: the whole field in view.
fn above(scene: &Scene) -> Camera {
    Camera { position: Vec3::new(0.0, scene.ground(0.0, 0.0) + 12.0, 0.0), yaw_deg: 0.0, pitch_deg: -89.0 }
}

/// Three frames of `scene` from `camera` under `wind`, animated by `animation`: the last one's
/// counts, visible list, draws, pose records and uniforms.
fn render(scene: &Scene, camera: &Camera, animation: AnimationSettings, wind: Wind) -> Frame {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(SEGMENTS, culling());
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        *renderer.wind_mut() = wind;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut timings = None;
        for k in 0..3 {
            timings = Some(renderer.render_offscreen(&mut target, camera, k as f32 / 60.0)?);
        }
        let (visible, draws) = renderer.read_visible_list()?;
        let records = renderer.read_pose_records()?;
        let uniforms = renderer.frame_uniforms(camera, 2.0 / 60.0, EXTENT);
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        let counts = timings.and_then(|t| t.cull).expect("culled");
        Ok(Frame { counts, visible, draws, records, uniforms })
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// The flowers' entries: (entry index, stored blade) of both their buckets, after the blades'.
fn flower_entries(frame: &Frame) -> Vec<(usize, u32)> {
    bucket_entries(frame, 0..2)
}

/// The entries of the flowers' buckets `buckets` (0 near, 1 far).
fn bucket_entries(frame: &Frame, buckets: std::ops::Range<u32>) -> Vec<(usize, u32)> {
    let batch = RenderSettings::offscreen(SEGMENTS, culling()).blades_per_instance;
    let first_bucket = culling().buckets().len() as u32;
    (first_bucket + buckets.start..first_bucket + buckets.end)
        .flat_map(|bucket| {
            let draw = &frame.draws[(bucket * DRAW_WORDS) as usize..];
            let first = draw[DRAW_FIRST_INSTANCE as usize] * batch;
            let count = draw[DRAW_INSTANCES as usize] * batch;
            (first..first + count).map(|i| (i as usize, frame.visible[i as usize][0]))
        })
        .filter(|&(_, blade)| blade != u32::MAX)
        .collect()
}

fn flowers() -> Flowers {
    Flowers::new(PER_M2).expect("valid")
}

fn keyframes() -> AnimationSettings {
    AnimationSettings { eval: Eval::Blade, ..Default::default() }
}

#[test]
fn the_flowers_are_the_reference_blades_under_the_share() {
    let scene = Scene::generate(BLADES, 1).with_flowers(flowers()).expect("flowers");
    let frame = render(&scene, &above(&scene), keyframes(), Wind::default());
    let share = scene.flower_share();
    assert_eq!(share, 0.25);
    let kept = reference_kept(&scene, &frame.uniforms);
    let expected: HashSet<u32> =
        kept.iter().map(|k| k.1).filter(|&b| claimed(flower_hash(STORED_KEY, b), share, 1.0, 1.0)).collect();
    let drawn: HashSet<u32> = flower_entries(&frame).into_iter().map(|e| e.1).collect();
    assert!(expected.len() > 1_000, "{} flowers of {} kept blades", expected.len(), kept.len());
    assert_eq!(drawn, expected, "the flowers drawn");
    let counts = &frame.counts;
    assert_eq!(counts.classes[0].name, "flowers");
    assert_eq!(counts.classes[0].drawn as usize, expected.len(), "{}", counts.summary());
    assert_eq!(counts.blades_drawn() as usize, kept.len() - expected.len(), "{}", counts.summary());
    assert!(counts.summary().contains(&format!("{} flowers drawn", expected.len())), "{}", counts.summary());
    // About a quarter of the kept blades, the share.
    let fraction = expected.len() as f64 / kept.len() as f64;
    assert!((fraction - 0.25).abs() < 0.02, "{fraction}");
}

#[test]
fn a_covering_map_without_green_grows_no_flower_there() {
    let plain = Scene::generate(BLADES, 1);
    let size = plain.terrain.size as f64;
    // Full grass everywhere; green 0 for x < 0, full past it.
    let green: Vec<u8> = (0..64).map(|x| if x < 32 { 0 } else { 255 }).collect();
    let map = CoverMap {
        width: 64,
        height: 1,
        grass: vec![255; 64],
        flowers: green,
        placement: MapPlacement { x: size, z: size, mirrored: false },
    };
    let cover = Cover { slope_limit_deg: None, map: Some(Arc::new(map)) };
    let scene = plain.with_cover(cover, BLADES, 1).with_flowers(flowers()).expect("flowers");
    assert_eq!(scene.blades.len() as u32, BLADES, "full grass keeps every blade");
    let frame = render(&scene, &above(&scene), keyframes(), Wind::default());
    let x: Vec<f32> = flower_entries(&frame).iter().map(|e| scene.blades[e.1 as usize].position[0]).collect();
    // Past a texel and a terrain cell of the edge, where the green is bilinear across it.
    let margin = (size / 64.0) as f32 + scene.terrain.cell_size();
    let bare = x.iter().filter(|&&x| x < -margin).count();
    let flowering = x.iter().filter(|&&x| x > margin).count();
    assert_eq!(bare, 0, "flowers where the map's green is 0");
    assert!(flowering > 500, "{flowering} flowers where the green is full");
}

/// The mean downwind (+x) lean of the flowers' stem tips, in metres: each flower's tip in its
/// pose records (by entry) turned into the world by its blade's frame.
fn mean_tip_x(scene: &Scene, frame: &Frame) -> f32 {
    mean_tip_x_of(scene, frame, &flower_entries(frame), 300)
}

/// The same over `entries`, at least `least` of them.
fn mean_tip_x_of(scene: &Scene, frame: &Frame, entries: &[(usize, u32)], least: usize) -> f32 {
    assert!(entries.len() > least, "{} flowers", entries.len());
    let sum: f32 = entries
        .iter()
        .map(|&(entry, blade)| {
            let b = &scene.blades[blade as usize];
            let (across, normal) = bezier::frame(b);
            let tip = recorded_point(&frame.records, (entry, SEGMENTS), SEGMENTS, b.height);
            (across * tip.x + Vec3::Y * tip.y + normal * tip.z).x
        })
        .sum();
    sum / entries.len() as f32
}

fn towards(direction_deg: f32) -> Wind {
    Wind { global: Some(GlobalWind { direction_deg, strength: 0.8, gusts: false }), ..Default::default() }
}

#[test]
fn the_flowers_bend_the_way_the_wind_blows_under_keyframes_and_verlet() {
    let scene = Scene::generate(BLADES, 1).with_flowers(flowers()).expect("flowers");
    let camera = above(&scene);
    let verlet = AnimationSettings { mode: Mode::Verlet, ..Default::default() };
    for (name, animation) in [("keyframes", keyframes()), ("verlet", verlet)] {
        let east = mean_tip_x(&scene, &render(&scene, &camera, animation.clone(), towards(0.0)));
        let west = mean_tip_x(&scene, &render(&scene, &camera, animation.clone(), towards(180.0)));
        let calm = mean_tip_x(&scene, &render(&scene, &camera, animation, Wind::default()));
        // Measured: the tips 0.21 m (keyframes) and 0.24 m (Verlet) downwind either way.
        assert!(
            east > calm + 0.1 && west < calm - 0.1,
            "{name}: tips at x {east} (east wind), {calm} (calm), {west} (west)"
        );
    }
}

#[test]
fn near_flowers_are_posed_in_their_own_bucket_and_bend_downwind() {
    // A metre above the ground looking down: heads 8 pixels across and more, the near bucket (a
    // stem of 4 segments, its pose pipeline the response's at 4 segments).
    let scene = Scene::generate(BLADES, 1).with_flowers(flowers()).expect("flowers");
    let camera = Camera { position: Vec3::new(0.0, scene.ground(0.0, 0.0) + 1.0, 0.0), yaw_deg: 0.0, pitch_deg: -89.0 };
    let east = render(&scene, &camera, keyframes(), towards(0.0));
    let calm = render(&scene, &camera, keyframes(), Wind::default());
    let near = bucket_entries(&east, 0..1);
    assert_eq!(near, bucket_entries(&calm, 0..1), "the wind moves no flower between buckets");
    let (lean, rest) = (mean_tip_x_of(&scene, &east, &near, 20), mean_tip_x_of(&scene, &calm, &near, 20));
    assert!(lean > rest + 0.1, "near tips at x {lean} (east wind), {rest} (calm)");
    // Every level of a near flower's stem is written: its mid-level leans with its tip.
    let mid = |frame: &Frame| -> f32 {
        near.iter()
            .map(|&(entry, blade)| {
                let b = &scene.blades[blade as usize];
                let (across, normal) = bezier::frame(b);
                let p = recorded_point(&frame.records, (entry, SEGMENTS / 2), SEGMENTS, b.height);
                (across * p.x + normal * p.z).x
            })
            .sum::<f32>()
            / near.len() as f32
    };
    assert!(mid(&east) > mid(&calm) + 0.02, "mid-levels at x {} (east), {} (calm)", mid(&east), mid(&calm));
}

#[test]
fn render_names_the_flowers_in_its_scene_line_and_counts_them_beside_the_blades() {
    let (output, written) =
        map_files::render_cli("flowers-line", &["--flowers", "40", "--clumps", "2", "--validation"]);
    support::assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = |start: &str| stdout.lines().find(|l| l.starts_with(start)).unwrap_or_default().to_string();
    assert!(line("scene: ").ends_with(", clumps of 2 m, 40 flowers per m²"), "{stdout}");
    let cull = line("cull: ");
    let flowers: u32 = cull
        .rsplit("; ")
        .next()
        .and_then(|t| t.strip_suffix(" flowers drawn"))
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(flowers > 0 && written, "{stdout}");
}

#[test]
fn bad_flower_values_and_combinations_are_refused_in_one_line() {
    for (case, value) in [("negative", "-1"), ("nan", "NaN"), ("zero", "0"), ("huge", "1e12")] {
        refused(&format!("flowers-{case}"), &["--flowers", value], "--flowers");
    }
    // Denser than the blades (a flower takes a blade's place): the field's own budget.
    refused("flowers-dense", &["--flowers", "401"], "a flower takes a blade's place");
    refused(
        "flowers-dense-field",
        &["--flowers", "60", "--field", "64", "--density", "50"],
        "a flower takes a blade's place",
    );
    refused("flowers-brute", &["--flowers", "20", "--brute-force"], "--brute-force");
    refused("flowers-vertex", &["--flowers", "20", "--eval", "vertex"], "--eval vertex");
    refused("flowers-floor", &["--flowers", "20", "--mode", "floor"], "--mode floor");
    // The flowers' two buckets after seven of the blades': more than the cull's eight.
    refused("flowers-buckets", &["--flowers", "20", "--lod-segments", "8,7,6,5,4,3,2"], "--lod-segments");
}
