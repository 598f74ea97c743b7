//! The scene on the GPU: blade storage buffer, the ground's clipmap and triangle list
//! (`render::ground`), cluster records, the blade alpha texture and its sampler, uploaded once
//! through staging; and set `SET_SCENE` that every scene
//! pass binds (the scene and one frame's uniforms and forces). What animates the blades is the
//! blade response's (`render::animation::response`).

use ash::vk;

use crate::error::Result;
use crate::render::draw_rows::TileRows;
use crate::render::gpu_constants::{self, FIELD_TERRAIN_CELLS, GROUND_TILE_CELLS};
use crate::render::ground::{GroundGpu, GroundParts, GroundSource};
use crate::render::limits::BLADES_PER_INSTANCE_RANGE;
use crate::scene::clusters::{BladeCluster, ClusterGrid};
use crate::scene::tiles::{BladeTile, TileGrid, MAX_TILES_PER_SIDE};
use crate::scene::{alpha, Scene};
use crate::vk::descriptor::{Resource, SetLayout};
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, BufferDesc, Destroy, Device, Image, ImageDesc, TexelView};

/// Bytes of the `--eval blade` pose records: `segments + 1` records of `POSE_WORDS` words per
/// blade (`shaders/common/bindings.glsl`).
pub fn pose_bytes(blades: u32, segments: u32) -> u64 {
    4 * u64::from(gpu_constants::POSE_WORDS) * u64::from(blades.max(1)) * u64::from(segments + 1)
}

/// `--eval blade` pose records for `scene`: one per stored blade or, with the cull, one per entry
/// of its visible list (the blade-pose pass evaluates only what is drawn), as many as one
/// storage buffer holds (`maxStorageBufferRange`). The cull then keeps at most that many
/// entries (`Renderer::frame_uniforms`); brute force needs one per blade (`check_pose_records`).
pub fn pose_records(device: &Device, scene: &SceneGpu, segments: u32) -> u32 {
    u64::from(scene.visible_capacity.max(scene.blade_count)).min(most_pose_records(device, segments)) as u32
}

/// The most `--eval blade` records of `segments` segments one storage buffer holds.
pub fn most_pose_records(device: &Device, segments: u32) -> u64 {
    u64::from(device.limits().max_storage_buffer_range) / pose_bytes(1, segments)
}

/// Bytes of the placed, lit levels of `records` drawn blades of `segments` segments
/// (`shaders/blades/blade_levels.comp`): `segments + 1` levels of `LEVEL_UVEC2S` uvec2 per record.
pub fn level_bytes(records: u32, segments: u32) -> u64 {
    8 * u64::from(gpu_constants::LEVEL_UVEC2S) * u64::from(records.max(1)) * u64::from(segments + 1)
}

/// Placed levels for `records` pose records: as many as one storage buffer holds, and as its
/// texel view (RG32UI, `maxTexelBufferElements`) reaches.
pub fn level_records(device: &Device, records: u32, segments: u32) -> u32 {
    let limits = device.limits();
    let by_range = u64::from(limits.max_storage_buffer_range) / level_bytes(1, segments);
    let by_texels = u64::from(limits.max_texel_buffer_elements) / (level_bytes(1, segments) / 8);
    u64::from(records).min(by_range).min(by_texels) as u32
}

/// Placed levels to make room for (`PoseRecords`): one per entry the cull's list may hold, at most
/// `records`; none without the cull, which alone places them.
pub fn level_room(scene: &SceneGpu, records: u32, culled: bool) -> u32 {
    if culled {
        scene.visible_capacity.min(records)
    } else {
        0
    }
}

/// Entries of the cull's visible list a frame may fill: its capacity, and with pose records
/// (`--eval blade`, `per_blade` the records' room for placed levels) at most one per record
/// (`pose_records`) and per placed level when the records have room for them (with the cull).
pub fn visible_limit(device: &Device, scene: &SceneGpu, segments: u32, per_blade: Option<u32>) -> u32 {
    match per_blade {
        None => scene.visible_capacity,
        Some(levels) => {
            let records = scene.visible_capacity.min(pose_records(device, scene, segments));
            if levels > 0 {
                records.min(levels)
            } else {
                records
            }
        }
    }
}

