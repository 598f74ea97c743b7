//! Cull step 3 (`shaders/cull/cull_scan.comp`): one workgroup turns the slot counts into offsets (a
//! prefix sum in slot order, near to far), writes one indirect draw per LOD bucket, the pose and
//! levels passes' indirect dispatch, the list of slots that draw with the emit pass's indirect
//! dispatch over them, the blade class's per-tile rows (`render::draw_rows`), and the frame's
//! counts into the frame's host-visible buffer (read after its fence). Every word it writes is
//! written whole each frame: there is no counter to clear.

use std::rc::Rc;

use super::{CullSetup, CullStep, Groups};
use crate::error::Result;
use crate::render::recording::PassSet;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{Access, Device};

/// The scan dispatch, one workgroup; it writes each frame's host-visible counts.
pub fn pass(device: &Device, setup: &CullSetup, scene: &SceneGpu, set: &Rc<PassSet>) -> Result<CullStep> {
    let uses = vec![
        (scene.slot_counts.raw, Access::ComputeShaderRead),
        (scene.slot_counts.raw, Access::ComputeShaderWrite),
        (scene.draws.raw, Access::ComputeShaderWrite),
        // The slots without room for their verdicts, counted (`STAT_NO_ROOM`).
        (scene.cull_alloc.raw, Access::ComputeShaderRead),
        // The padding of each bucket's last instance.
        (scene.visible.raw, Access::ComputeShaderWrite),
        // The blade class's per-tile rows, when it draws a row per tile (`draw_rows`).
        (scene.tile_rows.raw, Access::ComputeShaderWrite),
    ];
    let mut step = CullStep::new(
        device,
        ("cull scan", shaders::CULL_SCAN_COMP.code(device.profile)),
        (setup, set),
        uses,
        Groups::One,
    )?;
    // Each frame's host-visible counts, by frame slot.
    step.per_frame = setup.frame_stats.clone();
    Ok(step)
}
