//! The descriptor-set and pipeline layouts the scene pipelines share (`SET_SCENE` for the scene
//! and one frame's uniforms and forces, `SET_POSES` for the pose records a blade response
//! writes), and each frame in flight's uniforms and scene set (`SceneFrame`).
//!
//! Both set layouts come from the shaders themselves: each is the union of what the scene shaders
//! (`render::shaders::SCENE`, every library shader that reads a set-0 declaration) bind in
//! that set, reflected from their SPIR-V for the device's backend profile (`vk::reflect`). A
//! resource is declared once, in GLSL. Set 0's are declared by their owners' headers as
//! `layout(SCENE(Name), …)` and numbered by `build.rs` (`build/scene_set.rs`); each owner gives
//! its resources by that name (`SceneGpu::write_descriptors`, `frame_resources`,
//! `FrameForces::scene_resources`), and no set-0 number appears in Rust. Set 1 is numbered in
//! `shared.glsl` and given by number (`PoseRecords::new`). A blade response's own resources are
//! in the own sets (`SET_PASS`) of the passes that read them, given by name.

use ash::vk;

use crate::error::Result;
use crate::render::frame::{FrameUniforms, PerFrame};
use crate::render::gpu_constants as gpu;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::submission;
use crate::vk::descriptor::{self, Binding, Resource, SetLayout};
use crate::vk::profile::Profile;
use crate::vk::{pipeline, reflect, Buffer, BufferDesc, Destroy, Device, Guard};

/// The descriptor-set layouts of the scene pipelines (`SET_SCENE`, `SET_POSES`), the
/// pipeline layout they share, and the pool of the per-frame scene sets.
#[derive(Default)]
pub struct SceneLayouts {
    /// `SET_SCENE`.
    pub scene: SetLayout,
    /// `SET_POSES`.
    pub poses: SetLayout,
    /// Both sets and the push-constant range.
    pub pipeline_layout: vk::PipelineLayout,
    /// The per-frame scene sets' pool.
    pub pool: vk::DescriptorPool,
}

/// A reflected set's bindings, each with its name (`vk::reflect::merge_named`).
pub type NamedBindings = Vec<(Binding, String)>;

/// The bindings of sets `SET_SCENE` (with their names, as they are written) and `SET_POSES`,
/// as the scene shaders of `profile` use them (reflected). Set `SET_PASS` is each pass's own
/// (`recording::PassSet`), numbered by the pass alone: not merged here.
pub fn scene_bindings(profile: Profile) -> Result<(NamedBindings, Vec<Binding>)> {
    let code: Vec<(&str, &[u8])> = shaders::SCENE.iter().map(|s| (s.path, s.code(profile))).collect();
    let mut sets = reflect::merge_sets(&code, &|set| set != gpu::SET_PASS)?;
    if let Some(&other) = sets.keys().find(|&&set| set != gpu::SET_SCENE && set != gpu::SET_POSES) {
        return Err(crate::error::Error::Internal(format!("a scene shader binds set {other}, not the scene's")));
    }
    let poses = sets.remove(&gpu::SET_POSES).unwrap_or_default().into_iter().map(|(b, _)| b).collect();
    Ok((sets.remove(&gpu::SET_SCENE).unwrap_or_default(), poses))
}

