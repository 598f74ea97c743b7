//! The thin Vulkan layer: one module per concept. Leaves (`Buffer`, `Image`, pipelines) are
//! destroyed explicitly by their owners; owners hold an `Arc<Device>` and wait for their GPU work
//! before destroying.

pub mod address_space;
pub mod buffer;
pub mod capabilities;
pub mod commands;
pub mod debug;
pub mod descriptor;
pub mod device;
pub mod fault;
pub mod guard;
pub mod image;
pub mod instance;
pub mod live;
pub mod multisample;
pub mod physical;
pub mod pipeline;
pub mod profile;
pub mod query;
pub mod reflect;
pub mod swapchain;
pub mod sync;
pub mod tracker;
pub mod upload;

pub use buffer::{Buffer, BufferDesc, TexelView};
pub use device::{Device, DeviceDesc, DeviceSelector};
pub use guard::{Destroy, Guard, SurfaceGuard};
pub use image::{Image, ImageDesc};
pub use instance::{Instance, InstanceDesc, ValidationCounter};
pub use sync::Access;
pub use tracker::{Resource, ResourceStates};
