//! Wind debug view (`--debug-view wind`, the viewer's F3): the wind field the grass feels this
//! frame, drawn as arrows on a slice `SLICE_HEIGHT` above the ground over the finished picture
//! (`shaders/debug/wind_arrows.vert`): one at every `stride`-th cluster corner, along the corner's
//! velocity, coloured by speed. Whatever the field (analytic, Perlin, fluid), the arrows read the
//! frame's corner buffer the blade responses read, so they show what bends the blades: the flow
//! round a collider in the fluid, the noise's gusts in the Perlin field. A pass of its own pipeline
//! layout (set 0 and a push constant), added to the graph with one line.

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

/// Most arrows per side: a stored field's corners are thinned to this by a stride.
pub const MAX_ARROWS_PER_SIDE: u32 = 33;

/// The slice the arrows stand on, in metres above the ground: the fluid wind's sampling height
/// (`render::wind::fluid::SAMPLE_HEIGHT`), where the grass reads every field.
pub const SLICE_HEIGHT: f32 = crate::render::wind::fluid::SAMPLE_HEIGHT;

/// An arrow's length per m/s of wind, in arrow spacings: a 4 m/s wind draws one spacing (at most
/// 1.5).
const SPACINGS_PER_SPEED: f32 = 0.25;

/// The push constant of `wind_arrows.vert`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Arrows {
    origin: f32,
    spacing: f32,
    corners: u32,
    stride: u32,
    per_side: u32,
    lift: f32,
    metres_per_speed: f32,
    pad: f32,
}

impl Arrows {
    /// The arrows over a scene's corner grid: every corner of a block field's finest level, a
    /// stored field's thinned to at most `MAX_ARROWS_PER_SIDE` a side.
    fn over(scene: &SceneGpu) -> Self {
        let g = &scene.grid;
        let corners = g.corners_per_side();
        let (stride, per_side) = thinned(corners);
        let metres_per_speed = SPACINGS_PER_SPEED * g.cluster_size * stride as f32;
        let (origin, spacing, lift) = (g.origin, g.cluster_size, SLICE_HEIGHT);
        Self { origin, spacing, corners, stride, per_side, lift, metres_per_speed, pad: 0.0 }
    }

    /// Vertices drawn: six per arrow (a shaft and two strokes of its head).
    fn vertices(&self) -> u32 {
        6 * self.per_side * self.per_side
    }
}

/// Of `corners` a side, the stride between arrows and the arrows a side: corner 0 and every
/// `stride`-th after it, at most `MAX_ARROWS_PER_SIDE`.
fn thinned(corners: u32) -> (u32, u32) {
    let stride = corners.div_ceil(MAX_ARROWS_PER_SIDE).max(1);
    (stride, (corners - 1) / stride + 1)
}

/// The line pipeline and the arrows it draws.
pub struct WindArrowsPass {
    lines: DebugLines,
    arrows: Arrows,
    /// The ground the slice follows: its clipmap (`render::ground`).
    ground: vk::Buffer,
    /// Each frame's wind at the cluster corners, which the arrows draw.
    wind: Vec<vk::Buffer>,
}

impl WindArrowsPass {
    /// Build the pipeline on a layout of its own: the scene's set 0 and the arrows' push
    /// constant; `wind` is each frame's corner buffer.
    pub fn new(
        device: &Device,
        (set_layout, target): (vk::DescriptorSetLayout, PipelineTarget),
        constants: &Specialization,
        scene: &SceneGpu,
        wind: &[vk::Buffer],
    ) -> Result<Self> {
        let vertex = shaders::WIND_ARROWS_VERT.code(device.profile);
        let size = std::mem::size_of::<Arrows>() as u32;
        let lines = DebugLines::new(device, "wind arrows", vertex, (set_layout, target), (constants, size))?;
        Ok(Self { lines, arrows: Arrows::over(scene), ground: scene.ground.texels.raw, wind: wind.to_vec() })
    }
}

impl Pass for WindArrowsPass {
    fn name(&self) -> &'static str {
        "wind arrows"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let rendering = passes::scene_rendering(ctx, self.lines.pipeline(), false, false);
        let declaration = Declaration::graphics(rendering).buffer(self.ground, ctx.device.profile.vertex_fetch());
        Some(declaration.buffer(self.wind[ctx.slot], Access::VertexShaderStorageRead))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        self.lines.record(ctx, cmd, bytemuck::bytes_of(&self.arrows), self.arrows.vertices());
        Ok(())
    }

    fn replay_key(&self, _: &PassContext) -> Option<u64> {
        // One draw of every arrow; the frame's uniforms and corners move them.
        Some(0)
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.lines.destroy(device) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stride_thins_the_corners_to_at_most_the_arrows_a_side_and_keeps_corner_zero() {
        for corners in [2u32, 21, 65, 66, 130, 201, 1001] {
            let (stride, per_side) = thinned(corners);
            assert!(per_side <= MAX_ARROWS_PER_SIDE, "{corners} corners: {per_side} arrows");
            assert!((per_side - 1) * stride < corners, "{corners} corners: the last arrow is on the grid");
            assert!(per_side * stride >= corners, "{corners} corners: the grid is covered to its far edge");
        }
    }
}
