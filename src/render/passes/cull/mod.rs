//! The GPU-driven cull (thesis §5.3, Zhang Xia §5.2, Belyaev §2.2, Jahrmann & Wimmer 2017) as
//! four compute passes of the graph, each one dispatch: `tiles` (the tile tests of every ring
//! slot around the culling camera's tile; lists the slots with candidates), `count` (per listed
//! slot: blade tests, counts per LOD bucket), `scan` (offsets, the indirect draws, the frame's
//! counts for the host) and `emit` (the visible list, in a deterministic near-to-far order), each
//! a [`CullStep`] with its own shader and declared uses. Every word they write is written each
//! frame: there is no counter to clear. The blade pass then draws each bucket indirectly
//! (`passes::blades`). The graph orders them by what each declares (`shaders/cull*.comp`).

pub mod count;
pub mod emit;
pub mod scan;
pub mod tiles;

use std::rc::Rc;

use ash::vk;

use crate::error::Result;
use crate::render::culling::CullCounts;
use crate::render::gpu_constants::CULL_STATS_WORDS;
use crate::render::graph::{Declaration, Graph, Pass, PassContext};
use crate::render::recording::{self, PassSet, SceneSets};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource;
use crate::vk::{pipeline, Access, Buffer, BufferDesc, Destroy, Device, Guard};

/// What the cull passes are built from: the scene's set layouts (sets 0 and 1 of their pipeline
/// layout), the push-constant range, the specialization constants, and the frames' host-visible
/// count buffers the scan writes.
pub struct CullSetup<'a> {
    /// The sets before the cull's own, and the frames in flight.
    pub sets: SceneSets<'a>,
    /// Specialization constants.
    pub constants: &'a Specialization,
    /// Each frame's counts buffer (`CullFrame::stats`), by slot.
    pub frame_stats: Vec<vk::Buffer>,
    /// The count pass's shader: the library's `cull_count.comp` (the blade class alone), or a
    /// set of draw classes' with their selection (`render::draw_class::DrawClasses`).
    pub count_shader: crate::vk::profile::Shader,
    /// The tiles pass's shader: the library's `cull_tiles.comp` (the blade tiles' candidates
    /// alone), or a set of draw classes' with its own candidate source's
    /// (`render::draw_class::CandidateSource`).
    pub tiles_shader: crate::vk::profile::Shader,
}

/// The cull's part of one frame in flight (`frame::PerFrame`): the counts its scan writes for
/// the host, and how to read them. It outlives the passes (a rebuild keeps it: set 0 names it).
pub struct CullFrame {
    /// The frame's counts (`CULL_STATS_WORDS` words), written by the scan, read after the fence.
    pub stats: Buffer,
    /// Segments of the LOD buckets of the frame's cull (empty: no cull ran).
    segments: Vec<u32>,
    /// Whether the frame's buckets drew blades with one tip vertex (the outline as geometry).
    collapsed_tip: bool,
    /// The frame's further draw classes: name, first bucket, buckets (`render::draw_class`).
    classes: Vec<(&'static str, u32, u32)>,
}

impl CullFrame {
    /// The counts buffer of frame `slot`.
    pub fn new(device: &Device, slot: usize) -> Result<Self> {
        let name = format!("frame {slot} cull counts");
        let bytes = 4 * u64::from(CULL_STATS_WORDS);
        let stats = Buffer::new(device, &BufferDesc::readback(&name, bytes, vk::BufferUsageFlags::STORAGE_BUFFER))?;
        Ok(Self { stats, segments: Vec::new(), collapsed_tip: false, classes: Vec::new() })
    }

