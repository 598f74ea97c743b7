//! Interaction patches (Belyaev §3.4, issue #34): blades within reach of a collider switch from
//! whatever cheap response draws them (keyframes, sine, …) to Belyaev's inertial chain (§3.1,
//! `chain`, `shaders/animation/chain.glsl`), and hand back once they settle.
//!
//! - **Who.** A blade whose root lies inside a collider's ground ellipse grown by `REACH_M`, and
//!   which the collider comes down to (its lowest point below the blade's top plus `REACH_M`).
//! - **Hand-in.** The chain starts at rest, fitted to the pose the cheap response drew this frame
//!   (each segment along the drawn backbone), so nothing pops.
//! - **Pushed.** Push-out (`push_out`) moves the drawn blade out of the collider; the chain is then
//!   fitted to the pushed pose and its angular velocities are zeroed from the first joint moved:
//!   the collider holds the chain where it pushes it, and lets it spring back, with the chain's
//!   own inertia and damping, where it leaves.
//! - **Hand-back.** Out of reach, a patch is freed once it settles: every angular velocity under
//!   `SETTLED_RAD_S`, and every drawn point within a pixel of the cheap response's at the blade's
//!   distance. A patch that does not settle (gusts that never stop) times out: `TIMEOUT_S` after its
//!   last contact it blends to the cheap pose over `BLEND_S`, then is freed. Contact again turns
//!   the blend back at the same rate.
//! - **Sparse.** Only those blades hold state: a hash table of `CAPACITY` records of
//!   `RECORD_WORDS` words, keyed on the blade's identity (a stored blade's index; a block field's
//!   world cell and index in its block), open addressing over a window of `WINDOW` slots, claimed
//!   with an atomic compare-and-swap on the record's step word. A record is free once its step is
//!   neither the previous frame's nor this frame's (a patch not stepped last frame restarts, as the
//!   blade-state store's records do). A blade that finds its window full is drawn without a
//!   patch (push-out still holds it out of the collider).
//! - **Where to look.** A blade out of reach looks its record up only where one may live: each
//!   cell of the pressed map's grid (`pressed`, same cells and slots) holds the time until which a
//!   patch in it may live (`atomicMax`, renewed every frame a patch lives), so the blades far from
//!   every path pay one read.
//!
//! The push-out pass lists the blades to patch (`shaders/animation/push_out.comp`) and the patch
//! pass steps them (`patch_pass`, `shaders/animation/patch.comp`); the store is the renderer's
//! pressed map's, so it outlives the passes' rebuilds. `Renderer::read_patches` reads it back.

use std::cell::Cell;

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::error::Result;
use crate::render::animation::blade_state::StepSpan;
use crate::render::animation::chain::{ChainParams, CHAIN_SEGMENTS};
use crate::render::animation::clock::StepClock;
use crate::vk::{Buffer, BufferDesc, Device};

/// Records the store holds.
pub const CAPACITY: u32 = 1 << 16;
/// Slots a blade's record may sit in, from its hash on.
pub const WINDOW: u32 = 16;
/// Header words of a record: its blade (two words), its step plus one, its blend to the cheap pose
/// (f32, 0 the chain alone), seconds since its last contact (f32), then three unused.
pub const HEADER_WORDS: u32 = 8;
/// Words a record: the header, then per joint ψ and ω (`chain::CHAIN_SEGMENTS` joints).
pub const RECORD_WORDS: u32 = HEADER_WORDS + 6 * CHAIN_SEGMENTS as u32;
/// How far past a collider's ground ellipse a blade is within its reach, in metres: the chain
/// takes over a few frames before the collider touches the blade (0.1 m is four frames of a
/// walker at 1.5 m/s).
pub const REACH_M: f32 = 0.1;
/// A patch out of reach this long starts its blend back, in seconds.
pub const TIMEOUT_S: f32 = 1.5;
/// The blend back to the cheap pose, in seconds.
pub const BLEND_S: f32 = 0.5;
/// A render at `--time T` with interaction patches and no other state steps from T − this, in
/// seconds (`Renderer::warm_up_from`): every patch then was handed in within it, or has settled
/// under a collider at rest (the chain's damper halves its swing in 0.35 s).
pub const WARM_UP_S: f32 = 4.0;
/// Every joint's angular velocity under this counts as settled, in rad/s.
pub const SETTLED_RAD_S: f32 = 0.5;
/// Cells per side of the presence grid: the pressed map's (`pressed::DIMS`, a test in `pressed`
/// keeps them equal), whose slots it shares.
pub const PRESENCE_DIMS: u32 = 512;
/// Words before the records: the presence grid, one word per pressed-map cell.
pub const PRESENCE_WORDS: u64 = PRESENCE_DIMS as u64 * PRESENCE_DIMS as u64;

