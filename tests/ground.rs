//! The ground's clipmap (issue #30 item 2, `render::ground`, `render::ground_clipmap`) on
//! lavapipe, read back from the GPU: a block field's levels hold the relief at their world
//! vertices (at the camera and out to 5 km, near the origin and 100 km from it), a scroll keeps
//! exactly the texels a fresh fill writes, the cull's roots lie on the drawn ground on both sides
//! of a level boundary, and vertical rays cast through the drawn levels' triangles find no crack
//! where levels meet; a stored field's one level holds its terrain's heights bit for bit; and
//! every reader of the ground goes through one include.

#[path = "support/roots.rs"]
mod roots;

use ash::vk;
use glam::{DVec2, I64Vec2, IVec2, Mat4, UVec2, UVec3, Vec3};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::camera_grid;
use meadow::render::culling::Culling;
use meadow::render::field_gpu::Origin;
use meadow::render::ground::tiles;
use meadow::render::ground_clipmap::{self, Clipmap, CELLS};
use meadow::render::terrain_chunks::{self, GridPlacement, TerrainChunk};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::{FieldSpec, Relief, BLOCK_SIZE};
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;

const EXTENT: vk::Extent2D = vk::Extent2D { width: 320, height: 180 };
const VIEW: f32 = 5000.0;

fn culling() -> Culling {
    Culling { view_distance: VIEW, ..Culling::default_for(4) }
}

fn clipmap() -> Clipmap {
    let c = culling();
    Clipmap::for_view(c.view_distance, c.blade_range())
}

fn scene() -> Scene {
    Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1)
}

/// What one frame left on the GPU: the clipmap's texels in slot order, the visible list and the
/// cull's `draws` words.
struct Frame {
    camera: Camera,
    grid: Vec<[f32; 4]>,
    visible: Vec<[u32; 2]>,
    draws: Vec<u32>,
}

