//! Descriptor set layouts, pools and writes.

use ash::vk;

use crate::error::{Result, VkContext};
use crate::vk::device::Device;

/// One binding of a set layout.
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    /// Binding number in the shader.
    pub binding: u32,
    /// Descriptor type.
    pub kind: vk::DescriptorType,
    /// Stages that read it.
    pub stages: vk::ShaderStageFlags,
}

/// Create a named set layout from bindings (one descriptor each).
pub fn set_layout(device: &Device, name: &str, bindings: &[Binding]) -> Result<vk::DescriptorSetLayout> {
    let raw: Vec<_> = bindings
        .iter()
        .map(|b| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(b.binding)
                .descriptor_type(b.kind)
                .descriptor_count(1)
                .stage_flags(b.stages)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&raw);
    // SAFETY: valid create info.
    let layout = super::live::created(
        unsafe { device.raw.create_descriptor_set_layout(&info, None) }.vk("vkCreateDescriptorSetLayout")?,
    );
    device.set_name(layout, name);
    Ok(layout)
}

/// Create a pool able to hold `sets` sets of `bindings` and allocate them all with `layout`.
pub fn allocate_sets(
    device: &Device,
    name: &str,
    layout: vk::DescriptorSetLayout,
    bindings: &[Binding],
    sets: u32,
) -> Result<(vk::DescriptorPool, Vec<vk::DescriptorSet>)> {
    let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
    for b in bindings {
        match sizes.iter_mut().find(|s| s.ty == b.kind) {
            Some(size) => size.descriptor_count += sets,
            None => sizes.push(vk::DescriptorPoolSize { ty: b.kind, descriptor_count: sets }),
        }
    }
    let info = vk::DescriptorPoolCreateInfo::default().max_sets(sets).pool_sizes(&sizes);
    // SAFETY: valid create info.
    let pool =
        super::live::created(unsafe { device.raw.create_descriptor_pool(&info, None) }.vk("vkCreateDescriptorPool")?);
    device.set_name(pool, &format!("{name} pool"));
    let layouts = vec![layout; sets as usize];
    let alloc = vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&layouts);
    // SAFETY: the pool was sized for these sets.
    match unsafe { device.raw.allocate_descriptor_sets(&alloc) } {
        Ok(sets) => {
            for (i, set) in sets.iter().enumerate() {
                device.set_name(*set, &format!("{name} #{i}"));
            }
            Ok((pool, sets))
        }
        Err(result) => {
            // SAFETY: nothing allocated from it.
            unsafe {
                super::live::destroyed(pool);
                device.raw.destroy_descriptor_pool(pool, None)
            };
            Err(crate::error::Error::vulkan("vkAllocateDescriptorSets", result))
        }
    }
}

/// What one descriptor write points at.
#[derive(Clone)]
pub enum Resource {
    /// A uniform or storage buffer range.
    Buffer(vk::DescriptorBufferInfo),
    /// A combined image sampler.
    Image(vk::DescriptorImageInfo),
    /// A uniform texel buffer's view (`TexelView`).
    Texels(vk::BufferView),
}

/// Write descriptors into `set`: `(binding, type, resource)`.
pub fn write(device: &Device, set: vk::DescriptorSet, writes: &[(u32, vk::DescriptorType, Resource)]) {
    // Each write points at its one resource where `writes` holds it.
    let raw: Vec<_> = writes
        .iter()
        .map(|(binding, kind, resource)| {
            let w = vk::WriteDescriptorSet::default().dst_set(set).dst_binding(*binding).descriptor_type(*kind);
            match resource {
                Resource::Buffer(info) => w.buffer_info(std::slice::from_ref(info)),
                Resource::Image(info) => w.image_info(std::slice::from_ref(info)),
                Resource::Texels(view) => w.texel_buffer_view(std::slice::from_ref(view)),
            }
        })
        .collect();
    // SAFETY: the writes reference live resources and match the set's layout.
    unsafe { device.raw.update_descriptor_sets(&raw, &[]) };
}

/// Refuse a device whose `maxPerStageDescriptorStorageBuffers` is below what one stage of a
/// pipeline layout of `sets` binds (`what` names its pipelines; the spec's minimum is 4).
pub fn check_storage_buffers(device: &Device, what: &str, sets: &[&[Binding]]) -> Result<()> {
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
                "{} allows {limit} storage buffers per shader stage; meadow's {name} stage binds {used} ({what})",
                device.info.name
            )));
        }
    }
    Ok(())
}

/// A set layout with the bindings it was made of, as its sets are allocated and written.
#[derive(Default)]
pub struct SetLayout {
    /// The layout.
    pub raw: vk::DescriptorSetLayout,
    /// Its bindings, by binding number.
    pub bindings: Vec<Binding>,
    /// Each binding's name as its shaders declare it (`vk::reflect::Descriptor::name`), in the
    /// order of `bindings`; empty for a layout not reflected.
    pub names: Vec<String>,
}