/// Device-local copies of the scene and of its animation data.
pub struct SceneGpu {
    /// One `BladeInstance` per blade.
    pub blades: Buffer,
    /// Number of blades in `blades`.
    pub blade_count: u32,
    /// The ground: its source, its clipmap and the terrain's triangle list.
    pub ground: GroundGpu,
    /// A stored terrain's grid origin and cell size (the CPU's cull mirror reads them from the
    /// frame's `terrain`).
    pub terrain_origin: f32,
    /// Cell edge in metres.
    pub terrain_cell_size: f32,
    /// The blade outline (R8).
    pub blade_alpha: Image,
    /// Linear, clamped sampler for the alpha texture.
    pub sampler: vk::Sampler,
    /// One `BladeCluster` per blade.
    pub clusters: Buffer,
    /// The cluster grid the records refer to; a block field's innermost wind level
    /// (`field_gpu::cluster_grid`).
    pub grid: ClusterGrid,
    /// The wind's nested levels, each `grid.corner_count()` corners, innermost first: a stored
    /// field's one grid, or those a block field's blades reach (`field_gpu::wind_levels`).
    pub wind_levels: u32,
    /// One `BladeTile` per tile.
    pub tiles: Buffer,
    /// The tile grid.
    pub tile_grid: TileGrid,
    /// A block field's size, density and relief (`None`: a stored field).
    pub field: Option<crate::scene::Field>,
    /// The ground's steepest slope: a block field's (`scene::FieldGround::slope_bound`) or the
    /// stored terrain's (`scene::terrain::Terrain::slope_bound`), once (a heightmap's visits every
    /// texel). It tells a frame whether its terrain can hide anything (`render::occlusion`).
    pub ground_slope: f32,
    /// A block field's clump size in millimetres, the shaders' `CLUMP_SIZE_MM` (0: none; a
    /// stored field's blades were clumped on the CPU).
    pub clump_size_mm: u32,
    /// The share of candidate blades the flowers claim, the shaders' `FLOWER_SHARE`
    /// (`scene::Scene::flower_share`; 0: no flowers).
    pub flower_share: f32,
    /// The share the far field's flower tiles are baked at (`scene::Scene::far_flower_share`).
    pub far_flower_share: f32,
    /// The cull's visible list: (blade index, packed scale) per drawn blade.
    pub visible: Buffer,
    /// The visible list as RG32UI texels, as its readers fetch it.
    pub visible_texels: TexelView,
    /// Entries of `visible`.
    pub visible_capacity: u32,
    /// Ring slots the cull's buffers hold (`slot_counts`, the slot list in `draws`): a block
    /// field's for the view distance it was uploaded with.
    pub slot_capacity: u32,
    /// The cull's `SLOT_WORDS` words per ring slot.
    pub slot_counts: Buffer,
    /// The cull's `VkDrawIndexedIndirectCommand` per LOD bucket, then its dispatches.
    pub draws: Buffer,
    /// The count pass's verdict per candidate blade, for the emit pass.
    pub cull_results: Buffer,
    /// The same verdicts as RG32UI texels, as the emit pass reads them (`TexelView` says why).
    pub cull_result_texels: TexelView,
    /// The blades as RGBA32UI texels, two per blade, as the scene's shaders read them.
    pub blade_texels: TexelView,
    /// The depth pyramid (`PYRAMID_FLOATS` floats) the depth-pyramid pass writes.
    pub depth_pyramid: Buffer,
    /// The same floats as R32 texels: the occlusion test reads them (`TexelView` says why).
    pub depth_pyramid_texels: TexelView,
    /// The cull tiles pass's output: the count pass's dispatch, each slot's first verdict (a block
    /// field's) and candidates, the slots with candidates.
    pub cull_alloc: Buffer,
    /// Verdicts `cull_results` holds.
    pub verdict_capacity: u32,
    /// The blade class's rows per tile (`draw_rows`, `slot_capacity` a bucket), the scan writes.
    pub tile_rows: Buffer,
}

