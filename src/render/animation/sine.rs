//! Pelzer's sine animation (GPU Gems ch. 7, §7.4) as a blade response: each blade's levels move
//! along the wind by a translation that a sine wave sways, posed once per drawn blade by
//! `shaders/animation/sine.comp` into the renderer's pose records. The shader's header gives the
//! translation (`T = g·w + a·|w|·sin θ · ŵ`, θ = ω·t − κ·d̂·p) and the three variants, which
//! differ in where the phase is taken: per object (§7.4.4, the blade's root), per vertex (§7.4.3,
//! each level's own rest point) and per cluster (§7.4.2, the centre of the blade's tile, drawn
//! one draw per visible tile). Its parameters are constants, documented in `docs/animation.md`.

use std::cell::Cell;
use std::f64::consts::TAU;
use std::rc::Rc;

use glam::{DVec2, Vec3};

use crate::error::Result;
use crate::render::animation::pose_pass::{PosePass, PoseShader, PoseUniforms};
use crate::render::animation::response::{BladeInput, BladeResponse, ResponseSetup, ResponseStep};
use crate::render::graph::Pass;
use crate::render::shaders;
use crate::vk::Device;

/// The tip's lean per m/s of wind, in blade heights (g): 8 m/s leans a tip 0.4 heights.
pub const LEAN_PER_MS: f32 = 0.05;
/// The sway's amplitude per m/s, in blade heights (a); less than `LEAN_PER_MS`, so a tip under
/// a wind never swings upwind.
pub const SWAY_PER_MS: f32 = 0.02;
/// The most a tip moves, in blade heights.
pub const MOST: f32 = 0.7;
/// The sway's wavelength along the wind, metres (κ = 2π / λ).
pub const WAVELENGTH: f64 = 6.0;
/// The sway's period, seconds (ω = 2π / period).
pub const PERIOD: f64 = 2.0;

/// Where a variant takes its phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SinePhase {
    /// One phase per blade, at its root (Pelzer §7.4.4, "per grass object").
    Object,
    /// A phase per level of the blade, at its rest point (Pelzer §7.4.3, "per vertex").
    Vertex,
    /// One phase per tile of the cull, at its centre (Pelzer §7.4.2's clusters, one draw each:
    /// the blade class then draws a row per visible tile, `draw_rows::DrawRows::PerTile`).
    Cluster,
}

/// The sine response.
pub struct SineResponse {
    phase: SinePhase,
    /// The global wind's direction d̂ (x, z): the sway's wave runs along it.
    direction: DVec2,
    /// This frame's block (`SineShape`), made by `step`, read when the graph plans the frame.
    block: Rc<Cell<[f32; 8]>>,
}

impl SineResponse {
    /// The variant `phase`, its wave along `direction_deg` (the global wind's, degrees from +x
    /// towards +z).
    pub fn new(phase: SinePhase, direction_deg: f32) -> Self {
        let a = f64::from(direction_deg).to_radians();
        let response = Self { phase, direction: DVec2::new(a.cos(), a.sin()), block: Rc::new(Cell::new([0.0; 8])) };
        response.block.set(response.shape_block(0.0, DVec2::ZERO));
        response
    }

    /// The `SineShape` block at simulation time `time` for positions relative to `origin`: the
    /// phase at O, ω·t − κ·d̂·O, folded into [0, 2π) in f64, so a blade 100 km out sways as one
    /// at the origin does.
    pub fn shape_block(&self, time: f64, origin: DVec2) -> [f32; 8] {
        let kappa = TAU / WAVELENGTH;
        let phase = (TAU / PERIOD * time - kappa * self.direction.dot(origin)).rem_euclid(TAU);
        let d = self.direction.as_vec2();
        [LEAN_PER_MS, SWAY_PER_MS, MOST, kappa as f32, d.x, d.y, phase as f32, 0.0]
    }
}

impl BladeResponse for SineResponse {
    fn name(&self) -> &'static str {
        match self.phase {
            SinePhase::Object => "sine per object",
            SinePhase::Vertex => "sine per vertex",
            SinePhase::Cluster => "sine per cluster",
        }
    }

    fn blade_input(&self) -> BladeInput {
        BladeInput::PoseRecords
    }

    fn passes(&self, device: &Device, setup: &ResponseSetup) -> Result<Vec<Box<dyn Pass>>> {
        let block = self.block.clone();
        let shader = PoseShader {
            name: "sine poses",
            spirv: match self.phase {
                SinePhase::Object => shaders::SINE_COMP.code(device.profile),
                SinePhase::Vertex => shaders::SINE_VERTEX_COMP.code(device.profile),
                SinePhase::Cluster => shaders::SINE_CLUSTER_COMP.code(device.profile),
            },
            resources: Vec::new(),
            uses: Vec::new(),
            uniforms: Some(PoseUniforms {
                name: "SineShape",
                size: 32,
                control: None,
                fill: Box::new(move |_| bytemuck::cast_slice(&block.get()).to_vec()),
            }),
            store: None,
        };
        Ok(vec![Box::new(PosePass::new(device, setup, shader)?)])
    }

    fn step(&mut self, step: &ResponseStep) {
        self.block.set(self.shape_block(step.time, step.origin));
    }

    fn tip_offset(&self, wind: Vec3) -> Vec3 {
        // The mean lean, without the sway.
        (Vec3::new(wind.x, 0.0, wind.z) * LEAN_PER_MS).clamp_length_max(MOST)
    }

    unsafe fn destroy(self: Box<Self>, _: &Device) {}
}
