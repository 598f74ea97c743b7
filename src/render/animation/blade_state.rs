//! The blade-state store (issue #29 item 5): per-blade state that a stateful blade response keeps
//! from step to step, keyed on the blade's stable identity.
//!
//! - **Identity.** A stored field's blade is its index. A block field's is (world cell, blade in
//!   the block): the cull's visible entry carries both (`visible_instance`,
//!   `shaders/common/field.glsl`).
//! - **Where.** A stored field holds a record for every blade. A block field holds them for the
//!   blocks within `radius` blocks of the camera's block (Chebyshev distance), in a camera grid of
//!   (2·radius + 1)² blocks addressed toroidally (`render::camera_grid`: world cell `w` in slot
//!   `w mod dims`), so records of blocks that stay keep their slot when the camera crosses a
//!   block. Past the radius a blade has no state: the response draws its stateless counterpart,
//!   and across the outermost ring of blocks it blends the two (`stateless` in
//!   `shaders/animation/blade_state.glsl`, 0 within radius − ½ block, 1 at radius + ½).
//! - **A record.** Two header words — the world cell it belongs to (packed 16 + 16 bits; 0 in a
//!   stored field) and the step it holds plus one (0: never written) — then the response's
//!   `words`.
//! - **Validity.** A frame advances the state from the step the previous frame drew to the one
//!   this frame draws (`StepSpan`). A record is carried on only if it holds that previous step
//!   and its cell: a blade not stepped last frame (culled, outside the store, in a block that just
//!   entered, a dropped frame, a jump in time) restarts at the equilibrium under this frame's
//!   wind. So the policy for culled blades is **reset**: the cost per step follows the drawn
//!   blades, not the stored ones.

use ash::vk;

use crate::error::{Error, Result};
use crate::render::animation::clock::MAX_STEPS_PER_FRAME;
use crate::render::scene_gpu::SceneGpu;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{Buffer, BufferDesc, Destroy, Device};

/// Header words of a record (its cell and its step plus one).
pub const HEADER_WORDS: u32 = 2;

/// What a store's records are: the response's words per blade, and for a block field the
/// radius in blocks and the blades of a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StoreShape {
    /// The response's words per blade (after the header).
    pub words: u32,
    /// A block field's store: its radius in blocks and the blades of a block; `None` for a
    /// stored field.
    pub blocks: Option<(u32, u32)>,
}

impl StoreShape {
    /// This frame's `BladeStateFrame` block (`shaders/animation/blade_state.glsl`) for `span`,
    /// each step `dt` seconds.
    pub fn frame_block(&self, span: StepSpan, dt: f32) -> [u32; 12] {
        let (radius, per_block, blocks) = match self.blocks {
            Some((radius, per_block)) => (radius, per_block, 1),
            None => (0, 0, 0),
        };
        // Steps plus one, in 32 bits (0: none): a run of 2^32 steps (2.3 years at 1/60 s) wraps.
        let from = span.from.map_or(0, |s| (s as u32).wrapping_add(1));
        let to = (span.to as u32).wrapping_add(1).max(1);
        [from, span.steps, self.words, per_block, radius, 2 * radius + 1, blocks, to, dt.to_bits(), 0, 0, 0]
    }

    /// The first word of the record of `blade` in world cell `cell`: a stored field's blade
    /// `blade` (its index; `cell` unused), or a block field's, in slot `cell mod dims`
    /// (`camera_grid::world_slot`) then by its index in the block; as blade_state.glsl places it.
    pub fn record_base(&self, cell: glam::I64Vec2, blade: u32) -> u64 {
        let per_record = u64::from(HEADER_WORDS + self.words);
        match self.blocks {
            Some((radius, per_block)) => {
                let dims = i64::from(2 * radius + 1);
                let slot = cell.y.rem_euclid(dims) * dims + cell.x.rem_euclid(dims);
                (slot as u64 * u64::from(per_block) + u64::from(blade)) * per_record
            }
            None => u64::from(blade) * per_record,
        }
    }
}

/// The records of the blades a stateful response keeps state for.
pub struct BladeStateStore {
    /// The records, `HEADER_WORDS + words` words each.
    pub buffer: Buffer,
    /// Records the store holds.
    pub records: u64,
    /// What they are.
    pub shape: StoreShape,
}

