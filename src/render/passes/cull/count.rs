//! Cull step 2 (`shaders/cull/cull_count.comp`): one workgroup per ring slot the tiles pass listed
//! (its indirect dispatch) runs the tile tests again and the blade tests, and writes the slot's
//! counts per LOD bucket and after each test, and each candidate's verdict. Reads the scene and
//! the tiles pass's list and room, writes the slot counts and the verdicts.

use std::rc::Rc;

use super::{CullSetup, CullStep, Groups};
use crate::error::Result;
use crate::render::recording::PassSet;
use crate::render::scene_gpu::SceneGpu;

use crate::vk::{Access, Device};

/// The counting dispatch, one workgroup per listed ring slot.
pub fn pass(device: &Device, setup: &CullSetup, scene: &SceneGpu, set: &Rc<PassSet>) -> Result<CullStep> {
    let read = Access::ComputeShaderRead;
    let uses = vec![
        (scene.tiles.raw, read),
        (scene.depth_pyramid.raw, device.profile.compute_fetch()),
        (scene.blades.raw, device.profile.compute_fetch()),
        // The roots sit on the ground, its normal under the tile; its cover thins them.
        (scene.ground.texels.raw, device.profile.compute_fetch()),
        (scene.ground.cover.0.raw, device.profile.compute_fetch()),
        (scene.slot_counts.raw, Access::ComputeShaderWrite),
        (scene.cull_results.raw, Access::ComputeShaderWrite),
        // The listed slots, their room and the dispatch over them.
        (scene.cull_alloc.raw, read),
        (scene.cull_alloc.raw, Access::IndirectCommandRead),
    ];
    let groups = Groups::Indirect(scene.cull_alloc.raw, 0);
    CullStep::new(device, ("cull count", setup.count_shader.code(device.profile)), (setup, set), uses, groups)
}
