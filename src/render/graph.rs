//! The pass graph: an ordered list of passes, compute or graphics, each declaring the resources it
//! reads and writes as `vk::sync::Access` values. The graph owns everything between the passes:
//!
//! - **barriers**: it tracks each resource's last access across passes and frames
//!   (`vk::tracker`) and derives every barrier through `vk::sync::transition`, image layouts,
//!   swapchain acquire and present included;
//! - **rendering instances**: a graphics pass names its attachments and how they load; the graph
//!   begins and ends the dynamic-rendering instance around the pass's draws;
//! - **GPU scopes**: a debug label, a timestamp pair and, for graphics passes, a
//!   pipeline-statistics query around each pass, so every report lists every pass with no
//!   per-pass code;
//! - **outputs**: the frame's last uses of its target (present, a copy for the host to read).
//!
//! A pass records only its own commands: adding a pass is one file that implements [`Pass`] and
//! one `graph.add(…)` line.

use ash::vk;

use crate::error::{Error, Result};
use crate::render::target::TargetView;
use crate::render::uniforms::FrameUniforms;
use crate::vk::query::{StatisticsQueries, TimestampQueries};
use crate::vk::tracker::{Barriers, Resource, ResourceStates};
use crate::vk::{debug, image, sync, Access, Device};

/// What a frame's passes are recorded for.
pub struct PassContext<'a> {
    /// The device.
    pub device: &'a Device,
    /// The colour and depth images the scene passes draw into: the frame's target, or with
    /// `--msaa` the multisampled pair the resolve pass reads (`render::msaa`).
    pub target: &'a TargetView,
    /// The frame's target: what is read back or presented after the passes.
    pub output: &'a TargetView,
    /// The frame in flight being recorded (indexes per-frame resources a pass owns).
    pub slot: usize,
    /// The frame's descriptor set 0 (scene, per-frame uniforms and forces).
    pub descriptor_set: vk::DescriptorSet,
    /// The frame's uniforms as written for the GPU (what a pass sizes its dispatches by).
    pub uniforms: &'a FrameUniforms,
}

/// How an attachment's contents start.
#[derive(Clone, Copy)]
pub enum Load {
    /// Cleared to a value.
    Clear(vk::ClearValue),
    /// Kept from the previous pass.
    Keep,
    /// Undefined: the pass writes every pixel (or does not use the contents).
    Discard,
}

/// One attachment of a graphics pass.
#[derive(Clone, Copy)]
pub struct Attachment {
    /// The image (tracked as a resource).
    pub image: vk::Image,
    /// The view drawn into.
    pub view: vk::ImageView,
    /// How its contents start.
    pub load: Load,
    /// Whether its contents are stored for a later pass (depth a later pass does not read is not).
    pub store: bool,
}

/// The rendering instance of a graphics pass.
#[derive(Clone, Copy)]
pub struct Rendering {
    /// Render area, from the origin.
    pub extent: vk::Extent2D,
    /// Colour attachment.
    pub color: Option<Attachment>,
    /// Depth attachment (reversed Z: depth test and write).
    pub depth: Option<Attachment>,
    /// The pass's first pipeline. Bound before its statistics query begins: lavapipe (Mesa 22.3)
    /// emits the bound graphics state at `vkCmdBeginQuery` and crashes when there is none.
    pub pipeline: vk::Pipeline,
    /// The draws come from secondary command buffers. Such a pass goes uncounted by the
    /// statistics queries (that would need `inheritedQueries`).
    pub secondary: bool,
}

/// What kind of work a pass records.
pub enum Kind {
    /// Dispatches, outside any rendering instance.
    Compute,
    /// Draws inside a rendering instance the graph opens.
    Graphics(Rendering),
}

/// What a pass does this frame: its kind and every resource it touches, with how.
pub struct Declaration {
    /// Compute or graphics.
    pub kind: Kind,
    /// `(resource, access)` uses, attachments excluded (the graph adds those).
    pub uses: Vec<(Resource, Access)>,
}

impl Declaration {
    /// A compute pass.
    pub fn compute() -> Self {
        Self { kind: Kind::Compute, uses: Vec::new() }
    }

