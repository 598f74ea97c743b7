//! A run-once pass (`Runs::OnChange`) with its own set-0 instance (`Renderer::frame_instance`)
//! and its own orthographic camera, defined here with its own shader
//! (`tests/shaders/bake_project.comp`, which reads the library's `FrameUniforms` through
//! `common/bindings.glsl`) and its own set: it projects points through the camera of its own
//! frame uniforms, which match a CPU reference of that orthographic camera and not the main
//! camera the frame renders with; it runs once, and again only when its camera changes.

#[path = "support/glsl.rs"]
mod glsl;
mod support;

use std::cell::Cell;
use std::rc::Rc;

use ash::vk;
use glam::{Vec2, Vec3, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::culling::Culling;
use meadow::render::graph::{Declaration, Pass, PassContext, PassUniforms, Runs};
use meadow::render::recording::{PassSet, PassSetDesc};
use meadow::render::renderer::FrameInstance;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{Camera, OrthographicCamera};
use meadow::vk::descriptor::Resource as Descriptor;
use meadow::vk::{pipeline, Access, Buffer, BufferDesc, Device, DeviceSelector};

/// Points projected.
const POINTS: usize = 64;

/// The bake: its camera, its frame instance, its own set and pipeline, the points and their
/// projections.
struct BakePass {
    camera: Rc<Cell<OrthographicCamera>>,
    frame: FrameInstance,
    set: PassSet,
    pipeline: vk::Pipeline,
    buffers: [vk::Buffer; 2],
    recorded: Rc<Cell<u32>>,
}

/// A digest of the camera: the bake's only input.
fn camera_key(c: &OrthographicCamera) -> u64 {
    let words = [c.position.to_array(), c.forward.to_array(), c.up.to_array()].concat().into_iter().chain([
        c.half_extent.x,
        c.half_extent.y,
        c.near,
        c.far,
    ]);
    words.fold(0xcbf2_9ce4_8422_2325u64, |h, w| (h ^ u64::from(w.to_bits())).wrapping_mul(0x100_0000_01b3))
}

impl Pass for BakePass {
    fn name(&self) -> &'static str {
        "test bake"
    }

    fn runs(&self, _: &PassContext) -> Runs {
        Runs::OnChange(camera_key(&self.camera.get()))
    }

    fn uniforms(&self, ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        let own = ctx.uniforms.with_orthographic(&self.camera.get());
        Some((&self.frame.uniforms, bytemuck::bytes_of(&own).to_vec()))
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        let declaration = Declaration::compute()
            .buffer(self.buffers[0], Access::ComputeShaderRead)
            .buffer(self.buffers[1], Access::ComputeShaderWrite)
            .step("to host")
            .buffer(self.buffers[1], Access::HostRead);
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        if ctx.step != 0 {
            return Ok(());
        }
        self.recorded.set(self.recorded.get() + 1);
        let (device, bind) = (ctx.device, vk::PipelineBindPoint::COMPUTE);
        // SAFETY: cmd is recording outside a rendering instance; both sets match the layout.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, bind, self.pipeline);
            device.raw.cmd_bind_descriptor_sets(cmd, bind, self.set.layout, 0, &[self.frame.set(ctx.slot)], &[]);
        }
        self.set.bind(device, cmd, bind, 0);
        // SAFETY: as above.
        unsafe { device.raw.cmd_dispatch(cmd, (POINTS as u32).div_ceil(64), 1, 1) };
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            meadow::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
            self.frame.destroy(device);
        }
    }
}

/// The points: a spread around the default camera's view and the bake's box.
fn points() -> Vec<Vec4> {
    (0..POINTS).map(|i| Vec4::new(i as f32 * 0.37 - 9.0, (i % 7) as f32 * 0.1, 4.0 - (i % 5) as f32, 1.0)).collect()
}

/// The cameras the bake renders with: from the side, then from above.
fn cameras() -> [OrthographicCamera; 2] {
    let side = OrthographicCamera {
        position: Vec3::new(12.0, 0.3, 0.0),
        forward: Vec3::NEG_X,
        up: Vec3::Y,
        half_extent: Vec2::new(6.0, 1.0),
        near: 0.0,
        far: 30.0,
    };
    let above = OrthographicCamera {
        position: Vec3::new(0.0, 20.0, 0.0),
        forward: Vec3::NEG_Y,
        up: Vec3::NEG_Z,
        half_extent: Vec2::new(10.0, 10.0),
        near: 1.0,
        far: 40.0,
    };
    [side, above]
}

