//! A pass's own descriptor set (`SET_PASS`), one per frame in flight: what the pass's shaders
//! bind in that set is reflected from their SPIR-V, numbered in the pass's own header (a
//! pass-local binding space: no table of numbers shared with any other pass), and given by the
//! owner of each resource by the name its GLSL declares it with (`SetLayout::write_named`). A
//! resource several passes read (the cull's `Draws`) is declared once, in its owner's header,
//! and each reader names it in its own set. The sets before `SET_PASS` (the frame's and the
//! pose records') come from whoever builds the pass, so the pipeline layout is theirs plus this one.
//! A pass with no sets before its own (the depth pyramid, the resolve) has it as set 0; one whose
//! resources change from frame to frame (the frame's own depth or colour image) builds it
//! [`PassSet::unwritten`] and writes a slot's set when it records it.

use ash::vk;

use crate::error::Result;
use crate::vk::descriptor::{Resource, SetLayout};
use crate::vk::{pipeline, Destroy, Device, Guard};

/// What a pass set is built from.
pub struct PassSetDesc<'a> {
    /// Names the layout, the sets and the pipeline layout.
    pub name: &'a str,
    /// The pass's shaders (`(name, SPIR-V)`): set `SET_PASS` is the union of what they bind there.
    pub shaders: &'a [(&'a str, &'a [u8])],
    /// The layouts of the sets before the pass's own, as every pipeline of the pass binds them:
    /// for a scene pass sets 0 .. `SET_PASS` (the frame's, the pose records', `SceneSets`); none for a
    /// pass with no scene sets, whose own set is then set 0. The own set's number is their count.
    pub before: &'a [&'a SetLayout],
    /// The pass's push-constant ranges.
    pub push: &'a [vk::PushConstantRange],
    /// Sets to allocate: one per frame in flight (more for a pass that indexes its sets by
    /// something else too, a temporal pair's side).
    pub frames: usize,
}

/// The sets a scene pass binds before its own (`SET_SCENE`, `SET_POSES`), the scene
/// pipelines' push constants and the frames in flight: what a scene pass's `PassSet` is built on.
#[derive(Clone, Copy)]
pub struct SceneSets<'a> {
    /// The layouts of `SET_SCENE` and `SET_POSES`.
    pub before: [&'a SetLayout; 2],
    /// The scene pipelines' push-constant range.
    pub push: vk::PushConstantRange,
    /// Frames in flight.
    pub frames: usize,
}

impl<'a> SceneSets<'a> {
    /// The description of a scene pass's set (`SET_PASS`) over `shaders`.
    pub fn desc(&'a self, name: &'a str, shaders: &'a [(&'a str, &'a [u8])]) -> PassSetDesc<'a> {
        PassSetDesc { name, shaders, before: &self.before, push: std::slice::from_ref(&self.push), frames: self.frames }
    }
}

/// The layout of the pass's own set, the pipeline layout with the sets before it, and one set
/// per frame in flight.
pub struct PassSet {
    /// The set's layout (reflected, with the bindings' names).
    pub set_layout: SetLayout,
    /// Sets 0 .. `SET_PASS` and this one, and the push constants.
    pub layout: vk::PipelineLayout,
    pool: vk::DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    /// The own set's number (`SET_PASS` for a scene pass).
    index: u32,
}

impl PassSet {
    /// Reflect the set, build the pipeline layout and point each frame's set at
    /// `resources(slot)` (by name; a resource the shaders do not bind is left out, a binding no
    /// resource is named for is an error naming it). On failure nothing is left (a guard holds
    /// what is made so far).
    pub fn new<'r>(
        device: &Device,
        desc: &PassSetDesc,
        resources: impl Fn(usize) -> Vec<(&'r str, Resource)>,
    ) -> Result<Self> {
        let made = Guard::new(device, Self::unwritten(device, desc)?);
        for slot in 0..made.sets.len() {
            made.write(device, slot, desc.name, &resources(slot))?;
        }
        Ok(made.take())
    }

    /// The layouts and sets, not pointed at anything yet: for a pass whose resources change from
    /// frame to frame (the frame's own depth or colour image), which [`PassSet::write`]s a set
    /// when it records it. On failure nothing is left.
    pub fn unwritten(device: &Device, desc: &PassSetDesc) -> Result<Self> {
        let mut made = Guard::new(
            device,
            Self {
                set_layout: SetLayout::default(),
                layout: vk::PipelineLayout::null(),
                pool: vk::DescriptorPool::null(),
                sets: Vec::new(),
                index: desc.before.len() as u32,
            },
        );
        let name = desc.name;
        made.set_layout = SetLayout::reflected(device, &format!("{name} set layout"), desc.shaders, made.index)?;
        let mut bindings: Vec<&[crate::vk::descriptor::Binding]> =
            desc.before.iter().map(|l| l.bindings.as_slice()).collect();
        bindings.push(&made.set_layout.bindings);
        crate::vk::descriptor::check_storage_buffers(device, name, &bindings)?;
        let mut raw: Vec<vk::DescriptorSetLayout> = desc.before.iter().map(|l| l.raw).collect();
        raw.push(made.set_layout.raw);
        made.layout = pipeline::layout(device, &format!("{name} layout"), &raw, desc.push)?;
        (made.pool, made.sets) = made.set_layout.allocate(device, &format!("{name} sets"), desc.frames as u32)?;
        Ok(made.take())
    }

    /// Point set `index` at `resources` (by name, as [`PassSet::new`]); `name` is the pass's, for
    /// errors. The set may not be in use: a frame slot's set is free once the slot's fence was
    /// waited, when the slot's next frame is recorded.
    pub fn write(&self, device: &Device, index: usize, name: &str, resources: &[(&str, Resource)]) -> Result<()> {
        self.set_layout.write_named(device, self.sets[index], &format!("{name} set"), resources)
    }

    /// Set `index` (a frame slot).
    pub fn set(&self, index: usize) -> vk::DescriptorSet {
        self.sets[index]
    }

    /// Bind set `index` (a frame slot) at its number in `layout`, at `bind_point`.
    pub fn bind(&self, device: &Device, cmd: vk::CommandBuffer, bind_point: vk::PipelineBindPoint, index: usize) {
        // SAFETY: cmd is recording; the set matches the layout's set `self.index`.
        unsafe {
            device.raw.cmd_bind_descriptor_sets(cmd, bind_point, self.layout, self.index, &[self.sets[index]], &[])
        };
    }

    /// Destroy everything (the sets go with the pool).
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(&self, device: &Device) {
        // SAFETY: per the contract; destroying null handles is a no-op.
        unsafe {
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            crate::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
            SetLayout::destroy(&self.set_layout, device);
        }
    }
}

/// A pass set being built, or in a pass being built, is guarded like any object (`vk::Guard`).
impl Destroy for PassSet {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract (the inherent `destroy`, by reference).
        unsafe { PassSet::destroy(&self, device) };
    }
}

// `SceneSets::before` holds the sets 0 .. `SET_PASS`.
const _: () = assert!(crate::render::gpu_constants::SET_PASS == 2);