/// The frame's uniforms as set 0 names them (`shaders/common/frame.glsl`): the uniform block
/// `Frame` and, for the lavapipe profile's cull, its storage twin `FrameStorage`.
pub fn frame_resources(block: Resource) -> [(&'static str, Resource); 2] {
    [("Frame", block.clone()), ("FrameStorage", block)]
}

/// The layouts of `SET_SCENE` and `SET_POSES` and the scene pipeline layout (the pool comes
/// with the frames).
pub fn scene_layouts(device: &Device) -> Result<SceneLayouts> {
    let (scene, poses) = scene_bindings(device.profile)?;
    let numbered: Vec<Binding> = scene.iter().map(|(b, _)| *b).collect();
    descriptor::check_storage_buffers(device, "the scene pipelines", &[&numbered, &poses])?;
    let mut layouts = crate::vk::guard::empty::<SceneLayouts>(device);
    {
        layouts.scene = SetLayout::with_names(device, "scene set layout", scene)?;
        layouts.poses = SetLayout::new(device, "pose set layout", poses)?;
        // Sets in `SET_SCENE`, `SET_POSES` order.
        layouts.pipeline_layout = pipeline::layout(
            device,
            "scene pipeline layout",
            &[layouts.scene.raw, layouts.poses.raw],
            &[submission::push_constant_range()],
        )?;
    }
    Ok(layouts.take())
}

impl Destroy for SceneLayouts {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { SceneLayouts::destroy(&self, device) };
    }
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
            SetLayout::destroy(&self.poses, device);
            SetLayout::destroy(&self.scene, device);
        }
    }
}

/// The uniforms' and sets' part of one frame in flight (`frame::PerFrame`): the frame's
/// uniforms and its set 0, which points at them, at the scene and at the frame's forces and cull
/// counts.
pub struct SceneFrame {
    /// Host-visible `FrameUniforms`.
    pub uniforms: Buffer,
    /// Set 0 of the scene passes (it goes with `SceneLayouts::pool`).
    pub set: vk::DescriptorSet,
}

impl Destroy for SceneFrame {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract (the set goes with its pool).
        unsafe { self.uniforms.destroy(device) };
    }
}

