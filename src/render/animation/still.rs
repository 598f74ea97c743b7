//! The static response: neutral Bézier blades, no forces on them (thesis 4.1). It has no
//! resources and no pass; the wind field still runs each frame (the debug views show it).

use glam::Vec3;

use crate::error::Result;
use crate::render::animation::response::{BladeInput, BladeResponse, ResponseSetup};
use crate::render::graph::Pass;
use crate::vk::Device;

/// Static blades.
pub struct StaticResponse;

impl BladeResponse for StaticResponse {
    fn name(&self) -> &'static str {
        "static"
    }

    fn blade_input(&self) -> BladeInput {
        BladeInput::Neutral
    }

    fn passes(&self, _: &Device, _: &ResponseSetup) -> Result<Vec<Box<dyn Pass>>> {
        Ok(Vec::new())
    }

    fn tip_offset(&self, _: Vec3) -> Vec3 {
        Vec3::ZERO
    }

    unsafe fn destroy(self: Box<Self>, _: &Device) {}
}
