//! The pressed map (issue #34; `render::animation::pressed`): trampling that stays and recovers,
//! and cutting that regrows. On lavapipe with validation and synchronization validation, on a
//! stored field by brute force with the keyframes per blade (records by stored blade, read back
//! after each frame; no wind, so a blade's pose is its rest pose but for the map):
//! - a sphere rolling across the field leaves a trail: the blades it passed lean, and go on
//!   leaning after it has gone; their records are the same to the bit whether or not the camera
//!   moves meanwhile (the map is anchored in the world);
//! - a trampled blade's tip is back to 5 % of its pressed displacement at `--recovery-s` ± 10 %
//!   (the bend recovers as a critically damped spring, in closed form);
//! - a cut blade is a stub, regrows, and has its full length again within `--regrow-s` ± 10 %
//!   (then its record is the uncut run's to the bit);
//! - walking 1 km over a block field with a collider under the eye leaves the allocator's bytes
//!   as they were.

#[path = "support/pose_records.rs"]
mod pose_records;
mod support;

use ash::vk;
use glam::Vec3;
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::pressed::{PressedParams, CELL_M, FIVE_PERCENT, STUB};
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Collider, Wind};
use pose_records::{backbone, SEGMENTS};

const RADIUS: f32 = 0.3;
/// The sphere rolls along z = PATH_Z (the centre line of a row of map cells) towards +x at SPEED
/// m/s, from x = START_X at t = 0.
const PATH_Z: f32 = 0.125;
const SPEED: f32 = 2.0;
const START_X: f32 = -3.0;
const RECOVERY_S: f32 = 2.0;
const REGROW_S: f32 = 3.0;

fn scene() -> Scene {
    Scene::generate(4000, 4)
}

/// The rolling sphere (a collider, or with `cut` a cutter).
fn rolling(scene: &Scene, cut: bool) -> Wind {
    let sphere = Collider {
        center: Vec3::new(START_X, scene.ground(0.0, PATH_Z) + RADIUS, PATH_Z),
        radii: Vec3::splat(RADIUS),
        velocity: Vec3::new(SPEED, 0.0, 0.0),
    };
    match cut {
        true => Wind { cuts: vec![sphere], ..Default::default() },
        false => Wind { colliders: vec![sphere], ..Default::default() },
    }
}

/// The keyframes per blade, `--recovery-s 2 --regrow-s 3`.
fn animation() -> AnimationSettings {
    let pressed = PressedParams { recovery_s: RECOVERY_S, regrow_s: REGROW_S };
    AnimationSettings { mode: Mode::Texture, eval: Eval::Blade, pressed, ..Default::default() }
}

