//! Zhang Xia's Verlet blades (§3.2.3–3.2.5) as a stateful blade response: each blade's Bézier
//! control points are integrated with Verlet (eq. 7) under a drag towards the wind and a spring
//! towards the rest shape, put back to their rest lengths (§3.2.4), and the width turns to face
//! the wind (§3.2.5). `shaders/animation/verlet.comp` steps the drawn blades in the blade-state
//! store (`blade_state`); [`VerletBlade`] is its CPU mirror, step for step, the reference the
//! tests measure the GPU's oscillation against. The shader's header gives the equations and what
//! meadow chose where the paper is silent.

use std::cell::Cell;
use std::rc::Rc;

use ash::vk;
use glam::{Vec2, Vec3};

use crate::error::{Error, Result};
use crate::render::animation::blade_state::{BladeStateStore, SharedSpan, StepSpan};
use crate::render::animation::pose_pass::{PosePass, PoseShader, PoseUniforms};
use crate::render::animation::response::{BladeInput, BladeResponse, ResponseSetup, ResponseStep};
use crate::render::graph::Pass;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::scene::{bezier, BladeInstance};
use crate::vk::{Buffer, BufferDesc, Destroy, Device, Guard};

/// Chords the curve's arc length is measured over (verlet.comp's `ARC_SAMPLES`).
pub const ARC_SAMPLES: u32 = 8;
/// State words a blade: P1..P3, then their previous positions.
pub const STATE_WORDS: u32 = 18;
/// A block field's store: the blocks within this many of the camera's (121 blocks).
pub const STORE_RADIUS: u32 = 5;

/// The stiffness flag's range (1/s²): at the largest, √k_s · Δt stays under 2 at the longest
/// step, 1/15 s (√400 / 15 = 1.33), where the explicit step is stable.
pub const STIFFNESS_RANGE: (f32, f32) = (1.0, 400.0);
/// The drag rate's range (1/s): k_a · Δt ≤ 1.33 at 1/15 s.
pub const DAMPING_RANGE: (f32, f32) = (0.0, 20.0);

/// The model's constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerletParams {
    /// k_s, the spring towards the rest shape (1/s²): the natural period is about 2π/√k_s.
    pub stiffness: f32,
    /// k_a, the drag rate towards the wind (1/s): it damps the swing, and the wind moves a point
    /// by k_a / k_s · w at equilibrium.
    pub damping: f32,
}

impl Default for VerletParams {
    fn default() -> Self {
        Self { stiffness: 100.0, damping: 4.0 }
    }
}

/// One blade on the CPU, as verlet.comp steps it.
#[derive(Clone, Copy, Debug)]
pub struct VerletBlade {
    /// The rest control points P1..P3 (world axes, relative to the root).
    pub rest: [Vec3; 3],
    /// The rest curve's arc length over `ARC_SAMPLES` chords.
    pub rest_arc: f32,
    /// The constants.
    pub params: VerletParams,
}

/// A blade's state: P1..P3 and their previous positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerletState {
    /// Where the control points are.
    pub x: [Vec3; 3],
    /// Where they were a step ago.
    pub previous: [Vec3; 3],
}

impl VerletBlade {
    /// `blade`'s rest shape.
    pub fn new(blade: &BladeInstance, params: VerletParams) -> Self {
        let n = bezier::neutral_control_points(blade);
        let (across, normal) = bezier::frame(blade);
        let rest = [1, 2, 3].map(|k| across * n[k].x + Vec3::Y * n[k].y + normal * n[k].z);
        Self { rest, rest_arc: arc_length(&rest), params }
    }

    /// The equilibrium under the horizontal wind `w` (m/s), at rest.
    pub fn equilibrium(&self, w: Vec2) -> VerletState {
        let w = Vec3::new(w.x, 0.0, w.y);
        let mut x = self.rest.map(|r| r + (self.params.damping / self.params.stiffness) * w);
        self.constrain(&mut x);
        VerletState { x, previous: x }
    }

    /// One step of `dt` seconds under the horizontal wind `w` (m/s).
    pub fn step(&self, state: &mut VerletState, w: Vec2, dt: f32) {
        let w = Vec3::new(w.x, 0.0, w.y);
        let (ks, ka) = (self.params.stiffness, self.params.damping);
        for k in 0..3 {
            let v = (state.x[k] - state.previous[k]) / dt;
            let a = ka * (w - v) + ks * (self.rest[k] - state.x[k]);
            let next = 2.0 * state.x[k] - state.previous[k] + a * (dt * dt);
            state.previous[k] = state.x[k];
            state.x[k] = next;
        }
        self.constrain(&mut state.x);
    }

