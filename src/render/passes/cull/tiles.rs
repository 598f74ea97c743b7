//! Cull step 1 (`shaders/cull/cull_tiles.comp`): one workgroup runs the tile tests of every ring slot
//! (frustum, distance, occlusion, the density LOD's prefix), writes the counts of the slots
//! without candidates, and lists the others near to far with the count pass's indirect dispatch
//! and, in a block field, each one's room for verdicts (a prefix sum: no atomics, no counter).
//! Reads the scene, writes the slot counts and `cull_alloc`.

use std::rc::Rc;

use super::{CullSetup, CullStep, Groups};
use crate::error::Result;
use crate::render::recording::PassSet;
use crate::render::scene_gpu::SceneGpu;
use crate::vk::{Access, Device};

/// The tile tests' dispatch: one workgroup.
pub fn pass(device: &Device, setup: &CullSetup, scene: &SceneGpu, set: &Rc<PassSet>) -> Result<CullStep> {
    let read = Access::ComputeShaderRead;
    let uses = vec![
        (scene.tiles.raw, read),
        (scene.depth_pyramid.raw, device.profile.compute_fetch()),
        // The ground's normal under each tile, and its cover.
        (scene.ground.texels.raw, device.profile.compute_fetch()),
        (scene.ground.cover.0.raw, device.profile.compute_fetch()),
        (scene.slot_counts.raw, Access::ComputeShaderWrite),
        // Written, then read back by the invocation that wrote it.
        (scene.cull_alloc.raw, read),
        (scene.cull_alloc.raw, Access::ComputeShaderWrite),
    ];
    CullStep::new(device, ("cull tiles", setup.tiles_shader.code(device.profile)), (setup, set), uses, Groups::One)
}
