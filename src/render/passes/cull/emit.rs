//! Cull step 4 (`shaders/cull/cull_emit.comp`): one workgroup per ring slot that draws (the scan
//! lists them and writes the indirect dispatch) reads the count pass's
//! verdicts and writes each drawn blade (its index and its LOD fade and widening) into the
//! visible list at its bucket's base plus its slot's offset plus its rank in the slot: the same
//! list on every run and thread count, buckets then slots near to far.

use std::rc::Rc;

use super::{CullSetup, CullStep, Groups};
use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::recording::PassSet;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{Access, Device};

/// The emitting dispatch, one workgroup per ring slot that draws.
pub fn pass(device: &Device, setup: &CullSetup, scene: &SceneGpu, set: &Rc<PassSet>) -> Result<CullStep> {
    let read = Access::ComputeShaderRead;
    let uses = vec![
        // A stored field's tiles (where a slot's blades start); the tile tests' result is the
        // tiles pass's, in `cull_alloc`.
        (scene.tiles.raw, read),
        // A block field's roots on the ground (the slot's blades).
        (scene.ground.texels.raw, device.profile.compute_fetch()),
        // The count pass's verdicts, fetched as texels in the lavapipe profile.
        (scene.cull_results.raw, device.profile.compute_fetch()),
        (scene.cull_alloc.raw, read),
        (scene.slot_counts.raw, read),
        (scene.draws.raw, read),
        (scene.draws.raw, Access::IndirectCommandRead),
        (scene.visible.raw, Access::ComputeShaderWrite),
    ];
    let groups = Groups::Indirect(scene.draws.raw, gpu::EMIT_DISPATCH_WORD);
    let step =
        CullStep::new(device, ("cull emit", shaders::CULL_EMIT_COMP.code(device.profile)), (setup, set), uses, groups)?;
    Ok(step)
}
