//! The cull's tests on the CPU (`shaders/cull/cull.glsl`, same formulas in the same order, in `f32`):
//! the reference the tests hold the GPU's counts to. Not used when rendering.

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::render::culling::{far_field_distance, CullCounts, A1, FADE_BAND, MAX_LOD_BUCKETS};
use crate::render::draw_rows::DrawRows;
use crate::render::gpu_constants as gpu;
use crate::render::uniforms::FrameUniforms;
use crate::scene::tiles::{ring_cell, BladeTile};
use crate::scene::Scene;

/// `EDGE_ON` of `shaders/cull/cull.glsl`.
const EDGE_ON: f32 = 0.97;

/// What the cull keeps of `scene` with the frame's `uniforms` (`Renderer::frame_uniforms`).
/// The occlusion test needs the GPU's depth of the frame: the reference is for uniforms without
/// `CULL_OCCLUSION` (refused otherwise). `collapsed_tip`: how the blades are drawn
/// (`scene::bezier::BladeMesh`), for the triangle count.
pub fn reference_counts(scene: &Scene, uniforms: &FrameUniforms, collapsed_tip: bool) -> CullCounts {
    reference_counts_drawn(scene, uniforms, (collapsed_tip, DrawRows::PerBucket))
}

/// `reference_counts` for a blade class drawn by `rows`: with a row per tile, the draws are the
/// (tile, LOD bucket) pairs that draw a blade (`CullCounts::tile_draws`).
pub fn reference_counts_drawn(
    scene: &Scene,
    uniforms: &FrameUniforms,
    (collapsed_tip, rows): (bool, DrawRows),
) -> CullCounts {
    assert_eq!(uniforms.cull_lod.z & gpu::CULL_OCCLUSION, 0, "the CPU reference has no depth pyramid");
    let cull = Cull { scene, u: uniforms, planes: planes(uniforms.cull_view_proj) };
    let mut counts = CullCounts { collapsed_tip, ..CullCounts::default() };
    let buckets = uniforms.cull_lod.x as usize;
    for b in 0..buckets {
        counts.segments[b] = ((uniforms.cull_lod.y >> (4 * b)) & 15) + 1;
    }
    for slot in 0..uniforms.cull_tiles.y {
        let Some(tile) = cull.slot_tile(slot) else { continue };
        counts.tiles += 1;
        counts.considered += tile.count;
        let Some(candidates) = cull.candidates(&tile) else { continue };
        counts.tiles_visible += 1;
        counts.after_tiles += tile.count;
        let normal =
            cull.terrain_normal(Vec2::new(0.5 * (tile.min[0] + tile.max[0]), 0.5 * (tile.min[2] + tile.max[2])));
        let mut drawn = [false; MAX_LOD_BUCKETS];
        for rank in 0..candidates {
            match cull.blade(&tile, rank, normal) {
                Ok(bucket) => {
                    drawn[bucket.min(MAX_LOD_BUCKETS - 1)] = true;
                    counts.after_density += 1;
                    counts.after_frustum += 1;
                    counts.after_orientation += 1;
                    counts.after_occlusion += 1;
                    counts.drawn[bucket.min(MAX_LOD_BUCKETS - 1)] += 1;
                }
                Err(failed) => {
                    counts.after_density += u32::from(failed > gpu::STAT_DENSITY);
                    counts.after_frustum += u32::from(failed > gpu::STAT_FRUSTUM);
                    counts.after_orientation += u32::from(failed > gpu::STAT_ORIENTATION);
                }
            }
        }
        if rows == DrawRows::PerTile {
            counts.tile_draws += drawn.iter().filter(|&&d| d).count() as u32;
        }
    }
    // The reference models a visible list that holds every kept blade (`CullCounts::scale`).
    counts.wanted = counts.total_drawn() as u32;
    counts.scale = crate::render::culling::SCALE_ONE;
    counts
}

