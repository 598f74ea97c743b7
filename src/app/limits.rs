//! What a device's limits and meadow's own admit, checked before anything is allocated: the
//! picture size, its multisampling and the blade count against the device's image, buffer and
//! memory limits, a scene's cluster corners and keyframe tables, and `--budget-ms` against the
//! queue's timestamps. Shared by `render`, the viewer (also when a control rebuilds it) and
//! `bench`; each refusal is one line naming the flag.

use ash::vk;

use crate::error::{Error, Result};
use crate::render::animation::{AnimationSettings, KeyframeTexture, KeyframeUniforms};
use crate::render::gpu_constants as gpu;
use crate::render::msaa::Msaa;
use crate::render::scene_gpu::{FIELD_VERDICTS, FIELD_VISIBLE};
use crate::render::target::offscreen_bytes;
use crate::scene::BladeInstance;
use crate::vk::device::format_bytes;
use crate::vk::Device;

/// Most cluster corners meadow computes forces for each frame.
pub const MAX_CORNERS: u32 = 1 << 20;

/// `--budget-ms` steers by the measured GPU time: refused on a queue without timestamps.
pub fn check_timestamps_for_budget(device: &Device, budget_ms: Option<f32>) -> Result<()> {
    match budget_ms.is_some() && !device.has_timestamps() {
        true => Err(Error::Environment(format!(
            "--budget-ms needs GPU timestamps, which {} cannot write on its queue",
            device.info.name
        ))),
        false => Ok(()),
    }
}

/// Check the picture size, its multisampling and the blade count against the device before
/// allocating anything; the memory budget counts the scene and every target of a frame (the
/// offscreen pair and its readback, and the multisampled pair: `msaa::target_bytes`, or with
/// `linear` and no multisampling `--fade blend`'s linear pair: `msaa::linear_bytes`).
pub fn check_limits(
    device: &Device,
    blades: u32,
    (size, msaa, linear): ((u32, u32), Msaa, bool),
    terrain_cells: u32,
) -> Result<()> {
    let limits = device.limits();
    let max_dim = limits.max_image_dimension2_d.min(limits.max_framebuffer_width).min(limits.max_framebuffer_height);
    if size.0 > max_dim || size.1 > max_dim {
        return Err(Error::bad_input(format!(
            "--size {}x{} exceeds the device's maxImageDimension2D/maxFramebufferWidth of {max_dim}",
            size.0, size.1
        )));
    }
    let blade_bytes = u64::from(blades) * std::mem::size_of::<BladeInstance>() as u64;
    let max_range = u64::from(limits.max_storage_buffer_range);
    if blade_bytes > max_range {
        return Err(Error::bad_input(format!(
            "--blades {blades} needs a {} blade buffer, over the device's maxStorageBufferRange of {} (at most {} blades)",
            format_bytes(blade_bytes),
            format_bytes(max_range),
            max_range / std::mem::size_of::<BladeInstance>() as u64
        )));
    }
    // The scene's shaders read the blades as two texels each, a block field's visible list and
    // verdicts and the depth pyramid as one per entry (`vk::buffer::TexelView`); a stored field's
    // verdicts are one per blade.
    let max_texels = u64::from(limits.max_texel_buffer_elements);
    let fixed = u64::from(gpu::PYRAMID_FLOATS).max(u64::from(FIELD_VISIBLE)).max(u64::from(FIELD_VERDICTS));
    if fixed > max_texels {
        return Err(Error::bad_input(format!(
            "the device's maxTexelBufferElements of {max_texels} is below the {fixed} texels meadow's cull reads"
        )));
    }
    if 2 * u64::from(blades) > max_texels {
        return Err(Error::bad_input(format!(
            "--blades {blades} needs {} blade texels, over the device's maxTexelBufferElements of {max_texels} (at most {} blades)",
            2 * u64::from(blades),
            max_texels / 2
        )));
    }
    let extent = vk::Extent2D { width: size.0, height: size.1 };
    crate::render::msaa::check(device, &msaa)?;
    let total = crate::render::scene_gpu::SceneGpu::memory_bytes(u64::from(blades), u64::from(terrain_cells))
        + frame_target_bytes(extent, &msaa, linear);
    let msaa_said = match (msaa.enabled(), linear) {
        (true, _) => format!(" with --msaa {}", msaa.samples),
        (false, true) => " with --fade blend's linear scene".to_owned(),
        (false, false) => String::new(),
    };
    device.check_budget(total, &format!("rendering {blades} blades at {}x{}{msaa_said}", size.0, size.1))?;
    crate::render::msaa::check_target(device, extent, &msaa, &format!("--size {}x{}", size.0, size.1))
}

/// Bytes of device memory a frame's targets of `extent` take: the offscreen colour, depth and
/// readback, and the multisampled colour and depth with `msaa`, or the linear pair when the scene
/// is `linear` without multisampling (`RenderSettings::linear_scene`: `--fade blend`).
pub fn frame_target_bytes(extent: vk::Extent2D, msaa: &Msaa, linear: bool) -> u64 {
    let linear_pair = if linear && !msaa.enabled() { crate::render::msaa::linear_bytes(extent) } else { 0 };
    offscreen_bytes(extent) + crate::render::msaa::target_bytes(extent, msaa) + linear_pair
}