    /// The frame being recorded culls blades into buckets of `segments` (empty: it does not
    /// cull), their tips collapsed or not, and into the buckets of further `classes` (name, first
    /// bucket, buckets).
    pub fn recorded(&mut self, segments: &[u32], collapsed_tip: bool, classes: &[(&'static str, u32, u32)]) {
        self.segments.clear();
        self.segments.extend_from_slice(segments);
        self.collapsed_tip = collapsed_tip;
        self.classes.clear();
        self.classes.extend_from_slice(classes);
    }

    /// What the frame's cull kept and drew (its fence has signalled); `None` when it did not
    /// cull.
    pub fn counts(&self) -> Option<CullCounts> {
        (!self.segments.is_empty()).then(|| {
            let words: &[u32] = bytemuck::cast_slice(self.stats.mapped());
            CullCounts::from_words(words, &self.segments, self.collapsed_tip).with_classes(words, &self.classes)
        })
    }
}

impl Destroy for CullFrame {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.stats.destroy(device) };
    }
}

/// The cull's own set (`SET_PASS`, declared in `shaders/cull/cull.glsl` and `cull_emit.comp`),
/// one per frame in flight: the resources only the cull binds, by the names its GLSL gives them.
fn cull_set(device: &Device, setup: &CullSetup, scene: &SceneGpu) -> Result<PassSet> {
    let code: Vec<(&str, &[u8])> = [setup.tiles_shader, setup.count_shader, shaders::CULL_SCAN_COMP]
        .iter()
        .chain([&shaders::CULL_EMIT_COMP])
        .map(|s| (s.path, s.code(device.profile)))
        .collect();
    let desc = setup.sets.desc("cull", &code);
    let buffer = |b: &crate::vk::Buffer| Resource::Buffer(b.descriptor());
    PassSet::new(device, &desc, |slot| {
        let stats = vk::DescriptorBufferInfo { buffer: setup.frame_stats[slot], offset: 0, range: vk::WHOLE_SIZE };
        vec![
            ("SlotCounts", buffer(&scene.slot_counts)),
            ("Draws", buffer(&scene.draws)),
            ("CullStats", Resource::Buffer(stats)),
            ("CullResults", buffer(&scene.cull_results)),
            ("verdict_texels", Resource::Texels(scene.cull_result_texels.raw)),
            ("CullAlloc", buffer(&scene.cull_alloc)),
            ("Pyramid", buffer(&scene.depth_pyramid)),
            ("pyramid_texels", Resource::Texels(scene.depth_pyramid_texels.raw)),
            ("TileRows", buffer(&scene.tile_rows)),
        ]
    })
}

/// Add the four passes to `graph`, in order.
pub fn add_passes(graph: &mut Graph, device: &Device, setup: &CullSetup, scene: &SceneGpu) -> Result<()> {
    // The passes share the set: each holds a clone, and the last one destroyed destroys it.
    let set = Guard::new(device, Rc::new(cull_set(device, setup, scene)?));
    let steps = [tiles::pass, count::pass, scan::pass, emit::pass];
    let mut built: Guard<Vec<CullStep>> = Guard::new(device, Vec::with_capacity(steps.len()));
    for step in steps {
        built.push(step(device, setup, scene, &set)?);
    }
    drop(set.take());
    built.take().into_iter().for_each(|pass| graph.add(pass));
    Ok(())
}

/// Invocations of a count or emit workgroup (`CULL_GROUP`): the device's subgroup size,
/// within 4..=64. A slot's tile tests then run once per subgroup, the blade tests fill it, and
/// the emit's serial prefix over the group stays short. On llvmpipe (8-wide), 64 invocations ran
/// the tile tests 8 times and its barriers switched 8 coroutines: 40 ms of cull at 1M blades
/// against 27 ms.
pub fn workgroup_size(subgroup_size: u32) -> u32 {
    subgroup_size.clamp(4, 64)
}

/// How many workgroups a cull step dispatches.
#[derive(Clone, Copy)]
enum Groups {
    /// One.
    One,
    /// As many as an earlier step wrote into this buffer at this word (the tiles pass's list for
    /// the count, the scan's `EMIT_DISPATCH_WORD` for the emit).
    Indirect(vk::Buffer, u32),
}

/// One cull dispatch as a pass of the graph: its pipeline, its declared uses (and a per-frame
/// buffer it writes, for the scan) and its workgroup count. `tiles`, `count`, `scan` and `emit`
/// each build one with their own shader and uses.
pub struct CullStep {
    name: &'static str,
    pipeline: vk::Pipeline,
    /// The cull's set, shared by its four steps (the last one destroyed frees it).
    set: Rc<PassSet>,
    uses: Vec<(vk::Buffer, Access)>,
    /// Written by the step, one buffer per frame in flight (by slot).
    per_frame: Vec<vk::Buffer>,
    groups: Groups,
}

impl CullStep {
    fn new(
        device: &Device,
        (name, spirv): (&'static str, &[u8]),
        (setup, set): (&CullSetup, &Rc<PassSet>),
        uses: Vec<(vk::Buffer, Access)>,
        groups: Groups,
    ) -> Result<Self> {
        let pipeline = pipeline::compute(device, name, spirv, set.layout, &setup.constants.named())?;
        Ok(Self { name, pipeline, set: set.clone(), uses, per_frame: Vec::new(), groups })
    }
}

impl Pass for CullStep {
    fn name(&self) -> &'static str {
        self.name
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let frame = self.per_frame.get(ctx.slot).map(|&b| (b, Access::ComputeShaderWrite));
        Some(self.uses.iter().copied().chain(frame).fold(Declaration::compute(), |d, (b, a)| d.buffer(b, a)))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let compute = vk::PipelineBindPoint::COMPUTE;
        recording::bind_scene_set(device, ctx, cmd, self.set.layout, compute);
        self.set.bind(device, cmd, compute, ctx.slot);
        // SAFETY: cmd is recording outside a rendering instance; sets 0 and 2 are bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            match self.groups {
                Groups::One => device.raw.cmd_dispatch(cmd, 1, 1, 1),
                Groups::Indirect(buffer, word) => device.raw.cmd_dispatch_indirect(cmd, buffer, 4 * u64::from(word)),
            }
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            if let Some(set) = Rc::into_inner(self.set) {
                set.destroy(device);
            }
        };
    }
}