    /// The ground, the polygon's rest lengths (§3.2.4), the curve's length.
    fn constrain(&self, p: &mut [Vec3; 3]) {
        let (mut below, mut rest_below) = (Vec3::ZERO, Vec3::ZERO);
        for (point, rest) in p.iter_mut().zip(self.rest) {
            point.y = point.y.abs();
            let d = *point - below;
            let (len, l) = (d.length(), (rest - rest_below).length());
            *point = if len > 1e-6 { below + d * (l / len) } else { rest };
            below = *point;
            rest_below = rest;
        }
        let scale = self.rest_arc / arc_length(p).max(1e-6);
        p.iter_mut().for_each(|point| *point *= scale);
    }
}

/// The Bézier curve's length from the root through `p`, over `ARC_SAMPLES` chords.
pub fn arc_length(p: &[Vec3; 3]) -> f32 {
    let controls = [Vec3::ZERO, p[0], p[1], p[2]];
    let points: Vec<Vec3> =
        (0..=ARC_SAMPLES).map(|k| bezier::point(&controls, k as f32 / ARC_SAMPLES as f32)).collect();
    points.windows(2).map(|pair| (pair[1] - pair[0]).length()).sum()
}

/// The Verlet response: its store, its constants and the span of steps each frame takes.
pub struct VerletResponse {
    params: VerletParams,
    store: BladeStateStore,
    /// `VerletShape`, written once (host-visible).
    shape: Buffer,
    previous: Option<u64>,
    /// This frame's span and step, read when the graph plans the frame.
    span: SharedSpan,
}

impl VerletResponse {
    /// A store for `scene`'s blades (a block field's within `STORE_RADIUS` blocks) and the
    /// constants' block. Refused with one line if the store does not fit.
    pub fn new(device: &Device, scene: &SceneGpu, params: VerletParams) -> Result<Self> {
        let ((lo, hi), (dlo, dhi)) = (STIFFNESS_RANGE, DAMPING_RANGE);
        if !(lo..=hi).contains(&params.stiffness) {
            return Err(Error::bad_input(format!("--stiffness {}: outside {lo}..={hi} (1/s²)", params.stiffness)));
        }
        if !(dlo..=dhi).contains(&params.damping) {
            return Err(Error::bad_input(format!("--damping {}: outside {dlo}..={dhi} (1/s)", params.damping)));
        }
        let store = Guard::new(device, BladeStateStore::new(device, scene, STATE_WORDS, STORE_RADIUS, false)?);
        let usage = vk::BufferUsageFlags::UNIFORM_BUFFER;
        let mut shape = Buffer::new(device, &BufferDesc::upload("verlet shape", 16, usage))?;
        shape.write(0, &[params.stiffness, params.damping, 0.0, 0.0]);
        let span = Rc::new(Cell::new((StepSpan::between(None, 0), 1.0 / 60.0)));
        Ok(Self { params, store: store.take(), shape, previous: None, span })
    }
}

impl BladeResponse for VerletResponse {
    fn name(&self) -> &'static str {
        "verlet"
    }

    fn blade_input(&self) -> BladeInput {
        BladeInput::PoseRecords
    }

    fn passes(&self, device: &Device, setup: &ResponseSetup) -> Result<Vec<Box<dyn Pass>>> {
        let shader = PoseShader {
            name: "verlet",
            spirv: shaders::VERLET_COMP.code(device.profile),
            resources: vec![
                ("VerletShape", crate::vk::descriptor::Resource::Buffer(self.shape.descriptor())),
                self.store.resource(),
            ],
            uses: Vec::new(),
            uniforms: Some(PoseUniforms::blade_state(&self.store, self.span.clone())),
            store: Some(self.store.buffer.raw),
        };
        Ok(vec![Box::new(PosePass::new(device, setup, shader)?)])
    }

    fn step(&mut self, step: &ResponseStep) {
        self.span.set((StepSpan::between(self.previous, step.step), step.dt));
        self.previous = Some(step.step);
    }

    fn stateful(&self) -> bool {
        true
    }

    fn tip_offset(&self, wind: Vec3) -> Vec3 {
        // A unit upright blade's equilibrium tip under the wind.
        let upright =
            VerletBlade { rest: [Vec3::Y / 3.0, Vec3::Y * (2.0 / 3.0), Vec3::Y], rest_arc: 1.0, params: self.params };
        upright.equilibrium(Vec2::new(wind.x, wind.z)).x[2] - Vec3::Y
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.store.destroy(device);
            self.shape.destroy(device);
        }
    }
}
