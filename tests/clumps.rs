//! Blades in clumps (`--clumps`, issue #36 item 2, `scene::clumps`): on lavapipe with validation
//! and synchronization validation, a clumped block field renders the same 100 km from the origin
//! and the same across runs and llvmpipe thread counts, and clumping changes the picture; a stored
//! field's clumps share their tint; bad sizes are refused in one line.

mod support;

use std::collections::HashMap;

use ash::vk;
use glam::{Vec2, Vec3};
use meadow::app::{with_device, GpuOptions};
use meadow::imagediff::compare_rgb;
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::clumps::Clumps;
use meadow::scene::field::FieldSpec;
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use support::{meadow, scratch, transcript};

const CLUMPS: Clumps = Clumps { size_m: 1.5 };

/// Each camera's picture (RGBA) and cull counts over `scene`, static blades.
fn render(scene: &Scene, cameras: &[Camera]) -> Vec<(Vec<u8>, CullCounts)> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 320, height: 180 })?;
        let mut out = Vec::new();
        for camera in cameras {
            let timings = renderer.render_offscreen(&mut target, camera, 0.0)?;
            out.push((target.pixels().to_vec(), timings.cull.expect("the cull ran")));
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(out)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

#[test]
fn a_clumped_field_is_the_same_100_km_away_and_clumping_changes_it() {
    let plain = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1);
    let clumped = plain.clone().with_clumps(CLUMPS);
    let camera = |x: f32, z: f32| {
        let ground = plain.ground(x, z);
        Camera { position: Vec3::new(x, ground + 1.7, z), yaw_deg: 30.0, pitch_deg: -20.0 }
    };
    let cameras = [camera(1.5, 2.5), camera(100_001.5, 100_002.5)];
    let views = render(&clumped, &cameras);
    let (near, near_counts) = &views[0];
    let (far, far_counts) = &views[1];
    assert!(near_counts.total_drawn() > 10_000, "{}", near_counts.summary());
    assert_eq!(far_counts, near_counts);
    let (stats, _) = compare_rgb(far, near, 3);
    assert!(stats.within_fraction() >= 0.999, "100 km away: {:.4} within ±3", stats.within_fraction());
    let (unclumped, _) = &render(&plain, &cameras[..1])[0];
    let (stats, _) = compare_rgb(unclumped, near, 8);
    assert!(stats.within_fraction() < 0.7, "clumping changed only {:.3} of the picture", 1.0 - stats.within_fraction());
}

#[test]
fn a_clumped_field_is_identical_across_runs_and_thread_counts() {
    let dir = scratch("clumps-threads");
    let shot = |name: &str, threads: &str| {
        let out = dir.join(name);
        let output = meadow()
            .args(["render", "--validation", "--device", support::DEVICE, "--field", "infinite", "--clumps", "1.5"])
            .args(["--size", "320x180", "--out"])
            .arg(&out)
            .env("LP_NUM_THREADS", threads)
            .output()
            .expect("run meadow");
        support::assert_clean(&output);
        std::fs::read(&out).expect("written")
    };
    let one = shot("one.png", "1");
    assert!(one == shot("four.png", "4"), "LP_NUM_THREADS 1 and 4 differ");
    assert!(one == shot("again.png", "1"), "two runs differ");
}

#[test]
fn a_stored_fields_clumps_share_their_tint() {
    let scene = Scene::generate(20_000, 3).with_clumps(CLUMPS);
    // Each blade's clump (its position is unchanged by clumping) and hue.
    let mut hues: HashMap<[i32; 2], Vec<f32>> = HashMap::new();
    for blade in &scene.blades {
        let (k, _) = CLUMPS.apply(blade, Vec2::new(blade.position[0], blade.position[2]));
        hues.entry(k).or_default().push(blade.variation(0));
    }
    let big: Vec<&Vec<f32>> = hues.values().filter(|h| h.len() >= 20).collect();
    assert!(big.len() >= 10, "{} clumps of 20 blades or more", big.len());
    // Within a clump, the blade's own hue keeps a quarter of its say; between clumps the clump's
    // hue spans most of the range.
    let mut means = Vec::new();
    for h in &big {
        let (lo, hi) = h.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        assert!(hi - lo <= 0.26, "a clump's hues span {lo}..{hi}");
        means.push(h.iter().sum::<f32>() / h.len() as f32);
    }
    let (lo, hi) = means.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    assert!(hi - lo > 0.4, "the clumps' hues span only {lo}..{hi}");
    // The tiles still hold every blade.
    assert_eq!(scene.tiles.iter().map(|t| t.count).sum::<u32>() as usize, scene.blades.len());
}

#[test]
fn bad_clump_sizes_are_refused_in_one_line() {
    for size in ["0", "-1", "NaN", "51"] {
        let output = meadow().args(["render", "--clumps", size, "--out", "/nonexistent/x.png"]).output().expect("run");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{size}: {}", transcript(&output));
        assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1, "{size}: {stderr}");
        assert!(stderr.contains("--clumps"), "{size}: {stderr}");
    }
}
