//! A blade response's pose pass: a compute dispatch, one invocation per blade, that poses each
//! blade once and writes each level's point, tangent and twist (12 bytes) into the renderer's
//! pose records (set `SET_POSES`, `render::scene_gpu::pose_bytes`) for the blade pass. The pass is
//! its shader and its own set: the response's resources by the names its GLSL declares, the cull's
//! `Draws`, and optionally a uniform block filled each frame (`PoseUniforms`). The keyframes'
//! `--eval blade` (`shaders/animation/blade_pose.comp`) and Pelzer's sine
//! (`shaders/animation/sine.comp`) are two of them; `tests/new_model.rs`' lean a third.
//!
//! Its records are written here and read by the blade pass (or the blade-levels pass); the graph
//! orders the two, and this frame's write after the previous frame's reads. With the cull it runs
//! after it, indirectly, over the visible list, one dispatch per LOD bucket
//! (`recording::BladeDispatch`): each drawn blade once, its records by list entry, the levels its
//! bucket reads.

use std::cell::Cell;

use ash::vk;

use crate::error::Result;
use crate::render::animation::blade_state;
use crate::render::animation::response::ResponseSetup;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::{BladeDispatch, PassSet};
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{Access, Device, Guard, Resource};

/// What fills a pose pass's uniform block for the frame being planned.
pub type FillUniforms = Box<dyn Fn(&PassContext) -> Vec<u8>>;

/// A pose pass's own uniform block: its GLSL name, its size in bytes, and what it holds each
/// frame (called when the graph plans the frame).
pub struct PoseUniforms {
    /// The block's name in the shader (`layout(set = SET_PASS, …) uniform NAME`).
    pub name: &'static str,
    /// Its std140 size in bytes.
    pub size: u64,
    /// The name of the same block bound again as a storage buffer, for the values that decide
    /// control flow (`shaders/common/profile.glsl`'s rule), if the shader has one.
    pub control: Option<&'static str>,
    /// Its bytes for the frame being planned.
    pub fill: FillUniforms,
}

impl PoseUniforms {
    /// The `BladeStateFrame` block a stateful response's pose pass reads
    /// (`shaders/animation/blade_state.glsl`) for `store`, filled each frame from `span`.
    pub fn blade_state(store: &blade_state::BladeStateStore, span: blade_state::SharedSpan) -> Self {
        let shape = store.shape;
        Self {
            name: "BladeStateFrame",
            size: 48,
            control: Some("BladeStateControl"),
            fill: Box::new(move |_| {
                let (span, dt) = span.get();
                bytemuck::cast_slice(&shape.frame_block(span, dt)).to_vec()
            }),
        }
    }
}

/// What a pose pass runs: its shader and what the response gives it.
pub struct PoseShader<'a> {
    /// The pass's name in timings and labels.
    pub name: &'static str,
    /// The shader (`render::shaders`, the backend profile's code).
    pub spirv: &'a [u8],
    /// The response's resources in the pass's own set, by the names the shader declares (the
    /// cull's `Draws` is added).
    pub resources: Vec<(&'static str, Descriptor)>,
    /// What the shader does with them (reads; a write is declared like any access).
    pub uses: Vec<(Resource, Access)>,
    /// A uniform block filled each frame, if the shader declares one.
    pub uniforms: Option<PoseUniforms>,
    /// A stateful response's blade-state store (`blade_state::BladeStateStore`, given in
    /// `resources` by name too): the pass clears it before its first dispatch and again after a
    /// dropped frame, and declares that the shader reads and writes it.
    pub store: Option<vk::Buffer>,
}

/// The pipelines, the sets and what the pass touches.
pub struct PosePass {
    name: &'static str,
    dispatch: BladeDispatch,
    set: PassSet,
    /// Set `SET_POSES` and the records it writes there.
    poses: (vk::DescriptorSet, vk::Buffer),
    /// The stored blades and their clusters.
    reads: [vk::Buffer; 2],
    uses: Vec<(Resource, Access)>,
    uniforms: Option<(PassUniforms, FillUniforms)>,
    /// The blade-state store, and whether a submitted frame has cleared it.
    store: Option<(vk::Buffer, Cell<bool>)>,
    /// Each frame's wind at the cluster corners (`ResponseSetup::wind`).
    wind: Vec<vk::Buffer>,
}

