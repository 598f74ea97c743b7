//! Rendering: the scene on the GPU, per-frame data, targets, passes, and the renderer that
//! records them. Data flows one way: CPU scene → GPU buffers → passes → image.

pub mod animation;
pub mod budget;
pub mod camera_grid;
pub mod cull_reference;
pub mod culling;
pub mod draw_class;
pub mod draw_rows;
pub mod far_field;
pub mod far_rings;
pub mod field_gpu;
pub mod flowers;
pub mod frame;
pub mod gpu_constants;
pub mod graph;
pub mod ground;
pub mod ground_clipmap;
pub mod layouts;
pub mod limits;
pub mod msaa;
pub mod occlusion;
pub mod overlay;
pub mod passes;
pub mod recording;
pub mod renderer;
pub mod scene_gpu;
pub mod settings;
pub mod shaders;
pub mod specialization;
pub mod submission;
pub mod target;
pub mod terrain_chunks;
pub mod uniforms;
pub mod wind;

pub use renderer::{FrameTimings, Models, PassTime, RenderSettings, Renderer};
pub use target::OffscreenTarget;
