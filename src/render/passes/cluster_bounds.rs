//! Cluster-bounds debug view (`--debug-view bounds`): the edges of every force cluster (thesis
//! 3.2.2) drawn as lines over the finished picture, each corner coloured by this frame's force
//! there (`shaders/debug/cluster_bounds.vert`). A pass of its own pipeline layout (set 0 and a push
//! constant with the grid), added to the graph with one line.

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes::debug_lines::DebugLines;
use crate::render::passes::{self, PipelineTarget};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::{Access, Device};

/// The push constant of `cluster_bounds.vert`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Grid {
    origin: f32,
    cluster_size: f32,
    corners: u32,
    lift: f32,
}

/// The line pipeline and the grid it draws.
pub struct ClusterBoundsPass {
    lines: DebugLines,
    grid: Grid,
    /// The ground the lines follow: its clipmap (`render::ground`).
    ground: vk::Buffer,
    /// Each frame's wind at the cluster corners, which colours the edges.
    wind: Vec<vk::Buffer>,
}

impl ClusterBoundsPass {
    /// Build the pipeline on a layout of its own: the scene's set 0 and the grid push constant;
    /// `wind` is each frame's corner buffer (`PassSetup::wind`).
    pub fn new(
        device: &Device,
        (set_layout, target): (vk::DescriptorSetLayout, PipelineTarget),
        constants: &Specialization,
        scene: &SceneGpu,
        wind: &[vk::Buffer],
    ) -> Result<Self> {
        let vertex = shaders::CLUSTER_BOUNDS_VERT.code(device.profile);
        let size = std::mem::size_of::<Grid>() as u32;
        let lines = DebugLines::new(device, "cluster bounds", vertex, (set_layout, target), (constants, size))?;
        let g = &scene.grid;
        let grid = Grid { origin: g.origin, cluster_size: g.cluster_size, corners: g.corners_per_side(), lift: 0.05 };
        Ok(Self { lines, grid, ground: scene.ground.texels.raw, wind: wind.to_vec() })
    }

    /// Vertices drawn: two per edge between neighbouring corners, along x and along z.
    fn vertices(&self) -> u32 {
        let n = self.grid.corners;
        2 * 2 * n * (n - 1)
    }
}

impl Pass for ClusterBoundsPass {
    fn name(&self) -> &'static str {
        "cluster bounds"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let rendering = passes::scene_rendering(ctx, self.lines.pipeline(), false, false);
        let declaration = Declaration::graphics(rendering).buffer(self.ground, ctx.device.profile.vertex_fetch());
        Some(declaration.buffer(self.wind[ctx.slot], Access::VertexShaderStorageRead))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        self.lines.record(ctx, cmd, bytemuck::bytes_of(&self.grid), self.vertices());
        Ok(())
    }

    fn replay_key(&self, _: &PassContext) -> Option<u64> {
        // One draw of every cluster's box.
        Some(0)
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.lines.destroy(device) }
    }
}