impl SetLayout {
    /// A named layout of `bindings`.
    pub fn new(device: &Device, name: &str, bindings: Vec<Binding>) -> Result<Self> {
        Ok(Self { raw: set_layout(device, name, &bindings)?, bindings, names: Vec::new() })
    }

    /// The layout of set `set` as `shaders` (`(name, SPIR-V)`, e.g. a pipeline's stages) declare
    /// it together (`vk::reflect::merge_named`): what a pass's shaders bind is the pass's layout,
    /// with no list to keep beside the GLSL. A set no shader uses is an empty layout.
    pub fn reflected(device: &Device, name: &str, shaders: &[(&str, &[u8])], set: u32) -> Result<Self> {
        let named = super::reflect::merge_named(shaders)?.remove(&set).unwrap_or_default();
        Self::with_names(device, name, named)
    }

    /// A named layout of reflected `(binding, name)` pairs.
    pub fn with_names(device: &Device, name: &str, named: Vec<(Binding, String)>) -> Result<Self> {
        let (bindings, names): (Vec<Binding>, Vec<String>) = named.into_iter().unzip();
        Ok(Self { raw: set_layout(device, name, &bindings)?, bindings, names })
    }

    /// Point every binding of `set` at its resource in `resources`, by the name its shaders
    /// declare it with (a block's interface name, an opaque variable's name): the owner of a
    /// resource names it once, in its GLSL, and no binding number appears in Rust. Names the
    /// layout lacks are left out (a profile's twins, a shader that does not read them); a
    /// binding with no resource or one of another kind is an error naming it.
    pub fn write_named(
        &self,
        device: &Device,
        set: vk::DescriptorSet,
        what: &str,
        resources: &[(&str, Resource)],
    ) -> Result<()> {
        let mut numbered = Vec::with_capacity(self.bindings.len());
        for (b, name) in self.bindings.iter().zip(&self.names) {
            if let Some((_, r)) = resources.iter().find(|(n, _)| n == name) {
                numbered.push((b.binding, r.clone()));
            }
        }
        self.write(device, set, what, &numbered).map_err(|e| match e {
            crate::error::Error::Internal(why) => {
                let names: Vec<String> =
                    self.bindings.iter().zip(&self.names).map(|(b, n)| format!("{} `{n}`", b.binding)).collect();
                crate::error::Error::Internal(format!("{why} (the set binds {})", names.join(", ")))
            }
            other => other,
        })
    }

    /// A pool for `count` sets of this layout, and the sets.
    pub fn allocate(
        &self,
        device: &Device,
        name: &str,
        count: u32,
    ) -> Result<(vk::DescriptorPool, Vec<vk::DescriptorSet>)> {
        allocate_sets(device, name, self.raw, &self.bindings, count)
    }

    /// Point every binding of `set` (a set of this layout) at its resource in `resources`, by
    /// binding number; resources for bindings the layout lacks are left out (a profile's twins,
    /// a shader that does not read them). A binding with no resource, or with a resource of
    /// another kind, is an error naming it (`what` names the set).
    pub fn write(
        &self,
        device: &Device,
        set: vk::DescriptorSet,
        what: &str,
        resources: &[(u32, Resource)],
    ) -> Result<()> {
        let mut writes = Vec::with_capacity(self.bindings.len());
        for b in &self.bindings {
            let resource = resources.iter().find(|(binding, _)| *binding == b.binding).map(|(_, r)| r);
            let fits = |r: &Resource| {
                use vk::DescriptorType as T;
                match r {
                    Resource::Buffer(_) => [T::UNIFORM_BUFFER, T::STORAGE_BUFFER].contains(&b.kind),
                    Resource::Image(_) => {
                        [T::COMBINED_IMAGE_SAMPLER, T::SAMPLED_IMAGE, T::STORAGE_IMAGE].contains(&b.kind)
                    }
                    Resource::Texels(_) => [T::UNIFORM_TEXEL_BUFFER, T::STORAGE_TEXEL_BUFFER].contains(&b.kind),
                }
            };
            match resource {
                Some(r) if fits(r) => writes.push((b.binding, b.kind, r.clone())),
                Some(_) => {
                    return Err(crate::error::Error::Internal(format!(
                        "{what}: binding {} is a {:?}, and its resource is not",
                        b.binding, b.kind
                    )))
                }
                None => {
                    return Err(crate::error::Error::Internal(format!(
                        "{what}: the shaders bind {} ({:?}), and nothing is given for it",
                        b.binding, b.kind
                    )))
                }
            }
        }
        write(device, set, &writes);
        Ok(())
    }

    /// # Safety
    /// No set of it may be in use.
    pub unsafe fn destroy(&self, device: &Device) {
        // SAFETY: per the contract; destroying a null handle is a no-op.
        unsafe {
            super::live::destroyed(self.raw);
            device.raw.destroy_descriptor_set_layout(self.raw, None);
        }
    }
}
