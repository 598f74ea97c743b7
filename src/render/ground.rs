//! The ground under the grass from one source (issue #30 item 2). A [`GroundSource`] writes the
//! ground into one clipmap, the levels of a camera grid (`render::camera_grid`), and every reader
//! reads it there through one include, `shaders/common/ground.glsl`: the terrain mesh, the cull's
//! roots and tile normals, the blades' lighting and the debug views. No reader asks which source
//! it is.
//!
//! A texel is what its grid vertex alone decides: x the ground's height, y the height of the next
//! level's mesh there (the morph's target, `render::ground_clipmap`), zw the ground's rise along x
//! and z over the level's run (`ground_levels[l].w`), so the normal at the vertex is
//! (−z, run, −w). A level is a window of `cells`² cells at its step; its vertices sit in the slots
//! `camera_grid::slot` gives from the window's toroidal base.
//!
//! Three sources today:
//! - [`StoredGround`]: a stored field's terrain (`scene::Terrain`), its 0.5 m lattice as one level
//!   uploaded with the scene; its texels hold the stored heights and the central differences the
//!   terrain was always lit with, over a run of two cells, so the pictures are the ones before the
//!   clipmap, bit for bit.
//! - [`ReliefGround`]: a block field's relief (`scene::field::Relief`) in nested levels around the
//!   camera out to the view distance (`ground_clipmap::Clipmap`), filled on the GPU as the camera
//!   moves by `passes::ground_fill` running the source's [`GroundFill`] (`relief_fill.comp`).
//! - [`HeightmapGround`]: a block field on a heightmap (`scene::heightmap`, issue #35): the
//!   relief's clipmap, filled from the map's texels (`heightmap_fill.comp`), which its fill reads
//!   from a buffer of its own (`GroundSource::buffers`, 2 bytes a texel). A stored field on a
//!   heightmap is a `StoredGround` whose terrain sampled the map.
//!
//! A new source is an implementation of [`GroundSource`], with a [`GroundFill`] and its fill
//! shader when the camera's moves fill it, and its arm in [`source`].

use std::sync::atomic::AtomicU64;
use std::sync::Arc;

use ash::vk;
use glam::{I64Vec3, IVec2, IVec4, UVec4, Vec4};

use crate::error::{Error, Result};
use crate::render::camera_grid::GridShape;
use crate::render::gpu_constants as gpu;
use crate::render::ground_clipmap::{self, Clipmap};
use crate::render::shaders;
use crate::render::terrain_chunks;
use crate::render::uniforms::FrameUniforms;
use crate::scene::cover::Cover;
use crate::scene::heightmap::Heightmap;
use crate::scene::{field, FieldGround, Scene, Terrain};
use crate::vk::profile::Shader;
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, BufferDesc, Destroy, Device, TexelView};

/// Where the ground comes from: what the renderer needs of it.
pub trait GroundSource: Send + Sync {
    /// Cells per side of a level's window.
    fn cells(&self) -> u32;
    /// Levels it holds for the (view distance, blade range): the `ground.z` its `fill_uniforms`
    /// writes (the shaders' `GROUND_LEVELS`, fixed per graph).
    fn levels(&self, distances: (f32, f32)) -> u32;
    /// Cells per side of a chunk of the terrain's index list (a level's hole is whole chunks).
    fn chunk_cells(&self) -> u32;
    /// Texels the clipmap's buffer holds, fixed at upload: every level the source can draw.
    fn texel_count(&self) -> u64;
    /// The lowest and highest height its ground can have (the terrain chunks' bounds).
    fn height_range(&self) -> (f32, f32);
    /// Texels uploaded with the scene, in slot order; `None` when its [`GroundFill`] writes them.
    fn texels(&self) -> Option<Vec<[f32; 4]>>;
    /// This frame's clipmap for O's cell `cell` (a stored field's O is the world's origin) and
    /// the (view distance, blade range): `ground`, `ground_levels`, `ground_windows` and what its
    /// fill reads.
    fn fill_uniforms(&self, uniforms: &mut FrameUniforms, cell: IVec2, distances: (f32, f32));
    /// How the camera's moves fill it on the GPU; `None` when it is uploaded once.
    fn fill(&self) -> Option<Box<dyn GroundFill>>;
    /// Where grass grows on it (`scene::cover`): its fill (or its uploaded `cover_texels`) writes
    /// the cover channel.
    fn cover(&self) -> &Cover;
    /// The cover per texel uploaded with the scene (with `texels`), in the same slots.
    fn cover_texels(&self) -> Option<Vec<f32>> {
        None
    }
    /// Read-only buffers its fill shader reads in its own set (`SET_PASS`), by the names it
    /// declares them with, uploaded with the scene (`GroundGpu::extra`): a heightmap's texels, the covering map.
    fn buffers(&self) -> Vec<(&'static str, Vec<u32>)> {
        Vec::new()
    }
}

