//! How a per-blade compute pass of a blade response dispatches: one invocation per stored blade
//! without the cull, or with it one indirect dispatch per LOD bucket over the visible list
//! ([`BucketDispatch`]). Every pose-writing pass has the same two shapes, so a response's pass is
//! its shader and its own set (`animation::pose_pass::PosePass`, or a pass of its own built on
//! this, as `tests/blade_state.rs`' spring).

use ash::vk;

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, PassContext};
use crate::render::recording::bucket_dispatch::BucketDispatch;
use crate::render::specialization::Specialization;
use crate::vk::{pipeline, Device};

/// What a per-blade pass runs over: the stored blades' count, and the cull's `draws` (its
/// buckets' ranges and dispatches) and visible list.
#[derive(Clone, Copy)]
pub struct BladeSource<'a> {
    /// The stored blades.
    pub blades: u32,
    /// With the cull, the segments of its LOD buckets; `None` without it.
    pub buckets: Option<&'a [u32]>,
    /// With the cull, the buckets of further draw classes posed as blades, and their segments
    /// (`render::draw_class::ClassLayout::posed`).
    pub posed: &'a [(u32, u32)],
    /// The cull's `draws` buffer.
    pub draws: vk::Buffer,
    /// The cull's visible list.
    pub visible: vk::Buffer,
}

/// A per-blade pass's pipelines and what they dispatch from.
pub enum BladeDispatch {
    /// One invocation per stored blade (`POSE_GROUP` a workgroup), every model level.
    Stored {
        /// The pipeline, built with the scene's constants.
        pipeline: vk::Pipeline,
        /// The stored blades.
        blades: u32,
    },
    /// One dispatch per bucket of the visible list, which the shaders read.
    Buckets {
        /// The buckets' pipelines.
        buckets: BucketDispatch,
        /// The visible list.
        visible: vk::Buffer,
    },
}

impl BladeDispatch {
    /// Build `spirv` (`name` in labels) on `layout` from `constants`: once, or once per LOD bucket
    /// of `source`.
    pub fn new(
        device: &Device,
        name: &str,
        spirv: &[u8],
        layout: vk::PipelineLayout,
        constants: &Specialization,
        source: BladeSource,
    ) -> Result<Self> {
        Ok(match source.buckets {
            Some(buckets) => BladeDispatch::Buckets {
                buckets: BucketDispatch::new(
                    device,
                    name,
                    spirv,
                    layout,
                    (constants, buckets, source.posed),
                    source.draws,
                )?,
                visible: source.visible,
            },
            None => BladeDispatch::Stored {
                pipeline: pipeline::compute(device, name, spirv, layout, &constants.named())?,
                blades: source.blades,
            },
        })
    }

    /// Add what the dispatches read to a pass's declaration: with the cull, the visible list and
    /// the buckets' `draws` (by the shaders and as the indirect dispatches).
    pub fn declare(&self, ctx: &PassContext, declaration: Declaration) -> Declaration {
        match self {
            BladeDispatch::Buckets { buckets, visible } => {
                buckets.declare(declaration.buffer(*visible, ctx.device.profile.compute_fetch()))
            }
            BladeDispatch::Stored { .. } => declaration,
        }
    }

    /// Bind the frame's set, the pose records' set `poses` and the pipelines on `layout`, and
    /// record the dispatches (the pass's own set is bound by the caller).
    pub fn record(
        &self,
        ctx: &PassContext,
        cmd: vk::CommandBuffer,
        layout: vk::PipelineLayout,
        poses: vk::DescriptorSet,
    ) {
        match self {
            BladeDispatch::Stored { pipeline, blades } => {
                super::bind_blade_compute(ctx, cmd, (layout, *pipeline), poses);
                // SAFETY: cmd is recording outside a rendering instance; both sets and the pipeline are bound.
                unsafe { ctx.device.raw.cmd_dispatch(cmd, blades.div_ceil(gpu::POSE_GROUP), 1, 1) };
            }
            BladeDispatch::Buckets { buckets, .. } => {
                super::bind_blade_sets(ctx, cmd, layout, poses);
                buckets.record(ctx.device, cmd);
            }
        }
    }

    /// Destroy the pipelines.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        match self {
            BladeDispatch::Stored { pipeline, .. } => {
                crate::vk::live::destroyed(pipeline);
                // SAFETY: per the contract.
                unsafe { device.raw.destroy_pipeline(pipeline, None) };
            }
            // SAFETY: per the contract.
            BladeDispatch::Buckets { buckets, .. } => unsafe { buckets.destroy(device) },
        }
    }
}

impl crate::vk::Destroy for BladeDispatch {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { BladeDispatch::destroy(self, device) };
    }
}
