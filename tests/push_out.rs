//! Push-out (Zhang Xia §6.2, issue #34; `render::animation::push_out`), on lavapipe with
//! validation and synchronization validation: for every blade whose root lies inside a resting
//! sphere's ground circle, every recorded backbone point above the root lies outside the sphere
//! within 2 mm, read back from the pose records:
//! - by brute force (records by stored blade) under the keyframes, Pelzer's sine, Verlet and the
//!   inertial chains: stateless and stateful responses alike;
//! - through the cull (records by visible entry, each LOD bucket's levels), under the keyframes
//!   and Verlet.
//!
//! The control: the same blades under the same sphere 50 m up (whose ground circle holds the same
//! roots, and which pushes nothing) have points inside the resting sphere's volume, so the check
//! can fail; and the blades no circle holds are recorded to the bit as without the sphere.

#[path = "support/pose_records.rs"]
mod pose_records;
mod support;

use ash::vk;
use glam::Vec3;
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::poses::recorded_point;
use meadow::render::animation::push_out::circle_holds;
use meadow::render::animation::sine::SinePhase;
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::render::culling::Culling;
use meadow::render::gpu_constants::{DRAW_FIRST_INSTANCE, DRAW_INSTANCES, DRAW_WORDS};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{bezier, Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Collider, Wind};
use pose_records::{backbone, run, SEGMENTS};

const RADIUS: f32 = 0.3;
/// Within this of the surface counts as outside (the records are 16-bit).
const TOLERANCE: f32 = 0.002;

fn scene() -> Scene {
    Scene::generate(4000, 4)
}

/// A sphere of `RADIUS` whose lowest point is `lift` above the ground at (0.1, 0.2).
fn sphere(scene: &Scene, lift: f32) -> Collider {
    let (x, z) = (0.1, 0.2);
    Collider::at_rest(Vec3::new(x, scene.ground(x, z) + RADIUS + lift, z), Vec3::splat(RADIUS))
}

/// A light steady wind and `collider`.
fn windy(collider: Collider) -> Wind {
    Wind { colliders: vec![collider], ..pose_records::wind(30.0, 0.3) }
}

/// The roots the ground circle of `collider` holds.
fn held(scene: &Scene, collider: &Collider) -> Vec<usize> {
    let held: Vec<usize> = (0..scene.blades.len())
        .filter(|&b| circle_holds(collider.center, collider.radii, Vec3::from(scene.blades[b].position)))
        .collect();
    assert!(held.len() > 60, "{} blades under the sphere", held.len());
    held
}

/// The points of `points` (world, the root first) inside `collider` by more than the tolerance.
fn inside(points: &[Vec3], collider: &Collider) -> usize {
    points[1..].iter().filter(|p| (**p - collider.center).length() < RADIUS - TOLERANCE).count()
}

/// Stored blade `blade`'s recorded backbone in the world.
fn world_backbone(records: &[u32], scene: &Scene, blade: usize) -> Vec<Vec3> {
    let root = Vec3::from(scene.blades[blade].position);
    backbone(records, scene, blade).into_iter().map(|p| root + p).collect()
}

/// Three frames by brute force under `collider`: the last frame's records.
fn brute_records(scene: &Scene, animation: &AnimationSettings, collider: Collider) -> Vec<u32> {
    let (frames, _) = run(scene, animation.clone(), 1.0 / 60.0, &vec![windy(collider); 3]);
    frames.into_iter().last().expect("frames").records
}

fn responses() -> Vec<(&'static str, AnimationSettings)> {
    let with = |mode, eval| AnimationSettings { mode, eval, ..Default::default() };
    vec![
        ("keyframes", with(Mode::Texture, Eval::Blade)),
        ("sine", with(Mode::Sine(SinePhase::Object), Eval::Blade)),
        ("verlet", with(Mode::Verlet, Eval::Blade)),
        ("inertial", with(Mode::Inertial, Eval::Blade)),
    ]
}

#[test]
fn every_response_pushes_the_backbones_out_of_a_resting_sphere_by_brute_force() {
    let scene = scene();
    let (resting, high) = (sphere(&scene, 0.0), sphere(&scene, 50.0));
    let held = held(&scene, &resting);
    for (name, animation) in responses() {
        let pushed = brute_records(&scene, &animation, resting);
        let free = brute_records(&scene, &animation, high);
        let mut entered = 0;
        for &b in &held {
            let points = world_backbone(&pushed, &scene, b);
            assert_eq!(inside(&points, &resting), 0, "{name}: blade {b} inside the sphere: {points:?}");
            entered += usize::from(inside(&world_backbone(&free, &scene, b), &resting) > 0);
        }
        assert!(
            entered * 2 > held.len(),
            "{name}: {entered} of {} blades enter the sphere without push-out",
            held.len()
        );
        // A blade no circle holds is left to the bit (the force of the sphere 50 m up is none).
        let words = (SEGMENTS as usize + 1) * meadow::render::gpu_constants::POSE_WORDS as usize;
        for b in (0..scene.blades.len()).filter(|b| !held.contains(b)).step_by(7) {
            let range = b * words..(b + 1) * words;
            if !circle_holds(resting.center, resting.radii * 2.5, Vec3::from(scene.blades[b].position)) {
                assert_eq!(pushed[range.clone()], free[range], "{name}: blade {b} far from the sphere changed");
            }
        }
    }
}