    /// A graphics pass with its rendering instance.
    pub fn graphics(rendering: Rendering) -> Self {
        Self { kind: Kind::Graphics(rendering), uses: Vec::new() }
    }

    /// The pass uses `resource` as `access`.
    pub fn uses(mut self, resource: Resource, access: Access) -> Self {
        self.uses.push((resource, access));
        self
    }

    /// The pass uses buffer `buffer` as `access`.
    pub fn buffer(self, buffer: vk::Buffer, access: Access) -> Self {
        self.uses(Resource::Buffer(buffer), access)
    }

    /// Every use grouped by resource, in order of first appearance, the attachments included.
    fn grouped(&self) -> Vec<(Resource, Vec<Access>)> {
        let mut groups: Vec<(Resource, Vec<Access>)> = Vec::new();
        let mut add = |resource: Resource, access: Access| match groups.iter_mut().find(|(r, _)| *r == resource) {
            Some((_, accesses)) => accesses.push(access),
            None => groups.push((resource, vec![access])),
        };
        if let Kind::Graphics(rendering) = &self.kind {
            if let Some(color) = rendering.color {
                add(Resource::color(color.image), Access::ColorAttachmentWrite);
            }
            if let Some(depth) = rendering.depth {
                add(Resource::depth(depth.image), Access::DepthAttachmentReadWrite);
            }
        }
        for &(resource, access) in &self.uses {
            add(resource, access);
        }
        groups
    }
}

/// A pass of the graph: one file, its own pipelines, its declaration, its commands.
pub trait Pass {
    /// Name in debug labels, timings and reports.
    fn name(&self) -> &'static str;

    /// What the pass does this frame, or `None` to skip it this frame.
    fn declare(&self, ctx: &PassContext) -> Option<Declaration>;

    /// Record the pass's commands: binds and dispatches or draws. Barriers, the rendering instance,
    /// labels and queries are the graph's. Set 0 is not bound by the graph.
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()>;

    /// The frame last recorded will not run (it failed to record or submit): forget anything the
    /// pass assumed that frame's commands would leave behind (`ReliefGridPass` keeps what its
    /// last dispatch computed). Nothing to forget by default.
    fn frame_dropped(&self) {}

    /// Destroy the pass's pipelines and resources.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    unsafe fn destroy(self: Box<Self>, device: &Device);
}

/// The queries a frame's passes are measured with.
pub struct Scopes<'a> {
    /// Timestamps: two per pass, and one at each end of the frame.
    pub timestamps: &'a mut TimestampQueries,
    /// Pipeline statistics, one query per counted graphics pass, when available.
    pub statistics: Option<&'a mut StatisticsQueries>,
}

/// A pass as recorded in a frame: which queries measured it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordedPass {
    /// The pass's name.
    pub name: &'static str,
    /// Timestamp written before the pass (before its barriers).
    pub begin: u32,
    /// Timestamp written after the pass.
    pub end: u32,
    /// Its pipeline-statistics query, if counted.
    pub statistics: Option<u32>,
}

/// What the frame's target goes on to after the passes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Outputs {
    /// Copy the colour image into this host-visible buffer (tightly packed, 4 bytes a texel).
    pub readback: Option<vk::Buffer>,
    /// Hand the colour image to the presentation engine.
    pub present: bool,
}

/// Passes in order, and the states of the resources they touch.
#[derive(Default)]
pub struct Graph {
    passes: Vec<Box<dyn Pass>>,
    states: ResourceStates,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Append a pass: passes run in the order they were added.
    pub fn add(&mut self, pass: impl Pass + 'static) {
        self.passes.push(Box::new(pass));
    }

    /// Append a pass built elsewhere (an animation model's compute passes).
    pub fn add_boxed(&mut self, pass: Box<dyn Pass>) {
        self.passes.push(pass);
    }

