//! Blade-pose pass (`--eval blade`), the keyframe response's own: a compute dispatch, one invocation
//! per blade, that does the animation once per blade instead of once per vertex — force, keyframe
//! selection, the blend of every level — and writes each level's point, tangent and twist (12
//! bytes) for the blade pass (`shaders/animation/blade_pose.comp`,
//! `render::scene_gpu::pose_bytes`), into the renderer's pose records (set `SET_POSES`); its own set
//! holds the keyframe tables and the cull's `Draws`, by name. Its records are written here and read by the blade pass's
//! vertex shader; the graph orders the two, and this frame's write after the previous frame's
//! reads. With the cull it runs after it, indirectly, over the visible list, one dispatch per LOD
//! bucket (`render::recording::bucket_dispatch`): each drawn blade once, its records by list
//! entry, the levels its bucket reads.

use ash::vk;

use crate::error::Result;
use crate::render::animation::response::ResponseSetup;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::recording;
use crate::render::recording::bucket_dispatch::BucketDispatch;
use crate::render::recording::PassSet;
use crate::render::shaders;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{pipeline, Access, Device, Guard, Resource};

/// How the pass dispatches: over the stored blades, or with the cull over its LOD buckets.
enum Dispatch {
    /// One invocation per stored blade, every model level.
    Stored(vk::Pipeline, u32),
    /// One dispatch per bucket of the visible list (which it reads).
    Buckets(BucketDispatch, vk::Buffer),
}

/// The compute pipelines and the buffers they touch.
pub struct BladePosePass {
    dispatch: Dispatch,
    /// Its own set: the keyframe tables and the cull's `Draws` (the shader declares it with or
    /// without the cull).
    set: PassSet,
    /// Set `SET_POSES` and the records it writes there.
    poses: (vk::DescriptorSet, vk::Buffer),
    reads: [vk::Buffer; 2],
    /// The response's resources the shader reads (the keyframe texture, its uniforms).
    tables: Vec<(Resource, Access)>,
    /// Each frame's wind at the cluster corners (`PassSetup::wind`).
    wind: Vec<vk::Buffer>,
}

impl BladePosePass {
    /// Build the pipeline on its own set's layout, writing the pose records of `setup.poses` from
    /// the keyframe `tables` (by name) it reads as `reads`.
    pub fn new(
        device: &Device,
        setup: &ResponseSetup,
        tables: &[(&'static str, Descriptor)],
        reads: Vec<(Resource, Access)>,
    ) -> Result<Self> {
        let scene = setup.scene;
        let (name, spirv) = ("blade poses", shaders::BLADE_POSE_COMP.code(device.profile));
        let shaders = [(name, spirv)];
        let resources = |_| {
            let mut own = tables.to_vec();
            own.push(("Draws", Descriptor::Buffer(scene.draws.descriptor())));
            own
        };
        let own = Guard::new(device, PassSet::new(device, &setup.sets.desc(name, &shaders), resources)?);
        let dispatch = match setup.buckets {
            Some(buckets) => {
                let constants = (setup.constants, buckets);
                BucketDispatch::new(device, name, spirv, own.layout, constants, scene.draws.raw)
                    .map(|buckets| Dispatch::Buckets(buckets, scene.visible.raw))
            }
            None => pipeline::compute(device, name, spirv, own.layout, &setup.constants.named())
                .map(|pipeline| Dispatch::Stored(pipeline, scene.blade_count)),
        };
        Ok(Self {
            dispatch: dispatch?,
            set: own.take(),
            poses: setup.poses,
            reads: [scene.blades.raw, scene.clusters.raw],
            tables: reads,
            wind: setup.wind.to_vec(),
        })
    }
}

impl Pass for BladePosePass {
    fn name(&self) -> &'static str {
        "blade poses"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let fetch = ctx.device.profile.compute_fetch();
        let declaration = Declaration::compute()
            .buffer(self.poses.1, Access::ComputeShaderWrite)
            .buffer(self.reads[0], fetch)
            .buffer(self.reads[1], Access::ComputeShaderRead)
            .buffer(self.wind[ctx.slot], Access::ComputeShaderRead);
        let declaration = self.tables.iter().fold(declaration, |d, &(table, access)| d.uses(table, access));
        let declaration = match &self.dispatch {
            Dispatch::Buckets(buckets, visible) => buckets.declare(declaration.buffer(*visible, fetch)),
            Dispatch::Stored(..) => declaration,
        };
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        self.set.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        match &self.dispatch {
            Dispatch::Stored(pipeline, blades) => {
                recording::bind_blade_compute(ctx, cmd, (self.set.layout, *pipeline), self.poses.0);
                // SAFETY: cmd is recording outside a rendering instance; both sets and the pipeline are bound.
                unsafe { device.raw.cmd_dispatch(cmd, blades.div_ceil(gpu::POSE_GROUP), 1, 1) };
            }
            Dispatch::Buckets(buckets, _) => {
                recording::bind_blade_sets(ctx, cmd, self.set.layout, self.poses.0);
                buckets.record(device, cmd);
            }
        }
        Ok(())
    }

    fn replay_key(&self, _: &PassContext) -> Option<u64> {
        // Dispatches sized at construction.
        Some(0)
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.set.destroy(device) };
        match self.dispatch {
            Dispatch::Stored(pipeline, _) => {
                crate::vk::live::destroyed(pipeline);
                // SAFETY: per the contract.
                unsafe { device.raw.destroy_pipeline(pipeline, None) };
            }
            // SAFETY: per the contract.
            Dispatch::Buckets(buckets, _) => unsafe { buckets.destroy(device) },
        }
    }
}