/// What a culled frame read back: the visible list, the draws and the records.
struct Culled {
    visible: Vec<[u32; 2]>,
    draws: Vec<u32>,
    records: Vec<u32>,
}

/// Three frames through the cull, looking down at the sphere from 2.5 m.
fn culled(scene: &Scene, animation: AnimationSettings, collider: Collider) -> Culled {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let culling = Culling { orientation: false, occlusion: false, ..Culling::default_for(SEGMENTS) };
        let settings = RenderSettings::offscreen(SEGMENTS, culling);
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        *renderer.wind_mut() = windy(collider);
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 160, height: 160 })?;
        let position = Vec3::new(collider.center.x, collider.center.y + 2.5, collider.center.z);
        let camera = Camera { position, yaw_deg: 0.0, pitch_deg: -89.0 };
        for k in 0..3 {
            renderer.render_offscreen(&mut target, &camera, k as f32 / 60.0)?;
        }
        let (visible, draws) = renderer.read_visible_list()?;
        let records = renderer.read_pose_records()?;
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(Culled { visible, draws, records })
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

#[test]
fn the_culled_buckets_push_their_levels_out_too() {
    let scene = scene();
    let resting = sphere(&scene, 0.0);
    let held = held(&scene, &resting);
    let buckets = Culling::default_for(SEGMENTS).buckets().to_vec();
    let batch = RenderSettings::offscreen(SEGMENTS, Culling::default_for(SEGMENTS)).blades_per_instance;
    for (name, animation) in responses().into_iter().filter(|(n, _)| matches!(*n, "keyframes" | "verlet")) {
        let frame = culled(&scene, animation, resting);
        let mut checked = 0;
        for (bucket, &segments) in buckets.iter().enumerate() {
            let draw = &frame.draws[bucket * DRAW_WORDS as usize..];
            let first = draw[DRAW_FIRST_INSTANCE as usize] * batch;
            let count = draw[DRAW_INSTANCES as usize] * batch;
            for entry in (first..first + count).map(|i| i as usize) {
                let blade = frame.visible[entry][0] as usize;
                if blade == u32::MAX as usize || !held.contains(&blade) {
                    continue;
                }
                let b = &scene.blades[blade];
                let (across, normal) = bezier::frame(b);
                let root = Vec3::from(b.position);
                // The levels this bucket's strip reads.
                let points: Vec<Vec3> = (0..=SEGMENTS)
                    .filter(|level| level * segments % SEGMENTS == 0)
                    .map(|level| recorded_point(&frame.records, (entry, level), SEGMENTS, b.height))
                    .map(|l| root + across * l.x + Vec3::Y * l.y + normal * l.z)
                    .collect();
                assert_eq!(inside(&points, &resting), 0, "{name}: bucket {bucket} blade {blade}: {points:?}");
                checked += 1;
            }
        }
        assert!(checked * 10 > held.len() * 9, "{name}: {checked} of {} held blades drawn", held.len());
    }
}

/// Issue 34: a collider moves at its velocity. At `--time 2` a sphere started at x = 0 moving at
/// 1.5 m/s draws what the same sphere at rest at x = 3 draws, to the bit, and not what it draws at
/// rest at x = 0 (culled, so the GPU's emitters, and by brute force, the CPU's corners). The
/// keyframes per vertex, which feel the colliders' force alone: per blade, the moving sphere's
/// trail in the pressed map would tell it from the resting one (`tests/pressed.rs`).
#[test]
fn a_moving_collider_is_where_its_velocity_takes_it() {
    let picture = |name: &str, args: &[&str]| {
        let path = support::scratch(&format!("push-out-{name}")).join("out.png");
        support::render(args, &path);
        support::Picture::load(&path).rgb
    };
    for (name, path) in [("culled", &["--eval", "vertex"][..]), ("brute", &["--brute-force"][..])] {
        let base = [&["--blades", "20000", "--seed", "1", "--size", "160x96", "--time", "2"][..], path].concat();
        let with = |collider: &'static str| [&base[..], &["--collider", collider]].concat();
        let moving = picture(&format!("{name}-moving"), &with("sphere:0,0.3,1.5,0.5,1.5,0,-0.25"));
        let there = picture(&format!("{name}-there"), &with("sphere:3,0.3,1,0.5"));
        let start = picture(&format!("{name}-start"), &with("sphere:0,0.3,1.5,0.5"));
        assert!(moving == there, "{name}: the moving sphere is not where 2 s take it");
        assert!(moving != start, "{name}: the moving sphere stayed at its start");
    }
}