    /// The names of the passes, in order.
    pub fn pass_names(&self) -> Vec<&'static str> {
        self.passes.iter().map(|p| p.name()).collect()
    }

    /// `resource` was last accessed by `accesses` (uploaded data, a target's previous frame, an
    /// acquired swapchain image). Images must be imported before a pass uses them.
    pub fn import(&mut self, resource: Resource, accesses: &[Access]) {
        self.states.import(resource, accesses);
    }

    /// Forget `resource` (destroyed: its handle may be reused).
    pub fn forget(&mut self, resource: Resource) {
        self.states.forget(resource);
    }

    /// The resource states, e.g. to tell whether a recorded command buffer can be replayed (its
    /// barriers assumed the states it started from).
    pub fn states(&self) -> &ResourceStates {
        &self.states
    }

    /// Replace the resource states (after replaying a recording that ends in them).
    pub fn set_states(&mut self, states: ResourceStates) {
        self.states = states;
    }

    /// The frame last recorded will not run: tell each pass (`Pass::frame_dropped`).
    pub fn frame_dropped(&self) {
        for pass in &self.passes {
            pass.frame_dropped();
        }
    }

    /// Record every pass into `cmd` with its barriers, rendering instance, label and queries,
    /// then the outputs. `ctx.target`'s images must have been imported for this frame.
    pub fn record(
        &mut self,
        ctx: &PassContext,
        cmd: vk::CommandBuffer,
        scopes: &mut Scopes,
        outputs: Outputs,
    ) -> Result<Vec<RecordedPass>> {
        let device = ctx.device;
        scopes.timestamps.reset(device, cmd);
        if let Some(statistics) = scopes.statistics.as_deref_mut() {
            statistics.reset(device, cmd);
        }
        scopes.timestamps.write(device, cmd);
        let mut recorded = Vec::with_capacity(self.passes.len());
        for pass in &self.passes {
            let Some(declaration) = pass.declare(ctx) else { continue };
            let barriers = transitions(&mut self.states, pass.name(), &declaration)?;
            // The pass's time starts before its barriers (it includes waiting for its inputs).
            // Measured on lavapipe: a timestamp written after the barrier is taken before the
            // pass's binned work is rasterized, and the blade pass read 0.5 ms of a 63 ms frame.
            let begin = scopes.timestamps.write(device, cmd);
            sync::cmd_barriers(device, cmd, &barriers.buffers, &barriers.images);
            recorded.push(record_pass(ctx, cmd, scopes, pass.as_ref(), &declaration, begin)?);
        }
        self.record_outputs(ctx, cmd, outputs);
        scopes.timestamps.write(device, cmd);
        Ok(recorded)
    }

    /// The target's last uses: a copy to the host (then host read), presentation.
    fn record_outputs(&mut self, ctx: &PassContext, cmd: vk::CommandBuffer, outputs: Outputs) {
        let device = ctx.device;
        let color = Resource::color(ctx.output.color);
        if let Some(raw) = outputs.readback {
            let buffer = Resource::Buffer(raw);
            self.release(device, cmd, &[(color, Access::TransferRead), (buffer, Access::TransferWrite)]);
            image::record_copy_to_buffer(device, cmd, ctx.output.color, ctx.output.extent, raw);
            self.release(device, cmd, &[(buffer, Access::HostRead)]);
        }
        if outputs.present {
            self.release(device, cmd, &[(color, Access::Present)]);
        }
    }

    /// Record the barriers that make `uses` safe after everything recorded so far (e.g. a host
    /// read of a buffer the frame wrote).
    pub fn release(&mut self, device: &Device, cmd: vk::CommandBuffer, uses: &[(Resource, Access)]) {
        let mut barriers = Barriers::default();
        for &(resource, access) in uses {
            if let Some(hazard) = self.states.access(resource, &[access]) {
                barriers.push(resource, &hazard);
            }
        }
        sync::cmd_barriers(device, cmd, &barriers.buffers, &barriers.images);
    }

    /// Destroy every pass.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        for pass in self.passes {
            // SAFETY: per the contract.
            unsafe { pass.destroy(device) };
        }
    }
}

