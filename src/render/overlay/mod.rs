//! The egui overlay on the GPU (issue 12): what egui produced for a frame ([`OverlayFrame`],
//! handed to `Renderer::set_overlay`), and the state the overlay's two passes
//! (`render/passes/overlay.rs`: "overlay upload", "overlay") share with the renderer across
//! frames and `Renderer::rebuild`s ([`OverlayGpu`]): the pipeline for the renderer's output
//! format, egui's textures by id (`textures`), and per frame in flight the vertex, index and
//! staging buffers and what the passes record (`frame`).
//!
//! Lifetimes follow the frame ring's rules: a frame's buffers are rewritten once its fence has
//! been waited; a replaced buffer, a replaced or freed texture goes on the renderer's deletion
//! queue and is destroyed once the frames that may use it have finished. The whole state is
//! destroyed with the renderer.
//!
//! Kept between frames: the textures (egui sends the font once) and the last frame's primitives,
//! drawn again by every submitted frame until `set_overlay` replaces them (`None` hides the
//! overlay). A frame's texture copies are done by the next submitted frame that draws the
//! overlay; a submission that fails leaves them pending for the next.

mod frame;
mod textures;
mod uploads;

use ash::vk;

pub use frame::{scissor, Copy, Draw, SlotFrame, VERTEX_WORDS};
pub use textures::{Texture, TextureChanges, Textures, MAX_VERTICES};

use crate::error::Result;
use crate::render::shaders;
use crate::vk::descriptor::{self, Binding};
use crate::vk::{pipeline, Buffer, Destroy, Device, Guard};

/// What egui produced for one frame.
pub struct OverlayFrame {
    /// From `ctx.tessellate(shapes, pixels_per_point)`.
    pub primitives: Vec<egui::ClippedPrimitive>,
    /// `full_output.textures_delta`.
    pub textures: egui::TexturesDelta,
    /// Pixels per point of the tessellation (the window's scale factor times egui's zoom).
    pub pixels_per_point: f32,
}

/// The overlay's GPU state, shared by the renderer and its passes (`Rc<RefCell<…>>`: the graph's
/// passes are not `Send`, and one thread records frames).
pub struct OverlayGpu {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    vertex_set_layout: vk::DescriptorSetLayout,
    vertex_pool: vk::DescriptorPool,
    textures: Textures,
    slots: Vec<SlotFrame>,
    /// The primitives drawn and their scale (`None`: hidden).
    shown: Option<(Vec<egui::ClippedPrimitive>, f32)>,
    /// Pending copies staged by the last prepared frame (done once it is submitted).
    staged: usize,
}

fn vertex_bindings() -> [Binding; 1] {
    let vs = vk::ShaderStageFlags::VERTEX;
    [Binding { binding: 0, kind: vk::DescriptorType::STORAGE_BUFFER, stages: vs }]
}

/// The vertex shader's push constant: the screen's size in points.
const PUSH_CONSTANTS: vk::PushConstantRange =
    vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::VERTEX, offset: 0, size: 8 };

impl OverlayGpu {
    /// The layouts, the pipeline drawing into targets of `format` (`linear_target`: an *_SRGB
    /// format that encodes what the shader writes) and `frames` frames in flight. On failure
    /// nothing is left.
    pub fn new(device: &Device, format: vk::Format, linear_target: bool, frames: usize) -> Result<Self> {
        // Null handles are ignored when a failure destroys what was made.
        let mut made = Guard::new(
            device,
            Self {
                pipeline: vk::Pipeline::null(),
                layout: vk::PipelineLayout::null(),
                vertex_set_layout: vk::DescriptorSetLayout::null(),
                vertex_pool: vk::DescriptorPool::null(),
                textures: Textures::new(vk::DescriptorSetLayout::null()),
                slots: Vec::new(),
                shown: None,
                staged: 0,
            },
        );
        made.build(device, format, linear_target, frames)?;
        Ok(made.take())
    }