impl BladeStateStore {
    /// A store of `words` words per blade for `scene`: every stored blade, or a block field's
    /// blocks within `radius` blocks of the camera. Refused with one line if it does not fit one
    /// storage buffer or the memory budget. `readable`: host-visible, for tests that read it
    /// back. Its contents are undefined until the owner's first pass clears it
    /// ([`record_clear`]).
    pub fn new(device: &Device, scene: &SceneGpu, words: u32, radius: u32, readable: bool) -> Result<Self> {
        let blocks = scene.field.as_ref().map(|_| (radius, scene.blade_count));
        let records = match blocks {
            Some((radius, per_block)) => u64::from(2 * radius + 1).pow(2) * u64::from(per_block),
            None => u64::from(scene.blade_count),
        };
        let bytes = 4 * records.max(1) * u64::from(HEADER_WORDS + words);
        let range = u64::from(device.limits().max_storage_buffer_range);
        if bytes > range {
            return Err(Error::bad_input(format!(
                "the blade-state store of {records} blades x {} bytes needs {} MiB, over the device's maxStorageBufferRange of {} MiB",
                4 * (HEADER_WORDS + words),
                bytes >> 20,
                range >> 20
            )));
        }
        device.check_budget(bytes, "the blade-state store")?;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let desc = match readable {
            true => BufferDesc::readback("blade states", bytes, usage),
            false => BufferDesc::gpu_only("blade states", bytes, usage),
        };
        let buffer = Buffer::new(device, &desc)?;
        Ok(Self { buffer, records, shape: StoreShape { words, blocks } })
    }

    /// The store as its GLSL declares it (`BladeStates`).
    pub fn resource(&self) -> (&'static str, Descriptor) {
        ("BladeStates", Descriptor::Buffer(self.buffer.descriptor()))
    }
}

/// A stateful response's frame span and step, set in `BladeResponse::step` and read when the graph
/// plans the frame.
pub type SharedSpan = std::rc::Rc<std::cell::Cell<(StepSpan, f32)>>;

/// Record the clear of a store's `buffer` (every record empty) into `cmd`, before its first use:
/// a transfer write the pass declares (`Access::TransferWrite`).
pub fn record_clear(device: &Device, cmd: vk::CommandBuffer, buffer: vk::Buffer) {
    // SAFETY: cmd is recording outside a rendering instance; zero is every record's empty header.
    unsafe { device.raw.cmd_fill_buffer(cmd, buffer, 0, vk::WHOLE_SIZE, 0) };
}

impl Destroy for BladeStateStore {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.buffer.destroy(device) };
    }
}

/// What one frame does to the state: carry it on from step `from` (the step the previous frame
/// drew) by `steps` steps to `to`, or, with `from` `None`, restart every blade at equilibrium at
/// `to` (the first frame, a jump in time, a step backwards, or more than `MAX_STEPS_PER_FRAME`
/// steps at once).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepSpan {
    /// The step the state holds before this frame.
    pub from: Option<u64>,
    /// The step this frame draws.
    pub to: u64,
    /// Steps to take.
    pub steps: u32,
}

impl StepSpan {
    /// The span from `previous` (the step the last frame drew, if any) to `step`.
    pub fn between(previous: Option<u64>, step: u64) -> Self {
        match previous {
            Some(p) if step >= p && step - p <= u64::from(MAX_STEPS_PER_FRAME) => {
                StepSpan { from: Some(p), to: step, steps: (step - p) as u32 }
            }
            _ => StepSpan { from: None, to: step, steps: 0 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_span_steps_forward_by_at_most_four_and_restarts_otherwise() {
        assert_eq!(StepSpan::between(None, 5), StepSpan { from: None, to: 5, steps: 0 });
        assert_eq!(StepSpan::between(Some(5), 6), StepSpan { from: Some(5), to: 6, steps: 1 });
        assert_eq!(StepSpan::between(Some(5), 9), StepSpan { from: Some(5), to: 9, steps: 4 });
        assert_eq!(StepSpan::between(Some(5), 5), StepSpan { from: Some(5), to: 5, steps: 0 });
        // A jump forward past four steps, or any step backwards: restart.
        assert_eq!(StepSpan::between(Some(5), 10), StepSpan { from: None, to: 10, steps: 0 });
        assert_eq!(StepSpan::between(Some(5), 4), StepSpan { from: None, to: 4, steps: 0 });
    }
}