/// The barriers `declaration` needs after the tracked states; the states move on to its uses.
/// A declaration that uses an image never imported, or one image in two layouts, is refused.
fn transitions(states: &mut ResourceStates, name: &str, declaration: &Declaration) -> Result<Barriers> {
    let mut barriers = Barriers::default();
    for (resource, accesses) in declaration.grouped() {
        if resource.is_image() {
            if !states.get(resource).is_some_and(|s| s.is_imported()) {
                return Err(Error::Internal(format!("pass `{name}` uses an image never imported: {resource:?}")));
            }
            if !sync::one_layout(&accesses) {
                return Err(Error::Internal(format!("pass `{name}` declares one image in two layouts: {accesses:?}")));
            }
        }
        if let Some(hazard) = states.access(resource, &accesses) {
            barriers.push(resource, &hazard);
        }
    }
    Ok(barriers)
}

/// Record one pass inside its label, timestamps, statistics query and rendering instance.
fn record_pass(
    ctx: &PassContext,
    cmd: vk::CommandBuffer,
    scopes: &mut Scopes,
    pass: &dyn Pass,
    declaration: &Declaration,
    begin: u32,
) -> Result<RecordedPass> {
    let device = ctx.device;
    let graphics = match &declaration.kind {
        Kind::Graphics(rendering) => Some(rendering),
        Kind::Compute => None,
    };
    let color = if graphics.is_some() { [0.3, 0.6, 0.2, 1.0] } else { [0.7, 0.5, 0.2, 1.0] };
    debug::begin_label(device, cmd, pass.name(), color);
    let counted = graphics.filter(|r| !r.secondary);
    let statistics = match (counted, scopes.statistics.as_deref_mut()) {
        (Some(rendering), Some(queries)) => {
            // SAFETY: cmd is recording, outside a rendering instance (see `Rendering::pipeline`).
            unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, rendering.pipeline) };
            Some(queries.begin(device, cmd))
        }
        _ => None,
    };
    if let Some(rendering) = graphics {
        begin_rendering(device, cmd, rendering);
    }
    // A failed recording (a secondary command buffer) fails the frame, after the instance and
    // scopes are closed: a frame without a pass must not be measured.
    let result = pass.record(ctx, cmd);
    if graphics.is_some() {
        // SAFETY: matches begin_rendering.
        unsafe { device.raw.cmd_end_rendering(cmd) };
    }
    if let (Some(query), Some(queries)) = (statistics, scopes.statistics.as_deref()) {
        queries.end(device, cmd, query);
    }
    let end = scopes.timestamps.write(device, cmd);
    debug::end_label(device, cmd);
    result.map(|()| RecordedPass { name: pass.name(), begin, end, statistics })
}

/// Begin the rendering instance of a graphics pass (the attachments are in their layouts: the
/// graph's barriers put them there).
fn begin_rendering(device: &Device, cmd: vk::CommandBuffer, rendering: &Rendering) {
    let info = |attachment: Attachment, layout| {
        let (load, clear) = match attachment.load {
            Load::Clear(value) => (vk::AttachmentLoadOp::CLEAR, value),
            Load::Keep => (vk::AttachmentLoadOp::LOAD, vk::ClearValue::default()),
            Load::Discard => (vk::AttachmentLoadOp::DONT_CARE, vk::ClearValue::default()),
        };
        let store = if attachment.store { vk::AttachmentStoreOp::STORE } else { vk::AttachmentStoreOp::DONT_CARE };
        vk::RenderingAttachmentInfo::default()
            .image_view(attachment.view)
            .image_layout(layout)
            .load_op(load)
            .store_op(store)
            .clear_value(clear)
    };
    let color: Vec<_> =
        rendering.color.map(|c| info(c, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)).into_iter().collect();
    let depth = rendering.depth.map(|d| info(d, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL));
    let flags = if rendering.secondary {
        vk::RenderingFlags::CONTENTS_SECONDARY_COMMAND_BUFFERS
    } else {
        vk::RenderingFlags::empty()
    };
    let mut begin = vk::RenderingInfo::default()
        .flags(flags)
        .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent: rendering.extent })
        .layer_count(1)
        .color_attachments(&color);
    if let Some(depth) = &depth {
        begin = begin.depth_attachment(depth);
    }
    // SAFETY: cmd is recording outside a rendering instance; the views are live.
    unsafe { device.raw.cmd_begin_rendering(cmd, &begin) };
}