/// A source's fill on the GPU (`passes::ground_fill`): the shader that writes the texels of the
/// vertices that entered a level's window, and, from a frame's uniforms, the windows.
pub trait GroundFill {
    /// The fill shader: one invocation per entered vertex (`camera_grid_entered`), its level in
    /// the push constants' `base.w`.
    fn shader(&self) -> Shader;
    /// The camera grid of this frame's clipmap.
    fn shape(&self, uniforms: &FrameUniforms) -> GridShape;
    /// What the texels are a function of besides their vertex: a change refills every level.
    fn key(&self, uniforms: &FrameUniforms) -> Vec<u32>;
    /// Each level's window this frame: its first vertex on the level's lattice.
    fn windows(&self, uniforms: &FrameUniforms) -> Vec<I64Vec3>;
}

/// The ground on the GPU (`SceneGpu::ground`): its source, its clipmap and the terrain's
/// triangle list.
pub struct GroundGpu {
    /// Where the ground comes from.
    pub source: Box<dyn GroundSource>,
    /// The clipmap's texels (`shaders/terrain/ground_texels.glsl`): `source.texel_count()` of
    /// 16 bytes.
    pub texels: Buffer,
    /// The same texels as RGBA32F, as its readers fetch them under the lavapipe profile.
    pub texel_view: TexelView,
    /// The cover per texel (`GroundCover`, f32), and as R32F texels.
    pub cover: (Buffer, TexelView),
    /// The triangle list over a level's `(cells + 1)²` vertices, chunk by chunk
    /// (`render::terrain_chunks`). Indexed, a vertex shared by six triangles is shaded about once
    /// instead of six times.
    pub indices: Buffer,
    /// Terrain triangles the terrain pass drew in the last frame it recorded (the chunks in view;
    /// a level's triangles before the first).
    pub drawn: Arc<AtomicU64>,
    /// The source's buffers its fill reads (`GroundSource::buffers`), by name.
    pub extra: Vec<(&'static str, Buffer)>,
}

impl GroundGpu {
    /// Free the buffers.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.texel_view.destroy(device);
            self.texels.destroy(device);
            self.cover.1.destroy(device);
            self.cover.0.destroy(device);
            self.indices.destroy(device);
            for (_, buffer) in self.extra {
                buffer.destroy(device);
            }
        }
    }
}