/// Every blade the cull keeps, in the order the emit pass writes each bucket's (slots near to
/// far, then stored order): (ring slot, blade index, LOD bucket). For uniforms without
/// `CULL_OCCLUSION`, as `reference_counts`; the draw classes' selections split this list
/// (`tests/draw_class.rs`).
pub fn reference_kept(scene: &Scene, uniforms: &FrameUniforms) -> Vec<(u32, u32, usize)> {
    assert_eq!(uniforms.cull_lod.z & gpu::CULL_OCCLUSION, 0, "the CPU reference has no depth pyramid");
    let cull = Cull { scene, u: uniforms, planes: planes(uniforms.cull_view_proj) };
    let mut kept = Vec::new();
    for slot in 0..uniforms.cull_tiles.y {
        let Some(tile) = cull.slot_tile(slot) else { continue };
        let Some(candidates) = cull.candidates(&tile) else { continue };
        let normal =
            cull.terrain_normal(Vec2::new(0.5 * (tile.min[0] + tile.max[0]), 0.5 * (tile.min[2] + tile.max[2])));
        for rank in 0..candidates {
            if let Ok(bucket) = cull.blade(&tile, rank, normal) {
                kept.push((slot, tile.first + rank, bucket.min(MAX_LOD_BUCKETS - 1)));
            }
        }
    }
    kept
}

/// The ring slots whose tile passes the tile tests, near to far, with their tile: where a
/// draw-class set's own source places its candidates (`render::draw_class::CandidateSource`). For
/// uniforms without `CULL_OCCLUSION`, as `reference_counts`.
pub fn reference_slots(scene: &Scene, uniforms: &FrameUniforms) -> Vec<(u32, BladeTile)> {
    assert_eq!(uniforms.cull_lod.z & gpu::CULL_OCCLUSION, 0, "the CPU reference has no depth pyramid");
    let cull = Cull { scene, u: uniforms, planes: planes(uniforms.cull_view_proj) };
    (0..uniforms.cull_tiles.y)
        .filter_map(|slot| cull.slot_tile(slot).filter(|tile| cull.candidates(tile).is_some()).map(|tile| (slot, tile)))
        .collect()
}

struct Cull<'a> {
    scene: &'a Scene,
    u: &'a FrameUniforms,
    planes: [Vec4; 5],
}

fn planes(m: Mat4) -> [Vec4; 5] {
    let row = |i: usize| Vec4::new(m.x_axis[i], m.y_axis[i], m.z_axis[i], m.w_axis[i]);
    let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 - r2].map(|p| p / p.truncate().length())
}