/// Render `cameras` in turn with one renderer (static blades) and read each frame back.
fn render(cameras: &[Camera]) -> Vec<Frame> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let scene = scene();
    let (result, messages) = with_device(&options, false, |device| {
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, culling());
        let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut frames = Vec::new();
        for camera in cameras {
            renderer.render_offscreen(&mut target, camera, 0.0)?;
            let grid = renderer.read_ground()?;
            let (visible, draws) = renderer.read_visible_list()?;
            frames.push(Frame { camera: *camera, grid, visible, draws });
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(frames)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

fn camera(x: f32, z: f32, yaw_deg: f32) -> Camera {
    let relief = scene().field.expect("a field").ground.relief().expect("a relief").clone();
    let ground = relief.height(f64::from(x), f64::from(z)) as f32;
    Camera { position: Vec3::new(x, ground + 1.7, z), yaw_deg, pitch_deg: -10.0 }
}

/// The texel of local vertex `v` of `level` in a frame's grid (windows for O's cell `cell`).
fn texel(frame: &Frame, windows: &[I64Vec2], level: u32, v: UVec2) -> [f32; 4] {
    let dims = clipmap().shape().dims;
    let first = windows[level as usize];
    let base = ground_clipmap::grid_window(first).rem_euclid(dims.as_i64vec3()).as_uvec3();
    let cells = dims.x * dims.y * dims.z;
    frame.grid[(level * cells + camera_grid::slot(UVec3::new(v.x, 0, v.y), base, dims)) as usize]
}

/// The relief's height and slope (x, z) at world `p`, in f64: the slope by central differences half a
/// metre either side, as relief_fill.comp takes it.
fn relief_at(relief: &Relief, p: DVec2) -> (f64, DVec2) {
    let h = 0.5;
    let dx = relief.height(p.x + h, p.y) - relief.height(p.x - h, p.y);
    let dz = relief.height(p.x, p.y + h) - relief.height(p.x, p.y - h);
    (relief.height(p.x, p.y), DVec2::new(dx, dz) / (2.0 * h))
}

#[test]
fn every_levels_texels_are_the_relief_at_their_world_vertices_and_a_scroll_keeps_them_exact() {
    let relief = scene().field.expect("a field").ground.relief().expect("a relief").clone();
    let clipmap = clipmap();
    assert!(clipmap.levels >= 7 && clipmap.reach() >= VIEW, "{clipmap:?}");
    // Near the origin; 11 blocks on, where level 0's window has moved (a fill of what entered);
    // 100 km out. Then the moved view again from a fresh renderer.
    let (here, there, far) = (camera(1.5, 2.5, 30.0), camera(45.5, 2.5, 30.0), camera(100_001.5, -99_997.5, 30.0));
    let moved = render(&[here, there, far]);
    let fresh = render(&[there]);
    let (a, b) = (Origin::under(&here).cell, Origin::under(&there).cell);
    assert_ne!(
        clipmap.windows(a)[0],
        clipmap.windows(b)[0],
        "level 0's window must move for the test to mean anything"
    );
    assert!(moved[1].grid == fresh[0].grid, "a scrolled clipmap differs from a fresh one's");
    for frame in &moved {
        let cell = Origin::under(&frame.camera).cell;
        let windows = clipmap.windows(cell);
        let (mut worst, mut worst_normal, mut coarse_moved) = (0.0f64, 0.0f64, 0.0f64);
        for level in 0..clipmap.levels {
            let step = f64::from(clipmap.step(level));
            for z in 0..=CELLS {
                for x in 0..=CELLS {
                    let v = UVec2::new(x, z);
                    let t = texel(frame, &windows, level, v);
                    let world = (windows[level as usize] + v.as_i64vec2()).as_dvec2() * step;
                    let (h, slope) = relief_at(&relief, world);
                    worst = worst.max((f64::from(t[0]) - h).abs());
                    // The texel's rise over its level's run of 1 m: the slope.
                    worst_normal =
                        worst_normal.max((f64::from(t[2]) - slope.x).abs().max((f64::from(t[3]) - slope.y).abs()));
                    let odd = IVec2::new((x & 1) as i32, (z & 1) as i32).as_dvec2();
                    let coarse = if odd == DVec2::ZERO {
                        h
                    } else {
                        0.5 * (relief.height(world.x - odd.x * step, world.y - odd.y * step)
                            + relief.height(world.x + odd.x * step, world.y + odd.y * step))
                    };
                    worst = worst.max((f64::from(t[1]) - coarse).abs());
                    coarse_moved = coarse_moved.max((coarse - h).abs());
                }
            }
        }
        let at = frame.camera.position;
        assert!(worst <= 1e-4, "camera at {at}: a texel {worst} m off the relief");
        assert!(worst_normal <= 1e-3, "camera at {at}: a slope {worst_normal} off the relief's");
        assert!(coarse_moved > 0.05, "the next level's mesh is the relief ({coarse_moved} m): the check means nothing");
    }
}

#[test]
fn roots_lie_on_the_drawn_ground_on_both_sides_of_a_level_boundary() {
    let scene = scene();
    let relief = scene.field.as_ref().expect("a field").ground.relief().expect("a relief").clone();
    let clipmap = clipmap();
    let frames = render(&[camera(1.5, 2.5, 30.0), camera(37.5, -21.5, 200.0)]);
    let blades_per_instance = RenderSettings::offscreen(4, culling()).blades_per_instance;
    for frame in &frames {
        let origin = Origin::under(&frame.camera);
        let windows = clipmap.windows(origin.cell);
        // Level 0's window edge, metres inside it (> 0) or outside it (< 0).
        let step0 = f64::from(clipmap.step(0));
        let lo = windows[0].as_dvec2() * step0;
        let hi = lo + DVec2::splat(f64::from(CELLS) * step0);
        let (mut worst, mut inside, mut outside, mut roots) = (0.0f64, 0, 0, 0);
        let eye_y = frame.camera.position.y;
        let drawn = roots::roots(&scene, (&frame.visible, &frame.draws), (origin.cell, eye_y), blades_per_instance);
        for (p, root) in drawn {
            let ground = clipmap.drawn_height(&relief, origin.cell, p) - 0.01;
            worst = worst.max((root - ground).abs());
            // The windows lie in the world's period that holds O (`period_cell`).
            let shift = (origin.cell - ground_clipmap::period_cell(origin.cell)).as_dvec2() * f64::from(BLOCK_SIZE);
            let edge = (p - shift - lo).min(hi - p + shift).min_element();
            inside += usize::from((0.0..4.0).contains(&edge));
            outside += usize::from((-4.0..0.0).contains(&edge));
            roots += 1;
        }
        let at = frame.camera.position;
        assert!(roots > 10_000, "camera at {at}: {roots} roots");
        assert!(inside > 50 && outside > 50, "camera at {at}: {inside} roots inside level 0's edge, {outside} outside");
        assert!(worst <= 1e-3, "camera at {at}: a root {worst} m off the drawn ground");
    }
}

/// The drawn triangles of `level` under world point `p`, as (x, y, z) corners: the terrain
/// pass's index list and chunks (its hole left out) over the level's vertices, lifted as
/// terrain.vert lifts them (`ground_clipmap::drawn_texel_height`).
fn triangles_under(
    frame: &Frame,
    windows: &[I64Vec2],
    level: u32,
    p: DVec2,
    (chunks, indices, drawn): (&[TerrainChunk], &[u32], &[(u32, u32)]),
) -> Vec<[glam::DVec3; 3]> {
    let step = f64::from(clipmap().step(level));
    let first = windows[level as usize].as_dvec2();
    let g = p / step - first;
    let mut out = Vec::new();
    // The cell under `p` and, for a point on a cell's edge, the cells that share it.
    let base = g.floor().as_ivec2();
    for dz in -1..=0 {
        for dx in -1..=0 {
            let c = base + IVec2::new(dx, dz);
            if c.min_element() < 0 || c.max_element() >= CELLS as i32 {
                continue;
            }
            let c = c.as_uvec2();
            let chunk = chunks.iter().find(|k| (0..2).all(|a| k.lo[a] <= c[a] && c[a] < k.hi[a])).expect("a chunk");
            if !drawn.iter().any(|&(f, n)| (f..f + n).contains(&chunk.first_index)) {
                continue;
            }
            let within = (c.y - chunk.lo[1]) * (chunk.hi[0] - chunk.lo[0]) + (c.x - chunk.lo[0]);
            let at = (chunk.first_index + 6 * within) as usize;
            for t in indices[at..at + 6].chunks(3) {
                out.push(std::array::from_fn(|i| {
                    let v = UVec2::new(t[i] % (CELLS + 1), t[i] / (CELLS + 1));
                    let h = ground_clipmap::drawn_texel_height(&clipmap(), level, texel(frame, windows, level, v), v);
                    let xz = (first + v.as_dvec2()) * step;
                    glam::DVec3::new(xz.x, f64::from(h), xz.y)
                }));
            }
        }
    }
    out
}

/// Where a vertical ray at `p` meets triangle `t` (x, z), if it does.
fn hit(t: &[glam::DVec3; 3], p: DVec2) -> Option<f64> {
    let [a, b, c] = t.map(|v| DVec2::new(v.x, v.z));
    let area = (b - a).perp_dot(c - a);
    let w = [(c - b).perp_dot(p - b) / area, (a - c).perp_dot(p - c) / area, (b - a).perp_dot(p - a) / area];
    w.iter().all(|&w| w >= -1e-9).then(|| w[0] * t[0].y + w[1] * t[1].y + w[2] * t[2].y)
}

#[test]
fn every_levels_tiles_hold_the_range_and_cover_of_their_vertices_and_a_scroll_renews_them() {
    let clipmap = clipmap();
    // Near the origin, then 11 blocks on (level 0's window moved: its tiles are written anew).
    let moved = render(&[camera(1.5, 2.5, 30.0), camera(45.5, 2.5, 30.0)]);
    let texel_count = |frame: &Frame| frame.grid.len();
    let mut spans = 0.0f32;
    for frame in &moved {
        let windows = clipmap.windows(Origin::under(&frame.camera).cell);
        let n = (CELLS + 1) as usize;
        for level in 0..clipmap.levels {
            // The level's vertices row by row from its window's first, as an uploaded level's.
            let vertices: Vec<[f32; 4]> =
                (0..n * n).map(|i| texel(frame, &windows, level, UVec2::new((i % n) as u32, (i / n) as u32))).collect();
            let expected = tiles::tiles_of(CELLS, &vertices, &vec![(1.0, 1.0); n * n]);
            let side = tiles::per_side(CELLS);
            for (k, want) in expected.iter().enumerate() {
                let at = tiles::texel(clipmap.levels, CELLS, level, (k as u32 % side, k as u32 / side));
                assert!(at < texel_count(frame), "tile texel {at} past the clipmap's {}", texel_count(frame));
                assert_eq!(frame.grid[at], *want, "level {level}'s tile {k} at {}", frame.camera.position);
                spans = spans.max(want[1] - want[0]);
            }
        }
    }
    assert!(spans > 0.1, "every tile flat ({spans} m): the check means nothing");
}

#[test]
fn vertical_rays_find_no_crack_where_the_levels_meet() {
    let clipmap = clipmap();
    let frames = render(&[camera(1.5, 2.5, 30.0), camera(100_037.5, -99_021.5, 200.0)]);
    let chunks = terrain_chunks::chunks(CELLS, terrain_chunks::GROUND_CHUNK_CELLS);
    let indices = terrain_chunks::chunked_indices(CELLS, terrain_chunks::GROUND_CHUNK_CELLS);
    for frame in &frames {
        let cell = Origin::under(&frame.camera).cell;
        let windows = clipmap.windows(cell);
        // Each level's chunks as the terrain pass draws them, every one in view (a zero matrix:
        // every frustum plane passes), but the finer level's square.
        let drawn: Vec<Vec<(u32, u32)>> = (0..clipmap.levels)
            .map(|l| {
                let placement = GridPlacement { offset: [0.0, 0.0], step: 1.0, heights: (0.0, 0.0) };
                let hole = Clipmap::hole(&windows, l).map(|h| [h.x, h.y]);
                terrain_chunks::visible_runs(&chunks, &placement, &Mat4::ZERO, hole)
            })
            .collect();
        let (mut rays, mut seams, mut worst) = (0, 0, 0.0f64);
        for level in 0..clipmap.levels - 1 {
            // Rays along the four edges of the level's window, on the edge and a fifth of a cell
            // either side of it.
            let step = f64::from(clipmap.step(level));
            let lo = windows[level as usize].as_dvec2() * step;
            let side = f64::from(CELLS) * step;
            for k in 0..400 {
                let along = (f64::from(k) + 0.37) / 400.0 * side;
                for off in [-0.2 * step, 0.0, 0.2 * step] {
                    for p in [
                        lo + DVec2::new(along, off),
                        lo + DVec2::new(off, along),
                        lo + DVec2::new(along, side - off),
                        lo + DVec2::new(side - off, along),
                    ] {
                        let hits: Vec<(u32, f64)> = (0..clipmap.levels)
                            .flat_map(|l| {
                                let parts = (chunks.as_slice(), indices.as_slice(), drawn[l as usize].as_slice());
                                let triangles = triangles_under(frame, &windows, l, p, parts);
                                triangles
                                    .into_iter()
                                    .filter_map(|t| hit(&t, p))
                                    .map(move |h| (l, h))
                                    .collect::<Vec<_>>()
                            })
                            .collect();
                        assert!(!hits.is_empty(), "a crack at {p} (level {level}'s edge)");
                        let spread = hits.iter().fold(0.0f64, |m, &(_, h)| m.max((h - hits[0].1).abs()));
                        worst = worst.max(spread);
                        seams += usize::from(hits.iter().any(|&(l, _)| l != hits[0].0));
                        rays += 1;
                    }
                }
            }
        }
        let at = frame.camera.position;
        assert!(worst <= 1e-3, "camera at {at}: the levels meet {worst} m apart");
        assert!(seams > 1000, "camera at {at}: {seams} rays on an edge met both levels");
        assert!(rays >= 4800 * (clipmap.levels as usize - 1));
    }
}

#[test]
fn a_stored_fields_one_level_is_its_terrains_heights_and_central_differences() {
    let scene = Scene::generate(2_000, 3);
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (grid, messages) = with_device(&options, false, |device| {
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        renderer.render_offscreen(&mut target, &scene.default_camera(), 0.0)?;
        let grid = renderer.read_ground();
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        grid
    });
    assert_eq!(messages, Some(0), "validation messages");
    let grid = grid.expect("read back");
    let terrain = &scene.terrain;
    let n = terrain.cells as usize + 1;
    assert_eq!(grid.len() as u64, (n * n) as u64 + tiles::count(1, terrain.cells));
    let h = |x: usize, z: usize| terrain.heights[z.min(n - 1) * n + x.min(n - 1)];
    // After its vertices, its tiles: the range of each tile's vertices, full cover (none given).
    let (vertices, tile_texels) = grid.split_at(n * n);
    assert_eq!(tile_texels, &tiles::tiles_of(terrain.cells, vertices, &vec![(1.0, 1.0); n * n])[..]);
    for (z, row) in vertices.chunks(n).enumerate() {
        for (x, t) in row.iter().enumerate() {
            // The same bits: the pictures drawn from it are the ones drawn from the heights.
            assert_eq!(t[0].to_bits(), h(x, z).to_bits(), "({x}, {z})");
            assert_eq!(t[1].to_bits(), t[0].to_bits());
            let dx = h(x + 1, z) - h(x.saturating_sub(1), z);
            let dz = h(x, z + 1) - h(x, z.saturating_sub(1));
            assert_eq!([t[2].to_bits(), t[3].to_bits()], [dx.to_bits(), dz.to_bits()], "({x}, {z})");
        }
    }
}

/// The shaders of the library, by path under `shaders/`, and their text.
fn shader_sources() -> Vec<(String, String)> {
    fn walk(dir: &std::path::Path, out: &mut Vec<(String, String)>) {
        for entry in std::fs::read_dir(dir).expect("shaders/") {
            let path = entry.expect("an entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else {
                let text = std::fs::read_to_string(&path).expect("a shader");
                out.push((path.to_string_lossy().into_owned(), text));
            }
        }
    }
    let mut out = Vec::new();
    walk(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders"), &mut out);
    out
}

#[test]
fn every_reader_of_the_ground_goes_through_one_include() {
    let sources = shader_sources();
    assert!(sources.len() > 40, "{} shaders", sources.len());
    let mut readers = 0;
    for (path, text) in &sources {
        let code: String = text.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
        let owner = path.ends_with("common/ground.glsl") || path.ends_with("terrain/ground_texels.glsl");
        // Texels are fetched in ground.glsl alone (its writers, the sources' fills, write them).
        if !owner {
            assert!(!code.contains("ground_texel("), "{path} fetches the clipmap itself");
        }
        // No reader of the ground asks which field it is drawn under.
        let reads = ["ground_height(", "ground_normal(", "ground_vertex(", "ground_vertex_normal("];
        if !owner && reads.iter().any(|r| code.contains(r)) {
            readers += 1;
        }
        if path.ends_with("terrain/terrain.vert") || owner {
            assert!(!code.contains("FLAG_BLOCKS"), "{path} branches on the field");
        }
        for gone in ["heights[", "grid_terrain_", "relief_normal(", "field_ground_"] {
            assert!(!code.contains(gone), "{path} reads the ground around the include: `{gone}`");
        }
    }
    // The terrain, the cull, the blades' lighting and the two debug views.
    assert!(readers >= 5, "{readers} readers of the ground");
}