/// Each frame's projections and the bake's recordings so far.
type Frames = Vec<(Vec<Vec4>, u32)>;

/// Each frame's projections and recordings: three frames with the side camera, then three with
/// the camera from above. Also the main camera's view-projection.
fn run(device: &std::sync::Arc<Device>) -> meadow::Result<(Frames, glam::Mat4)> {
    let scene = meadow::scene::Scene::generate(300, 3);
    let settings = RenderSettings {
        frames_in_flight: 2,
        ..RenderSettings::offscreen(2, Culling { enabled: false, ..Culling::default_for(2) })
    };
    let mut renderer = Renderer::new(device.clone(), &scene, settings, Default::default())?;
    let bytes = (16 * POINTS) as u64;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let mut input = Buffer::new(device, &BufferDesc::upload("bake points", bytes, usage))?;
    input.write(0, &points());
    let output = Buffer::new(device, &BufferDesc::readback("bake projections", bytes, usage))?;
    let spirv = glsl::compile_for("bake_project.comp", device.profile);
    let frame = renderer.frame_instance("test bake")?;
    let desc = PassSetDesc {
        name: "test bake",
        shaders: &[("bake_project.comp", &spirv)],
        before: &[renderer.frame_set_layout()],
        push: &[],
        frames: 1,
    };
    let set = PassSet::new(device, &desc, |_| {
        vec![("Points", Descriptor::Buffer(input.descriptor())), ("Projected", Descriptor::Buffer(output.descriptor()))]
    })?;
    let pipeline = pipeline::compute(device, "test bake", &spirv, set.layout, &[])?;
    let camera = Rc::new(Cell::new(cameras()[0]));
    let recorded = Rc::new(Cell::new(0));
    let buffers = [input.raw, output.raw];
    let pass = BakePass { camera: camera.clone(), frame, set, pipeline, buffers, recorded: recorded.clone() };
    renderer.add_pass(Box::new(pass));
    let extent = vk::Extent2D { width: 32, height: 16 };
    let mut target = OffscreenTarget::new(device, extent)?;
    let main = Camera::default_for(&scene.terrain);
    let mut seen = Vec::new();
    for frame in 0..6 {
        if frame == 3 {
            camera.set(cameras()[1]);
        }
        renderer.render_offscreen(&mut target, &main, 0.0)?;
        renderer.wait_all_frames()?;
        let projected = bytemuck::cast_slice::<u8, Vec4>(output.mapped()).to_vec();
        seen.push((projected, recorded.get()));
    }
    drop(renderer);
    // SAFETY: the renderer waited for the device on drop.
    unsafe {
        target.destroy(device);
        input.destroy(device);
        output.destroy(device);
    }
    Ok((seen, main.view_projection(extent.width as f32 / extent.height as f32)))
}

fn close(a: &[Vec4], b: &[Vec4]) -> bool {
    a.iter().zip(b).all(|(x, y)| (*x - *y).abs().max_element() <= 1e-5 * (1.0 + y.abs().max_element()))
}

#[test]
fn a_run_once_pass_renders_with_its_own_orthographic_camera_and_not_the_main_one() {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, run);
    let (seen, main) = result.expect("frames");
    assert_eq!(messages, Some(0));
    let reference = |c: &OrthographicCamera| points().iter().map(|&p| c.view_projection() * p).collect::<Vec<_>>();
    let [side, above] = cameras();
    // Runs once for the side camera, once more when the camera changes.
    let recordings: Vec<u32> = seen.iter().map(|(_, n)| *n).collect();
    assert_eq!(recordings, [1, 1, 1, 2, 2, 2]);
    for (frame, (projected, _)) in seen.iter().enumerate() {
        let camera = if frame < 3 { &side } else { &above };
        assert!(
            close(projected, &reference(camera)),
            "frame {frame}: {:?} against {:?}",
            projected[1],
            reference(camera)[1]
        );
    }
    // Not the main camera's projection, nor the other bake camera's.
    let through_main: Vec<Vec4> = points().iter().map(|&p| main * p).collect();
    assert!(!close(&seen[0].0, &through_main), "the bake saw the main camera");
    assert!(!close(&seen[0].0, &reference(&above)));
}