/// What `GroundParts::upload` made so far, freed if a later step of the scene's upload fails;
/// `finish` makes them a `GroundGpu`.
#[derive(Default)]
pub struct GroundParts {
    texels: Option<Buffer>,
    texel_view: Option<TexelView>,
    cover: Option<Buffer>,
    cover_view: Option<TexelView>,
    indices: Option<Buffer>,
    extra: Vec<(&'static str, Buffer)>,
}

impl GroundParts {
    /// Upload `source`'s ground in `batch`: the clipmap's texels and cover (read back by
    /// `Renderer::read_ground`; a stored terrain's uploaded, a filled source's made for its fill
    /// pass) with their texel views, the terrain's triangle list, and the buffers its fill reads
    /// (a heightmap's texels), refused past one storage binding's range.
    pub fn upload(&mut self, device: &Device, batch: &mut UploadBatch, source: &dyn GroundSource) -> Result<()> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let usage = storage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        let count = source.texel_count();
        self.texels = Some(match source.texels() {
            Some(texels) => batch.buffer("ground texels", &texels, usage, device.profile.fetches())?,
            None => Buffer::new(device, &BufferDesc::gpu_only("ground texels", 16 * count, usage))?,
        });
        self.cover = Some(match source.cover_texels() {
            Some(cover) => batch.buffer("ground cover", &cover, usage, device.profile.fetches())?,
            None => Buffer::new(device, &BufferDesc::gpu_only("ground cover", 4 * count, usage))?,
        });
        let texels = self.texels.as_ref().expect("made");
        self.texel_view = Some(TexelView::new(device, texels, vk::Format::R32G32B32A32_SFLOAT, "ground texel view")?);
        let cover = self.cover.as_ref().expect("made");
        self.cover_view = Some(TexelView::new(device, cover, vk::Format::R32_SFLOAT, "ground cover view")?);
        let list = terrain_chunks::chunked_indices(source.cells(), source.chunk_cells());
        let index = vk::BufferUsageFlags::INDEX_BUFFER;
        self.indices = Some(batch.buffer("terrain indices", &list, index, &[Access::IndexRead])?);
        for (name, words) in source.buffers() {
            let (bytes, range) = (4 * words.len() as u64, u64::from(device.limits().max_storage_buffer_range));
            if bytes > range {
                return Err(Error::bad_input(format!(
                    "the ground's {name} needs {} MiB in one storage buffer; {} binds at most {} MiB (a smaller --heightmap)",
                    bytes >> 20,
                    device.info.name,
                    range >> 20
                )));
            }
            let buffer = batch.buffer(name, &words, storage, &[Access::ComputeShaderRead])?;
            self.extra.push((name, buffer));
        }
        Ok(())
    }

    /// The uploaded ground of `source`.
    pub fn finish(mut self, source: Box<dyn GroundSource>) -> GroundGpu {
        GroundGpu {
            texels: self.texels.take().expect("uploaded"),
            texel_view: self.texel_view.take().expect("uploaded"),
            cover: (self.cover.take().expect("uploaded"), self.cover_view.take().expect("uploaded")),
            indices: self.indices.take().expect("uploaded"),
            drawn: Arc::new(AtomicU64::new(2 * u64::from(source.cells()).pow(2))),
            extra: std::mem::take(&mut self.extra),
            source,
        }
    }
}

impl Destroy for GroundParts {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            for view in [self.texel_view, self.cover_view].into_iter().flatten() {
                view.destroy(device);
            }
            let extra = self.extra.into_iter().map(|(_, buffer)| buffer);
            for buffer in [self.texels, self.cover, self.indices].into_iter().flatten().chain(extra) {
                buffer.destroy(device);
            }
        }
    }
}

/// The ground source of `scene`: its relief for a block field, its stored terrain otherwise.
pub fn source(scene: &Scene) -> Box<dyn GroundSource> {
    let cover = scene.cover.clone();
    match scene.field.as_ref().map(|field| &field.ground) {
        Some(FieldGround::Relief(relief)) => Box::new(ReliefGround { relief: relief.clone(), cover }),
        Some(FieldGround::Heightmap(map)) => Box::new(HeightmapGround { map: Arc::clone(map), cover }),
        None => Box::new(StoredGround { terrain: scene.terrain.clone(), cover }),
    }
}

/// The cover rules' part of the frame's `ground` (`shaders/terrain/cover_fill.glsl`): y the slope
/// limit, w its soft edge's width, radians as f32 bits; without a limit, 10 radians (no slope
/// reaches it).
fn cover_uniforms(uniforms: &mut FrameUniforms, cover: &Cover) {
    let limit = cover.slope_limit_deg.map_or(10.0, f32::to_radians);
    uniforms.ground.y = limit.to_bits();
    uniforms.ground.w = crate::scene::cover::SLOPE_SOFT_DEG.to_radians().to_bits();
}