/// Every check of a scene against the device and meadow's limits, before anything is allocated:
/// shared by `render`, the viewer (also when a control rebuilds it) and `bench`. `culled`: the
/// cull draws the blades (`--eval blade` then needs records for the drawn blades only); `linear`:
/// the scene is drawn into the linear intermediate (`RenderSettings::linear_scene`).
pub fn check_scene(
    device: &Device,
    blades: u32,
    segments: u32,
    size: (u32, u32),
    animation: &AnimationSettings,
    floor: bool,
    (culled, msaa, linear): (bool, Msaa, bool),
) -> Result<()> {
    use crate::render::animation::{Mode, MAX_COLLIDERS, MAX_SOURCES};
    let field_m = crate::scene::blades::field_size(blades);
    check_limits(device, blades, (size, msaa, linear), crate::scene::terrain::Terrain::cells_for(field_m))?;
    KeyframeTexture::check_limits(device, animation.poses)?;
    if floor {
        // Pre-expanded vertices (12 bytes) and triangle-list indices (4 bytes), plus their
        // staging copies during the upload (`passes::floor::expand`).
        let per_blade = 12 * u64::from(2 * segments + 2) + 4 * 6 * u64::from(segments);
        device.check_budget(2 * per_blade * u64::from(blades), &format!("--mode floor with {blades} blades"))?;
    }
    if let Some(writer) = animation.pose_writer() {
        // At most one storage buffer of records (`scene_gpu::pose_records`): with the cull, one
        // per drawn blade (the cull keeps at most that many); brute force needs one per blade.
        crate::render::settings::check_pose_records(device, animation, (blades, segments), culled, floor)?;
        let most = crate::render::scene_gpu::most_pose_records(device, segments);
        let records = u64::from(blades).min(most) as u32;
        let groups = records.div_ceil(crate::render::gpu_constants::POSE_GROUP);
        let max = device.limits().max_compute_work_group_count[0];
        if groups > max {
            return Err(Error::bad_input(format!(
                "{writer} with {blades} blades needs {groups} workgroups, over the device's maxComputeWorkGroupCount[0] of {max}"
            )));
        }
        let mut bytes = crate::render::scene_gpu::pose_bytes(records, segments);
        if culled {
            // And the drawn blades' placed levels (`PoseRecords`).
            let levels = crate::render::scene_gpu::level_records(device, records, segments);
            bytes += crate::render::scene_gpu::level_bytes(levels, segments);
        }
        device.check_budget(bytes, &format!("{writer} with {blades} blades x {segments} segments"))?;
    }
    // Sources and colliders have room of their own in the emitter buffers.
    let (sources, colliders) = (animation.wind.sources.len(), animation.wind.colliders.len());
    if sources > MAX_SOURCES {
        return Err(Error::bad_input(format!("{sources} wind sources: at most {MAX_SOURCES}")));
    }
    if colliders > MAX_COLLIDERS {
        return Err(Error::bad_input(format!("{colliders} colliders: at most {MAX_COLLIDERS}")));
    }
    // The pressed map sweeps the colliders and the cuts each frame (`render::animation::pressed`).
    let (sweeps, most) =
        (animation.wind.colliders.len() + animation.wind.cuts.len(), crate::render::animation::pressed::MAX_SWEEPS);
    if sweeps > most {
        return Err(Error::bad_input(format!("{sweeps} colliders and cuts: at most {most} together")));
    }
    let (calm, most) = (animation.wind.calm.len(), crate::render::wind::analytic::MAX_CALM_AREAS);
    if calm > most {
        return Err(Error::bad_input(format!("{calm} calm areas: at most {most}")));
    }
    if animation.mode == Mode::Uniform {
        let records = match animation.representation {
            crate::keyframes::Representation::Vertex => segments,
            crate::keyframes::Representation::Curve => 3,
        };
        KeyframeUniforms::check_limits(device, animation.poses, records)?;
    }
    let corners = crate::scene::clusters::ClusterGrid::new(field_m, animation.cluster_size).corner_count();
    if corners > MAX_CORNERS {
        return Err(Error::bad_input(format!(
            "--cluster-size {} m makes {corners} cluster corners on a {field_m:.1} m field, more than the {MAX_CORNERS} the CPU updates per frame",
            animation.cluster_size
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_scene_counts_its_pair_unless_multisampled() {
        // `--fade blend` without `--msaa` adds the single-sampled linear pair; with `--msaa` the
        // multisampled pair is that scene already.
        let extent = vk::Extent2D { width: 1280, height: 720 };
        let plain = Msaa::default();
        let linear = crate::render::msaa::linear_bytes(extent);
        assert_eq!(frame_target_bytes(extent, &plain, true), frame_target_bytes(extent, &plain, false) + linear);
        assert_eq!(linear, 1280 * 720 * 12);
        let four = Msaa { samples: 4, alpha_to_coverage: true };
        assert_eq!(frame_target_bytes(extent, &four, true), frame_target_bytes(extent, &four, false));
    }
}
