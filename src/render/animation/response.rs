//! The blade-response seam (issue #29 item 2): what turns the wind field's wind
//! (`shaders/wind/wind_field.glsl`, m/s) into the blades' poses. A response either writes the
//! renderer's pose records from compute passes of its own (`BladeInput::PoseRecords`: the
//! records are the renderer's, `poses::PoseRecords`, set `SET_POSES`), or has the blade pass's
//! vertex shader pose each vertex through its own include, compiled into a variant of
//! `blades/blade.vert` (`BladeInput::PerVertex`: the thesis' per-vertex keyframes).
//!
//! A response owns its resources. Its shaders declare them in their passes' own sets
//! (`SET_PASS`, `recording::PassSet`, layouts reflected from the shaders) and it gives them by
//! the names its GLSL declares; its parameters are a uniform block of its own, never a field of
//! the shared `FrameUniforms`. The renderer imports what it lists in `tracked` into the graph,
//! forgets them when it is replaced, and names none of them.
//!
//! Responses: `still::StaticResponse` (neutral blades, thesis 4.1) and
//! `keyframed::KeyframeResponse` (thesis ch. 3–4: a texture or a uniform array, per vertex or per
//! blade). A response defined outside the library is built by a [`BuildResponse`] given to
//! `Renderer::with_models`; `tests/new_model.rs` is one, with its own GLSL.

use ash::vk;
use glam::Vec3;

use crate::error::Result;
use crate::render::animation::AnimationSettings;
use crate::render::graph::Pass;
use crate::render::scene_gpu::SceneGpu;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::profile::Shader;
use crate::vk::{Access, Device, Resource};

/// How the blade pass poses a blade.
#[derive(Clone)]
pub enum BladeInput {
    /// Neutral Bézier blades: `blade.vert`'s own path, nothing to read.
    Neutral,
    /// The response's per-vertex path: `vertex` is `blade.vert` built with the response's include
    /// (a variant of it), which reads the response's `resources` in the blade pass's own set
    /// (`SET_PASS`, by name); `reads` are what it reads of them, for the pass's declaration.
    PerVertex {
        /// The blade vertex shader.
        vertex: Shader,
        /// The response's resources, by the names its include declares.
        resources: Vec<(&'static str, Descriptor)>,
        /// What the vertex shader reads of them.
        reads: Vec<(Resource, Access)>,
    },
    /// Pose records (`POSE_WORDS` words per level, `poses::PoseRecords`), written by the
    /// response's passes before the blade pass; with the cull the renderer places and lights the
    /// drawn blades' levels from them (`passes::BladeLevelsPass`).
    PoseRecords,
}

impl BladeInput {
    /// Whether the blade pass reads pose records.
    pub fn pose_records(&self) -> bool {
        matches!(self, BladeInput::PoseRecords)
    }
}

/// What a response's compute passes are built with.
pub struct ResponseSetup<'a> {
    /// The layouts of sets `SET_SCENE` and `SET_POSES` and the frames in flight, for a pass's own
    /// set (`SceneSets::desc`, `recording::PassSet`): its pipeline layout is theirs plus its own.
    pub sets: crate::render::recording::SceneSets<'a>,
    /// The specialization constants of the scene pipelines (the response's own set).
    pub constants: &'a Specialization,
    /// The scene on the GPU (its blades, clusters, the cull's visible list and draws).
    pub scene: &'a SceneGpu,
    /// Set `SET_POSES` (bind it with `recording::bind_pose_set`) and its records (the buffer a
    /// pass writes, to declare).
    pub poses: (vk::DescriptorSet, vk::Buffer),
    /// Each frame's wind at the cluster corners (set 0's `Corners`, by frame slot), which the
    /// wind field's passes write: a pass whose shaders sample the wind declares its read of
    /// `wind[ctx.slot]`, so the graph orders it after that write.
    pub wind: &'a [vk::Buffer],
    /// With the cull before the blade pass, the segments of its LOD buckets: a per-blade pass
    /// then covers only its visible list, bucket by bucket (`recording::bucket_dispatch`), and is
    /// added after the cull's passes. `None` without the cull.
    pub buckets: Option<&'a [u32]>,
    /// With the cull, the buckets of further draw classes whose entries the response poses as
    /// blades, and their segments (`render::draw_class::ClassLayout::posed`): a per-blade pass
    /// dispatches over them too (flowers' stems).
    pub posed: &'a [(u32, u32)],
}