/// A stored field's terrain as the clipmap's one level: its whole grid at its own step, placed at
/// its origin, never moved.
pub struct StoredGround {
    /// The height field.
    pub terrain: Terrain,
    /// Where grass grows (its blades were scattered by it; the terrain is tinted by it).
    pub cover: Cover,
}

impl GroundSource for StoredGround {
    fn cells(&self) -> u32 {
        self.terrain.cells
    }

    fn levels(&self, _: (f32, f32)) -> u32 {
        1
    }

    fn chunk_cells(&self) -> u32 {
        terrain_chunks::CHUNK_CELLS
    }

    fn texel_count(&self) -> u64 {
        u64::from(self.terrain.cells + 1).pow(2)
    }

    fn height_range(&self) -> (f32, f32) {
        let heights = &self.terrain.heights;
        heights.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &h| (lo.min(h), hi.max(h)))
    }

    fn texels(&self) -> Option<Vec<[f32; 4]>> {
        Some(stored_texels(&self.terrain))
    }

    fn fill_uniforms(&self, uniforms: &mut FrameUniforms, _: IVec2, _: (f32, f32)) {
        let (origin, step) = (self.terrain.origin(), self.terrain.cell_size());
        uniforms.ground = UVec4::new(self.terrain.cells, 0, 1, 0);
        cover_uniforms(uniforms, &self.cover);
        // Rise over two cells: the central differences (`stored_texels`).
        uniforms.ground_levels[0] = Vec4::new(origin, origin, step, 2.0 * step);
        uniforms.ground_windows[0] = IVec4::ZERO;
    }

    fn fill(&self) -> Option<Box<dyn GroundFill>> {
        None
    }

    fn cover(&self) -> &Cover {
        &self.cover
    }

    fn cover_texels(&self) -> Option<Vec<f32>> {
        // At each vertex (row by row from the terrain's origin), the slope by its central
        // differences over two cells.
        let (step, run) = (self.terrain.cell_size(), 2.0 * self.terrain.cell_size());
        let (n, origin) = (self.terrain.cells + 1, self.terrain.origin());
        let texels = stored_texels(&self.terrain);
        let at = |i: u32| f64::from(origin + (i as f32) * step);
        let density = |(i, t): (usize, &[f32; 4])| {
            let slope = glam::Vec2::new(t[2], t[3]) / run;
            self.cover.density(at(i as u32 % n), at(i as u32 / n), slope)
        };
        Some(texels.iter().enumerate().map(density).collect())
    }
}

/// A stored terrain's texels, row by row (the one level's window has its base at slot 0): the
/// height, the same height as the next level's (there is none, and no morph), and the central
/// differences along x and z over two cells, clamped to the grid, as the terrain's vertices were
/// always lit.
pub fn stored_texels(terrain: &Terrain) -> Vec<[f32; 4]> {
    let n = terrain.cells as i64 + 1;
    let h = |x: i64, z: i64| terrain.heights[(z.clamp(0, n - 1) * n + x.clamp(0, n - 1)) as usize];
    let mut texels = Vec::with_capacity((n * n) as usize);
    for z in 0..n {
        for x in 0..n {
            let height = h(x, z);
            texels.push([height, height, h(x + 1, z) - h(x - 1, z), h(x, z + 1) - h(x, z - 1)]);
        }
    }
    texels
}

/// A block field's relief in nested levels around the camera (`ground_clipmap::Clipmap`), filled
/// as the camera moves.
pub struct ReliefGround {
    /// The relief, evaluated anywhere.
    pub relief: field::Relief,
    /// Where grass grows on it.
    pub cover: Cover,
}

impl ReliefGround {
    /// Texels of the clipmap of the most levels: any view distance fits.
    pub fn clipmap_texels() -> u64 {
        let shape = Clipmap { step: 1.0, levels: gpu::CAMERA_GRID_MAX_LEVELS }.shape();
        shape.cells_per_level() * u64::from(shape.levels)
    }
}