/// The store's bytes: the presence grid and the records.
pub const STORE_BYTES: u64 = 4 * (PRESENCE_WORDS + CAPACITY as u64 * RECORD_WORDS as u64);
/// The list's bytes: its head, then an entry of 16 bytes per record.
pub const LIST_BYTES: u64 = 16 * (1 + CAPACITY as u64);

/// The patches' part of the push-out pass's frame block (`PressedFrame` in
/// `shaders/animation/pressed.glsl`): `steps` the step the previous frame drew plus one (0:
/// restart), the steps to take, the step this frame draws plus one, and 1 when patches run;
/// `chain` the step (s), the chain's stiffness and damper, and the pixels per metre at 1 m.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PatchFrame {
    /// From, steps, to, on.
    pub steps: [u32; 4],
    /// dt, k/J, d/J, unused.
    pub chain: [f32; 4],
}

/// What the push-out and patch passes share of each frame: the steps the patches take, and
/// whether they run. A frame the passes do not run leaves the records at the step before it: the
/// next frame carries on from there if that is within `MAX_STEPS_PER_FRAME` steps, and restarts
/// otherwise.
#[derive(Debug)]
pub struct PatchClock {
    clock: StepClock,
    params: ChainParams,
    /// The step the last frame that ran the patches drew.
    previous: Cell<Option<u64>>,
    /// The block of the frame being planned, by its index (both passes read it).
    planned: Cell<Option<(u64, PatchFrame)>>,
    /// The patches run until this time (s): their longest life out of reach after a collider.
    live_until: Cell<f64>,
}

impl PatchClock {
    /// Steps of `clock`, the chain of `params`.
    pub fn new(clock: StepClock, params: ChainParams) -> Self {
        let (previous, planned, live_until) = (Cell::new(None), Cell::new(None), Cell::new(f64::NEG_INFINITY));
        Self { clock, params, previous, planned, live_until }
    }

    /// The block of frame `index` at `time` (s) with `colliders`: the same for every pass of the
    /// frame. The patches run with a collider, and for `TIMEOUT_S + BLEND_S` after the last one.
    pub fn frame(&self, index: u64, time: f64, colliders: u32) -> PatchFrame {
        match self.planned.get() {
            Some((planned, frame)) if planned == index => frame,
            _ => {
                if colliders > 0 {
                    self.live_until.set(time + f64::from(TIMEOUT_S + BLEND_S) + 0.1);
                }
                let frame = match colliders > 0 || time < self.live_until.get() {
                    true => self.step(time),
                    false => PatchFrame::default(),
                };
                self.planned.set(Some((index, frame)));
                frame
            }
        }
    }

    /// The steps to a frame at `time` that runs the patches.
    fn step(&self, time: f64) -> PatchFrame {
        let step = self.clock.steps_to(time);
        let span = StepSpan::between(self.previous.get(), step);
        self.previous.set(Some(step));
        let from = span.from.map_or(0, |s| (s as u32).wrapping_add(1));
        let to = (span.to as u32).wrapping_add(1).max(1);
        let chain = [self.clock.dt as f32, self.params.stiffness, self.params.damping, 0.0];
        PatchFrame { steps: [from, span.steps, to, 1], chain }
    }
}

