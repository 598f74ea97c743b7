//! The cull's cell heights from the ground's tiles (issue #30 item 2, `render::ground::tiles`):
//! the cull bounds a block field's cells by the clipmap's tiles under them (`FLAG_GROUND_BOUNDS`),
//! not by the ground's steepest slope anywhere. On lavapipe with validation and synchronization
//! validation, on a heightmap (issue #35): a flat map with one spike far from the view culls
//! exactly as the same map without it (the same tiles in view, the same blades up to the
//! occlusion test; by the origin, across the map's mirror edge and 100 km out), where the spike's
//! slope alone makes every cell's box metres taller; and looking at the spike, the cull draws the
//! same blades with the tiles' bounds as with the slope's.

mod support;

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::gpu_constants::{DRAW_FIRST_INSTANCE, DRAW_INSTANCES, DRAW_WORDS, MAX_LOD_BUCKETS};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::heightmap::{Heightmap, TerrainScale};
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;

const SCALE: TerrainScale = TerrainScale { x: 1000.0, y: 40.0, z: 1000.0 };
/// 1.95 m texels: the spike's one texel is steeper than any relief.
const SIDE: u32 = 513;

/// A flat map at a fifth of white, with a spike of white at texel `spike` if any.
fn map(spike: Option<(u32, u32)>) -> Heightmap {
    let mut texels = vec![13_107u16; (SIDE * SIDE) as usize];
    if let Some((x, z)) = spike {
        texels[(z * SIDE + x) as usize] = 65_535;
    }
    Heightmap { width: SIDE, height: SIDE, texels, bits: 16, scale: SCALE, mirrored: true }
}

/// The cull's counts and visible list of one frame of a block field on `map` from each of
/// `cameras`, its cells bounded by the ground's tiles or (`tiles` false) its steepest slope.
fn counts(map: Heightmap, cameras: &[Camera], tiles: bool) -> Vec<(CullCounts, Vec<u32>)> {
    let scene = Scene::blocks_on_map(FieldSpec { size: None, density: 100.0 }, Arc::new(map), 1);
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, Culling { ground_bounds: tiles, ..Culling::default_for(4) });
        let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 160, height: 90 })?;
        let mut counts = Vec::new();
        for camera in cameras {
            // Twice: the second frame's occlusion test reads the first one's depth.
            renderer.render_offscreen(&mut target, camera, 0.0)?;
            let frame = renderer.render_offscreen(&mut target, camera, 0.0)?.cull.expect("culled");
            let (visible, draws) = renderer.read_visible_list()?;
            counts.push((frame, drawn_entries(&visible, &draws)));
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frames.
        unsafe { target.destroy(device) };
        Ok(counts)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// The visible list's entries of every bucket's draw (padding left out), sorted.
fn drawn_entries(visible: &[[u32; 2]], draws: &[u32]) -> Vec<u32> {
    let batch = RenderSettings::offscreen(4, Culling::default_for(4)).blades_per_instance;
    let mut entries: Vec<u32> = (0..MAX_LOD_BUCKETS)
        .flat_map(|b| {
            let draw = &draws[(b * DRAW_WORDS) as usize..];
            let first = draw[DRAW_FIRST_INSTANCE as usize] * batch;
            (first..first + draw[DRAW_INSTANCES as usize] * batch).map(|i| visible[i as usize][0])
        })
        .filter(|&e| e != u32::MAX)
        .collect();
    entries.sort_unstable();
    entries
}

#[test]
fn a_spike_far_from_the_view_does_not_widen_the_cells_in_it() {
    // The spike 476 m out along x and z: its slope (32 m over a 1.95 m texel) is the map's
    // steepest, and bounds every cell's heights by ±16 m a metre of the cell's reach without the
    // tiles. The cameras: by the origin, across the map's mirror edge at x = 500 m, and 100 km
    // out (50 mirrored periods: the origin's ground).
    let spiked = map(Some((500, 500)));
    assert!(spiked.slope_bound() > 10.0, "{}", spiked.slope_bound());
    let ground = 0.2 * SCALE.y as f32;
    let cameras = [
        Camera { position: Vec3::new(0.0, ground + 1.7, 0.0), yaw_deg: 0.0, pitch_deg: -12.0 },
        Camera { position: Vec3::new(10.0, ground + 6.0, -20.0), yaw_deg: 90.0, pitch_deg: -35.0 },
        Camera { position: Vec3::new(492.0, ground + 3.0, -100.0), yaw_deg: -90.0, pitch_deg: -20.0 },
        Camera { position: Vec3::new(100_000.0, ground + 1.7, 0.0), yaw_deg: 0.0, pitch_deg: -12.0 },
    ];
    let flat = counts(map(None), &cameras, true);
    let bounded = counts(spiked.clone(), &cameras, true);
    let sloped = counts(spiked, &cameras, false);
    for ((flat, _), ((bounded, _), (sloped, _))) in flat.iter().zip(bounded.iter().zip(&sloped)) {
        // With the tiles, the spiked map's cells are the flat map's: the same tiles, the same blades.
        let tiles = |c: &CullCounts| (c.tiles_visible, c.after_tiles);
        assert_eq!(tiles(bounded), tiles(flat), "{} | {}", bounded.summary(), flat.summary());
        // The same blades up to the occlusion test. A frame over the flat map may skip that test
        // (its ground provably hides nothing from a camera looking down, `render::occlusion`)
        // where the same frame over the spiked map, whose slope bound is 16, runs it.
        let kept = |c: &CullCounts| c.after_orientation;
        assert_eq!(kept(bounded), kept(flat), "{} | {}", bounded.summary(), flat.summary());
        assert!(bounded.total_drawn() <= flat.total_drawn(), "{} | {}", bounded.summary(), flat.summary());
        assert!(bounded.total_drawn() > 1_000, "{}", bounded.summary());
        // Without it, taller boxes: more candidates in visible tiles for the same blades drawn.
        assert!(sloped.after_tiles > bounded.after_tiles, "{} | {}", sloped.summary(), bounded.summary());
        assert_eq!(sloped.total_drawn(), bounded.total_drawn(), "{} | {}", sloped.summary(), bounded.summary());
    }
}

#[test]
fn the_tiles_bound_the_spike_where_it_stands_and_the_cull_keeps_its_blades() {
    let spiked = map(Some((256, 256)));
    // Looking at the spike from 30 m and from above it: the cull draws the same blades with the
    // tiles' bounds as with the slope's (which hold wherever the ground is), on its flanks too.
    let cameras = [
        Camera { position: Vec3::new(0.0, 25.0, 30.0), yaw_deg: 0.0, pitch_deg: -30.0 },
        Camera { position: Vec3::new(0.0, 60.0, 0.0), yaw_deg: 0.0, pitch_deg: -89.0 },
    ];
    let bounded = counts(spiked.clone(), &cameras, true);
    let sloped = counts(spiked, &cameras, false);
    for ((b, b_list), (s, s_list)) in bounded.iter().zip(&sloped) {
        assert!(b.total_drawn() > 1_000, "{}", b.summary());
        assert_eq!(b.total_drawn(), s.total_drawn(), "{} | {}", b.summary(), s.summary());
        assert_eq!(b_list.len() as u64, b.total_drawn());
        assert_eq!(b_list, s_list, "the blades drawn");
    }
}