impl PosePass {
    /// Build `shader` on its own set's layout, writing the pose records of `setup.poses`.
    pub fn new(device: &Device, setup: &ResponseSetup, shader: PoseShader) -> Result<Self> {
        let scene = setup.scene;
        let PoseShader { name, spirv, resources, uses, uniforms, store } = shader;
        let (buffers, block) = match uniforms {
            Some(block) => {
                let names = (block.name, block.control);
                (Some(PassUniforms::new(device, name, block.size, setup.sets.frames)?), Some((names, block.fill)))
            }
            None => (None, None),
        };
        let buffers = Guard::new(device, buffers);
        let own = |slot| {
            let mut own = resources.clone();
            own.push(("Draws", Descriptor::Buffer(scene.draws.descriptor())));
            if let (Some(buffers), Some(((block, control), _))) = (buffers.as_ref(), &block) {
                own.push((*block, buffers.resource(slot)));
                own.extend(control.map(|control| (control, buffers.resource(slot))));
            }
            own
        };
        let set = Guard::new(device, PassSet::new(device, &setup.sets.desc(name, &[(name, spirv)]), own)?);
        let source = setup.blade_source();
        let dispatch = BladeDispatch::new(device, name, spirv, set.layout, setup.constants, source)?;
        Ok(Self {
            name,
            dispatch,
            set: set.take(),
            poses: setup.poses,
            reads: [scene.blades.raw, scene.clusters.raw],
            uses,
            uniforms: buffers.take().zip(block.map(|(_, fill)| fill)),
            store: store.map(|buffer| (buffer, Cell::new(false))),
            wind: setup.wind.to_vec(),
        })
    }
}

impl Pass for PosePass {
    fn name(&self) -> &'static str {
        self.name
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let declaration = match &self.store {
            // The clear first, as a step of its own (`record` records it at step 0).
            Some((store, cleared)) if !cleared.get() => {
                Declaration::compute().step("clear").buffer(*store, Access::TransferWrite).step(self.name)
            }
            _ => Declaration::compute(),
        };
        Some(self.declare_from(ctx, declaration))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        if let Some((store, cleared)) = &self.store {
            if !cleared.get() {
                if ctx.step == 0 {
                    blade_state::record_clear(ctx.device, cmd, *store);
                    return Ok(());
                }
                cleared.set(true);
            }
        }
        self.record_dispatch(ctx, cmd);
        Ok(())
    }

    fn uniforms(&self, ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        self.uniforms.as_ref().map(|(buffers, fill)| (buffers, fill(ctx)))
    }

    fn replay_key(&self, _: &PassContext) -> Option<u64> {
        // Dispatches sized at construction; the uniform block is written before each submission.
        // A store's clear is recorded once: such a pass is recorded anew.
        self.store.is_none().then_some(0)
    }

    fn frame_dropped(&self) {
        // The clear may not have run: do it again.
        if let Some((_, cleared)) = &self.store {
            cleared.set(false);
        }
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.set.destroy(device);
            self.dispatch.destroy(device);
            if let Some((buffers, _)) = self.uniforms {
                buffers.destroy(device);
            }
        }
    }
}

impl PosePass {
    /// `declaration` (any steps before the dispatch; the current step is the dispatch's) with what
    /// the dispatch uses: for a pass that wraps this one with steps of its own before it.
    pub fn declare_from(&self, ctx: &PassContext, declaration: Declaration) -> Declaration {
        let declaration = match &self.store {
            Some((store, _)) => {
                declaration.buffer(*store, Access::ComputeShaderRead).buffer(*store, Access::ComputeShaderWrite)
            }
            None => declaration,
        };
        let declaration = declaration
            .buffer(self.poses.1, Access::ComputeShaderWrite)
            .buffer(self.reads[0], ctx.device.profile.compute_fetch())
            .buffer(self.reads[1], Access::ComputeShaderRead)
            .buffer(self.wind[ctx.slot], Access::ComputeShaderRead);
        let declaration = self.uses.iter().fold(declaration, |d, &(resource, access)| d.uses(resource, access));
        self.dispatch.declare(ctx, declaration)
    }

    /// Bind the pass's sets and record its dispatches (a wrapping pass's dispatch step).
    pub fn record_dispatch(&self, ctx: &PassContext, cmd: vk::CommandBuffer) {
        self.set.bind(ctx.device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        self.dispatch.record(ctx, cmd, self.set.layout, self.poses.0);
    }
}
