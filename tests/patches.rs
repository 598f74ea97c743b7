//! Interaction patches (Belyaev §3.4, issue #34; `render::animation::patches`), on lavapipe with
//! validation and synchronization validation, by brute force (every stored blade posed each frame),
//! the keyframes per blade as the cheap response, the store read back:
//! - the blades a resting sphere (the 100th collider) reaches, and only they, hold a patch, and the chain draws them
//!   (their records differ from the keyframes'); the same sphere 50 m up gives none; through the
//!   cull, the drawn blades within reach hold them;
//! - with no wind, once the sphere is taken away the patches hand back by settling: each is freed
//!   with no blend, all but a few swinging ones (at most 5 %) before the timeout;
//! - under a gusty wind, whose keyframed poses the chain does not match to a pixel, they time out:
//!   the blend rises, and every patch is gone `TIMEOUT_S + BLEND_S` after the last contact;
//! - `--debug-view patches` shows them, and is refused where no records are patched.

#[path = "support/pose_records.rs"]
mod pose_records;
mod support;

use ash::vk;
use glam::{Vec2, Vec3};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::clock::StepClock;
use meadow::render::animation::patches::{live, LivePatch, BLEND_S, REACH_M, TIMEOUT_S};
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Collider, GlobalWind, Wind};
use pose_records::SEGMENTS;

const RADIUS: f32 = 0.3;
const DT: f64 = 1.0 / 60.0;

fn scene() -> Scene {
    Scene::generate(4000, 4)
}

/// A sphere of `RADIUS` whose lowest point is `lift` above the ground at (0.1, 0.2).
fn sphere(scene: &Scene, lift: f32) -> Collider {
    let (x, z) = (0.1, 0.2);
    Collider::at_rest(Vec3::new(x, scene.ground(x, z) + RADIUS + lift, z), Vec3::splat(RADIUS))
}

/// What a run read after the frames `reads` names: the live patches, and the pose records.
struct Read {
    frame: usize,
    patches: Vec<LivePatch>,
    records: Vec<u32>,
}

/// `frames` frames by brute force, frame k at step k under `wind` with `collider` for the frames
/// before `until`; the store and the records read after the frames of `reads`.
fn run(scene: &Scene, wind: &Wind, collider: Collider, frames: (usize, usize), reads: &[usize]) -> Vec<Read> {
    let camera = Camera::default_for(&scene.terrain);
    run_with((Culling::brute_force(SEGMENTS), camera), scene, wind, collider, frames, reads)
}