/// Ring slots the cull may dispatch for a grid of `tiles` per side: the rings around a tile of
/// the grid reach at most `tiles − 1` tiles away.
pub fn max_ring_slots(tiles: u32) -> u32 {
    (2 * tiles - 1) * (2 * tiles - 1)
}

/// Bytes of `cull_alloc` for `slots` ring slots: the count pass's dispatch (4 words), each slot's
/// first verdict, each slot's candidates, the listed slots, each slot's blade candidates
/// (`shaders/cull/tiles_main.glsl`).
fn cull_alloc_bytes(slots: u32) -> u64 {
    4 * (4 + 4 * u64::from(slots))
}

/// Bytes of the cull's buffers for `blades` stored blades, `slots` ring slots and a visible list
/// of `visible` entries.
fn cull_bytes(blades: u64, slots: u32, visible: u32) -> [u64; 4] {
    // The buckets' indirect draws, their pose and levels dispatches, the emit's, its slots.
    let draws = 4 * (u64::from(gpu_constants::EMIT_SLOTS_WORD) + u64::from(slots));
    [
        8 * u64::from(visible.max(1)),
        4 * u64::from(gpu_constants::SLOT_WORDS) * u64::from(slots),
        draws,
        8 * blades.max(1),
    ]
}

/// Entries past the drawn blades for the padding of each LOD bucket's last instance
/// (`cull_scan.comp`), at the largest `--blades-per-instance`.
const VISIBLE_PADDING: u32 = gpu_constants::MAX_LOD_BUCKETS * (*BLADES_PER_INSTANCE_RANGE.end() - 1);

/// Most entries of a block field's visible list (32 MiB): the blades the cull keeps out to the
/// view distance stay well under it; past it every bucket is thinned evenly (`cull_scan.comp`).
pub const FIELD_VISIBLE: u32 = 1 << 22;

/// Most verdicts of a block field's candidates in a frame (32 MiB): its slots take room for theirs
/// each frame, and a slot finding none draws nothing (`shaders/cull/cull_count.comp`).
pub const FIELD_VERDICTS: u32 = 1 << 22;

/// Verdicts `cull_results` holds for `scene` over `slots` ring slots, where a draw-class set's own
/// source adds up to `source_room` candidates a slot (`render::draw_class::CandidateSource`): a
/// block field's `FIELD_VERDICTS`, shared by its slots' candidates; a stored field's one per blade
/// (a tile is one slot's) and the source's room, up to `FIELD_VERDICTS` past the blades (the
/// slots past it draw nothing, and the cull reports their candidates as lost).
pub fn verdict_capacity(scene: &Scene, slots: u32, source_room: u32) -> u32 {
    if scene.field.is_some() {
        FIELD_VERDICTS
    } else {
        let room = u64::from(slots) * u64::from(source_room);
        scene.blades.len() as u32 + room.min(u64::from(FIELD_VERDICTS)) as u32
    }
}

/// Ring slots and visible-list entries the cull needs for `scene` with blades out to
/// `blade_range` (`Culling::blade_range`).
pub fn cull_capacity(scene: &Scene, blade_range: f32) -> (u32, u32) {
    match &scene.field {
        Some(_) => {
            let slots = crate::render::field_gpu::ring_slots(blade_range);
            (slots, (u64::from(slots) * scene.blades.len() as u64).min(u64::from(FIELD_VISIBLE)) as u32)
        }
        None => (max_ring_slots(scene.tile_grid.tiles), scene.blades.len() as u32 + VISIBLE_PADDING),
    }
}

impl SceneGpu {
    /// The wind's corners over every level (`wind_levels` × the grid's).
    pub fn wind_corner_count(&self) -> u32 {
        self.wind_levels * self.grid.corner_count()
    }
}

/// Bytes of the depth pyramid.
const PYRAMID_BYTES: u64 = 4 * gpu_constants::PYRAMID_FLOATS as u64;

/// Resources created so far by `upload`, freed if it fails half-way.
#[derive(Default)]
struct Partial {
    blades: Option<Buffer>,
    ground: GroundParts,
    clusters: Option<Buffer>,
    blade_alpha: Option<Image>,
    tiles: Option<Buffer>,
    cull: Vec<Buffer>,
    pyramid_texels: Option<TexelView>,
    blade_texels: Option<TexelView>,
    visible_texels: Option<TexelView>,
    result_texels: Option<TexelView>,
}

