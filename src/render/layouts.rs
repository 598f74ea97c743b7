//! The descriptor-set and pipeline layouts the scene pipelines share (`SET_SCENE` for the scene
//! and one frame's uniforms and forces, `SET_ANIMATION` for the animation model), and the frames
//! in flight with their scene sets.

use ash::vk;

use crate::error::Result;
use crate::render::animation::{self, model};
use crate::render::frame::Frame;
use crate::render::scene_gpu::SceneGpu;
use crate::render::scene_set;
use crate::render::settings::RenderSettings;
use crate::render::submission;
use crate::vk::{descriptor, pipeline, Device};

/// The descriptor-set layouts of the scene pipelines (`SET_SCENE`, `SET_ANIMATION`), the
/// pipeline layout they share, and the pool of the per-frame scene sets.
#[derive(Default)]
pub struct SceneLayouts {
    /// `SET_SCENE`.
    pub set_layout: vk::DescriptorSetLayout,
    /// `SET_ANIMATION`.
    pub animation_layout: vk::DescriptorSetLayout,
    /// Both sets and the push-constant range.
    pub pipeline_layout: vk::PipelineLayout,
    /// The per-frame scene sets' pool.
    pub pool: vk::DescriptorPool,
}

/// The layouts of `SET_SCENE` and `SET_ANIMATION` and the scene pipeline layout (the pool comes
/// with the frames).
pub fn scene_layouts(device: &Device) -> Result<SceneLayouts> {
    check_storage_buffers(device, &[&scene_set::bindings(), &model::bindings()])?;
    let mut layouts = SceneLayouts::default();
    let built = (|| {
        layouts.set_layout = descriptor::set_layout(device, "scene set layout", &scene_set::bindings())?;
        layouts.animation_layout = descriptor::set_layout(device, "animation set layout", &model::bindings())?;
        // Sets in `SET_SCENE`, `SET_ANIMATION` order.
        layouts.pipeline_layout = pipeline::layout(
            device,
            "scene pipeline layout",
            &[layouts.set_layout, layouts.animation_layout],
            &[submission::push_constant_range()],
        )?;
        Ok(())
    })();
    match built {
        Ok(()) => Ok(layouts),
        Err(e) => {
            // SAFETY: nothing uses them.
            unsafe { layouts.destroy(device) };
            Err(e)
        }
    }
}

/// Refuse a device whose `maxPerStageDescriptorStorageBuffers` is below what one stage of the
/// scene pipelines binds (the cull's compute stage binds the most; the spec's minimum is 4).
fn check_storage_buffers(device: &Device, sets: &[&[descriptor::Binding]]) -> Result<()> {
    use ash::vk::ShaderStageFlags as S;
    let limit = device.limits().max_per_stage_descriptor_storage_buffers;
    for (stage, name) in [(S::VERTEX, "vertex"), (S::FRAGMENT, "fragment"), (S::COMPUTE, "compute")] {
        let used = sets
            .iter()
            .flat_map(|set| set.iter())
            .filter(|b| b.kind == vk::DescriptorType::STORAGE_BUFFER && b.stages.contains(stage))
            .count() as u32;
        if used > limit {
            return Err(crate::error::Error::Environment(format!(
                "{} allows {limit} storage buffers per shader stage; meadow's {name} stage binds {used}",
                device.info.name
            )));
        }
    }
    Ok(())
}

impl SceneLayouts {
    /// # Safety
    /// No pending work may use them; the sets go with the pool.
    pub unsafe fn destroy(&self, device: &Device) {
        // SAFETY: per the contract; destroying null handles is a no-op.
        unsafe {
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            crate::vk::live::destroyed(self.pipeline_layout);
            device.raw.destroy_pipeline_layout(self.pipeline_layout, None);
            crate::vk::live::destroyed(self.animation_layout);
            device.raw.destroy_descriptor_set_layout(self.animation_layout, None);
            crate::vk::live::destroyed(self.set_layout);
            device.raw.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

/// The frames in flight, each with its set 0 pointing at the scene and at its own uniforms.
pub fn build_frames(
    device: &Device,
    layouts: &mut SceneLayouts,
    scene: &SceneGpu,
    settings: &RenderSettings,
) -> Result<Vec<Frame>> {
    let bindings = scene_set::bindings();
    let count = settings.frames_in_flight as u32;
    let (pool, sets) = descriptor::allocate_sets(device, "scene sets", layouts.set_layout, &bindings, count)?;
    layouts.pool = pool;
    let corners = scene.grid.corner_count();
    let emitters = animation::MAX_EMITTERS as u32;
    let mut frames = Vec::with_capacity(sets.len());
    for (index, set) in sets.into_iter().enumerate() {
        match Frame::new(device, index, set, corners, emitters, settings.pipeline_statistics) {
            Ok(frame) => {
                scene.write_descriptors(device, set, &frame);
                frames.push(frame);
            }
            Err(e) => {
                for frame in frames {
                    // SAFETY: never submitted.
                    unsafe { frame.destroy(device) };
                }
                return Err(e);
            }
        }
    }
    Ok(frames)
}
