//! The pressed map (issue #34): trampling that stays and recovers, and cutting that regrows.
//!
//! - **The map.** A world-space grid of `DIMS`² cells of `CELL_M` (128 m across) round the camera.
//!   World cell w lives in slot w mod `DIMS` with w as its tag, so a cell keeps its value while the
//!   window scrolls, and a cell that left reads as never pressed. Its memory (`DIMS`² × 16 B, 4 MiB)
//!   is all it ever holds, however far the camera walks.
//! - **What a cell holds** (`shaders/animation/pressed.glsl`): the bend its last press left
//!   (direction × amount, 0 to 1), the press's time, the last cut's time.
//! - **Recovery.** The bend recovers as a critically damped spring from rest,
//!   (1 + ω τ) e^(−ω τ). ω = `FIVE_PERCENT` / `--recovery-s`, so the bend is 5 % of the pressed one
//!   at `--recovery-s`. A cut blade regrows linearly from `STUB` of its length to all of it over
//!   `--regrow-s`. Both are in closed form, so the map is the same at any frame rate.
//! - **Writing** ([`PressPass`], `shaders/animation/press.comp`). Each frame, every collider and
//!   every `--cut` sweeps its ground ellipse from where it was at the previous frame to where it is
//!   now. A cell it covered takes the press (or cut) at the last moment it was covered.
//!   - The first frame sweeps from t = 0, so `--time T` draws the trail of the path from 0 to T.
//!   - A step back in time clears the map and sweeps from 0 again.
//! - **Reading.** The push-out pass (`push_out`) bends each posed blade by its cell and shortens a
//!   cut one, before it pushes blades out of the colliders.
//!   - This works for every response that writes pose records, and for the flowers' stems and so
//!     their heads.
//!   - It is added after the response's pose, not into a stateful response's rest pose: a
//!     stateful blade's state does not feel it.
//!
//! The map is read on frames with a collider or a cut, and until its last press has recovered and
//! its last cut regrown; otherwise neither pass is recorded.

use std::cell::RefCell;
use std::rc::Rc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{DVec2, DVec3};

use crate::error::Result;
use crate::render::animation::response::ResponseSetup;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::PassSet;
use crate::render::shaders;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{pipeline, Access, Buffer, BufferDesc, Device, Guard};
use crate::wind::{Collider, Wind};

/// Cells per side of the map.
pub const DIMS: u32 = 512;
/// A cell's edge, in metres.
pub const CELL_M: f32 = 0.25;
/// Colliders and cuts the map sweeps each frame (colliders first): every collider
/// (`MAX_COLLIDERS`) and as many cuts.
pub const MAX_SWEEPS: usize = 2 * super::MAX_COLLIDERS;
/// A cut blade's length, as a share of its own, when just cut.
pub const STUB: f32 = 0.2;
/// A collider presses (or cuts) only where its lowest point is within this of the ground, in metres.
pub const REACH_M: f32 = 1.2;
/// ω T of the critically damped spring's 5 % time T: the root of (1 + x) e^(−x) = 0.05.
pub const FIVE_PERCENT: f64 = 4.743_864_518_390_579;
/// Workgroups a row of the press dispatch holds (Vulkan's least `maxComputeWorkGroupCount[0]`).
const MAX_GROUPS_X: u32 = 65_535;

/// How far the press leans a blade at full amount, in degrees (of its chord from the root to each
/// point: the tip's displacement is linear in the amount).
pub const LEAN_DEG: f32 = 70.0;

/// The recovery and regrowth times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PressedParams {
    /// `--recovery-s`: a trampled blade is back to 5 % of its pressed displacement after this.
    pub recovery_s: f32,
    /// `--regrow-s`: a cut blade has its full length again after this.
    pub regrow_s: f32,
}

impl Default for PressedParams {
    fn default() -> Self {
        Self { recovery_s: 20.0, regrow_s: 30.0 }
    }
}