impl Cull<'_> {
    fn on(&self, bit: u32) -> bool {
        self.u.cull_lod.z & bit != 0
    }

    fn slot_tile(&self, slot: u32) -> Option<BladeTile> {
        let (dx, dz) = ring_cell(slot);
        let (x, z) = (self.u.cull_tiles.z as i32 + dx, self.u.cull_tiles.w as i32 + dz);
        let n = self.u.cull_tiles.x as i32;
        ((0..n).contains(&x) && (0..n).contains(&z)).then(|| self.scene.tiles[(z * n + x) as usize])
    }

    fn box_in_frustum(&self, lo: Vec3, hi: Vec3) -> bool {
        self.planes.iter().all(|p| {
            let corner = Vec3::select(p.truncate().cmpge(Vec3::ZERO), hi, lo);
            p.truncate().dot(corner) + p.w >= 0.0
        })
    }

    fn density_keep(&self, d: f32, n_dot_r: f32) -> f32 {
        let t = (1.0 - n_dot_r.abs()).powi(2).powi(2).powi(2);
        let visible = (1.0 - t) * n_dot_r + t;
        let d0 = self.u.lod.y;
        visible / (A1 + A1 * (d * d) / (d0 * d0)) * self.far_field(d)
    }

    fn far_field(&self, d: f32) -> f32 {
        (far_field_distance(self.u.lod.y, self.u.lod.w) / d).min(1.0)
    }

    fn candidates(&self, tile: &BladeTile) -> Option<u32> {
        let eye = self.u.cull_eye.truncate();
        let (lo, hi) = (Vec3::from(tile.min), Vec3::from(tile.max));
        let nearest = (eye.clamp(lo, hi) - eye).length();
        let culled = tile.count == 0
            || (self.on(gpu::CULL_FRUSTUM) && !self.box_in_frustum(lo, hi))
            || (self.on(gpu::CULL_DISTANCE) && nearest > self.u.lod.x);
        if culled {
            return None;
        }
        if !self.on(gpu::LOD_DENSITY) {
            return Some(tile.count);
        }
        let d0 = self.u.lod.y;
        let keep = 1.0 / (A1 + A1 * (nearest * nearest) / (d0 * d0)) * self.far_field(nearest.max(1e-3));
        Some((keep * tile.count as f32 - 0.5).ceil().clamp(0.0, tile.count as f32) as u32)
    }

    fn terrain_normal(&self, xz: Vec2) -> Vec3 {
        let terrain = &self.scene.terrain;
        let step = self.u.terrain.y;
        let g = ((xz - Vec2::splat(self.u.terrain.x)) / step).round();
        let n = terrain.cells as i32 + 1;
        let h = |x: i32, z: i32| terrain.heights[(z.clamp(0, n - 1) * n + x.clamp(0, n - 1)) as usize];
        let (x, z) = (g.x as i32, g.y as i32);
        Vec3::new(-(h(x + 1, z) - h(x - 1, z)), 2.0 * step, -(h(x, z + 1) - h(x, z - 1))).normalize()
    }

    /// The blade's bucket, or the `STAT_*` of the test it failed.
    fn blade(&self, tile: &BladeTile, rank: u32, normal: Vec3) -> Result<usize, u32> {
        let blade = &self.scene.blades[(tile.first + rank) as usize];
        let position = Vec3::from(blade.position);
        let to_eye = self.u.cull_eye.truncate() - position;
        let d = to_eye.length().max(1e-3);
        let mut scale = Vec2::ONE;
        if self.on(gpu::LOD_DENSITY) {
            let keep = self.density_keep(d, normal.dot(to_eye / d));
            let w = (rank as f32 + 0.5) / tile.count as f32;
            if w >= keep {
                return Err(gpu::STAT_DENSITY);
            }
            let fade = ((keep - w) / (FADE_BAND * keep)).clamp(0.0, 1.0);
            let covered = (keep * (1.0 - 0.5 * FADE_BAND)).min(1.0);
            scale = Vec2::new(fade, (1.0 / covered).min(self.u.lod.w));
        }
        let reach = blade.height + 0.5 * blade.width * scale.x * scale.y;
        let outside = self.planes.iter().any(|p| p.truncate().dot(position) + p.w < -reach);
        if (self.on(gpu::CULL_FRUSTUM) && outside) || (self.on(gpu::CULL_DISTANCE) && d - reach > self.u.lod.x) {
            return Err(gpu::STAT_FRUSTUM);
        }
        if self.on(gpu::CULL_ORIENTATION) {
            let across = Vec2::new(blade.facing.cos(), -blade.facing.sin());
            let view = Vec2::new(to_eye.x, to_eye.z) / Vec2::new(to_eye.x, to_eye.z).length().max(1e-6);
            if view.dot(across).abs() > EDGE_ON {
                return Err(gpu::STAT_ORIENTATION);
            }
        }
        let mut bucket = 0;
        if self.on(gpu::LOD_SEGMENTS) {
            let needed = scale.x * blade.height * self.u.cull_eye.w / d / self.u.lod.z;
            for b in 1..self.u.cull_lod.x as usize {
                if ((self.u.cull_lod.y >> (4 * b)) & 15) as f32 + 1.0 >= needed {
                    bucket = b;
                }
            }
        }
        Ok(bucket)
    }
}
