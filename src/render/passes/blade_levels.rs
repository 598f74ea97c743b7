//! Blade-levels pass (with the cull and pose records): a compute dispatch, one invocation per
//! entry of the cull's visible list, that places each drawn blade's strip levels in the world and
//! lights them once — the blade's record, a block field's placement, the terrain normal, Belyaev's
//! lighting, the fog — so the blade pass's vertex shader only widens and projects them
//! (`shaders/blades/blade_levels.comp`). llvmpipe runs vertex shaders on one thread and compute on all of
//! them; the work also drops from once per strip vertex to once per level. It reads the
//! renderer's pose records (whatever response wrote them) and writes `PoseRecords::levels`; the graph orders it
//! after the pose pass and before the blade pass, and this frame's write after the previous
//! frame's reads.

use ash::vk;

use crate::error::Result;
use crate::render::animation::poses::PoseRecords;
use crate::render::animation::response::ResponseSetup;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::recording;
use crate::render::recording::bucket_dispatch::{self, BucketDispatch};
use crate::render::recording::PassSet;
use crate::render::shaders;
use crate::vk::{Access, Device, Guard};

/// The compute pipelines (one per LOD bucket) and the buffers they touch.
pub struct BladeLevelsPass {
    buckets: BucketDispatch,
    /// Its own set: the cull's `Draws`.
    set: PassSet,
    /// Set `SET_POSES`.
    pose_set: vk::DescriptorSet,
    /// Pose records (read), placed levels (written).
    poses: vk::Buffer,
    levels: vk::Buffer,
    /// The stored blades (a block field's are placed per cell) and the ground's clipmap (the
    /// ground's normal under each root).
    reads: [vk::Buffer; 3],
    /// The cull's visible list (the buckets' ranges and dispatches are the `buckets`' reads).
    visible: vk::Buffer,
}

impl BladeLevelsPass {
    /// Build the pipelines on its own set's layout, from and into the buffers of `records`.
    pub fn new(device: &Device, setup: &ResponseSetup, records: &PoseRecords) -> Result<Self> {
        let scene = setup.scene;
        let Some(buckets) = setup.buckets else {
            return Err(crate::error::Error::Internal("the blade levels pass needs the cull's visible list".into()));
        };
        let (name, spirv) = ("blade levels", shaders::BLADE_LEVELS_COMP.code(device.profile));
        // The blade class's buckets alone: a further class's entries have no placed levels.
        let constants = (setup.constants, buckets, &[][..]);
        let own = Guard::new(device, bucket_dispatch::draws_set(device, name, spirv, &setup.sets, &scene.draws)?);
        let buckets = BucketDispatch::new(device, name, spirv, own.layout, constants, scene.draws.raw)?;
        Ok(Self {
            buckets,
            set: own.take(),
            pose_set: records.set,
            poses: records.poses.raw,
            levels: records.levels.raw,
            reads: [scene.blades.raw, scene.ground.texels.raw, scene.ground.cover.0.raw],
            visible: scene.visible.raw,
        })
    }
}

impl Pass for BladeLevelsPass {
    fn name(&self) -> &'static str {
        "blade levels"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let fetch = ctx.device.profile.compute_fetch();
        let declaration = Declaration::compute()
            .buffer(self.levels, Access::ComputeShaderWrite)
            .buffer(self.poses, Access::ComputeShaderRead)
            .buffer(self.reads[0], fetch)
            .buffer(self.reads[1], fetch)
            .buffer(self.reads[2], fetch)
            .buffer(self.visible, fetch);
        Some(self.buckets.declare(declaration))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        recording::bind_blade_sets(ctx, cmd, self.set.layout, self.pose_set);
        self.set.bind(ctx.device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        self.buckets.record(ctx.device, cmd);
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.buckets.destroy(device);
            self.set.destroy(device);
        }
    }
}