impl ResponseSetup<'_> {
    /// What a per-blade pass runs over (`recording::BladeDispatch`): the stored blades, or with
    /// the cull its buckets over the visible list.
    pub fn blade_source(&self) -> crate::render::recording::BladeSource<'_> {
        crate::render::recording::BladeSource {
            blades: self.scene.blade_count,
            buckets: self.buckets,
            posed: self.posed,
            draws: self.scene.draws.raw,
            visible: self.scene.visible.raw,
        }
    }
}

/// One simulation step, as `BladeResponse::step` sees it (a stateless response ignores it).
#[derive(Clone, Copy, Debug)]
pub struct ResponseStep {
    /// The step the next frame draws (`StepClock::steps_to`).
    pub step: u64,
    /// The fixed step, seconds.
    pub dt: f32,
    /// Frames submitted before this one (`FrameClock::index`).
    pub frame: u64,
    /// The frame slot.
    pub slot: usize,
    /// The frame's simulation time, seconds.
    pub time: f64,
    /// World (x, z) the GPU's positions are relative to, exact in f64 (a block field's origin O;
    /// zero for a stored field), for phases taken in the world.
    pub origin: glam::DVec2,
}

/// A blade response.
pub trait BladeResponse {
    /// Name in reports.
    fn name(&self) -> &'static str;

    /// Set the constants that choose the response's shader path (a keyframe response's mode,
    /// smoothing, encoding, representation, the uniform array's size; the renderer sets the wind
    /// field's attenuation). Nothing by default: the constants' own defaults are a response with
    /// no table (`MODE_STATIC`).
    fn specialize(&self, _specialization: &mut Specialization) {}

    /// How the blade pass poses a blade.
    fn blade_input(&self) -> BladeInput;

    /// The response's resources the graph tracks, each with the accesses its upload left: the
    /// renderer imports them when it builds its passes and forgets them when the response goes.
    /// None by default (a response whose resources no GPU command writes before its passes).
    fn tracked(&self) -> Vec<(Resource, Vec<Access>)> {
        Vec::new()
    }

    /// The compute passes that run before the blade pass (after the cull's, with the cull).
    fn passes(&self, device: &Device, setup: &ResponseSetup) -> Result<Vec<Box<dyn Pass>>>;

    /// Before each frame: the step it draws (a stateful response advances its state to it).
    fn step(&mut self, _step: &ResponseStep) {}

    /// Whether the response keeps state from step to step (`blade_state`): reaching a time then
    /// takes every step from t = 0 (`Renderer::warm_up`). False by default.
    fn stateful(&self) -> bool {
        false
    }

    /// How far the tip of a unit blade (root at 0, upright along +y, facing +z) moves under
    /// `wind` (m/s, in the blade's frame): a far field's billboard leans by it.
    fn tip_offset(&self, wind: Vec3) -> Vec3;

    /// Destroy the response's resources.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    unsafe fn destroy(self: Box<Self>, device: &Device);
}

/// What a response is built from.
pub struct ResponseContext<'a> {
    /// The animation settings (the keyframe table's options, the clock).
    pub animation: &'a AnimationSettings,
    /// Segments per blade.
    pub segments: u32,
    /// Whether the cull runs (a per-blade response then covers only the drawn blades).
    pub culled: bool,
    /// The scene on the GPU (a stateful response sizes its store by it,
    /// `blade_state::BladeStateStore`).
    pub scene: &'a SceneGpu,
}

/// Builds a blade response: the library's for the CLI's modes is `animation::build_response`.
pub type BuildResponse = dyn Fn(&Device, &ResponseContext) -> Result<Box<dyn BladeResponse>>;

/// A response being built is guarded like any object (`vk::Guard`).
impl crate::vk::Destroy for Box<dyn BladeResponse> {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { BladeResponse::destroy(self, device) };
    }
}
