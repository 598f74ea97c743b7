//! Ownership of partly built objects: a [`Guard`] owns what a constructor has made so far and
//! destroys it when it drops, unless the constructor [`Guard::take`]s it out once everything is
//! made. A constructor written with `?` then frees every object made before any failure, with no
//! hand-written cleanup branch. Whatever a guard can hold implements [`Destroy`]: the `vk`
//! leaves, the raw handles meadow creates, and containers of them (`Option`, `Vec`, tuples);
//! boxed passes and models implement it where their traits are, and a type that owns several
//! objects implements it by destroying each of them.
//!
//! A guard is for what no submitted work uses yet: it destroys at once, with no fence wait.

use std::ops::{Deref, DerefMut};

use ash::vk;

use crate::vk::commands::CommandRecorder;
use crate::vk::descriptor::SetLayout;
use crate::vk::query::{StatisticsQueries, TimestampQueries};
use crate::vk::{live, Buffer, Device, Image, Instance, TexelView};

/// Something a device-owned value can be destroyed as.
pub trait Destroy {
    /// Destroy it and everything it owns.
    ///
    /// # Safety
    /// No pending GPU work may use it.
    unsafe fn destroy(self, device: &Device);
}

/// Owns `T` while it is being built and destroys it on drop, unless it was taken out.
pub struct Guard<'d, T: Destroy> {
    device: &'d Device,
    value: Option<T>,
}

impl<'d, T: Destroy> Guard<'d, T> {
    /// Guard `value`, which no submitted work uses (it is destroyed at once on drop).
    pub fn new(device: &'d Device, value: T) -> Self {
        Self { device, value: Some(value) }
    }

    /// The value, no longer guarded: the caller owns it again.
    pub fn take(mut self) -> T {
        self.value.take().expect("a guard holds its value until taken")
    }
}

impl<T: Destroy> Deref for Guard<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.value.as_ref().expect("a guard holds its value until taken")
    }
}

impl<T: Destroy> DerefMut for Guard<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        self.value.as_mut().expect("a guard holds its value until taken")
    }
}

impl<T: Destroy> Drop for Guard<'_, T> {
    fn drop(&mut self) {
        if let Some(value) = self.value.take() {
            // SAFETY: a guard holds only what no submitted work uses (`Guard::new`).
            unsafe { value.destroy(self.device) };
        }
    }
}

/// Guard a value that starts empty (`Default`: null handles, empty lists) and is filled in.
pub fn empty<T: Destroy + Default>(device: &Device) -> Guard<'_, T> {
    Guard::new(device, T::default())
}

impl<T: Destroy> Destroy for Option<T> {
    unsafe fn destroy(self, device: &Device) {
        if let Some(value) = self {
            // SAFETY: per the contract.
            unsafe { value.destroy(device) };
        }
    }
}

impl<T: Destroy> Destroy for Vec<T> {
    unsafe fn destroy(self, device: &Device) {
        for value in self {
            // SAFETY: per the contract.
            unsafe { value.destroy(device) };
        }
    }
}

/// A shared object goes with its last owner (the cull's set, shared by its four passes).
impl<T: Destroy> Destroy for std::rc::Rc<T> {
    unsafe fn destroy(self, device: &Device) {
        if let Some(value) = std::rc::Rc::into_inner(self) {
            // SAFETY: per the contract.
            unsafe { value.destroy(device) };
        }
    }
}

macro_rules! tuple_destroy {
    ($($name:ident),+) => {
        impl<$($name: Destroy),+> Destroy for ($($name,)+) {
            #[allow(non_snake_case, reason = "the tuple's parts, named by their types")]
            unsafe fn destroy(self, device: &Device) {
                let ($($name,)+) = self;
                // SAFETY: per the contract; later parts were made from earlier ones, so they go
                // first.
                unsafe { tuple_destroy!(@rev device; $($name),+) };
            }
        }
    };
    (@rev $device:ident; $first:ident $(, $rest:ident)*) => {
        { tuple_destroy!(@rev $device; $($rest),*); $first.destroy($device) }
    };
    (@rev $device:ident;) => { () };
}

tuple_destroy!(A, B);
tuple_destroy!(A, B, C);
tuple_destroy!(A, B, C, D);

/// The `vk` leaves, destroyed by their own `destroy(self, device)`.
macro_rules! leaf_destroy {
    ($($leaf:ty),+ $(,)?) => {
        $(impl Destroy for $leaf {
            unsafe fn destroy(self, device: &Device) {
                // SAFETY: per the contract.
                unsafe { <$leaf>::destroy(self, device) };
            }
        })+
    };
}

leaf_destroy!(Buffer, Image, TexelView, CommandRecorder, TimestampQueries, StatisticsQueries);

impl Destroy for SetLayout {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { SetLayout::destroy(&self, device) };
    }
}

/// Memory from the allocator, not yet bound to what owns it for good (an image being built).
impl Destroy for gpu_allocator::vulkan::Allocation {
    unsafe fn destroy(self, device: &Device) {
        device.free(self, "a partly built object");
    }
}

/// Raw handles meadow creates and counts (`vk::live`): destroyed with their `vkDestroy*`; a null
/// handle is a no-op.
macro_rules! handle_destroy {
    ($($handle:ty => $call:ident),+ $(,)?) => {
        $(impl Destroy for $handle {
            unsafe fn destroy(self, device: &Device) {
                live::destroyed(self);
                // SAFETY: per the contract; destroying a null handle is a no-op.
                unsafe { device.raw.$call(self, None) };
            }
        })+
    };
}

handle_destroy!(
    vk::Buffer => destroy_buffer,
    vk::Image => destroy_image,
    vk::Pipeline => destroy_pipeline,
    vk::PipelineLayout => destroy_pipeline_layout,
    vk::DescriptorSetLayout => destroy_descriptor_set_layout,
    vk::DescriptorPool => destroy_descriptor_pool,
    vk::Sampler => destroy_sampler,
    vk::ImageView => destroy_image_view,
    vk::ShaderModule => destroy_shader_module,
    vk::Fence => destroy_fence,
    vk::Semaphore => destroy_semaphore,
    vk::QueryPool => destroy_query_pool,
    vk::CommandPool => destroy_command_pool,
);

/// The instance-level counterpart of [`Guard`] for a window's surface: it destroys the surface on
/// drop (a failed device or swapchain), unless [`SurfaceGuard::take`]n by what owns it for good
/// (the swapchain).
pub struct SurfaceGuard<'i> {
    instance: &'i Instance,
    raw: Option<vk::SurfaceKHR>,
}

impl<'i> SurfaceGuard<'i> {
    /// Guard `raw`, a surface of `instance` that nothing was made from yet.
    pub fn new(instance: &'i Instance, raw: vk::SurfaceKHR) -> Self {
        Self { instance, raw: Some(raw) }
    }

    /// The surface, no longer guarded.
    pub fn take(mut self) -> vk::SurfaceKHR {
        self.raw.take().expect("a guard holds its surface until taken")
    }
}

impl Deref for SurfaceGuard<'_> {
    type Target = vk::SurfaceKHR;
    fn deref(&self) -> &vk::SurfaceKHR {
        self.raw.as_ref().expect("a guard holds its surface until taken")
    }
}

impl Drop for SurfaceGuard<'_> {
    fn drop(&mut self) {
        if let Some(raw) = self.raw.take() {
            let instance = self.instance;
            // SAFETY: nothing made from the surface is alive (`SurfaceGuard::new`).
            unsafe { ash::khr::surface::Instance::new(&instance.entry, &instance.raw).destroy_surface(raw, None) };
            live::destroyed(raw);
        }
    }
}