/// The records, and the presence grid before them, and the list of the blades to patch each frame;
/// owned by the renderer's pressed map (`pressed::PressedMap`), whose cells the presence grid
/// covers.
pub struct PatchStore {
    /// `STORE_BYTES`: the presence grid, then `CAPACITY` records.
    pub buffer: Buffer,
    /// `LIST_BYTES`: the patch dispatch's workgroups (x, y, z) and the blades listed, then
    /// `CAPACITY` entries (`shaders/animation/patches.glsl`, `PatchList`).
    pub list: Buffer,
}

impl PatchStore {
    /// The store, undefined until the push-out pass's first frame clears it. Refused with one
    /// line if it does not fit the memory budget.
    pub fn new(device: &Device) -> Result<Self> {
        device.check_budget(STORE_BYTES + LIST_BYTES, "the interaction patches")?;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let buffer = Buffer::new(device, &BufferDesc::gpu_only("interaction patches", STORE_BYTES, usage))?;
        let buffer = crate::vk::Guard::new(device, buffer);
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let list = Buffer::new(device, &BufferDesc::gpu_only("patch list", LIST_BYTES, usage))?;
        Ok(Self { buffer: buffer.take(), list })
    }

    /// Destroy the buffers.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::Destroy::destroy(self.buffer, device);
            crate::vk::Destroy::destroy(self.list, device);
        }
    }
}

/// A live patch as its record holds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LivePatch {
    /// Its blade: a block field's world cell (packed 16 | 16; 0 in a stored field), and its index
    /// (a stored blade's, or in its block).
    pub blade: (u32, u32),
    /// Its blend to the cheap pose (0: the chain alone).
    pub blend: f32,
    /// Seconds since a collider last reached it.
    pub idle: f32,
}

/// What the store holds after a frame that drew step `step` (its words read back,
/// `Renderer::read_patches`): the live patches.
pub fn live(words: &[u32], step: u64) -> Vec<LivePatch> {
    let to = (step as u32).wrapping_add(1).max(1);
    words[PRESENCE_WORDS as usize..]
        .chunks_exact(RECORD_WORDS as usize)
        .filter(|r| r[1] != 0 && r[2] == to)
        .map(|r| LivePatch { blade: (r[0], r[1] - 1), blend: f32::from_bits(r[3]), idle: f32::from_bits(r[4]) })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_carries_on_from_the_previous_one_and_restarts_after_a_jump() {
        let clock = PatchClock::new(StepClock::default(), ChainParams::default());
        let dt = StepClock::default().dt;
        assert_eq!(clock.frame(0, 10.0 * dt, 1).steps, [0, 0, 11, 1]);
        // Every pass of a frame reads the same block.
        assert_eq!(clock.frame(0, 10.0 * dt, 1).steps, [0, 0, 11, 1]);
        assert_eq!(clock.frame(1, 12.0 * dt, 1).steps, [11, 2, 13, 1]);
        // More than four steps at once (or a step back): every patch restarts.
        assert_eq!(clock.frame(2, 20.0 * dt, 1).steps, [0, 0, 21, 1]);
        // Without a collider the patches run their longest life on, then stop.
        assert_eq!(clock.frame(3, 21.0 * dt, 0).steps, [21, 1, 22, 1]);
        let later = 21.0 * dt + f64::from(TIMEOUT_S + BLEND_S) + 0.2;
        assert_eq!(clock.frame(4, later, 0), PatchFrame::default());
        assert_eq!(std::mem::size_of::<PatchFrame>(), 32);
    }

    #[test]
    fn live_records_are_those_of_the_step_drawn() {
        let mut words = vec![0u32; PRESENCE_WORDS as usize + 3 * RECORD_WORDS as usize];
        let record = |i: usize| PRESENCE_WORDS as usize + i * RECORD_WORDS as usize;
        // One live at step 6 (7 stored), one of an older step, one never written.
        words[record(0) + 1] = 5;
        words[record(0) + 2] = 7;
        words[record(0) + 3] = 0.25f32.to_bits();
        words[record(1) + 1] = 9;
        words[record(1) + 2] = 6;
        assert_eq!(live(&words, 6), vec![LivePatch { blade: (0, 4), blend: 0.25, idle: 0.0 }]);
        assert_eq!(live(&words, 5).len(), 1);
    }
}
