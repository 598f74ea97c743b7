//! The egui overlay's passes (`render::overlay`), the graph's last: "overlay upload" copies the
//! frame's texture sets from its staging buffer into egui's textures (outside any rendering
//! instance; only on frames that have some), and "overlay" draws egui's meshes over the frame's
//! output — after the resolve with `--msaa` — blended with premultiplied alpha, one scissored
//! indexed draw per mesh. Both read the state the renderer prepared for the frame's slot
//! (`OverlayGpu::prepare`) and skip the frame when the overlay is hidden.
//!
//! The images are declared (transfer write, then fragment-shader sampled read): their barriers
//! and layouts are the graph's. The vertex, index and staging buffers are host-visible and
//! written before the frame is submitted, which makes the writes visible to all its commands,
//! as with the frame's uniforms: no barrier, so they are not declared.

use std::cell::RefCell;
use std::rc::Rc;

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Attachment, Declaration, Load, Pass, PassContext, Rendering};
use crate::render::overlay::OverlayGpu;
use crate::render::passes;
use crate::vk::{Access, Device, Resource};

/// The images of `images`, each once, in order.
fn unique(images: impl Iterator<Item = vk::Image>) -> Vec<vk::Image> {
    let mut out: Vec<vk::Image> = Vec::new();
    for image in images {
        if !out.contains(&image) {
            out.push(image);
        }
    }
    out
}

/// Copies the frame's texture sets into egui's textures.
pub struct OverlayUploadPass {
    overlay: Rc<RefCell<OverlayGpu>>,
}

impl OverlayUploadPass {
    /// The pass over the shared overlay state.
    pub fn new(overlay: Rc<RefCell<OverlayGpu>>) -> Self {
        Self { overlay }
    }
}

impl Pass for OverlayUploadPass {
    fn name(&self) -> &'static str {
        "overlay upload"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let overlay = self.overlay.borrow();
        let frame = overlay.slot(ctx.slot);
        if !frame.shown || frame.copies.is_empty() {
            return None;
        }
        let images = unique(frame.copies.iter().map(|c| c.image));
        Some(
            images
                .into_iter()
                .fold(Declaration::compute(), |d, image| d.uses(Resource::color(image), Access::TransferWrite)),
        )
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let overlay = self.overlay.borrow();
        let frame = overlay.slot(ctx.slot);
        let staging = frame.staging.as_ref().expect("copies are staged").raw;
        for copy in &frame.copies {
            let layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
            // SAFETY: cmd is recording outside a rendering instance; the graph put the image in
            // TRANSFER_DST_OPTIMAL; the region lies inside the staging buffer and the image.
            unsafe { ctx.device.raw.cmd_copy_buffer_to_image(cmd, staging, copy.image, layout, &[copy.region]) };
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, _: &Device) {
        // The state is the renderer's: it outlives the graphs that draw it.
    }
}

/// Draws egui's meshes over the frame's output.
pub struct OverlayPass {
    overlay: Rc<RefCell<OverlayGpu>>,
}

impl OverlayPass {
    /// The pass over the shared overlay state.
    pub fn new(overlay: Rc<RefCell<OverlayGpu>>) -> Self {
        Self { overlay }
    }
}

impl Pass for OverlayPass {
    fn name(&self) -> &'static str {
        "overlay"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let overlay = self.overlay.borrow();
        let frame = overlay.slot(ctx.slot);
        if !frame.shown {
            return None;
        }
        let output = ctx.output;
        let color = Attachment { image: output.color, view: output.color_view, load: Load::Keep, store: true };
        let rendering = Rendering {
            extent: output.extent,
            color: Some(color),
            depth: None,
            pipeline: overlay.pipeline(),
            depth_write: false,
            secondary: false,
        };
        let images = unique(frame.draws.iter().map(|d| d.image));
        Some(images.into_iter().fold(Declaration::graphics(rendering), |d, image| {
            d.uses(Resource::color(image), Access::FragmentShaderSampledRead)
        }))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let overlay = self.overlay.borrow();
        let frame = overlay.slot(ctx.slot);
        let Some(indices) = frame.indices.as_ref().filter(|_| !frame.draws.is_empty()) else { return Ok(()) };
        let (device, layout, bind) = (ctx.device, overlay.layout(), vk::PipelineBindPoint::GRAPHICS);
        passes::set_full_viewport(device, cmd, ctx.output.extent);
        let screen: &[u8] = bytemuck::cast_slice(&frame.screen_points);
        // SAFETY: cmd is recording inside this pass's rendering instance; the sets match the
        // layout; the buffers hold the frame's vertices and indices (written before submission).
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, bind, overlay.pipeline());
            device.raw.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::VERTEX, 0, screen);
            device.raw.cmd_bind_descriptor_sets(cmd, bind, layout, 0, &[frame.set], &[]);
            device.raw.cmd_bind_index_buffer(cmd, indices.raw, 0, vk::IndexType::UINT32);
        }
        let mut bound = vk::DescriptorSet::null();
        for draw in &frame.draws {
            // SAFETY: as above; the texture's set is alive until the frames that bind it finish.
            unsafe {
                if draw.set != bound {
                    device.raw.cmd_bind_descriptor_sets(cmd, bind, layout, 1, &[draw.set], &[]);
                    bound = draw.set;
                }
                device.raw.cmd_set_scissor(cmd, 0, &[draw.scissor]);
                device.raw.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, draw.vertex_offset, 0);
            }
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, _: &Device) {
        // The state is the renderer's: it outlives the graphs that draw it.
    }
}