/// The uniforms and scene sets of `slots` frames in flight, each set pointed at the scene, at its
/// frame's uniforms and at what `others(slot)` gives by name: the other subsystems' parts of
/// that frame (its forces).
pub fn scene_frames(
    device: &Device,
    layouts: &mut SceneLayouts,
    scene: &SceneGpu,
    slots: usize,
    others: impl Fn(usize) -> Vec<(&'static str, Resource)>,
) -> Result<PerFrame<SceneFrame>> {
    let (pool, sets) = layouts.scene.allocate(device, "scene sets", slots as u32)?;
    layouts.pool = pool;
    // A storage buffer too: the lavapipe profile's cull reads it through `FrameStorage`.
    let usage = vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER;
    let size = std::mem::size_of::<FrameUniforms>() as u64;
    PerFrame::new(device, sets.len(), |slot| {
        let uniforms = Buffer::new(device, &BufferDesc::upload(&format!("frame {slot} uniforms"), size, usage))?;
        let frame = Guard::new(device, SceneFrame { uniforms, set: sets[slot] });
        let mut own = others(slot);
        own.extend(frame_resources(Resource::Buffer(frame.uniforms.descriptor())));
        scene.write_descriptors(device, &layouts.scene, frame.set, &own)?;
        Ok(frame.take())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::DescriptorType as T;

    fn kind(bindings: &[Binding], binding: u32) -> Option<T> {
        bindings.iter().find(|b| b.binding == binding).map(|b| b.kind)
    }

    /// The binding named `name` in a reflected set.
    fn named<'a>(set: &'a [(Binding, String)], name: &str) -> Option<&'a Binding> {
        set.iter().find(|(_, n)| n == name).map(|(b, _)| b)
    }

    #[test]
    fn the_lavapipe_profile_binds_the_twins_and_the_generic_one_each_resource_once() {
        let (scene, animation) = scene_bindings(Profile::Lavapipe).unwrap();
        assert_eq!(named(&scene, "FrameStorage").map(|b| b.kind), Some(T::STORAGE_BUFFER));
        assert_eq!(named(&scene, "blade_texels").map(|b| b.kind), Some(T::UNIFORM_TEXEL_BUFFER));
        assert!(named(&scene, "Blades").is_none());
        assert_eq!(kind(&animation, gpu::BINDING_LEVEL_TEXELS), Some(T::UNIFORM_TEXEL_BUFFER));

        let (scene, animation) = scene_bindings(Profile::Generic).unwrap();
        let texel = |b: &&Binding| b.kind == T::UNIFORM_TEXEL_BUFFER;
        let numbered: Vec<Binding> = scene.iter().map(|(b, _)| *b).collect();
        assert_eq!(numbered.iter().chain(&animation).filter(texel).count(), 0, "{scene:?} {animation:?}");
        assert!(named(&scene, "FrameStorage").is_none());
        for name in ["Blades", "Visible", "GroundTexels"] {
            assert_eq!(named(&scene, name).map(|b| b.kind), Some(T::STORAGE_BUFFER), "{name}");
        }
        assert_eq!(kind(&animation, gpu::BINDING_LEVELS), Some(T::STORAGE_BUFFER));
        // The frame's uniforms reach every stage in both.
        let frame = named(&scene, "Frame").unwrap();
        assert_eq!(frame.kind, T::UNIFORM_BUFFER);
        assert!(frame
            .stages
            .contains(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE));
    }

    #[test]
    fn in_the_lavapipe_profile_the_cull_reads_the_frame_through_storage() {
        // profile.glsl's rule: a value that decides control flow is read through a storage
        // binding (lavapipe before Mesa 23.1 compiles and keeps a variant per uniform value).
        for shader in
            [shaders::CULL_TILES_COMP, shaders::CULL_COUNT_COMP, shaders::CULL_SCAN_COMP, shaders::CULL_EMIT_COMP]
        {
            let lavapipe = reflect::reflect(shader.path, shader.code(Profile::Lavapipe)).unwrap().descriptors;
            let frame = lavapipe.iter().find(|d| d.name == "FrameStorage" && d.set == gpu::SET_SCENE);
            assert_eq!(frame.map(|d| d.kind), Some(T::STORAGE_BUFFER), "{}", shader.path);
            let generic = reflect::reflect(shader.path, shader.code(Profile::Generic)).unwrap().descriptors;
            assert!(!generic.iter().any(|d| d.name == "FrameStorage"), "{}", shader.path);
        }
    }

    #[test]
    fn every_scene_shader_is_found_and_binds_only_the_scene_sets() {
        let paths: Vec<&str> = shaders::SCENE.iter().map(|s| s.path).collect();
        for expected in
            ["blades/blade.vert", "blades/blade.frag.coverage", "cull/cull_count.comp", "terrain/relief_fill.comp"]
        {
            assert!(paths.contains(&expected), "{expected} not in {paths:?}");
        }
        assert!(!paths.contains(&"depth_pyramid/hiz.comp"), "hiz.comp has a set of its own");
        for profile in [Profile::Lavapipe, Profile::Generic] {
            scene_bindings(profile).unwrap();
        }
    }
}

/// `vk::reflect` on the library's own shaders (here, above `vk`, where the shaders are).
#[cfg(test)]
mod reflect_tests {
    use super::*;
    use crate::render::gpu_constants as gpu;
    use crate::vk::reflect::{merge, reflect};

    fn descriptors(spirv: &[u8]) -> Vec<(u32, u32, vk::DescriptorType)> {
        reflect("test", spirv).unwrap().descriptors.iter().map(|d| (d.set, d.binding, d.kind)).collect()
    }

    #[test]
    fn a_compute_shader_of_its_own_set() {
        // hiz.comp: `sampler2D depth` at 0, the pyramid's storage buffer at 1, the push constants
        // not a descriptor.
        let reflection = reflect("hiz", shaders::HIZ_COMP.code(Profile::Lavapipe)).unwrap();
        assert_eq!(reflection.stage, vk::ShaderStageFlags::COMPUTE);
        assert_eq!(
            descriptors(shaders::HIZ_COMP.code(Profile::Lavapipe)),
            [(0, 0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER), (0, 1, vk::DescriptorType::STORAGE_BUFFER)]
        );
    }

    #[test]
    fn only_what_the_entry_point_uses_counts() {
        // floor.vert includes bindings.glsl (two sets of declarations) and reads the frame's
        // uniforms alone.
        let floor = reflect("floor", shaders::FLOOR_VERT.code(Profile::Lavapipe)).unwrap().descriptors;
        let floor: Vec<(u32, vk::DescriptorType, &str)> =
            floor.iter().map(|d| (d.set, d.kind, d.name.as_str())).collect();
        assert_eq!(floor, [(0, vk::DescriptorType::UNIFORM_BUFFER, "Frame")]);
        assert_eq!(
            reflect("floor", shaders::FLOOR_FRAG.code(Profile::Lavapipe)).unwrap().stage,
            vk::ShaderStageFlags::FRAGMENT
        );
    }

    #[test]
    fn stages_merge_and_conflicts_are_named() {
        let vert = shaders::BLADE_VERT.code(Profile::Lavapipe);
        let frag = shaders::BLADE_FRAG.code(Profile::Lavapipe);
        let sets = crate::vk::reflect::merge_named(&[("blade.vert", vert), ("blade.frag", frag)]).unwrap();
        let frame = sets[&0].iter().find(|(_, n)| n == "Frame").map(|(b, _)| b).unwrap();
        assert_eq!(frame.stages, vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT);
        // hiz.comp numbers a set 0 of its own (a sampler and a buffer at 0 and 1), which the
        // generic blade shader's set 0 (build.rs's numbers) does not match.
        let (vert, hiz) = (shaders::BLADE_VERT.code(Profile::Generic), shaders::HIZ_COMP.code(Profile::Generic));
        let error = merge(&[("blade.vert", vert), ("hiz.comp", hiz)]).unwrap_err().to_string();
        assert!(error.contains("set 0 binding") && error.contains("blade.vert binds"), "{error}");
    }

    #[test]
    fn descriptors_carry_the_names_their_glsl_gives_them() {
        // hiz.comp: an opaque variable by its own name, a block by its interface name.
        let hiz = reflect("hiz", shaders::HIZ_COMP.code(Profile::Lavapipe)).unwrap().descriptors;
        let names: Vec<&str> = hiz.iter().map(|d| d.name.as_str()).collect();
        assert_eq!(names, ["depth", "Pyramid"]);
        // The cull's own set (SET_PASS) is numbered in cull/cull.glsl and holds the cull's
        // resources, by name; set 0 keeps none of them.
        for profile in [Profile::Lavapipe, Profile::Generic] {
            let sets =
                crate::vk::reflect::merge_named(&[("cull count", shaders::CULL_COUNT_COMP.code(profile))]).unwrap();
            let own: Vec<&str> = sets[&gpu::SET_PASS].iter().map(|(_, n)| n.as_str()).collect();
            for name in ["SlotCounts", "CullResults", "CullAlloc"] {
                assert!(own.contains(&name), "{profile:?}: {own:?}");
            }
            let pyramid = if profile == Profile::Lavapipe { "pyramid_texels" } else { "Pyramid" };
            assert!(own.contains(&pyramid), "{profile:?}: {own:?}");
            let (scene, _) = scene_bindings(profile).unwrap();
            // The ground's two (its texels and its cover, each with its texel view) among them.
            assert!(scene.len() <= 15, "set 0 holds the scene and the frame only: {scene:?}");
        }
        // One binding, two names: two resources, refused.
        let error = merge(&[
            ("hiz.comp", shaders::HIZ_COMP.code(Profile::Generic)),
            ("resolve.frag", shaders::RESOLVE_FRAG.code(Profile::Generic)),
        ])
        .unwrap_err();
        assert!(error.to_string().contains("set 0 binding 0"), "{error}");
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        assert!(reflect("empty", &[]).is_err());
        assert!(reflect("text", b"#version 460\n void main() {}\n").is_err());
        let mut truncated = shaders::FLOOR_VERT.code(Profile::Lavapipe).to_vec();
        truncated.truncate(40);
        assert!(reflect("truncated", &truncated).is_err());
    }
}
