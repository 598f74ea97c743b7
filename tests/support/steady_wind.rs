//! A wind field defined outside the library for the GPU tests (`render::wind::WindField`): one
//! velocity at every cluster corner, written by a compute pass of its own
//! (`tests/shaders/new_model/uniform_wind.comp`), which the test may change between frames, or a
//! ramp from calm at t = 0 to a given velocity. Included with
//! `#[path = "support/steady_wind.rs"] mod steady_wind;` by the tests that drive a response with
//! it (`new_model`, `blade_state`, `verlet`).
#![allow(dead_code)] // each test crate that includes it uses a different subset

use std::cell::Cell;
use std::rc::Rc;

use ash::vk;
use glam::Vec3;
use meadow::render::graph::{Declaration, Pass, PassContext};
use meadow::render::recording::{PassSet, PassSetDesc};
use meadow::render::wind::{FrameForces, WindField, WindInput, WindSetup};
use meadow::vk::descriptor::Resource as Descriptor;
use meadow::vk::profile::Shader;
use meadow::vk::{pipeline, Access, Device};

const UNIFORM_WIND_COMP: Shader = meadow::spirv_shader!("tests/new_model/uniform_wind.comp");

/// How the velocity changes with time.
#[derive(Clone)]
pub enum Velocity {
    /// What the cell holds when a frame is recorded.
    Shared(Rc<Cell<Vec3>>),
    /// From calm at t = 0 to the velocity at `rise` seconds, linearly, then steady.
    Ramp { to: Vec3, rise: f64 },
}

/// The uniform wind field.
pub struct SteadyWind(pub Velocity);

impl SteadyWind {
    /// A wind the test sets through the returned cell (calm at first).
    pub fn shared() -> (Self, Rc<Cell<Vec3>>) {
        let cell = Rc::new(Cell::new(Vec3::ZERO));
        (SteadyWind(Velocity::Shared(cell.clone())), cell)
    }

    /// A wind of `velocity` from the first frame on.
    pub fn constant(velocity: Vec3) -> Self {
        SteadyWind(Velocity::Shared(Rc::new(Cell::new(velocity))))
    }
}

impl WindField for SteadyWind {
    fn name(&self) -> &'static str {
        "steady wind"
    }

    /// Nothing on the CPU: the pass writes the corners, and there are no sources or colliders.
    fn update(&self, _: &mut FrameForces, _: &WindInput) {}

    fn passes(&self, device: &Device, setup: &WindSetup) -> meadow::Result<Vec<Box<dyn Pass>>> {
        let spirv = UNIFORM_WIND_COMP.code(device.profile);
        let push = vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 20 };
        let frames = setup.frames.len();
        let desc = PassSetDesc { name: "steady wind", shaders: &[("wind", spirv)], before: &[], push: &[push], frames };
        let set = PassSet::new(device, &desc, |slot| vec![("Corners", Descriptor::Buffer(setup.frames[slot].0))])?;
        let pipeline = pipeline::compute(device, "steady wind", spirv, set.layout, &[])?;
        let corners = setup.frames.iter().map(|(c, _)| c.buffer).collect();
        Ok(vec![Box::new(WindPass { set, pipeline, corners, count: setup.corners, velocity: self.0.clone() })])
    }
}

/// The pass that writes the wind at every corner of the frame.
struct WindPass {
    set: PassSet,
    pipeline: vk::Pipeline,
    /// Each frame's corners.
    corners: Vec<vk::Buffer>,
    count: u32,
    velocity: Velocity,
}

impl Pass for WindPass {
    fn name(&self) -> &'static str {
        "steady wind"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.corners[ctx.slot], Access::ComputeShaderWrite))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        let (device, bind) = (ctx.device, vk::PipelineBindPoint::COMPUTE);
        self.set.bind(device, cmd, bind, ctx.slot);
        let velocity = match &self.velocity {
            Velocity::Shared(cell) => cell.get(),
            Velocity::Ramp { to, rise } => *to * (ctx.clock.time / rise).clamp(0.0, 1.0) as f32,
        };
        let mut push = [0u32; 5];
        push[..4].copy_from_slice(bytemuck::cast_slice(&velocity.extend(0.0).to_array()));
        push[4] = self.count;
        // SAFETY: cmd is recording outside a rendering instance; the set is bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, bind, self.pipeline);
            let stages = vk::ShaderStageFlags::COMPUTE;
            device.raw.cmd_push_constants(cmd, self.set.layout, stages, 0, bytemuck::cast_slice(&push));
            device.raw.cmd_dispatch(cmd, self.count.div_ceil(64), 1, 1);
        }
        Ok(())
    }

    fn replay_key(&self, _: &PassContext) -> Option<u64> {
        // The velocity is a push constant recorded each frame: never replayed.
        None
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            meadow::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
        }
    }
}
