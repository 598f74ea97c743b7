//! Proof that a new model is only new files (issue #29 item 6): test files and their GLSL
//! (`tests/shaders/new_model/`) define a wind field — a uniform 3-D wind, written at every
//! cluster corner by a compute pass of its own (`tests/support/steady_wind.rs`, which other
//! tests drive responses with) — and, in this file, a blade response that writes the renderer's
//! pose records from its own compute shader, bending each blade along the wind it samples through
//! `wind/wind_field.glsl`. Nothing in the library names either: `Renderer::with_models` takes
//! them, the renderer imports the response's resources (its uniform block) and the graph orders
//! the passes from their declarations. A block field and a stored field render through the cull
//! and LOD with them, validation-clean (synchronization validation too), and the blades lean the
//! way the wind blows: the blades' coverage moves towards the side of the picture the wind blows
//! to, and away from it when the wind turns round.

#[path = "support/steady_wind.rs"]
mod steady_wind;
mod support;

use std::rc::Rc;

use ash::vk;
use glam::{Vec3, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::pose_pass::{PosePass, PoseShader};
use meadow::render::animation::response::{BladeInput, BladeResponse, ResponseSetup};
use meadow::render::culling::Culling;
use meadow::render::graph::Pass;
use meadow::render::specialization::Specialization;
use meadow::render::{Models, OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{Camera, Scene};
use meadow::vk::descriptor::Resource as Descriptor;
use meadow::vk::profile::Shader;
use meadow::vk::upload::UploadBatch;
use meadow::vk::{Access, Buffer, Device, DeviceSelector, Resource};

/// The models' shaders, compiled by build.rs from `tests/shaders/new_model/` in both profiles
/// (`tests/` shaders are not part of the library).
const LEAN_COMP: Shader = meadow::spirv_shader!("tests/new_model/lean.comp");

const EXTENT: vk::Extent2D = vk::Extent2D { width: 320, height: 180 };

/// Tip offset in blade heights per m/s of wind (`Lean.x` in lean.comp), and the most.
const LEAN_PER_MS: f32 = 0.08;
const MOST_LEAN: f32 = 0.6;

/// The lean response: its uniform block (`Lean`), uploaded once.
struct LeanResponse {
    lean: Buffer,
}

impl LeanResponse {
    fn new(device: &Device) -> meadow::Result<Self> {
        let mut batch = UploadBatch::new(device);
        let block = [LEAN_PER_MS, MOST_LEAN, 0.0, 0.0];
        let usage = vk::BufferUsageFlags::UNIFORM_BUFFER;
        let lean = batch.buffer("lean", &block, usage, &[Access::ComputeShaderUniformRead])?;
        batch.submit()?;
        Ok(Self { lean })
    }
}

impl BladeResponse for LeanResponse {
    fn name(&self) -> &'static str {
        "lean"
    }

    fn specialize(&self, _: &mut Specialization) {}

    fn blade_input(&self) -> BladeInput {
        BladeInput::PoseRecords
    }

    fn tracked(&self) -> Vec<(Resource, Vec<Access>)> {
        vec![(Resource::Buffer(self.lean.raw), vec![Access::ComputeShaderUniformRead])]
    }

    fn passes(&self, device: &Device, setup: &ResponseSetup) -> meadow::Result<Vec<Box<dyn Pass>>> {
        // The library's pose pass runs lean.comp over the drawn blades: the response is its shader
        // and its uniform block.
        let shader = PoseShader {
            name: "lean",
            spirv: LEAN_COMP.code(device.profile),
            resources: vec![("Lean", Descriptor::Buffer(self.lean.descriptor()))],
            uses: vec![(Resource::Buffer(self.lean.raw), Access::ComputeShaderUniformRead)],
            uniforms: None,
            store: None,
        };
        Ok(vec![Box::new(PosePass::new(device, setup, shader)?)])
    }

    fn tip_offset(&self, wind: Vec3) -> Vec3 {
        let offset = Vec3::new(wind.x, 0.0, wind.z) * LEAN_PER_MS;
        offset.clamp_length_max(MOST_LEAN)
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.lean.destroy(device) };
    }
}

