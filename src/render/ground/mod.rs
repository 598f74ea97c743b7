//! The ground under the grass from one source (issue #30 item 2). A [`GroundSource`] writes the
//! ground into one clipmap, the levels of a camera grid (`render::camera_grid`), and every reader
//! reads it there through one include, `shaders/common/ground.glsl`: the terrain mesh, the cull's
//! roots and tile normals, the blades' lighting and the debug views. No reader asks which source
//! it is.
//!
//! After every level's vertices, the clipmap holds per level its tiles' lowest and highest height
//! and most cover ([`tiles`]), which the cull bounds its cells by.
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
//! A new source is an implementation of [`GroundSource`] in a file of its own here, with a
//! [`GroundFill`] and its fill shader when the camera's moves fill it, and its arm in [`source`].
//! Every source writes the cover channel beside its texels (`cover`).

mod cover;
mod heightmap;
mod relief;
mod stored;
pub mod tiles;

pub use cover::{cover_map_words, COVER_MAP_HEADER_WORDS};
pub use heightmap::{map_words, HeightmapGround, MAP_HEADER_WORDS};
pub use relief::ReliefGround;
pub use stored::{stored_texels, StoredGround};

use std::sync::atomic::AtomicU64;
use std::sync::Arc;

use ash::vk;
use glam::{I64Vec3, IVec2};

use crate::error::{Error, Result};
use crate::render::camera_grid::GridShape;
use crate::render::ground_clipmap::{self, Clipmap};
use crate::render::terrain_chunks;
use crate::render::uniforms::FrameUniforms;
use crate::scene::cover::Cover;
use crate::scene::{FieldGround, Scene};
use crate::vk::profile::Shader;
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, BufferDesc, Destroy, Device, TexelView};

/// Texels of the camera-following clipmap of the most levels, its tiles after its vertices: any
/// view distance fits.
pub fn clipmap_texels() -> u64 {
    let shape = Clipmap { step: 1.0, levels: crate::render::gpu_constants::CAMERA_GRID_MAX_LEVELS }.shape();
    shape.cells_per_level() * u64::from(shape.levels) + tiles::count(shape.levels, ground_clipmap::CELLS)
}

/// Where the ground comes from: what the renderer needs of it. The shape's defaults are a block
/// field's camera-following clipmap (`ground_clipmap`), filled on the GPU: the relief's and the
/// heightmap's; a stored terrain's one uploaded level overrides them.
pub trait GroundSource: Send + Sync {
    /// Cells per side of a level's window.
    fn cells(&self) -> u32 {
        ground_clipmap::CELLS
    }
    /// Levels it holds for the (view distance, blade range): the `ground.z` its `fill_uniforms`
    /// writes (the shaders' `GROUND_LEVELS`, fixed per graph).
    fn levels(&self, (view_distance, blade_range): (f32, f32)) -> u32 {
        Clipmap::for_view(view_distance, blade_range).levels
    }
    /// Cells per side of a chunk of the terrain's index list (a level's hole is whole chunks).
    fn chunk_cells(&self) -> u32 {
        terrain_chunks::GROUND_CHUNK_CELLS
    }
    /// Texels the clipmap's buffer holds, fixed at upload: every level the source can draw (by
    /// default the clipmap of the most levels: any view distance fits).
    fn texel_count(&self) -> u64 {
        clipmap_texels()
    }
    /// The lowest and highest height its ground can have (the terrain chunks' bounds).
    fn height_range(&self) -> (f32, f32);
    /// Texels uploaded with the scene, in slot order; `None` when its [`GroundFill`] writes them.
    fn texels(&self) -> Option<Vec<[f32; 4]>> {
        None
    }
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
    fn cover_texels(&self) -> Option<Vec<u32>> {
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
    /// The cover per texel (`GroundCover`, `pack_cover`'s two unorm16), and as R32UI texels.
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
        self.cover_view = Some(TexelView::new(device, cover, vk::Format::R32_UINT, "ground cover view")?);
        let list = terrain_chunks::chunked_indices(source.cells(), source.chunk_cells());
        let index = vk::BufferUsageFlags::INDEX_BUFFER;
        self.indices = Some(batch.buffer("terrain indices", &list, index, &[Access::IndexRead])?);
        for (name, words) in source.buffers() {
            check_range(device, name, &words)?;
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

/// Refuse `words` for the ground's `name` past one storage binding's range (bad input: the map).
fn check_range(device: &Device, name: &str, words: &[u32]) -> Result<()> {
    let (bytes, range) = (4 * words.len() as u64, u64::from(device.limits().max_storage_buffer_range));
    if bytes > range {
        return Err(Error::bad_input(format!(
            "the ground's {name} needs {} MiB in one storage buffer; {} binds at most {} MiB (a smaller --heightmap)",
            bytes >> 20,
            device.info.name,
            range >> 20
        )));
    }
    Ok(())
}

/// A texel of `GroundCover`: the grass's density in the low half and the flowers' in the high
/// half, as unorm16 (`packUnorm2x16`, `shaders/terrain/ground_texels.glsl`).
pub fn pack_cover(grass: f32, flowers: f32) -> u32 {
    let unorm = |v: f32| (v.clamp(0.0, 1.0) * 65_535.0).round() as u32;
    unorm(grass) | (unorm(flowers) << 16)
}

/// `pack_cover`'s (grass, flowers) back, as `unpackUnorm2x16` gives them.
pub fn unpack_cover(packed: u32) -> (f32, f32) {
    ((packed & 0xffff) as f32 / 65_535.0, (packed >> 16) as f32 / 65_535.0)
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