impl GroundSource for ReliefGround {
    fn cells(&self) -> u32 {
        ground_clipmap::CELLS
    }

    fn levels(&self, (view_distance, blade_range): (f32, f32)) -> u32 {
        Clipmap::for_view(view_distance, blade_range).levels
    }

    fn chunk_cells(&self) -> u32 {
        terrain_chunks::GROUND_CHUNK_CELLS
    }

    fn texel_count(&self) -> u64 {
        Self::clipmap_texels()
    }

    fn height_range(&self) -> (f32, f32) {
        let bound = self.relief.height_bound();
        (-bound, bound)
    }

    fn texels(&self) -> Option<Vec<[f32; 4]>> {
        None
    }

    fn fill_uniforms(&self, uniforms: &mut FrameUniforms, cell: IVec2, distances: (f32, f32)) {
        clipmap_uniforms(uniforms, cell, distances);
        cover_uniforms(uniforms, &self.cover);
        // Taken mod the period in half-metres, so the fill's products fit 32 bits unsigned.
        let residue = |c: i32| c.rem_euclid(ground_clipmap::PERIOD_HALF_METRES as i32);
        uniforms.relief_cycles = std::array::from_fn(|i| {
            let (a, b) = (self.relief.cycles[2 * i], self.relief.cycles[2 * i + 1]);
            IVec4::new(residue(a.0), residue(a.1), residue(b.0), residue(b.1))
        });
    }

    fn fill(&self) -> Option<Box<dyn GroundFill>> {
        Some(Box::new(ClipmapFill { shader: shaders::RELIEF_FILL_COMP }))
    }

    fn buffers(&self) -> Vec<(&'static str, Vec<u32>)> {
        vec![("CoverMap", cover_map_words(&self.cover))]
    }

    fn cover(&self) -> &Cover {
        &self.cover
    }
}

/// A block field's clipmap for O's cell `cell` and the (view distance, blade range), as the
/// relief and the heightmap write it into the frame's uniforms: each texel's rise is its slope,
/// over a run of 1 m.
fn clipmap_uniforms(uniforms: &mut FrameUniforms, cell: IVec2, (view_distance, blade_range): (f32, f32)) {
    let clipmap = Clipmap::for_view(view_distance, blade_range);
    let (levels, windows) = clipmap.uniforms(cell);
    uniforms.ground_levels = levels.map(|l| Vec4::new(l.x, l.y, l.z, 1.0));
    uniforms.ground_windows = windows;
    uniforms.ground = UVec4::new(ground_clipmap::CELLS, 0, clipmap.levels, 0);
}

/// The fill of a block field's clipmap by `shader` (the relief's `relief_fill.comp`, the
/// heightmap's `heightmap_fill.comp`): its clipmap is read back from the frame's uniforms, level
/// 0's step and the levels, and the relief's waves are what else its texels depend on.
struct ClipmapFill {
    shader: Shader,
}

impl ClipmapFill {
    fn clipmap(uniforms: &FrameUniforms) -> Clipmap {
        Clipmap { step: uniforms.ground_levels[0].z, levels: uniforms.ground.z.max(1) }
    }
}

impl GroundFill for ClipmapFill {
    fn shader(&self) -> Shader {
        self.shader
    }

    fn shape(&self, uniforms: &FrameUniforms) -> GridShape {
        Self::clipmap(uniforms).shape()
    }

    fn key(&self, uniforms: &FrameUniforms) -> Vec<u32> {
        let clipmap = Self::clipmap(uniforms);
        let waves = uniforms.relief_waves.iter().flat_map(|w| w.to_array().map(f32::to_bits));
        let cycles = uniforms.relief_cycles.iter().flat_map(|c| c.to_array().map(|v| v as u32));
        [clipmap.step.to_bits(), clipmap.levels].into_iter().chain(waves).chain(cycles).collect()
    }