/// Frames at `times` by brute force under `wind`, the camera moved by `walk` metres along x each
/// frame: each frame's pose records.
fn frames(scene: &Scene, wind: &Wind, times: &[f32], walk: f32) -> Vec<Vec<u32>> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(SEGMENTS, Culling::brute_force(SEGMENTS));
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation())?;
        *renderer.wind_mut() = wind.clone();
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 36 })?;
        let start = Camera::default_for(&scene.terrain);
        let mut records = Vec::new();
        for (k, &t) in times.iter().enumerate() {
            let mut camera = start;
            camera.position.x += walk * k as f32;
            renderer.render_offscreen(&mut target, &camera, t)?;
            records.push(renderer.read_pose_records()?);
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(records)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// The blades between x = −1 and 1 whose map cell's centre lies within 5 cm of the path's centre
/// line, and the last moment the sphere covered that centre (the press's, or the cut's, time).
fn on_the_path(scene: &Scene) -> Vec<(usize, f32)> {
    let centre = |v: f32| ((f64::from(v) / f64::from(CELL_M)).floor() + 0.5) * f64::from(CELL_M);
    let blades: Vec<(usize, f32)> = (0..scene.blades.len())
        .filter_map(|b| {
            let p = scene.blades[b].position;
            let (x, z) = (centre(p[0]) as f32, centre(p[2]) as f32);
            let across = z - PATH_Z;
            let left = (x + (RADIUS * RADIUS - across * across).sqrt() - START_X) / SPEED;
            (across.abs() < 0.05 && p[0].abs() < 1.0).then_some((b, left))
        })
        .collect();
    assert!(blades.len() > 20, "{} blades on the path", blades.len());
    blades
}

/// How far blade `b`'s tip lies from its tip in `free`.
fn displacement(records: &[u32], free: &[u32], scene: &Scene, b: usize) -> f32 {
    let tip = |r: &[u32]| backbone(r, scene, b)[SEGMENTS as usize];
    (tip(records) - tip(free)).length()
}

/// The spring's share left `tau` seconds after a press.
fn recovery(tau: f32) -> f32 {
    let wt = tau * (FIVE_PERCENT as f32 / RECOVERY_S);
    (1.0 + wt) * (-wt).exp()
}

#[test]
fn a_trail_stays_where_it_was_made_and_recovers_by_the_recovery_time() {
    let scene = scene();
    let path = on_the_path(&scene);
    // The sphere has left x = 1.15 by t = 2.2; the blades it left between t = 1.4 and 1.8 are
    // at under 0.9 times the recovery time at the second frame and over 1.1 at the third.
    let times = [2.5, 3.2, 4.0];
    let trail = frames(&scene, &rolling(&scene, false), &times, 0.0);
    let walked = frames(&scene, &rolling(&scene, false), &times, 7.0);
    let free = frames(&scene, &Wind::default(), &times, 0.0);
    assert!(trail == walked, "the trail moved with the camera");
    let mut crossings = 0;
    for &(b, passed) in &path {
        let d: Vec<f32> = (0..3).map(|k| displacement(&trail[k], &free[k], &scene, b)).collect();
        // The full press's displacement, from the first frame's share of it.
        let full = d[0] / recovery(times[0] - passed);
        assert!(full > 0.1, "blade {b}: pressed by {full} m");
        // Its tip within 2 % of the spring's curve at every frame.
        for (k, &t) in times.iter().enumerate() {
            let expected = full * recovery(t - passed);
            assert!((d[k] - expected).abs() < 0.02 * full + 2e-4, "blade {b} at {t} s: {} m, not {expected} m", d[k]);
        }
        // Above 5 % of its pressed displacement before 0.9 times the recovery time after the
        // press, below it after 1.1 times.
        let at = |k: usize| times[k] - passed;
        let before: Vec<usize> = (0..3).filter(|&k| at(k) < 0.9 * RECOVERY_S).collect();
        let after: Vec<usize> = (0..3).filter(|&k| at(k) > 1.1 * RECOVERY_S).collect();
        assert!(before.iter().all(|&k| d[k] > 0.05 * full), "blade {b}: {d:?} of {full} m");
        assert!(after.iter().all(|&k| d[k] < 0.05 * full), "blade {b}: {d:?} of {full} m");
        crossings += usize::from(!before.is_empty() && !after.is_empty());
    }
    assert!(crossings > 10, "{crossings} blades crossed 5 % in the frames");
}

#[test]
fn a_cut_blade_is_a_stub_and_regrows_by_the_regrowth_time() {
    let scene = scene();
    let path = on_the_path(&scene);
    let times = [2.5, 2.5 + 0.5 * REGROW_S, 2.5 + 1.2 * REGROW_S];
    let cut = frames(&scene, &rolling(&scene, true), &times, 0.0);
    let free = frames(&scene, &Wind::default(), &times, 0.0);
    for &(b, passed) in &path {
        let height = |r: &[u32]| backbone(r, &scene, b)[SEGMENTS as usize].length();
        let full = height(&free[0]);
        for (k, &t) in times.iter().enumerate() {
            let since = t - passed;
            let share = STUB + (1.0 - STUB) * (since / REGROW_S).min(1.0);
            let length = height(&cut[k]);
            assert!(
                (length - share * full).abs() < 0.01 * full,
                "blade {b} at {since} s after its cut: {length} of {full} m"
            );
        }
        // Regrown: its record is the uncut run's.
        let words = (SEGMENTS as usize + 1) * meadow::render::gpu_constants::POSE_WORDS as usize;
        assert_eq!(cut[2][b * words..(b + 1) * words], free[2][b * words..(b + 1) * words], "blade {b} regrown");
    }
}

#[test]
fn walking_a_kilometre_with_a_collider_under_the_eye_allocates_nothing() {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 3);
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::new(device.clone(), &scene, settings, animation())?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
        let start = scene.default_camera();
        let mut bytes = Vec::new();
        // 1 km in 25 m steps, a sphere resting on the ground under the eye.
        for step in 0..=40 {
            let mut camera = start;
            camera.position.x += 25.0 * step as f32;
            let (x, z) = (camera.position.x, camera.position.z);
            let centre = Vec3::new(x, scene.ground(x, z) + RADIUS, z);
            renderer.wind_mut().colliders = vec![Collider::at_rest(centre, Vec3::splat(RADIUS))];
            renderer.render_offscreen(&mut target, &camera, step as f32 / 10.0)?;
            if step == 1 || step == 40 {
                bytes.push(device.allocator().generate_report().total_allocated_bytes);
            }
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(bytes)
    });
    assert_eq!(messages, Some(0), "validation messages");
    let bytes = result.expect("rendered");
    assert_eq!(bytes[0], bytes[1], "allocated bytes after 25 m and after 1 km");
}

/// `--debug-view pressed`: the trail is magenta on green; with no collider no blade is; blades
/// posed per vertex (which the map does not bend) refuse the view in one line.
#[test]
fn the_pressed_view_colours_the_trail() {
    let dir = support::scratch("pressed-view");
    let base = ["--blades", "20000", "--size", "240x180", "--camera", "2.2,1.1,1.0,62,-28", "--time", "3"];
    let magenta = |name: &str, extra: &[&str]| {
        let path = dir.join(format!("{name}.png"));
        support::render(&[&base[..], &["--debug-view", "pressed"], extra].concat(), &path);
        let picture = support::Picture::load(&path);
        picture.rgb.chunks_exact(3).filter(|p| p[0] > 2 * u16::from(p[1]) as u8 / 2 + 40 && p[2] > p[1] + 40).count()
    };
    let trail = magenta("trail", &["--collider", "sphere:-2.5,0.35,0,0.45,1.5,0,0"]);
    let none = magenta("none", &[]);
    assert!(trail > 500 && none == 0, "magenta pixels: {trail} with the trail, {none} without");
    let output = support::meadow()
        .args(["render", "--brute-force", "--blades", "2000", "--debug-view", "pressed", "--out"])
        .arg(dir.join("refused.png"))
        .output()
        .expect("run");
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.starts_with("error: --debug-view pressed:") && stderr.lines().count() == 1, "{stderr}");
    assert!(!dir.join("refused.png").exists());
}
