//! Render passes, one per file. Each implements `graph::Pass`: it owns its pipelines, declares
//! what it reads and writes, and records its own binds and draws or dispatches; the graph adds the
//! barriers, the rendering instance, the label and the GPU scopes.

pub mod blade_levels;
pub mod blades;
pub mod cluster_bounds;
pub mod cull;
pub mod debug_lines;
pub mod depth_pyramid;
pub mod floor;
pub mod ground_fill;
pub mod overlay;
pub mod resolve;
pub mod terrain;
pub mod wind_arrows;

pub use blade_levels::BladeLevelsPass;
pub use blades::BladePass;
pub use cluster_bounds::ClusterBoundsPass;
pub use floor::FloorPass;
pub use ground_fill::GroundFillPass;
pub use resolve::ResolvePass;
pub use terrain::TerrainPass;
pub use wind_arrows::WindArrowsPass;

use ash::vk;

use crate::render::graph::{Attachment, Load, PassContext, Rendering};
use crate::render::recording;
use crate::vk::Device;

/// The pipeline layout and attachment formats every scene pipeline is built for.
#[derive(Clone, Copy, Debug)]
pub struct PipelineTarget {
    /// Sets `SET_SCENE` and `SET_POSES`, and the push-constant range.
    pub layout: vk::PipelineLayout,
    /// Colour attachment format.
    pub color: vk::Format,
    /// Depth attachment format.
    pub depth: vk::Format,
    /// Fill or wireframe.
    pub polygon: vk::PolygonMode,
    /// Samples of the attachments (`--msaa`).
    pub samples: vk::SampleCountFlags,
    /// Alpha to coverage for the alpha-tested blade outline (with `samples` > 1).
    pub alpha_to_coverage: bool,
}

/// Set the viewport and scissor to the whole target (dynamic state of every scene pipeline).
pub fn set_full_viewport(device: &Device, cmd: vk::CommandBuffer, extent: vk::Extent2D) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
    // SAFETY: cmd is recording.
    unsafe {
        device.raw.cmd_set_viewport(cmd, 0, &[viewport]);
        device.raw.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// The start of every scene draw: set `SET_SCENE` bound, the viewport over the whole target,
/// `pipeline` bound.
pub fn bind_graphics(
    device: &Device,
    ctx: &PassContext,
    cmd: vk::CommandBuffer,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
) {
    recording::bind_scene_set(device, ctx, cmd, layout, vk::PipelineBindPoint::GRAPHICS);
    set_full_viewport(device, cmd, ctx.target.extent);
    // SAFETY: cmd is recording.
    unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
}

/// The rendering instance of a scene pass drawing over what the previous passes left in the
/// target (colour and depth loaded; depth stored when `store_depth`).
pub fn scene_rendering(ctx: &PassContext, pipeline: vk::Pipeline, store_depth: bool, secondary: bool) -> Rendering {
    let target = ctx.target;
    Rendering {
        extent: target.extent,
        color: Some(Attachment { image: target.color, view: target.color_view, load: Load::Keep, store: true }),
        depth: Some(Attachment { image: target.depth, view: target.depth_view, load: Load::Keep, store: store_depth }),
        depth_write: true,
        pipeline,
        secondary,
    }
}