    fn windows(&self, uniforms: &FrameUniforms) -> Vec<I64Vec3> {
        let cell = IVec2::new(uniforms.field_cells.x, uniforms.field_cells.y);
        Self::clipmap(uniforms).windows(cell).into_iter().map(ground_clipmap::grid_window).collect()
    }
}

/// A block field on a heightmap (`scene::heightmap`): the relief's clipmap, filled from the map's
/// texels (`shaders/terrain/heightmap_fill.comp`), which live on the GPU at 2 bytes each
/// (`GroundMap`: a header, then two texels a word).
pub struct HeightmapGround {
    /// The map.
    pub map: Arc<Heightmap>,
    /// Where grass grows on it.
    pub cover: Cover,
}

/// Words of `GroundMap`'s header: width, height, the extent in x and z and the height of white
/// (f32 bits), whether the map repeats mirrored (1) or is clamped past its edges (0).
pub const MAP_HEADER_WORDS: usize = 8;

impl GroundSource for HeightmapGround {
    fn cells(&self) -> u32 {
        ground_clipmap::CELLS
    }

    fn levels(&self, (view_distance, blade_range): (f32, f32)) -> u32 {
        Clipmap::for_view(view_distance, blade_range).levels
    }

    fn chunk_cells(&self) -> u32 {
        terrain_chunks::GROUND_CHUNK_CELLS
    }

    fn texel_count(&self) -> u64 {
        ReliefGround::clipmap_texels()
    }

    fn height_range(&self) -> (f32, f32) {
        (0.0, self.map.scale.y as f32)
    }

    fn texels(&self) -> Option<Vec<[f32; 4]>> {
        None
    }

    fn fill_uniforms(&self, uniforms: &mut FrameUniforms, cell: IVec2, distances: (f32, f32)) {
        clipmap_uniforms(uniforms, cell, distances);
        cover_uniforms(uniforms, &self.cover);
    }

    fn cover(&self) -> &Cover {
        &self.cover
    }

    fn fill(&self) -> Option<Box<dyn GroundFill>> {
        Some(Box::new(ClipmapFill { shader: shaders::HEIGHTMAP_FILL_COMP }))
    }

    fn buffers(&self) -> Vec<(&'static str, Vec<u32>)> {
        vec![("GroundMap", map_words(&self.map)), ("CoverMap", cover_map_words(&self.cover))]
    }
}

/// `GroundMap`'s words for `map` (`MAP_HEADER_WORDS`, then its texels two a word, the first in
/// the low half).
pub fn map_words(map: &Heightmap) -> Vec<u32> {
    let s = map.scale;
    let header = [map.width, map.height, (s.x as f32).to_bits(), (s.z as f32).to_bits(), (s.y as f32).to_bits()];
    let mut words = Vec::with_capacity(MAP_HEADER_WORDS + map.texels.len().div_ceil(2));
    words.extend_from_slice(&header);
    words.extend([u32::from(map.mirrored), 0, 0]);
    words.extend(map.texels.chunks(2).map(|t| u32::from(t[0]) | (u32::from(*t.get(1).unwrap_or(&0)) << 16)));
    words
}

/// Words of `CoverMap`'s header: width, height, the extent in x and z (f32 bits), whether the
/// map repeats mirrored (1) or is held past its edges (0).
pub const COVER_MAP_HEADER_WORDS: usize = 8;

