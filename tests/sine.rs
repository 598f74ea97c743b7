//! Pelzer's sine animation (GPU Gems ch. 7, §7.4; `render::animation::sine`), read back from the
//! GPU: the pose records its pass wrote, against a CPU reference of `shaders/animation/sine.comp`'s
//! translation. Its invariants:
//! - under no wind both variants rest at the neutral blade;
//! - under a wind towards +x every tip moves towards +x, and only along x;
//! - per object (§7.4.4): one translation per blade, every level displaced by T · s² · height;
//! - per vertex (§7.4.3): each level's translation is that of its own rest point in the world,
//!   so two blades at one place move alike (the reference depends on the position alone), and a
//!   reference that takes the phase at the root instead does not match;
//! - per cluster (§7.4.2): the phase is the centre of the blade's tile, so under a wind that is
//!   the same everywhere every blade of a tile moves by one translation, and tiles differ.
//!
//! Brute force on a stored field, so records are by stored blade and the CPU writes the cluster
//! corners; the cull's path is `tests/determinism.rs`' and the CLI's.

mod support;

use std::f64::consts::TAU;

use ash::vk;
use glam::{Vec2, Vec3, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::sine::{self, SinePhase};
use meadow::render::animation::{self, AnimationSettings, Mode};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{bezier, Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Attenuation, GlobalWind, Wind, KEYFRAME_WIND_SCALE};

const SEGMENTS: u32 = 4;
use meadow::render::animation::poses::POSE_SCALE;
const TIME: f32 = 1.3;
/// A record's quantisation (snorm16 over POSE_SCALE heights) and f32 rounding, in heights.
const TOLERANCE: f32 = 2e-4;

/// What a run read back: the records, the wind at the corners and the cluster grid.
struct ReadBack {
    records: Vec<u32>,
    corners: Vec<Vec4>,
    grid: meadow::scene::clusters::ClusterGrid,
}

fn run(scene: &Scene, phase: SinePhase, wind: &Wind) -> ReadBack {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(SEGMENTS, Culling::brute_force(SEGMENTS));
        let animation = AnimationSettings { mode: Mode::Sine(phase), wind: wind.clone(), ..Default::default() };
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
        renderer.render_offscreen(&mut target, &Camera::default_for(&scene.terrain), TIME)?;
        let records = renderer.read_pose_records()?;
        let corners = renderer.read_wind_corners(0)?.into_iter().map(Vec4::from).collect();
        let grid = renderer.cluster_grid();
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(ReadBack { records, corners, grid })
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// Level `level` of blade `blade`'s record: its point over the height and POSE_SCALE.
fn recorded(records: &[u32], blade: usize, level: u32) -> Vec3 {
    meadow::render::animation::poses::recorded_point(records, (blade, level), SEGMENTS, 1.0) / POSE_SCALE
}

/// sine.comp's translation at phase point `p` under wind `w` (m/s), in heights, world xz.
fn translation(p: Vec2, w: Vec2, direction: Vec2) -> Vec2 {
    let kappa = (TAU / sine::WAVELENGTH) as f32;
    let phase = (TAU / sine::PERIOD * f64::from(TIME)).rem_euclid(TAU) as f32;
    let speed = w.length();
    let along = if speed > 0.0 { w / speed } else { Vec2::ZERO };
    let theta = phase - kappa * direction.dot(p);
    let t = sine::LEAN_PER_MS * w + sine::SWAY_PER_MS * speed * theta.sin() * along;
    t.clamp_length_max(sine::MOST)
}

/// The CPU reference of every blade's levels (over height and POSE_SCALE), the phase taken as
/// `phase` says, with the wind the GPU read (its corners, read back).
fn reference(scene: &Scene, wind: &Wind, read: &ReadBack, phase: SinePhase) -> Vec<Vec<Vec3>> {
    let emitters = animation::emitters(wind, TIME);
    let direction = wind.global.map_or(Vec2::X, |g| g.direction());
    let per_vertex = if phase == SinePhase::Vertex { 1.0 } else { 0.0 };
    let grid = scene.tile_grid;
    // The centre of the tile under a root (`scene::tiles::TileGrid::cell`).
    let tile_centre = |root: Vec2| {
        let (x, z) = grid.cell(root.x, root.y);
        Vec2::splat(grid.origin) + (Vec2::new(x as f32, z as f32) + 0.5) * grid.tile_size
    };
    scene
        .blades
        .iter()
        .map(|b| {
            let root = Vec2::new(b.position[0], b.position[2]);
            let cluster = read.grid.locate(root.x, root.y);
            let force =
                animation::blade_force(&read.grid, &cluster, &read.corners, &emitters, 0, Attenuation::Cluster, b);
            let w = force * KEYFRAME_WIND_SCALE;
            let (across, normal) = bezier::frame(b);
            let (across, normal) = (Vec2::new(across.x, across.z), Vec2::new(normal.x, normal.z));
            let p = bezier::neutral_control_points(b);
            (0..=SEGMENTS)
                .map(|level| {
                    let s = level as f32 / SEGMENTS as f32;
                    let rest = bezier::point(&p, s);
                    let offset = across * rest.x + normal * rest.z;
                    let at = if phase == SinePhase::Cluster { tile_centre(root) } else { root + per_vertex * offset };
                    let d = translation(at, w, direction) * (s * s * b.height);
                    (rest + Vec3::new(d.dot(across), 0.0, d.dot(normal))) / (POSE_SCALE * b.height)
                })
                .collect()
        })
        .collect()
}

/// The largest difference between the records and `expected`, in heights over POSE_SCALE.
fn worst(records: &[u32], expected: &[Vec<Vec3>]) -> f32 {
    let mut most = 0.0f32;
    for (blade, levels) in expected.iter().enumerate() {
        for (level, e) in levels.iter().enumerate() {
            most = most.max((recorded(records, blade, level as u32) - *e).abs().max_element());
        }
    }
    most
}

fn gusty() -> Wind {
    Wind { global: Some(GlobalWind { direction_deg: 30.0, strength: 0.6, gusts: true }), ..Default::default() }
}

#[test]
fn every_variant_matches_the_cpu_reference_and_takes_its_phase_where_it_says() {
    let scene = Scene::generate(1500, 11);
    let wind = gusty();
    let pairs = [
        (SinePhase::Object, SinePhase::Vertex),
        (SinePhase::Vertex, SinePhase::Object),
        (SinePhase::Cluster, SinePhase::Object),
    ];
    for (phase, other) in pairs {
        let read = run(&scene, phase, &wind);
        let own = worst(&read.records, &reference(&scene, &wind, &read, phase));
        assert!(own < TOLERANCE, "{phase:?}: records differ from the reference by {own}");
        // The control: the other variant's phase does not match, by far more than the tolerance.
        let mismatch = worst(&read.records, &reference(&scene, &wind, &read, other));
        assert!(mismatch > 20.0 * TOLERANCE, "{phase:?} matches {other:?}'s phase too ({mismatch})");
    }
}

#[test]
fn per_object_every_level_moves_by_one_translation_scaled_by_height_squared() {
    let scene = Scene::generate(1500, 12);
    let wind = gusty();
    let read = run(&scene, SinePhase::Object, &wind);
    let still = reference(&scene, &Wind::default(), &read, SinePhase::Object);
    let mut checked = 0;
    for (blade, neutral) in still.iter().enumerate() {
        // The tip's displacement over s² = 1, and every other level's over its own s².
        let tip = recorded(&read.records, blade, SEGMENTS) - neutral[SEGMENTS as usize];
        for level in 2..SEGMENTS {
            let s2 = (level as f32 / SEGMENTS as f32).powi(2);
            let d = (recorded(&read.records, blade, level) - neutral[level as usize]) / s2;
            assert!((d - tip).abs().max_element() < TOLERANCE / s2, "blade {blade} level {level}: {d} against {tip}");
            checked += 1;
        }
    }
    assert!(checked > 2000);
}

#[test]
fn without_wind_blades_rest_and_under_wind_towards_plus_x_tips_move_towards_plus_x() {
    let scene = Scene::generate(1500, 13);
    let calm =
        Wind { global: Some(GlobalWind { direction_deg: 0.0, strength: 0.0, gusts: false }), ..Default::default() };
    let east =
        Wind { global: Some(GlobalWind { direction_deg: 0.0, strength: 0.5, gusts: false }), ..Default::default() };
    for phase in [SinePhase::Object, SinePhase::Vertex, SinePhase::Cluster] {
        let read = run(&scene, phase, &calm);
        let neutral = reference(&scene, &Wind::default(), &read, phase);
        let rest = worst(&read.records, &neutral);
        assert!(rest < TOLERANCE, "{phase:?}: without wind the blades moved by {rest}");
        let read = run(&scene, phase, &east);
        for (blade, (b, levels)) in scene.blades.iter().zip(&neutral).enumerate() {
            let d = recorded(&read.records, blade, SEGMENTS) - levels[SEGMENTS as usize];
            let (across, normal) = bezier::frame(b);
            let world = (across * d.x + normal * d.z) * POSE_SCALE;
            // 4 m/s: a lean of 0.2 heights, the sway at most ±0.08.
            assert!(world.x > 0.1, "{phase:?}: blade {blade}'s tip moved {world} (heights)");
            assert!(world.z.abs() < 2.0 * TOLERANCE * POSE_SCALE, "{phase:?}: blade {blade}'s tip moved {world}");
        }
    }
}

#[test]
fn per_cluster_every_blade_of_a_tile_moves_by_one_translation() {
    let scene = Scene::generate(20_000, 14);
    // A wind the same at every corner (no gusts, no sources): the translation differs only by
    // the phase.
    let steady = |strength| Wind {
        global: Some(GlobalWind { direction_deg: 0.0, strength, gusts: false }),
        ..Default::default()
    };
    let neutral =
        reference(&scene, &Wind::default(), &run(&scene, SinePhase::Cluster, &steady(0.0)), SinePhase::Cluster);
    let read = run(&scene, SinePhase::Cluster, &steady(0.5));
    assert!(read.corners.windows(2).all(|c| c[0] == c[1]), "the wind is the same everywhere");
    let mut by_tile: std::collections::BTreeMap<u32, Vec<Vec2>> = Default::default();
    for (blade, (b, levels)) in scene.blades.iter().zip(&neutral).enumerate() {
        let d = recorded(&read.records, blade, SEGMENTS) - levels[SEGMENTS as usize];
        let (across, normal) = bezier::frame(b);
        // The tip's translation in heights (s = 1), world xz.
        let world = (across * d.x + normal * d.z) * POSE_SCALE;
        by_tile
            .entry(scene.tile_grid.index(b.position[0], b.position[2]))
            .or_default()
            .push(Vec2::new(world.x, world.z));
    }
    let means: Vec<Vec2> = by_tile.values().map(|t| t.iter().sum::<Vec2>() / t.len() as f32).collect();
    for (tile, moves) in &by_tile {
        let first = moves[0];
        let spread = moves.iter().map(|m| (*m - first).abs().max_element()).fold(0.0, f32::max);
        assert!(spread < 4.0 * TOLERANCE * POSE_SCALE, "tile {tile}: its blades' tips move apart by {spread}");
    }
    // The control: the tiles sway with phases of their own.
    let (low, high) = means.iter().fold((f32::MAX, f32::MIN), |(l, h), m| (l.min(m.x), h.max(m.x)));
    assert!(by_tile.len() > 4 && high - low > 0.02, "{} tiles, tips from {low} to {high}", by_tile.len());
}