/// `run` with `culling`, from `camera`.
fn run_with(
    (culling, camera): (Culling, Camera),
    scene: &Scene,
    wind: &Wind,
    collider: Collider,
    (frames, until): (usize, usize),
    reads: &[usize],
) -> Vec<Read> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(SEGMENTS, culling);
        let clock = StepClock { dt: DT };
        let animation = AnimationSettings { mode: Mode::Texture, eval: Eval::Blade, clock, ..Default::default() };
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 320, height: 180 })?;
        let mut out = Vec::new();
        for k in 0..frames {
            // `wind`'s colliders, then `collider` until `until`.
            let mut colliders = wind.colliders.clone();
            colliders.extend((k < until).then_some(collider));
            *renderer.wind_mut() = Wind { colliders, ..wind.clone() };
            // Half a step in: an f32 time at step k exactly could round to the step before.
            renderer.render_offscreen(&mut target, &camera, ((k as f64 + 0.5) * DT) as f32)?;
            if reads.contains(&k) {
                let patches = live(&renderer.read_patches()?, k as u64);
                out.push(Read { frame: k, patches, records: renderer.read_pose_records()? });
            }
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(out)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// The blades `collider` reaches (`patches.glsl`'s `within_reach`), and those on the edge of its
/// reach, where the f32 sums of the GPU and the CPU may differ.
fn reached(scene: &Scene, collider: &Collider) -> (Vec<u32>, Vec<u32>) {
    let (mut inside, mut edge) = (Vec::new(), Vec::new());
    for (i, b) in scene.blades.iter().enumerate() {
        let root = Vec3::from(b.position);
        let q = (Vec2::new(root.x, root.z) - Vec2::new(collider.center.x, collider.center.z))
            / (Vec2::new(collider.radii.x, collider.radii.z) + REACH_M);
        let low = collider.center.y - collider.radii.y < root.y + b.height + REACH_M;
        match (q.length_squared(), low) {
            (d, true) if (d - 1.0).abs() < 1e-4 => edge.push(i as u32),
            (d, true) if d < 1.0 => inside.push(i as u32),
            _ => {}
        }
    }
    (inside, edge)
}

#[test]
fn the_blades_a_collider_reaches_and_only_they_hold_patches() {
    let scene = scene();
    // 99 colliders far away first: the sphere is the 100th, past the 64 that sources and
    // colliders shared before (the bins' masks hold 128).
    let far = |i: usize| Collider::at_rest(Vec3::new(100.0 + i as f32, 0.0, 0.0), Vec3::splat(0.2));
    let still = Wind { colliders: (0..99).map(far).collect(), ..Default::default() };
    let resting = sphere(&scene, 0.0);
    let (inside, edge) = reached(&scene, &resting);
    assert!(inside.len() > 100, "{} blades within reach", inside.len());
    let read = run(&scene, &still, resting, (4, 4), &[3]);
    let mut patched: Vec<u32> = read[0].patches.iter().map(|p| p.blade.1).collect();
    patched.sort_unstable();
    assert!(read[0].patches.iter().all(|p| p.blade.0 == 0 && p.blend == 0.0 && p.idle == 0.0));
    patched.retain(|b| !edge.contains(b));
    assert_eq!(patched, inside, "the patched blades are those within reach");
    // The chain draws them: its records are not the keyframes' (the sphere 50 m up reaches none,
    // and the keyframes alone draw every blade).
    let high = run(&scene, &Wind::default(), sphere(&scene, 50.0), (4, 4), &[3]);
    assert!(high[0].patches.is_empty(), "{} patches under a sphere 50 m up", high[0].patches.len());
    let words = (SEGMENTS as usize + 1) * meadow::render::gpu_constants::POSE_WORDS as usize;
    let record = |r: &Read, b: u32| r.records[b as usize * words..(b as usize + 1) * words].to_vec();
    let differ = inside.iter().filter(|&&b| record(&read[0], b) != record(&high[0], b)).count();
    assert!(differ * 10 > inside.len() * 9, "{differ} of {} patched records differ", inside.len());
}

/// Through the cull (records by visible entry, each LOD bucket's levels), the patched blades are
/// the drawn blades within reach.
#[test]
fn through_the_cull_the_drawn_blades_within_reach_hold_patches() {
    let scene = scene();
    let resting = sphere(&scene, 0.0);
    let (inside, edge) = reached(&scene, &resting);
    let culling = Culling { orientation: false, occlusion: false, ..Culling::default_for(SEGMENTS) };
    // Looking down at the sphere from 2.5 m: nearly every blade within reach is drawn.
    let position = Vec3::new(resting.center.x, resting.center.y + 2.5, resting.center.z);
    let camera = Camera { position, yaw_deg: 0.0, pitch_deg: -89.0 };
    let read = run_with((culling, camera), &scene, &Wind::default(), resting, (4, 4), &[3]);
    let patched: Vec<u32> = read[0].patches.iter().map(|p| p.blade.1).filter(|b| !edge.contains(b)).collect();
    assert!(patched.iter().all(|b| inside.contains(b)), "a patch out of reach: {patched:?}");
    assert!(patched.len() * 10 > inside.len() * 9, "{} of {} blades within reach patched", patched.len(), inside.len());
}

/// The last frame with the collider, which goes at `until`, and every third after it, each with
/// the patches live then.
fn after(scene: &Scene, wind: &Wind, until: usize, frames: usize) -> Vec<Read> {
    let reads: Vec<usize> = (until - 1..frames).step_by(3).collect();
    run(scene, wind, sphere(scene, 0.0), (frames, until), &reads)
}

#[test]
fn with_no_wind_the_patches_settle_and_hand_back() {
    let scene = scene();
    let until = 30;
    let reads = after(&scene, &Wind::default(), until, until + (60.0 * TIMEOUT_S) as usize);
    assert!(reads[0].patches.len() > 100, "{} patches when the sphere goes", reads[0].patches.len());
    // Most at once (their chains at rest within a pixel of the keyframes' pose), the swinging ones
    // as they come to rest: at most 5 % are left at the timeout.
    let (first, left) = (reads[0].patches.len(), reads[reads.len() - 1].patches.len());
    assert!(left * 20 <= first, "{left} of {first} patches live at the timeout");
    assert!(reads[1].patches.len() < first, "none handed back at once");
    for r in &reads {
        assert!(r.patches.iter().all(|p| p.blend == 0.0), "frame {}: a patch blending back", r.frame);
    }
}

#[test]
fn under_gusts_the_patches_time_out_through_the_blend() {
    let scene = scene();
    let gusts =
        Wind { global: Some(GlobalWind { direction_deg: 30.0, strength: 0.6, gusts: true }), ..Default::default() };
    let until = 30;
    let life = ((TIMEOUT_S + BLEND_S) as f64 / DT).ceil() as usize;
    let reads = after(&scene, &gusts, until, until + life + 6);
    let blending = reads.iter().map(|r| r.patches.iter().filter(|p| p.blend > 0.0 && p.blend < 1.0).count()).max();
    assert!(blending > Some(20), "{blending:?} patches blending back at once");
    for r in reads.iter().filter(|r| r.frame >= until + life) {
        assert!(r.patches.is_empty(), "frame {}: {} patches past their life", r.frame, r.patches.len());
    }
    // The blend follows the timeout: none before it.
    for r in reads.iter().filter(|r| ((r.frame + 1 - until) as f32) < TIMEOUT_S * 60.0 - 1.0) {
        assert!(r.patches.iter().all(|p| p.blend == 0.0), "frame {}: blending before the timeout", r.frame);
    }
}

/// `--debug-view patches`: the blades the sphere's patches draw are orange on grey-green; with no
/// collider no blade is; blades posed per vertex (which have no records to patch) refuse the view
/// in one line.
#[test]
fn the_patches_view_colours_the_patched_blades() {
    let dir = support::scratch("patches-view");
    let base = ["--blades", "20000", "--size", "240x180", "--camera", "2.2,1.1,1.0,62,-28", "--time", "1.5"];
    let orange = |name: &str, extra: &[&str]| {
        let path = dir.join(format!("{name}.png"));
        support::render(&[&base[..], &["--debug-view", "patches"], extra].concat(), &path);
        let picture = support::Picture::load(&path);
        picture.rgb.chunks_exact(3).filter(|p| p[0] > p[1].saturating_add(20) && p[1] > p[2].saturating_add(40)).count()
    };
    let patched = orange("patched", &["--collider", "sphere:-2.5,0.35,0,0.45,1.5,0,0"]);
    let none = orange("none", &[]);
    assert!(patched > 300 && none == 0, "orange pixels: {patched} with the sphere, {none} without");
    let output = support::meadow()
        .args(["render", "--eval", "vertex", "--blades", "2000", "--debug-view", "patches", "--out"])
        .arg(dir.join("refused.png"))
        .output()
        .expect("run");
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.starts_with("error: --debug-view patches:") && stderr.lines().count() == 1, "{stderr}");
    assert!(!dir.join("refused.png").exists());
}