impl Destroy for Partial {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.ground.destroy(device);
            let scene = [self.blades, self.clusters, self.tiles];
            for buffer in scene.into_iter().flatten().chain(self.cull) {
                buffer.destroy(device);
            }
            if let Some(image) = self.blade_alpha {
                image.destroy(device);
            }
            for view in
                [self.pyramid_texels, self.blade_texels, self.visible_texels, self.result_texels].into_iter().flatten()
            {
                view.destroy(device);
            }
        }
    }
}

impl SceneGpu {
    /// Bytes of device memory `upload` will allocate for `scene` (staging included, as it
    /// coexists with the destination during the upload).
    pub fn memory_bytes(blade_count: u64, terrain_cells: u64) -> u64 {
        // Blade record, cluster record, pose record (with --eval blade), visible-list entry, cull
        // verdict.
        let blades = blade_count
            * (std::mem::size_of::<crate::scene::BladeInstance>() + std::mem::size_of::<BladeCluster>() + 16 + 8 + 8)
                as u64;
        // The ground's texels and triangles: a stored terrain's grid and its tiles, or the
        // relief's clipmap (its tiles included).
        let relief = crate::render::ground::clipmap_texels();
        let stored = (terrain_cells + 1).pow(2) + terrain_cells.div_ceil(u64::from(GROUND_TILE_CELLS)).pow(2);
        let heights = 16 * (stored + relief) + 24 * terrain_cells.max(u64::from(FIELD_TERRAIN_CELLS)).pow(2);
        let alpha = u64::from(alpha::WIDTH * alpha::HEIGHT);
        let tiles = u64::from(MAX_TILES_PER_SIDE).pow(2) * std::mem::size_of::<BladeTile>() as u64
            + cull_bytes(0, max_ring_slots(MAX_TILES_PER_SIDE), 0)[1]
            + cull_alloc_bytes(max_ring_slots(MAX_TILES_PER_SIDE))
            + 8 * u64::from(FIELD_VISIBLE)
            + 8 * u64::from(FIELD_VERDICTS)
            + PYRAMID_BYTES;
        2 * (blades + heights + alpha + tiles)
    }

    /// Upload the scene and its cluster records (clusters of about `cluster_size` metres) in one
    /// batch, the cull's buffers for blades out to `blade_range` and a block field's force corners
    /// for plants out to `wind_reach` (the far field's, `Culling::wind_reach`).
    pub fn upload(
        device: &Device,
        scene: &Scene,
        cluster_size: f32,
        (blade_range, wind_reach): (f32, f32),
        source_room: u32,
    ) -> Result<Self> {
        // The batch waits for its submission or never submits.
        let mut partial = crate::vk::guard::empty::<Partial>(device);
        let (grid, wind_levels) = match &scene.field {
            // A block field's corners follow the camera over the cells it sees.
            Some(_) => crate::render::field_gpu::wind_grid(cluster_size, wind_reach),
            None => (ClusterGrid::new(scene.terrain.size, cluster_size), 1),
        };
        let mut capacity = cull_capacity(scene, blade_range);
        let verdicts = verdict_capacity(scene, capacity.0, source_room);
        if scene.field.is_none() {
            // A stored field's visible list holds what its verdicts may keep.
            capacity.1 += verdicts - scene.blades.len() as u32;
        }
        let source = crate::render::ground::source(scene);
        let room = (capacity.0, capacity.1, verdicts);
        let sampler = Self::upload_into(device, scene, source.as_ref(), (&grid, room), &mut partial)?;
        let mut partial = partial.take();
        let ground = std::mem::take(&mut partial.ground).finish(source);
        Ok(Self {
            blades: partial.blades.take().expect("uploaded"),
            blade_texels: partial.blade_texels.take().expect("created"),
            blade_count: scene.blades.len() as u32,
            ground,
            terrain_origin: scene.terrain.origin(),
            terrain_cell_size: scene.terrain.cell_size(),
            blade_alpha: partial.blade_alpha.take().expect("uploaded"),
            sampler,
            clusters: partial.clusters.take().expect("uploaded"),
            grid,
            wind_levels,
            tiles: partial.tiles.take().expect("uploaded"),
            tile_grid: scene.tile_grid,
            field: scene.field.clone(),
            ground_slope: scene.field.as_ref().map_or_else(|| scene.terrain.slope_bound(), |f| f.ground.slope_bound()),
            clump_size_mm: match (&scene.field, scene.clumps) {
                (Some(_), Some(clumps)) => clumps.size_mm(),
                _ => 0,
            },
            flower_share: scene.flower_share(),
            far_flower_share: scene.far_flower_share(),
            verdict_capacity: verdicts,
            visible_capacity: capacity.1,
            slot_capacity: capacity.0,
            tile_rows: partial.cull.pop().expect("created"),
            cull_alloc: partial.cull.pop().expect("created"),
            depth_pyramid_texels: partial.pyramid_texels.take().expect("created"),
            depth_pyramid: partial.cull.pop().expect("created"),
            cull_results: partial.cull.pop().expect("created"),
            cull_result_texels: partial.result_texels.take().expect("created"),
            draws: partial.cull.pop().expect("created"),
            slot_counts: partial.cull.pop().expect("created"),
            visible: partial.cull.pop().expect("created"),
            visible_texels: partial.visible_texels.take().expect("created"),
        })
    }