    fn build(&mut self, device: &Device, format: vk::Format, linear_target: bool, frames: usize) -> Result<()> {
        let bindings = vertex_bindings();
        self.vertex_set_layout = descriptor::set_layout(device, "overlay vertices set layout", &bindings)?;
        let texture_layout =
            descriptor::set_layout(device, "overlay texture set layout", &textures::texture_bindings())?;
        self.textures = Textures::new(texture_layout);
        let sets = [self.vertex_set_layout, texture_layout];
        self.layout = pipeline::layout(device, "overlay layout", &sets, &[PUSH_CONSTANTS])?;
        let (pool, sets) = descriptor::allocate_sets(
            device,
            "overlay vertices sets",
            self.vertex_set_layout,
            &bindings,
            frames as u32,
        )?;
        self.vertex_pool = pool;
        self.slots = sets.into_iter().map(SlotFrame::new).collect();
        for (slot, frame) in self.slots.iter_mut().enumerate() {
            frame.allocate(device, slot)?;
        }
        self.pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "overlay",
                vertex: shaders::OVERLAY_VERT.code(device.profile),
                fragment: shaders::OVERLAY_FRAG.code(device.profile),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                // egui's winding is not consistent.
                cull: vk::CullModeFlags::NONE,
                polygon: vk::PolygonMode::FILL,
                depth_compare: vk::CompareOp::ALWAYS,
                depth_write: true,
                color_format: format,
                depth_format: vk::Format::UNDEFINED,
                layout: self.layout,
                constants: &[("LINEAR_TARGET", u32::from(linear_target))],
                vertex_stride: 0,
                samples: vk::SampleCountFlags::TYPE_1,
                blend: pipeline::Blend::PremultipliedAlpha,
            },
        )?;
        Ok(())
    }

    /// The pipeline.
    pub fn pipeline(&self) -> vk::Pipeline {
        self.pipeline
    }

    /// The pipeline layout: set 0 the frame's vertices, set 1 a texture, the screen's size in
    /// points as vertex push constants.
    pub fn layout(&self) -> vk::PipelineLayout {
        self.layout
    }

    /// What frame `slot` records.
    pub fn slot(&self, slot: usize) -> &SlotFrame {
        &self.slots[slot]
    }

    /// Draw `frame` from the next submitted frame on: its texture sets applied (copied by that
    /// frame), its frees queued. Checked whole first: bad input changes nothing. Images made or
    /// textures replaced are added to `changes` (even when a later set fails).
    pub fn show(&mut self, device: &Device, frame: OverlayFrame, changes: &mut TextureChanges) -> Result<()> {
        self.textures.check(&frame, device.limits().max_image_dimension2_d)?;
        self.textures.apply(device, frame.textures, changes)?;
        self.shown = Some((frame.primitives, frame.pixels_per_point));
        Ok(())
    }

    /// Draw nothing from the next frame on (the textures and pending copies are kept).
    pub fn hide(&mut self) {
        self.shown = None;
    }

    /// Whether the overlay is drawn.
    pub fn is_shown(&self) -> bool {
        self.shown.is_some()
    }

    /// Work out what frame `slot` records into a target of `extent` and write its buffers (the
    /// slot's fence has been waited). Replaced buffers go to `retired`.
    pub fn prepare(
        &mut self,
        device: &Device,
        slot: usize,
        extent: vk::Extent2D,
        retired: &mut Vec<Buffer>,
    ) -> Result<()> {
        let frame = &mut self.slots[slot];
        frame.clear();
        self.staged = 0;
        let Some((primitives, ppp)) = &self.shown else { return Ok(()) };
        let (words, indices, draws) = frame::geometry(primitives, *ppp, extent, &self.textures);
        if !draws.is_empty() {
            frame.write_geometry(device, slot, (&words, &indices), retired)?;
        }
        frame.stage_uploads(device, slot, &self.textures, retired)?;
        frame.draws = draws;
        frame.screen_points = [extent.width as f32 / ppp, extent.height as f32 / ppp];
        frame.shown = true;
        self.staged = self.textures.uploads.len();
        Ok(())
    }

    /// The prepared frame was submitted (or not): its copies are done (or pending still). The
    /// textures freed since are returned, to destroy behind the frames that may sample them.
    pub fn submitted(&mut self, submitted: bool) -> Vec<Texture> {
        if submitted {
            self.textures.uploads.drain(..self.staged);
        }
        self.staged = 0;
        self.textures.take_frees()
    }

    /// Destroy everything (the sets go with their pools).
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(&mut self, device: &Device) {
        // SAFETY: per the contract; destroying null handles is a no-op.
        unsafe {
            for slot in &mut self.slots {
                for buffer in slot.take_buffers() {
                    buffer.destroy(device);
                }
            }
            self.slots.clear();
            self.textures.destroy(device);
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
            crate::vk::live::destroyed(self.vertex_pool);
            device.raw.destroy_descriptor_pool(self.vertex_pool, None);
            crate::vk::live::destroyed(self.vertex_set_layout);
            device.raw.destroy_descriptor_set_layout(self.vertex_set_layout, None);
        }
        self.pipeline = vk::Pipeline::null();
        self.layout = vk::PipelineLayout::null();
        self.vertex_pool = vk::DescriptorPool::null();
        self.vertex_set_layout = vk::DescriptorSetLayout::null();
        self.shown = None;
    }
}

impl Destroy for OverlayGpu {
    unsafe fn destroy(mut self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { OverlayGpu::destroy(&mut self, device) };
    }
}
