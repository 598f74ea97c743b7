//! The per-blade compute passes after the cull (blade poses, blade levels) as one indirect
//! dispatch per LOD bucket, each with its pipeline specialised for the bucket's segments
//! (`SEGMENTS`): a bucket's blades then write the levels its strip reads and no more, with no
//! loop or branch on a segment count that varies across the SIMD lanes (`shaders/blades/visible_buckets.glsl`).
//! The cull's scan writes each bucket's dispatch at `BUCKET_DISPATCH_WORD` of its `draws`; an
//! empty bucket dispatches no workgroup.

use ash::vk;

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::Declaration;
use crate::render::recording::{PassSet, SceneSets};
use crate::render::specialization::Specialization;
use crate::scene::alpha;
use crate::vk::descriptor::Resource;
use crate::vk::{pipeline, Access, Buffer, Device, Guard};

/// The own set (`SET_PASS`) of a per-blade pass after the cull, `name` over `spirv`: the cull's
/// `Draws` (`shaders/blades/visible_buckets.glsl`), given by name. Its pipelines are built on the
/// set's layout.
pub fn draws_set(device: &Device, name: &str, spirv: &[u8], sets: &SceneSets, draws: &Buffer) -> Result<PassSet> {
    let shaders = [(name, spirv)];
    PassSet::new(device, &sets.desc(name, &shaders), |_| vec![("Draws", Resource::Buffer(draws.descriptor()))])
}

/// The specialization constants of a LOD bucket's pipelines (this module's and the blade pass's
/// draws): the scene's `constants` with `SEGMENTS` the bucket's `segments`, its strip's
/// outline scales (`STRIP_AREA`, `STRIP_L6`) and `FLAG_CULLED`.
pub fn bucket_constants(constants: &Specialization, segments: u32) -> Specialization {
    Specialization {
        segments,
        strip_area: alpha::strip_area_scale(segments).to_bits(),
        strip_l6: alpha::strip_l6_scale(segments, constants.model_segments).to_bits(),
        flags: constants.flags | gpu::FLAG_CULLED,
        ..*constants
    }
}

/// One compute pipeline per LOD bucket (and per bucket of a further draw class the response
/// poses), and the `draws` buffer their dispatches come from.
pub struct BucketDispatch {
    /// Per bucket dispatched: its pipeline, and its index in the cull's bucket space.
    pipelines: Vec<vk::Pipeline>,
    buckets: Vec<u32>,
    draws: vk::Buffer,
}

impl BucketDispatch {
    /// Build `spirv` once per bucket of `buckets` (segments each) on `layout`, from
    /// `bucket_constants` of `constants`; and once per bucket of `posed` (a further class's
    /// bucket and the segments its entries are posed with, `DrawClass::posed`), specialised with
    /// `FLAG_POSE_CLASS` and the bucket as `LOD_BUCKET` (`shaders/blades/visible_buckets.glsl`).
    pub fn new(
        device: &Device,
        name: &str,
        spirv: &[u8],
        layout: vk::PipelineLayout,
        (constants, buckets, posed): (&Specialization, &[u32], &[(u32, u32)]),
        draws: vk::Buffer,
    ) -> Result<Self> {
        // The pipelines built so far were never recorded.
        let mut pipelines = Guard::new(device, Vec::with_capacity(buckets.len() + posed.len()));
        for (b, &segments) in buckets.iter().enumerate() {
            let constants = bucket_constants(constants, segments);
            let label = format!("{name}, LOD bucket {b} ({segments} segments)");
            pipelines.push(pipeline::compute(device, &label, spirv, layout, &constants.named())?);
        }
        for &(bucket, segments) in posed {
            let mut constants = bucket_constants(constants, segments);
            constants.flags |= gpu::FLAG_POSE_CLASS;
            constants.lod_bucket = bucket;
            let label = format!("{name}, class bucket {bucket} ({segments} segments)");
            pipelines.push(pipeline::compute(device, &label, spirv, layout, &constants.named())?);
        }
        let buckets = (0..buckets.len() as u32).chain(posed.iter().map(|p| p.0)).collect();
        Ok(Self { pipelines: pipelines.take(), buckets, draws })
    }

    /// Add what the dispatches read to a pass's declaration: `draws`, by the shaders (the buckets'
    /// ranges) and as the indirect dispatches.
    pub fn declare(&self, declaration: Declaration) -> Declaration {
        declaration.buffer(self.draws, Access::ComputeShaderRead).buffer(self.draws, Access::IndirectCommandRead)
    }

    /// Record each bucket's dispatch; the sets are bound.
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer) {
        for (&b, &pipeline) in self.buckets.iter().zip(&self.pipelines) {
            let word = gpu::BUCKET_DISPATCH_WORD + 3 * b;
            // SAFETY: cmd is recording outside a rendering instance; the pipeline uses the bound
            // layout, and `draws` holds the scan's dispatch at `word`.
            unsafe {
                device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
                device.raw.cmd_dispatch_indirect(cmd, self.draws, 4 * u64::from(word));
            }
        }
    }

    /// Destroy the pipelines.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        for pipeline in self.pipelines {
            crate::vk::live::destroyed(pipeline);
            // SAFETY: per the contract.
            unsafe { device.raw.destroy_pipeline(pipeline, None) };
        }
    }
}
