//! Recording one pass of a plan: each step after the barriers its uses need, inside the pass's
//! label, timestamps, statistics query and rendering instance.

use ash::vk;

use super::{Attachment, Declaration, Kind, Load, Pass, PassContext, RecordedPass, RecordedStep, Rendering, Scopes};
use crate::error::{Error, Result};
use crate::vk::tracker::{Barriers, ResourceStates};
use crate::vk::{debug, sync, Device};

/// The tracked states as one pass's steps move them on.
pub(super) struct StepStates<'s, 'c> {
    pub(super) states: &'s mut ResourceStates,
    pub(super) ctx: &'s PassContext<'c>,
    pub(super) name: &'static str,
    pub(super) declaration: &'s Declaration,
}

impl StepStates<'_, '_> {
    /// The barriers step `step` needs after the tracked states; the states move on to its uses.
    /// A use of an image never imported, or of one image in two layouts, is refused.
    fn transitions(&mut self, step: usize) -> Result<Barriers> {
        let (name, mut barriers) = (self.name, Barriers::default());
        for (resource, accesses) in self.declaration.grouped(step, |u| self.ctx.resolve(u)) {
            if resource.is_image() {
                if !self.states.get(resource).is_some_and(|s| s.is_imported()) {
                    return Err(Error::Internal(format!("pass `{name}` uses an image never imported: {resource:?}")));
                }
                if !sync::one_layout(&accesses) {
                    return Err(Error::Internal(format!(
                        "pass `{name}` declares one image in two layouts: {accesses:?}"
                    )));
                }
            }
            if let Some(hazard) = self.states.access(resource, &accesses) {
                barriers.push(resource, &hazard);
            }
        }
        Ok(barriers)
    }
}

/// Record one pass, each step after its barriers, inside its label, timestamps, statistics query
/// and rendering instance. The pass's time starts before its first barriers (it includes waiting
/// for its inputs): measured on lavapipe, a timestamp written after the barrier is taken before
/// the pass's binned work is rasterized, and the blade pass read 0.5 ms of a 63 ms frame.
pub(super) fn record_pass(
    ctx: &PassContext,
    cmd: vk::CommandBuffer,
    scopes: &mut Scopes,
    pass: &dyn Pass,
    states: &mut StepStates,
) -> Result<RecordedPass> {
    let device = ctx.device;
    let declaration = states.declaration;
    let graphics = match &declaration.kind {
        Kind::Graphics(rendering) => Some(rendering),
        Kind::Compute => None,
    };
    let begin = scopes.timestamps.write(device, cmd);
    let color = if graphics.is_some() { [0.3, 0.6, 0.2, 1.0] } else { [0.7, 0.5, 0.2, 1.0] };
    debug::begin_label(device, cmd, pass.name(), color);
    let mut steps = Vec::new();
    let mut statistics = None;
    let mut result = Ok(());
    for (index, step) in declaration.steps.iter().enumerate() {
        let step_begin = match (index, step.name) {
            (_, None) => None,
            (0, Some(_)) => Some(begin),
            (_, Some(_)) => Some(scopes.timestamps.write(device, cmd)),
        };
        let barriers = match states.transitions(index) {
            Ok(barriers) => barriers,
            Err(e) => {
                result = Err(e);
                break;
            }
        };
        sync::cmd_barriers(device, cmd, &barriers.buffers, &barriers.images);
        let step_ctx = PassContext { step: index, ..*ctx };
        if let Some(rendering) = graphics {
            statistics = record_graphics(&step_ctx, cmd, scopes, pass, rendering, &mut result);
        } else {
            result = pass.record(&step_ctx, cmd);
        }
        if let (Some(name), Some(begin)) = (step.name, step_begin) {
            steps.push(RecordedStep { name, begin, end: scopes.timestamps.write(device, cmd) });
        }
        if result.is_err() {
            break;
        }
    }
    let end = scopes.timestamps.write(device, cmd);
    debug::end_label(device, cmd);
    result.map(|()| RecordedPass { name: pass.name(), begin, end, statistics, steps })
}

/// Record a graphics pass inside its statistics query and rendering instance; returns the query.
/// A failed recording (a secondary command buffer) fails the frame, after the instance and scopes
/// are closed: a frame without a pass must not be measured.
fn record_graphics(
    ctx: &PassContext,
    cmd: vk::CommandBuffer,
    scopes: &mut Scopes,
    pass: &dyn Pass,
    rendering: &Rendering,
    result: &mut Result<()>,
) -> Option<u32> {
    let device = ctx.device;
    let statistics = match (!rendering.secondary, scopes.statistics.as_deref_mut()) {
        (true, Some(queries)) => {
            // SAFETY: cmd is recording, outside a rendering instance (see `Rendering::pipeline`).
            unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, rendering.pipeline) };
            Some(queries.begin(device, cmd))
        }
        _ => None,
    };
    begin_rendering(device, cmd, rendering);
    *result = pass.record(ctx, cmd);
    // SAFETY: matches begin_rendering.
    unsafe { device.raw.cmd_end_rendering(cmd) };
    if let (Some(query), Some(queries)) = (statistics, scopes.statistics.as_deref()) {
        queries.end(device, cmd, query);
    }
    statistics
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
    let color = rendering.color.map(|c| info(c, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL));
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
        .color_attachments(color.as_slice());
    if let Some(depth) = &depth {
        begin = begin.depth_attachment(depth);
    }
    // SAFETY: cmd is recording outside a rendering instance; the views are live.
    unsafe { device.raw.cmd_begin_rendering(cmd, &begin) };
}
