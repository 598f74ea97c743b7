//! The analytic wind field on the GPU (`render::wind`, `shaders/wind/analytic_corners.comp`),
//! run by the renderer's graph on lavapipe at 0 validation messages (synchronization validation
//! included), against its f64 CPU reference (`wind::Wind::corner_velocity_f64`): at every cluster
//! corner (the field's texel centres), within |Δ| ≤ 1e-4 · (1 + |w|) m/s, with gusts, moving point
//! sources and calm areas, under both attenuations, at the origin and 100 km from it. Colliders are
//! not wind: corners under one carry the same field as without it (the blades take the colliders'
//! shapes, `tests/forces.rs`).
//! The interpolation of the corners (eq. 3.6–3.8) against its CPU mirror is `tests/forces.rs`.

use ash::vk;
use glam::{DVec2, Vec2, Vec3};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::AnimationSettings;
use meadow::render::culling::Culling;
use meadow::render::field_gpu::Origin;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Attenuation, CalmArea, Collider, GlobalWind, PointSource, Wind};

const EXTENT: vk::Extent2D = vk::Extent2D { width: 160, height: 90 };

/// Sources, a calm area and a collider around world point `at`, under a gusty global wind.
fn wind_around(at: Vec2) -> Wind {
    Wind {
        global: Some(GlobalWind { direction_deg: 35.0, strength: 0.6, gusts: true }),
        sources: vec![
            PointSource {
                position: at + Vec2::new(1.3, -0.7),
                power: 0.3,
                sigma: 2.0,
                velocity: Vec2::ZERO,
                height: 0.5,
            },
            PointSource {
                position: at + Vec2::new(-2.1, 1.9),
                power: 0.5,
                sigma: 1.5,
                velocity: Vec2::new(0.4, -0.2),
                height: 0.5,
            },
        ],
        calm: vec![CalmArea { min: at + Vec2::new(-3.0, -3.0), max: at + Vec2::new(-1.0, -0.5) }],
        colliders: vec![Collider::at_rest(Vec3::new(at.x + 0.6, 0.2, at.y + 1.4), Vec3::new(0.9, 0.3, 1.2))],
        cuts: Vec::new(),
    }
}

/// What a case covered: corners in a calm area, corners where the sources move the wind by more
/// than 0.1 m/s, and corners under a collider (where a field that held the collider would differ
/// from the reference, which does not).
#[derive(Default, Debug)]
struct Coverage {
    calm: usize,
    sources: usize,
    under_colliders: usize,
}

/// Render one frame of `scene` from `camera` at `time` and compare the GPU's corners with the
/// f64 reference; returns what the case covered.
fn check(scene: &Scene, camera: Camera, wind: &Wind, attenuation: Attenuation, time: f32) -> Coverage {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let animation = AnimationSettings { wind: wind.clone(), attenuation, cluster_size: 0.5, ..Default::default() };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation.clone())?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        renderer.render_offscreen(&mut target, &camera, time)?;
        let corners = renderer.read_wind_corners(0);
        let levels = renderer.wind_levels();
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok((corners?, levels))
    });
    assert_eq!(messages, Some(0), "validation messages");
    let (corners, levels) = result.expect("rendered");
    let origin = match scene.field {
        Some(_) => Origin::under(&camera).world,
        None => DVec2::ZERO,
    };
    let per_level = levels[0].corner_count() as usize;
    assert_eq!(corners.len(), levels.len() * per_level);
    let (t, mut coverage) = (f64::from(time), Coverage::default());
    let alone = Wind { sources: Vec::new(), ..wind.clone() };
    let under = |p: DVec2| {
        wind.colliders.iter().any(|c| {
            let q =
                (p - DVec2::new(c.center.x.into(), c.center.z.into())) / DVec2::new(c.radii.x.into(), c.radii.z.into());
            q.length() < 1.0
        })
    };
    for (i, gpu) in corners.iter().enumerate() {
        // Every level's corners are texel centres of the field, innermost level first.
        let (grid, local) = (&levels[i / per_level], (i % per_level) as u32);
        let n = grid.corners_per_side();
        let (x, z) = ((local % n) as f64, (local / n) as f64);
        let size = f64::from(grid.cluster_size);
        let p = origin + DVec2::new(f64::from(grid.origin) + x * size, f64::from(grid.origin) + z * size);
        let (w, exposure) = wind.corner_velocity_f64(p, t, attenuation);
        let delta = DVec2::new(f64::from(gpu[0]) - w.x, f64::from(gpu[2]) - w.y).length().max(f64::from(gpu[1]).abs());
        assert!(
            delta <= 1e-4 * (1.0 + w.length()),
            "{attenuation:?}, O {origin}: corner {i} at {p}: GPU {gpu:?}, reference {w} (exposure {exposure})"
        );
        assert_eq!(f64::from(gpu[3]), exposure, "corner {i} at {p}: exposure");
        coverage.calm += usize::from(exposure == 0.0);
        let (bare, _) = alone.corner_velocity_f64(p, t, attenuation);
        coverage.sources += usize::from((w - bare).length() > 0.1 && exposure > 0.0);
        coverage.under_colliders += usize::from(under(p));
    }
    coverage
}

fn stored() -> Scene {
    Scene::generate(20000, 5)
}

fn camera(x: f32, z: f32) -> Camera {
    Camera { position: Vec3::new(x, 2.0, z), yaw_deg: 30.0, pitch_deg: -20.0 }
}

#[test]
fn the_gpu_field_matches_the_f64_reference_on_a_stored_field() {
    let wind = wind_around(Vec2::ZERO);
    let cluster = check(&stored(), camera(0.0, 4.0), &wind, Attenuation::Cluster, 1.5);
    assert!(cluster.calm > 10 && cluster.sources > 10 && cluster.under_colliders > 3, "{cluster:?}");
    // Delayed attenuation: the corners carry the global wind and the exposure only.
    let blade = check(&stored(), camera(0.0, 4.0), &wind, Attenuation::Blade, 1.5);
    assert!(blade.calm > 10 && blade.sources == 0 && blade.under_colliders > 3, "{blade:?}");
}

#[test]
fn the_gpu_field_is_as_exact_100_km_from_the_origin() {
    let scene = Scene::blocks(FieldSpec { size: None, density: 50.0 }, 1);
    for at in [Vec2::new(1.5, 2.5), Vec2::new(100_001.5, 100_002.5)] {
        let wind = wind_around(at);
        let cluster = check(&scene, camera(at.x, at.y), &wind, Attenuation::Cluster, 2.25);
        assert!(cluster.calm > 10 && cluster.sources > 10 && cluster.under_colliders > 3, "{at}: {cluster:?}");
        let blade = check(&scene, camera(at.x, at.y), &wind, Attenuation::Blade, 2.25);
        assert!(blade.calm > 10 && blade.sources == 0, "{at}: {blade:?}");
    }
}