/// The map's frame block (`PressedFrame` in `pressed.glsl`), std430.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct PressedFrame {
    counts: [u32; 4],
    window: [i32; 4],
    origin: [i32; 4],
    offset: [f32; 4],
    times: [f32; 4],
    sweeps: [[[f32; 4]; 3]; MAX_SWEEPS],
    boxes: [[i32; 4]; MAX_SWEEPS],
    /// The push-out pass's interaction patches (zero for the press pass).
    pub patches: super::patches::PatchFrame,
}

/// What the CPU keeps between frames.
struct PressState {
    /// The previous frame's time and the sweeps' centres then (world, f64).
    previous: Option<(f64, Vec<DVec3>)>,
    /// The map reads as empty from this time on (its last press recovered, its last cut regrown).
    active_until: f64,
    /// This frame's block: its counts say what the passes do (`press_cells`, `read`).
    frame: PressedFrame,
    /// The map must be cleared before its next press (new, or time went back).
    clear: bool,
}

impl PressState {
    /// Cells the press dispatch covers this frame (0: no press).
    fn press_cells(&self) -> u32 {
        self.frame.counts[2]
    }

    /// Whether the push-out pass reads the map this frame.
    fn read(&self) -> bool {
        self.frame.counts[1] != 0
    }
}

/// The map's cells, owned by the renderer (they outlive the passes' rebuilds), and what its
/// passes share of each frame.
pub struct PressedMap {
    /// `DIMS`² cells of 16 bytes.
    pub cells: Buffer,
    /// The interaction patches, whose presence grid is over the same cells (`patches`).
    pub patches: super::patches::PatchStore,
    state: Rc<RefCell<PressState>>,
}

impl PressedMap {
    /// The map, never pressed (cleared by the press pass before its first use).
    pub fn new(device: &Device) -> Result<Self> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let bytes = u64::from(DIMS * DIMS) * 16;
        let cells = Guard::new(device, Buffer::new(device, &BufferDesc::gpu_only("pressed map", bytes, usage))?);
        let patches = super::patches::PatchStore::new(device)?;
        let state =
            PressState { previous: None, active_until: f64::NEG_INFINITY, frame: Zeroable::zeroed(), clear: true };
        Ok(Self { cells: cells.take(), patches, state: Rc::new(RefCell::new(state)) })
    }

    /// The frame at `time` (s) with `wind`'s colliders and cuts, positions relative to `origin`
    /// (O), the window round `eye`: the sweeps since the previous frame and what the passes do.
    pub fn update(&self, wind: &Wind, params: PressedParams, origin: DVec2, time: f64, eye: DVec3) {
        let mut state = self.state.borrow_mut();
        let sweeping: Vec<(&Collider, f32)> = wind
            .colliders
            .iter()
            .map(|c| (c, 0.0))
            .chain(wind.cuts.iter().map(|c| (c, 1.0)))
            .take(MAX_SWEEPS)
            .collect();
        let now: Vec<DVec3> = sweeping.iter().map(|(c, _)| c.center_f64(time)).collect();
        // From t = 0 on the first frame and after a step back (the map cleared).
        let (then, before) = match state.previous.take() {
            Some((t, centres)) if t <= time => (t, Some(centres)),
            previous => {
                state.clear |= previous.is_some();
                (0.0, None)
            }
        };
        let start = |i: usize, c: &Collider| match &before {
            Some(centres) if centres.len() == now.len() => centres[i],
            _ => c.center_f64(then),
        };
        let edge = f64::from(CELL_M);
        let cell = |p: DVec2| (p / edge).floor().as_i64vec2();
        let window = cell(DVec2::new(eye.x, eye.z)) - i64::from(DIMS / 2);
        let mut frame: PressedFrame = Zeroable::zeroed();
        let mut press_cells = 0u32;
        for (i, (c, cut)) in sweeping.iter().enumerate() {
            let (p0, p1) = (start(i, c), now[i]);
            let r = DVec2::new(f64::from(c.radii.x), f64::from(c.radii.z));
            let (a, b) = (DVec2::new(p0.x, p0.z), DVec2::new(p1.x, p1.z));
            // The cells the sweep's ground ellipse covers, within the window.
            let lo = cell(a.min(b) - r).max(window);
            let hi = cell(a.max(b) + r).min(window + i64::from(DIMS - 1));
            let size = (hi - lo + 1).max(glam::I64Vec2::ZERO);
            frame.boxes[i] = [lo.x as i32, lo.y as i32, size.x.max(1) as i32, press_cells as i32];
            press_cells += (size.x * size.y) as u32;
            let relative = |p: DVec3| [(p.x - origin.x) as f32, p.y as f32, (p.z - origin.y) as f32, 0.0];
            frame.sweeps[i] = [relative(p0), relative(p1), [c.radii.x, c.radii.y, c.radii.z, *cut]];
        }
        if !sweeping.is_empty() {
            let params = (f64::from(params.recovery_s), f64::from(params.regrow_s));
            state.active_until = time + (3.0 * params.0).max(params.1);
        }
        let read = !sweeping.is_empty() || time < state.active_until;
        let o = cell(origin);
        let offset = origin - o.as_dvec2() * edge;
        frame.counts = [sweeping.len() as u32, u32::from(read), press_cells, 0];
        frame.window = [window.x as i32, window.y as i32, 0, 0];
        frame.origin = [o.x as i32, o.y as i32, 0, 0];
        frame.offset = [offset.x as f32, offset.y as f32, 0.0, 0.0];
        let rate = FIVE_PERCENT / f64::from(params.recovery_s);
        frame.times = [time as f32, then as f32, rate as f32, params.regrow_s];
        state.frame = frame;
        state.previous = Some((time, now));
    }

    /// The push-out pass's view of the map: its cells and each frame's block (`PressedCells`,
    /// `PressedFrame`), and whether it reads them this frame.
    pub fn reader(&self) -> MapReader {
        MapReader {
            cells: self.cells.raw,
            cells_descriptor: self.cells.descriptor(),
            patches: self.patches.buffer.raw,
            patches_descriptor: self.patches.buffer.descriptor(),
            patch_list: self.patches.list.raw,
            patch_list_descriptor: self.patches.list.descriptor(),
            state: self.state.clone(),
        }
    }

    /// Destroy the cells.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::Destroy::destroy(self.cells, device);
            self.patches.destroy(device);
        }
    }
}

