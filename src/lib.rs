//! meadow: a real-time grass renderer on raw Vulkan.
//!
//! Data flows one way: the CPU [`scene`] (terrain, blades) → GPU buffers ([`render::scene_gpu`])
//! → passes ([`render::passes`]) → an image (offscreen or swapchain). [`vk`] is the thin Vulkan
//! layer underneath.
//!
//! The crate has two layers:
//! - **The renderer library**: [`vk`], [`render`], [`scene`], [`keyframes`], [`wind`], [`error`]
//!   and [`imagediff`]. It never imports the tools (`tests/layers.rs` checks this).
//! - **The tools built on it**: [`app`] (the commands: render a picture, list devices, export the
//!   keyframe table, and the device and limit checks they share), [`harness`] (the measuring
//!   commands `bench`, `overhead`, `timing` and their charts), [`viewer`] (the interactive
//!   window) and [`cli`] (the command line of the `meadow` binary, which only calls
//!   [`cli::parse()`] and [`cli::run()`]).

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