/// `CoverMap`'s words for `cover`'s covering map (`shaders/terrain/cover_fill.glsl`):
/// `COVER_MAP_HEADER_WORDS`, then its grass densities four a word, the first in the low byte.
/// Without a map, a 1 × 1 map of full density.
pub fn cover_map_words(cover: &Cover) -> Vec<u32> {
    let (width, height, grass, placement) = match &cover.map {
        Some(m) => (m.width, m.height, m.grass.as_slice(), m.placement),
        None => (1, 1, &[255u8][..], crate::scene::cover::MapPlacement { x: 1.0, z: 1.0, mirrored: true }),
    };
    let (x, z) = ((placement.x as f32).to_bits(), (placement.z as f32).to_bits());
    let mut words = Vec::with_capacity(COVER_MAP_HEADER_WORDS + grass.len().div_ceil(4));
    words.extend([width, height, x, z, u32::from(placement.mirrored), 0, 0, 0]);
    words.extend(grass.chunks(4).map(|c| c.iter().rev().fold(0u32, |w, &b| (w << 8) | u32::from(b))));
    words
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stored_terrains_texels_are_its_heights_and_central_differences() {
        let terrain = Terrain::generate(6.0, 4);
        let texels = stored_texels(&terrain);
        let n = terrain.cells as usize + 1;
        assert_eq!(texels.len(), n * n);
        let h = |x: usize, z: usize| terrain.heights[z * n + x];
        // Inside: the differences over two cells; at the edge, clamped to the grid.
        assert_eq!(texels[2 * n + 3], [h(3, 2), h(3, 2), h(4, 2) - h(2, 2), h(3, 3) - h(3, 1)]);
        assert_eq!(texels[0], [h(0, 0), h(0, 0), h(1, 0) - h(0, 0), h(0, 1) - h(0, 0)]);
        let source = StoredGround { terrain: terrain.clone(), cover: Cover::default() };
        assert_eq!(source.texel_count(), texels.len() as u64);
        let mut uniforms: FrameUniforms = bytemuck::Zeroable::zeroed();
        source.fill_uniforms(&mut uniforms, IVec2::ZERO, (150.0, 150.0));
        assert_eq!(uniforms.ground_levels[0], Vec4::new(-3.0, -3.0, terrain.cell_size(), 2.0 * terrain.cell_size()));
        // No slope limit: 10 radians, which no slope reaches; the soft edge's width in radians.
        let soft = crate::scene::cover::SLOPE_SOFT_DEG.to_radians().to_bits();
        assert_eq!(uniforms.ground, UVec4::new(terrain.cells, 10f32.to_bits(), 1, soft));
        // A limit's radians.
        let limited = StoredGround { terrain, cover: Cover { slope_limit_deg: Some(30.0), map: None } };
        limited.fill_uniforms(&mut uniforms, IVec2::ZERO, (150.0, 150.0));
        assert_eq!(uniforms.ground.y, 30f32.to_radians().to_bits());
    }

    #[test]
    fn the_cover_maps_words_hold_its_header_and_its_densities_four_a_word() {
        let placement = crate::scene::cover::MapPlacement { x: 200.0, z: 100.0, mirrored: false };
        let map = crate::scene::cover::CoverMap { width: 5, height: 1, grass: vec![1, 2, 3, 4, 5], placement };
        let words = cover_map_words(&Cover { slope_limit_deg: None, map: Some(Arc::new(map)) });
        assert_eq!(words[..5], [5, 1, 200f32.to_bits(), 100f32.to_bits(), 0]);
        assert_eq!(words[COVER_MAP_HEADER_WORDS..], [0x0403_0201, 5]);
        // No map: one texel of full density.
        let none = cover_map_words(&Cover::default());
        assert_eq!((none[0], none[1], none[COVER_MAP_HEADER_WORDS]), (1, 1, 255));
    }

    #[test]
    fn the_reliefs_buffer_holds_its_clipmap_at_any_view_distance() {
        let relief = field::Relief::generate(1);
        let source = ReliefGround { relief, cover: Cover::default() };
        for view in [40.0, 150.0, 5000.0, 10_000.0] {
            let mut uniforms: FrameUniforms = bytemuck::Zeroable::zeroed();
            source.fill_uniforms(&mut uniforms, IVec2::new(3, -7), (view, view.min(150.0)));
            let fill = source.fill().expect("a relief fills on the GPU");
            let shape = fill.shape(&uniforms);
            assert!(shape.cells_per_level() * u64::from(shape.levels) <= source.texel_count(), "{view} m");
            assert_eq!(fill.windows(&uniforms).len() as u32, shape.levels);
            assert!(uniforms.ground_levels[..shape.levels as usize].iter().all(|l| l.w == 1.0));
        }
    }
}