/// What a pass that reads the map holds of it.
#[derive(Clone)]
pub struct MapReader {
    /// The cells.
    pub cells: vk::Buffer,
    cells_descriptor: vk::DescriptorBufferInfo,
    /// The interaction patches' store and list (`patches::PatchStore`).
    pub patches: vk::Buffer,
    patches_descriptor: vk::DescriptorBufferInfo,
    pub patch_list: vk::Buffer,
    patch_list_descriptor: vk::DescriptorBufferInfo,
    state: Rc<RefCell<PressState>>,
}

impl MapReader {
    /// The cells by the name `pressed.glsl` declares them with.
    pub fn resource(&self) -> (&'static str, Descriptor) {
        ("PressedCells", Descriptor::Buffer(self.cells_descriptor))
    }

    /// The patches' store and list by the names `patches.glsl` declares them with.
    pub fn patches_resources(&self) -> [(&'static str, Descriptor); 2] {
        [
            ("Patches", Descriptor::Buffer(self.patches_descriptor)),
            ("PatchList", Descriptor::Buffer(self.patch_list_descriptor)),
        ]
    }

    /// Whether the map is read this frame.
    pub fn read(&self) -> bool {
        self.state.borrow().read()
    }

    /// This frame's block, with the push-out pass's interaction patches (`PatchFrame::default()`
    /// for the press pass).
    pub fn frame_bytes(&self, patches: super::patches::PatchFrame) -> Vec<u8> {
        let frame = PressedFrame { patches, ..self.state.borrow().frame };
        bytemuck::bytes_of(&frame).to_vec()
    }

    /// The block's size.
    pub const FRAME_BYTES: u64 = std::mem::size_of::<PressedFrame>() as u64;
}

/// The press pass: clears the map when it must, then sweeps the frame's colliders and cuts into it.
pub struct PressPass {
    pipeline: vk::Pipeline,
    set: PassSet,
    uniforms: PassUniforms,
    map: MapReader,
    /// The ground's clipmap (each cell's ground height).
    ground: vk::Buffer,
    pose_set: vk::DescriptorSet,
}

impl PressPass {
    /// Build the pipeline on the scene's sets and its own (the map's cells and frame block).
    pub fn new(device: &Device, setup: &ResponseSetup, map: MapReader) -> Result<Self> {
        let (name, spirv) = ("press", shaders::PRESS_COMP.code(device.profile));
        let uniforms = Guard::new(device, PassUniforms::new(device, name, MapReader::FRAME_BYTES, setup.sets.frames)?);
        let set = PassSet::new(device, &setup.sets.desc(name, &[(name, spirv)]), |slot| {
            vec![map.resource(), ("PressedFrame", uniforms.resource(slot))]
        })?;
        let set = Guard::new(device, set);
        let pipeline = pipeline::compute(device, name, spirv, set.layout, &setup.constants.named())?;
        Ok(Self {
            pipeline,
            set: set.take(),
            uniforms: uniforms.take(),
            map,
            ground: setup.scene.ground.texels.raw,
            pose_set: setup.poses.0,
        })
    }

