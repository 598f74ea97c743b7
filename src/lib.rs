//! meadow: a real-time grass renderer on raw Vulkan.
//!
//! Data flows one way: the CPU [`scene`] (terrain, blades) → GPU buffers ([`render::scene_gpu`])
//! → passes ([`render::passes`]) → an image (offscreen or swapchain). [`vk`] is the thin Vulkan
//! layer underneath; [`app`] holds the commands the `meadow` binary dispatches to, and [`harness::plot`]
//! draws their benchmark charts.

pub mod app;
pub mod cli;
pub mod error;
pub mod harness;
pub mod imagediff;
pub mod keyframes;
pub mod render;
pub mod scene;
pub mod viewer;
pub mod vk;
pub mod wind;

pub use error::{Error, Result};