    fn upload_into(
        device: &Device,
        scene: &Scene,
        ground: &dyn GroundSource,
        (grid, (slots, visible_entries, verdicts)): (&ClusterGrid, (u32, u32, u32)),
        partial: &mut Partial,
    ) -> Result<vk::Sampler> {
        let mut batch = UploadBatch::new(device);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        // Clusters are also read by the blade-pose compute pass.
        let vertex_compute_read: &'static [Access] = &[Access::VertexShaderStorageRead, Access::ComputeShaderRead];
        // The scene's shaders read the blades as texels (`blade_record`).
        let texel_usage = storage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        partial.blades = Some(batch.buffer("blades", &scene.blades, texel_usage, device.profile.fetches())?);
        let blades = partial.blades.as_ref().expect("uploaded");
        partial.blade_texels = Some(TexelView::new(device, blades, vk::Format::R32G32B32A32_UINT, "blade texels")?);
        partial.ground.upload(device, &mut batch, ground)?;
        let clusters = grid.assign(&scene.blades);
        partial.clusters = Some(batch.buffer("blade clusters", &clusters, storage, vertex_compute_read)?);
        let desc = ImageDesc::color(
            "blade alpha",
            vk::Format::R8_UNORM,
            vk::Extent2D { width: alpha::WIDTH, height: alpha::HEIGHT },
            vk::ImageUsageFlags::SAMPLED,
        );
        partial.blade_alpha = Some(batch.image(&desc, &alpha::texels(), &[Access::FragmentShaderSampledRead])?);
        partial.tiles = Some(batch.buffer("blade tiles", &scene.tiles, storage, &[Access::ComputeShaderRead])?);
        batch.submit()?;
        let slots_count = slots;
        let [visible, slots, draws, results] = cull_bytes(u64::from(verdicts), slots, visible_entries);
        let indirect = storage | vk::BufferUsageFlags::INDIRECT_BUFFER;
        // The visible list and the draws are read back by `Renderer::read_*`.
        let (texels, read) = (vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER, vk::BufferUsageFlags::TRANSFER_SRC);
        for (name, size, usage) in [
            ("visible blades", visible, storage | texels | read),
            ("cull slot counts", slots, storage),
            ("cull draws", draws, indirect | read),
            ("cull results", results, storage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER),
            ("depth pyramid", PYRAMID_BYTES, storage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER),
            ("cull verdict room", cull_alloc_bytes(slots_count), indirect),
            // Always there (a rebuild may switch to a row per tile): 256 bytes a slot.
            ("cull tile rows", 4 * u64::from(TileRows { capacity: slots_count }.words()), indirect),
        ] {
            partial.cull.push(Buffer::new(device, &BufferDesc::gpu_only(name, size, usage))?);
        }
        // Texel views of four of them, by their place in the list above.
        let entries = &partial.cull[0];
        partial.visible_texels = Some(TexelView::new(device, entries, vk::Format::R32G32_UINT, "visible texels")?);
        let results = &partial.cull[3];
        partial.result_texels = Some(TexelView::new(device, results, vk::Format::R32G32_UINT, "cull result texels")?);
        let pyramid = &partial.cull[4];
        partial.pyramid_texels = Some(TexelView::new(device, pyramid, vk::Format::R32_SFLOAT, "depth pyramid texels")?);
        let sampler = crate::vk::image::clamped_sampler(device, vk::Filter::LINEAR, "blade alpha sampler")?;
        Ok(sampler)
    }