    /// Whether the map is cleared this frame: new, time went back, or a frame dropped, and the map
    /// is pressed or read this frame (a renderer with no collider never clears it).
    fn needs_clear(&self) -> bool {
        let state = self.map.state.borrow();
        state.clear && (state.press_cells() > 0 || state.read())
    }
}

impl Pass for PressPass {
    fn name(&self) -> &'static str {
        "press"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let press = self.map.state.borrow().press_cells() > 0;
        let declaration = match (self.needs_clear(), press) {
            (false, false) => return None,
            (true, _) => Declaration::compute().step("clear").buffer(self.map.cells, Access::TransferWrite),
            (false, true) => Declaration::compute(),
        };
        if !press {
            return Some(declaration);
        }
        let declaration = if self.needs_clear() { declaration.step("press") } else { declaration };
        Some(
            declaration
                .buffer(self.map.cells, Access::ComputeShaderRead)
                .buffer(self.map.cells, Access::ComputeShaderWrite)
                .buffer(self.ground, ctx.device.profile.compute_fetch()),
        )
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        if self.needs_clear() && ctx.step == 0 {
            // SAFETY: cmd is recording outside a rendering instance; the buffer allows transfers.
            unsafe { device.raw.cmd_fill_buffer(cmd, self.map.cells, 0, vk::WHOLE_SIZE, 0) };
            self.map.state.borrow_mut().clear = false;
            return Ok(());
        }
        let groups = self.map.state.borrow().press_cells().div_ceil(64);
        crate::render::recording::bind_blade_compute(ctx, cmd, (self.set.layout, self.pipeline), self.pose_set);
        self.set.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        // Rows of at most 65 535 workgroups (the least maxComputeWorkGroupCount).
        let row = groups.min(MAX_GROUPS_X);
        // SAFETY: as above; the sets and the pipeline are bound.
        unsafe { device.raw.cmd_dispatch(cmd, row, groups.div_ceil(row), 1) };
        Ok(())
    }

    fn uniforms(&self, _: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        Some((&self.uniforms, self.map.frame_bytes(Default::default())))
    }

    fn frame_dropped(&self) {
        // The clear, or the frame's sweep, may not have run: clear again and sweep from t = 0 (the
        // CLI's straight-line paths are drawn again whole; a viewer's trail is lost).
        let mut state = self.map.state.borrow_mut();
        state.clear = true;
        state.previous = None;
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
            self.uniforms.destroy(device);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_patches_presence_grid_has_the_maps_cells() {
        assert_eq!(crate::render::animation::patches::PRESENCE_DIMS, DIMS);
    }

    #[test]
    fn the_spring_is_at_five_percent_at_the_recovery_time() {
        let x = FIVE_PERCENT;
        assert!(((1.0 + x) * (-x).exp() - 0.05).abs() < 1e-12);
    }

    #[test]
    fn the_frame_block_is_what_the_shader_reads() {
        // pressed.glsl: five vec4 of counts, window, origin, offset and times, three per sweep,
        // then a box per sweep.
        assert_eq!(MapReader::FRAME_BYTES, 16 * (5 + 4 * MAX_SWEEPS as u64 + 2));
    }
}
