//! Belyaev's inertial blades (§3.1) as a stateful blade response: each drawn blade's segment
//! chain (`chain`, `shaders/animation/chain.glsl`) keeps its joints' rotations and angular
//! velocities in the blade-state store (`blade_state`), and `shaders/animation/inertial.comp`
//! steps them and draws the fitted curve. [`chain::Chain`] is the CPU mirror the tests measure it
//! against.

use std::cell::Cell;
use std::rc::Rc;

use ash::vk;
use glam::Vec3;

use crate::error::Result;
use crate::render::animation::blade_state::{BladeStateStore, SharedSpan, StepSpan};
use crate::render::animation::chain::{ChainParams, CHAIN_SEGMENTS};
use crate::render::animation::pose_pass::{PosePass, PoseShader, PoseUniforms};
use crate::render::animation::response::{BladeInput, BladeResponse, ResponseSetup, ResponseStep};
use crate::render::graph::Pass;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{Buffer, BufferDesc, Destroy, Device, Guard};

/// State words a blade: per joint ψ, then ω (inertial.comp's `read_chain`).
pub const STATE_WORDS: u32 = 6 * CHAIN_SEGMENTS as u32;
/// A block field's store: the blocks within this many of the camera's (121 blocks).
pub const STORE_RADIUS: u32 = 5;

/// The inertial response: its store, its constants and the span of steps each frame takes.
pub struct InertialResponse {
    params: ChainParams,
    store: BladeStateStore,
    /// `InertialShape`, written once (host-visible).
    shape: Buffer,
    previous: Option<u64>,
    /// This frame's span and step, read when the graph plans the frame.
    span: SharedSpan,
}

impl InertialResponse {
    /// A store for `scene`'s blades (a block field's within `STORE_RADIUS` blocks) and the
    /// constants' block. Refused with one line if the store does not fit.
    pub fn new(device: &Device, scene: &SceneGpu, params: ChainParams) -> Result<Self> {
        params.check()?;
        let store = Guard::new(device, BladeStateStore::new(device, scene, STATE_WORDS, STORE_RADIUS, false)?);
        let usage = vk::BufferUsageFlags::UNIFORM_BUFFER;
        let mut shape = Buffer::new(device, &BufferDesc::upload("inertial shape", 16, usage))?;
        shape.write(0, &[params.stiffness, params.damping, 0.0, 0.0]);
        let span = Rc::new(Cell::new((StepSpan::between(None, 0), 1.0 / 60.0)));
        Ok(Self { params, store: store.take(), shape, previous: None, span })
    }
}

impl BladeResponse for InertialResponse {
    fn name(&self) -> &'static str {
        "inertial"
    }

    fn blade_input(&self) -> BladeInput {
        BladeInput::PoseRecords
    }

    fn passes(&self, device: &Device, setup: &ResponseSetup) -> Result<Vec<Box<dyn Pass>>> {
        let shader = PoseShader {
            name: "inertial",
            spirv: shaders::INERTIAL_COMP.code(device.profile),
            resources: vec![
                ("InertialShape", crate::vk::descriptor::Resource::Buffer(self.shape.descriptor())),
                self.store.resource(),
            ],
            uses: Vec::new(),
            uniforms: Some(PoseUniforms::blade_state(&self.store, self.span.clone())),
            store: Some(self.store.buffer.raw),
        };
        Ok(vec![Box::new(PosePass::new(device, setup, shader)?)])
    }

    fn step(&mut self, step: &ResponseStep) {
        self.span.set((StepSpan::between(self.previous, step.step), step.dt));
        self.previous = Some(step.step);
    }

    fn stateful(&self) -> bool {
        true
    }

    fn tip_offset(&self, wind: Vec3) -> Vec3 {
        self.params.tip_offset(wind)
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.store.destroy(device);
            self.shape.destroy(device);
        }
    }
}
