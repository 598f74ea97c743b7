//! The GPU-driven cull (thesis §5.3, Zhang Xia §5.2, Belyaev §2.2, Jahrmann & Wimmer 2017) as
//! three compute passes of the graph, each one dispatch: `count` (per ring slot around the
//! culling camera's tile: tile tests, blade tests, counts per LOD bucket), `scan` (offsets, the
//! indirect draws, the frame's counts for the host) and `emit` (the visible list, in a
//! deterministic near-to-far order). The blade pass then draws each bucket indirectly
//! (`passes::blades`). The graph orders them by what each declares (`shaders/cull*.comp`).

pub mod clear;
pub mod count;
pub mod emit;
pub mod scan;

pub use clear::CullClearPass;
pub use count::CullCountPass;
pub use emit::CullEmitPass;
pub use scan::CullScanPass;

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Declaration, Graph, PassContext};
use crate::render::passes;
use crate::render::scene_gpu::SceneGpu;
use crate::vk::{pipeline, Access, Device};

/// What the three cull passes share: the scene pipeline layout and specialization constants,
/// and the frames' host-visible count buffers the scan writes.
pub struct CullSetup<'a> {
    /// The scene pipeline layout (set 0 holds every buffer the cull touches).
    pub layout: vk::PipelineLayout,
    /// Specialization constants.
    pub constants: &'a [u32],
    /// Each frame's `Frame::cull_stats`, by slot.
    pub frame_stats: Vec<vk::Buffer>,
}

/// Add the three passes to `graph`, in order.
pub fn add_passes(graph: &mut Graph, device: &Device, setup: &CullSetup, scene: &SceneGpu) -> Result<()> {
    if scene.field.is_some() {
        graph.add(CullClearPass::new(scene));
    }
    graph.add(CullCountPass::new(device, setup, scene)?);
    graph.add(CullScanPass::new(device, setup, scene)?);
    graph.add(CullEmitPass::new(device, setup, scene)?);
    Ok(())
}

/// One cull dispatch: its pipeline, its declared uses and its workgroup count.
struct CullStep {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    uses: Vec<(vk::Buffer, Access)>,
}

impl CullStep {
    fn new(
        device: &Device,
        name: &str,
        spirv: &[u8],
        setup: &CullSetup,
        uses: Vec<(vk::Buffer, Access)>,
    ) -> Result<Self> {
        let pipeline = pipeline::compute(device, name, spirv, setup.layout, setup.constants)?;
        Ok(Self { pipeline, layout: setup.layout, uses })
    }

    fn declare(&self, extra: &[(vk::Buffer, Access)]) -> Declaration {
        self.uses.iter().chain(extra).fold(Declaration::compute(), |d, &(b, a)| d.buffer(b, a))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer, groups: u32) {
        let device = ctx.device;
        passes::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::COMPUTE);
        // SAFETY: cmd is recording outside a rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_dispatch(cmd, groups, 1, 1);
        }
    }

    /// # Safety
    /// No pending GPU work may use the pipeline.
    unsafe fn destroy(&self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { device.raw.destroy_pipeline(self.pipeline, None) };
    }
}

/// Ring slots of this frame (one workgroup each): `FrameUniforms::cull_tiles.y`.
fn ring_slots(ctx: &PassContext) -> u32 {
    ctx.uniforms.cull_tiles.y
}
