//! The interaction patches' pass (issue #34; the design in `patches`): after the push-out pass,
//! which lists the blades a collider reaches, or that lie where a patch may still live, and leaves
//! them to it. One indirect dispatch (`shaders/animation/patch.comp`), one invocation per listed
//! blade, sized by the push-out walk: the blade's record found or claimed, its chain stepped, its
//! pose bent by the pressed map and walked out of the colliders as push-out would, and written.
//!
//! So the work of a patch is paid by the patched blades alone: the chain as a branch of the
//! push-out shader cost 6 ms more at the default scene on llvmpipe with no blade patched, and a
//! scan of its own over every drawn blade 2.5 ms (both measured, 2026-12-06).

use std::rc::Rc;

use ash::vk;

use crate::error::Result;
use crate::render::animation::patches::PatchClock;
use crate::render::animation::pressed::MapReader;
use crate::render::animation::response::ResponseSetup;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::PassSet;
use crate::render::shaders;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{pipeline, Access, Device, Guard};

/// Invocations a workgroup of the patch dispatch (`patch.comp`'s `local_size_x`, and how the
/// push-out walk sizes the dispatch).
pub const PATCH_GROUP: u32 = 64;

/// The patch pipeline, its set and what it touches.
pub struct PatchPass {
    patch: vk::Pipeline,
    set: PassSet,
    uniforms: PassUniforms,
    map: MapReader,
    clock: Rc<PatchClock>,
    /// Set `SET_POSES` and the pose records.
    poses: (vk::DescriptorSet, vk::Buffer),
    /// The stored blades and their clusters.
    reads: [vk::Buffer; 2],
    /// Each frame's wind at the cluster corners (`ResponseSetup::wind`).
    wind: Vec<vk::Buffer>,
}

impl PatchPass {
    /// Build the pipeline on the scene's sets and its own, stepping the patches in `map`'s store by
    /// `clock` (the push-out pass's).
    pub fn new(device: &Device, setup: &ResponseSetup, map: MapReader, clock: Rc<PatchClock>) -> Result<Self> {
        let (name, spirv) = ("patches", shaders::PATCH_COMP.code(device.profile));
        let uniforms = Guard::new(device, PassUniforms::new(device, name, MapReader::FRAME_BYTES, setup.sets.frames)?);
        let set = PassSet::new(device, &setup.sets.desc(name, &[(name, spirv)]), |slot| {
            let mut own = vec![map.resource(), ("PressedFrame", uniforms.resource(slot))];
            own.extend(map.patches_resources());
            own.push(("Draws", Descriptor::Buffer(setup.scene.draws.descriptor())));
            own
        })?;
        let set = Guard::new(device, set);
        // Every model level: the patch walks the whole backbone (`patch.comp`); with the cull, the
        // list's records are visible entries.
        let model = setup.constants.model_segments;
        let every_level = match setup.buckets {
            Some(_) => crate::render::recording::bucket_dispatch::bucket_constants(setup.constants, model),
            None => crate::render::specialization::Specialization { segments: model, ..*setup.constants },
        };
        let patch = pipeline::compute(device, name, spirv, set.layout, &every_level.named())?;
        let scene = setup.scene;
        Ok(Self {
            patch,
            set: set.take(),
            uniforms: uniforms.take(),
            map,
            clock,
            poses: setup.poses,
            reads: [scene.blades.raw, scene.clusters.raw],
            wind: setup.wind.to_vec(),
        })
    }
}

impl Pass for PatchPass {
    fn name(&self) -> &'static str {
        "patches"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        // The push-out pass lists the blades on the frames the patches run.
        let runs = self.clock.frame(ctx.clock.index, ctx.clock.time, ctx.uniforms.wind_counts.y).steps[3] != 0;
        runs.then(|| {
            let (store, list) = (self.map.patches, self.map.patch_list);
            Declaration::compute()
                .buffer(list, Access::IndirectCommandRead)
                .buffer(list, Access::ComputeShaderRead)
                .buffer(store, Access::ComputeShaderRead)
                .buffer(store, Access::ComputeShaderWrite)
                .buffer(self.map.cells, Access::ComputeShaderRead)
                .buffer(self.poses.1, Access::ComputeShaderRead)
                .buffer(self.poses.1, Access::ComputeShaderWrite)
                .buffer(self.reads[0], ctx.device.profile.compute_fetch())
                .buffer(self.reads[1], Access::ComputeShaderRead)
                .buffer(self.wind[ctx.slot], Access::ComputeShaderRead)
        })
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        crate::render::recording::bind_blade_compute(ctx, cmd, (self.set.layout, self.patch), self.poses.0);
        self.set.bind(ctx.device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        // SAFETY: cmd is recording outside a rendering instance; the sets and the pipeline are
        // bound, and the list's head is the dispatch the push-out walk sized.
        unsafe { ctx.device.raw.cmd_dispatch_indirect(cmd, self.map.patch_list, 0) };
        Ok(())
    }

    fn uniforms(&self, ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        let frame = self.clock.frame(ctx.clock.index, ctx.clock.time, ctx.uniforms.wind_counts.y);
        Some((&self.uniforms, self.map.frame_bytes(frame)))
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.patch);
            device.raw.destroy_pipeline(self.patch, None);
            self.set.destroy(device);
            self.uniforms.destroy(device);
        }
    }
}
