//! Belyaev's virtually-inertial blades (§3.3) as a blade response: the inertia is carried by
//! virtual blades at the wind corners (`virtual_blades`, a state pair of a chain per corner),
//! whose moments make a virtual wind; each drawn blade takes its static equilibrium under it
//! (`shaders/animation/virtual_inertial.comp`), with no state of its own. [`chain::Chain`]'s
//! `upright`, `step`, `virtual_forces` and `equilibrium_under` are the CPU mirror the tests
//! measure it against.

use std::cell::Cell;
use std::rc::Rc;

use ash::vk;
use glam::{UVec4, Vec3, Vec4};

use crate::error::Result;
use crate::render::animation::blade_state::StepSpan;
use crate::render::animation::chain::{ChainParams, CHAIN_SEGMENTS};
use crate::render::animation::pose_pass::{PosePass, PoseShader};
use crate::render::animation::response::{BladeInput, BladeResponse, ResponseSetup, ResponseStep};
use crate::render::animation::virtual_blades::{VirtualBladesPass, VirtualBuffers, VirtualFrame, STATE_FLOATS};
use crate::render::field_gpu;
use crate::render::graph::Pass;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{Buffer, BufferDesc, Device, Guard, Resource, TexelView};

/// The virtual blades' height (m): the middle of the blades' heights.
pub const VIRTUAL_HEIGHT: f32 = 0.4;

/// The virtually-inertial response: the virtual blades' state pair and wind, its constants, and
/// this frame's block of the virtual blades' pass.
pub struct VirtualInertialResponse {
    params: ChainParams,
    state: [Buffer; 2],
    /// A vec4 per corner and joint.
    virtual_wind: Buffer,
    /// Its texel view (`virtual_texels`, the lavapipe profile's gather).
    virtual_texels: TexelView,
    /// `VirtualShape`, written once (host-visible).
    shape: Buffer,
    frame: Rc<Cell<VirtualFrame>>,
    previous: Option<(u64, glam::DVec2)>,
}

impl VirtualInertialResponse {
    /// The virtual blades of `scene`'s wind corners (every level of a block field's) and the
    /// constants' block. Refused with one line if the constants are out of range or the buffers
    /// do not fit the memory budget.
    pub fn new(device: &Device, scene: &SceneGpu, params: ChainParams) -> Result<Self> {
        params.check()?;
        let corner_count = scene.wind_levels * scene.grid.corner_count();
        let state_bytes = 4 * u64::from(corner_count) * u64::from(STATE_FLOATS);
        let wind_bytes = 16 * u64::from(corner_count) * CHAIN_SEGMENTS as u64;
        device.check_budget(2 * state_bytes + wind_bytes, "the virtual blades")?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let texels = storage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let a =
            Guard::new(device, Buffer::new(device, &BufferDesc::gpu_only("virtual blades A", state_bytes, storage))?);
        let b =
            Guard::new(device, Buffer::new(device, &BufferDesc::gpu_only("virtual blades B", state_bytes, storage))?);
        let desc = BufferDesc::gpu_only("virtual wind", wind_bytes, texels);
        let virtual_wind = Guard::new(device, Buffer::new(device, &desc)?);
        let view = TexelView::new(device, &virtual_wind, vk::Format::R32G32B32A32_SFLOAT, "virtual wind texels")?;
        let virtual_texels = Guard::new(device, view);
        let mut shape =
            Buffer::new(device, &BufferDesc::upload("virtual shape", 16, vk::BufferUsageFlags::UNIFORM_BUFFER))?;
        shape.write(0, &[params.stiffness, params.damping, 0.0, 0.0]);
        let mut levels = [Vec4::ZERO; crate::render::gpu_constants::WIND_LEVELS as usize];
        for (l, level) in levels.iter_mut().enumerate().take(scene.wind_levels as usize) {
            let grid = match scene.field {
                Some(_) => field_gpu::wind_level(scene.grid.cluster_size, l as u32),
                None => scene.grid,
            };
            *level = Vec4::new(grid.origin, grid.origin, grid.cluster_size, 0.0);
        }
        let frame = VirtualFrame {
            counts: UVec4::new(corner_count, scene.grid.corners_per_side(), 1, 0),
            motion: Vec4::new(0.0, 0.0, 1.0 / 60.0, 0.0),
            chain: Vec4::new(params.stiffness, params.damping, VIRTUAL_HEIGHT, 0.0),
            levels,
        };
        Ok(Self {
            params,
            state: [a.take(), b.take()],
            virtual_wind: virtual_wind.take(),
            virtual_texels: virtual_texels.take(),
            shape,
            frame: Rc::new(Cell::new(frame)),
            previous: None,
        })
    }
}

impl BladeResponse for VirtualInertialResponse {
    fn name(&self) -> &'static str {
        "virtual-inertial"
    }

    fn blade_input(&self) -> BladeInput {
        BladeInput::PoseRecords
    }

    fn passes(&self, device: &Device, setup: &ResponseSetup) -> Result<Vec<Box<dyn Pass>>> {
        let buffers = VirtualBuffers {
            corners: setup.wind.to_vec(),
            state: [self.state[0].descriptor(), self.state[1].descriptor()],
            virtual_wind: self.virtual_wind.descriptor(),
        };
        let virtual_blades =
            Guard::new(device, VirtualBladesPass::new(device, setup.sets.frames, &buffers, self.frame.clone())?);
        let shader = PoseShader {
            name: "virtually-inertial",
            spirv: shaders::VIRTUAL_INERTIAL_COMP.code(device.profile),
            resources: vec![
                ("VirtualShape", Descriptor::Buffer(self.shape.descriptor())),
                ("VirtualWind", Descriptor::Buffer(self.virtual_wind.descriptor())),
                ("virtual_texels", Descriptor::Texels(self.virtual_texels.raw)),
            ],
            uses: vec![(Resource::Buffer(self.virtual_wind.raw), device.profile.compute_fetch())],
            uniforms: None,
            store: None,
        };
        let drawn = PosePass::new(device, setup, shader)?;
        Ok(vec![Box::new(virtual_blades.take()), Box::new(drawn)])
    }

    fn step(&mut self, step: &ResponseStep) {
        let span = StepSpan::between(self.previous.map(|(s, _)| s), step.step);
        let moved = self.previous.map_or(glam::DVec2::ZERO, |(_, origin)| step.origin - origin);
        let mut frame = self.frame.get();
        frame.counts.z = u32::from(span.from.is_none());
        frame.counts.w = span.steps;
        frame.motion = Vec4::new(moved.x as f32, moved.y as f32, step.dt, 0.0);
        self.frame.set(frame);
        self.previous = Some((step.step, step.origin));
    }

    fn stateful(&self) -> bool {
        true
    }

    fn tip_offset(&self, wind: Vec3) -> Vec3 {
        // Under a steady wind the virtual blades, and the blades with them, rest at the
        // equilibrium.
        self.params.tip_offset(wind)
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            let [a, b] = self.state;
            a.destroy(device);
            b.destroy(device);
            self.virtual_texels.destroy(device);
            self.virtual_wind.destroy(device);
            self.shape.destroy(device);
        }
    }
}