/// The pictures (RGBA) of `scene` from `camera` under each wind, with the new models, through
/// the cull and LOD, and the names of the passes of the last.
fn render(scene: &Scene, camera: &Camera, winds: &[Vec3]) -> (Vec<Vec<u8>>, Vec<&'static str>) {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut pictures = Vec::new();
        let mut passes = Vec::new();
        for &velocity in winds {
            let models = Models {
                wind: Box::new(steady_wind::SteadyWind::constant(velocity)),
                response: Rc::new(|device: &Device, _: &_| Ok(Box::new(LeanResponse::new(device)?) as Box<_>)),
                ..Models::default()
            };
            let settings = RenderSettings::offscreen(4, Culling::default_for(4));
            let mut renderer = Renderer::with_models(device.clone(), scene, settings, Default::default(), models)?;
            // Two frames: the second one's barriers follow the first one's accesses.
            for _ in 0..2 {
                renderer.render_offscreen(&mut target, camera, 0.0)?;
            }
            pictures.push(target.pixels().to_vec());
            passes = renderer.pass_names();
        }
        // SAFETY: render_offscreen waited for its frame; the renderers are gone.
        unsafe { target.destroy(device) };
        Ok((pictures, passes))
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// Where the picture's blades are, across: the mean column of the pixels that differ from the
/// calm picture's, weighted by how much greener than the calm picture they are (a blade moved
/// onto the pixel) minus how much less green (a blade moved off it). Positive: the blades'
/// coverage moved right.
fn coverage_shift(picture: &[u8], calm: &[u8]) -> f64 {
    let width = EXTENT.width as usize;
    let (mut moment, mut mass) = (0.0f64, 0.0f64);
    for (i, (p, c)) in picture.chunks_exact(4).zip(calm.chunks_exact(4)).enumerate() {
        let green = |px: &[u8]| f64::from(px[1]) - 0.5 * (f64::from(px[0]) + f64::from(px[2]));
        let gained = green(p) - green(c);
        let x = (i % width) as f64 - 0.5 * width as f64;
        moment += gained * x;
        mass += gained.abs();
    }
    if mass == 0.0 {
        0.0
    } else {
        moment / mass
    }
}

/// Which way, across the picture, world +x runs from `camera`: +1 right, -1 left.
fn screen_sign_of_x(camera: &Camera) -> f64 {
    let vp = camera.view_projection(EXTENT.width as f32 / EXTENT.height as f32);
    let ahead = camera.position + camera.forward() * 5.0;
    let ndc = |p: Vec3| {
        let c = vp * Vec4::new(p.x, p.y, p.z, 1.0);
        c.x / c.w
    };
    (ndc(ahead + Vec3::X) - ndc(ahead)).signum().into()
}

/// Both fields lean the way the wind blows.
fn assert_leans(scene: &Scene, camera: &Camera) {
    let wind = 5.0;
    let (pictures, passes) = render(scene, camera, &[Vec3::ZERO, Vec3::X * wind, -Vec3::X * wind]);
    for name in ["steady wind", "lean", "blade levels", "blades"] {
        assert!(passes.contains(&name), "{name} in {passes:?}");
    }
    let calm = &pictures[0];
    let sign = screen_sign_of_x(camera);
    let with = coverage_shift(&pictures[1], calm) * sign;
    let against = coverage_shift(&pictures[2], calm) * sign;
    // The wind along +x moves the blades' coverage towards +x on the screen; along -x, away.
    assert!(with > 1.0, "wind +x: coverage moved {with:.2} px along screen +x");
    assert!(against < -1.0, "wind -x: coverage moved {against:.2} px along screen +x");
    // (Measured: +6.6 / -3.4 px on the block field, +5.3 / -1.5 px on the stored field; a
    // response that ignored the wind, or a wind field whose pass did not run, moves nothing.)
}

#[test]
fn a_block_field_leans_the_way_a_uniform_wind_blows() {
    let scene = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1);
    let relief = scene.field.as_ref().expect("a field").ground.height(1.5, 2.5) as f32;
    let camera = Camera { position: Vec3::new(1.5, relief + 1.2, 2.5), yaw_deg: 0.0, pitch_deg: -20.0 };
    assert_leans(&scene, &camera);
}

#[test]
fn a_stored_field_leans_the_way_a_uniform_wind_blows() {
    let scene = Scene::generate(20_000, 4);
    let camera = Camera::default_for(&scene.terrain);
    assert_leans(&scene, &camera);
}