    /// Point `set` (of `layout`, `SET_SCENE`, reflected) at the scene's resources and at `frame`'s
    /// (one frame's own, given by their owners), each by the name its header declares it with
    /// (`layout(SCENE(Name), …)`: `shaders/blades/blade_records.glsl`, `terrain/ground_texels.glsl`,
    /// `blades/blade_alpha.glsl`, `blades/clusters.glsl`, `cull/tiles.glsl`, `cull/visible.glsl`,
    /// ); build.rs numbers them. The layout writes those its shaders bind.
    pub fn write_descriptors(
        &self,
        device: &Device,
        layout: &SetLayout,
        set: vk::DescriptorSet,
        frame: &[(&str, Resource)],
    ) -> Result<()> {
        let alpha = Resource::Image(vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: self.blade_alpha.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        });
        let (buffer, texels) = (|b: &Buffer| Resource::Buffer(b.descriptor()), |t: &TexelView| Resource::Texels(t.raw));
        let resources = [
            ("Blades", buffer(&self.blades)),
            ("blade_texels", texels(&self.blade_texels)),
            ("blade_alpha", alpha),
            ("Clusters", buffer(&self.clusters)),
            ("Tiles", buffer(&self.tiles)),
            ("Visible", buffer(&self.visible)),
            ("visible_texels", texels(&self.visible_texels)),
            ("GroundTexels", buffer(&self.ground.texels)),
            ("ground_texels", texels(&self.ground.texel_view)),
            ("GroundCover", buffer(&self.ground.cover.0)),
            ("ground_cover_texels", texels(&self.ground.cover.1)),
        ];
        let resources: Vec<_> = frame.iter().cloned().chain(resources).collect();
        layout.write_named(device, set, "scene set", &resources)
    }

    /// Free everything.
    ///
    /// # Safety
    /// No pending GPU work may use the scene.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            self.clusters.destroy(device);
            self.tiles.destroy(device);
            self.visible.destroy(device);
            self.slot_counts.destroy(device);
            self.draws.destroy(device);
            self.cull_results.destroy(device);
            self.cull_result_texels.destroy(device);
            self.depth_pyramid_texels.destroy(device);
            self.blade_texels.destroy(device);
            self.visible_texels.destroy(device);
            self.ground.destroy(device);
            self.depth_pyramid.destroy(device);
            self.cull_alloc.destroy(device);
            self.tile_rows.destroy(device);
            self.blade_alpha.destroy(device);
            self.blades.destroy(device);
        }
    }
}

// The buckets' pose and levels dispatches follow their draws in `draws`, then the emit pass's
// dispatch and its slots (`shaders/common/shared.glsl`; a draw's words, `draw_rows`).
const _: () =
    assert!(gpu_constants::BUCKET_DISPATCH_WORD == gpu_constants::DRAW_WORDS * gpu_constants::MAX_LOD_BUCKETS);
const _: () = assert!(
    gpu_constants::EMIT_DISPATCH_WORD == gpu_constants::BUCKET_DISPATCH_WORD + 3 * gpu_constants::MAX_LOD_BUCKETS
);
const _: () = assert!(gpu_constants::THIN_WORD == gpu_constants::EMIT_DISPATCH_WORD + 3);
const _: () = assert!(gpu_constants::EMIT_SLOTS_WORD == gpu_constants::THIN_WORD + 1);
