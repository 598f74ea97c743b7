//! The pass graph and the frame ring on lavapipe: barriers derived from declarations (a wrong
//! declaration is caught), declarations the graph refuses, a failed submission that reports
//! an error instead of hanging, query pools sized by the graph (40 passes timed), a run-once
//! pass, and `Prerecorded` replays that never go stale. (The test pass of a ping-pong chain is
//! `tests/graph_pass.rs`.)

#[path = "support/glsl.rs"]
mod glsl;
mod support;

use std::cell::Cell;
use std::rc::Rc;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use ash::vk::Handle;
use meadow::app::{with_device, GpuOptions};
use meadow::render::graph::{Declaration, Graph, Pass, PassContext, Rendering, Runs, Scopes};
use meadow::render::target::TargetView;
use meadow::vk::commands::{self, CommandRecorder};
use meadow::vk::query::TimestampQueries;
use meadow::vk::{Access, Buffer, BufferDesc, Device, DeviceSelector, Resource};
use support::{meadow, transcript};

fn options() -> GpuOptions {
    GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") }
}

const FILL: u32 = 0x5eed_1234;

/// Fills a buffer with `vkCmdFillBuffer`, declaring `declared` for it (right: `TransferWrite`).
struct FillPass {
    buffer: vk::Buffer,
    declared: Access,
}

impl Pass for FillPass {
    fn name(&self) -> &'static str {
        "fill"
    }
    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.buffer, self.declared))
    }
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        // SAFETY: recording outside a rendering instance; the buffer is live.
        unsafe { ctx.device.raw.cmd_fill_buffer(cmd, self.buffer, 0, vk::WHOLE_SIZE, FILL) };
        Ok(())
    }
    unsafe fn destroy(self: Box<Self>, _: &Device) {}
}

/// Copies one buffer into another, declaring both rightly.
struct CopyPass {
    from: vk::Buffer,
    to: vk::Buffer,
    bytes: u64,
}

impl Pass for CopyPass {
    fn name(&self) -> &'static str {
        "copy"
    }
    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.from, Access::TransferRead).buffer(self.to, Access::TransferWrite))
    }
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        let region = vk::BufferCopy { src_offset: 0, dst_offset: 0, size: self.bytes };
        // SAFETY: recording outside a rendering instance; both buffers hold `bytes`.
        unsafe { ctx.device.raw.cmd_copy_buffer(cmd, self.from, self.to, &[region]) };
        Ok(())
    }
    unsafe fn destroy(self: Box<Self>, _: &Device) {}
}

/// A graphics pass declaring uses of a colour image.
struct DrawPass {
    image: vk::Image,
    uses: Vec<Access>,
}

impl Pass for DrawPass {
    fn name(&self) -> &'static str {
        "draw"
    }
    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        let rendering = Rendering {
            extent: vk::Extent2D { width: 4, height: 4 },
            color: None,
            depth: None,
            depth_write: false,
            pipeline: vk::Pipeline::null(),
            secondary: false,
        };
        Some(self.uses.iter().fold(Declaration::graphics(rendering), |d, &a| d.uses(Resource::color(self.image), a)))
    }
    fn record(&self, _: &PassContext, _: vk::CommandBuffer) -> meadow::Result<()> {
        unreachable!("refused before recording")
    }
    unsafe fn destroy(self: Box<Self>, _: &Device) {}
}

fn null_target() -> TargetView {
    TargetView {
        color: vk::Image::null(),
        color_view: vk::ImageView::null(),
        depth: vk::Image::null(),
        depth_view: vk::ImageView::null(),
        extent: vk::Extent2D { width: 4, height: 4 },
        color_previous: Access::Nothing,
        depth_previous: Access::Nothing,
    }
}

/// Record `graph` once, submit, wait; the result of `graph.record`.
fn run(device: &Arc<Device>, graph: &mut Graph, release: &[(Resource, Access)]) -> meadow::Result<()> {
    let recorder = CommandRecorder::new(device, "graph test")?;
    let mut timestamps = TimestampQueries::new(device, "graph test timestamps", 8)?;
    let target = null_target();
    let result = (|| {
        let cmd = recorder.begin(device)?;
        let uniforms = bytemuck::Zeroable::zeroed();
        let ctx = PassContext {
            device,
            target: &target,
            output: &target,
            slot: 0,
            descriptor_set: vk::DescriptorSet::null(),
            uniforms: &uniforms,
            clock: Default::default(),
            step: 0,
            temporals: &[],
        };
        let plan = graph.plan(&ctx, false)?;
        assert!(plan.timestamps() <= timestamps.capacity());
        let mut scopes = Scopes { timestamps: &mut timestamps, statistics: None };
        graph.record(&ctx, &plan, cmd, &mut scopes, Default::default())?;
        graph.release(device, cmd, release);
        recorder.end(device)?;
        let fence = meadow::vk::sync::fence(device, false, "graph test fence")?;
        commands::submit(device, cmd, &[], &[], fence)?;
        meadow::vk::sync::wait_fence(device, fence)?;
        // SAFETY: waited.
        unsafe { device.raw.destroy_fence(fence, None) };
        Ok(())
    })();
    if result.is_err() {
        let _ = device.wait_idle();
    }
    // SAFETY: waited (or idle).
    unsafe {
        timestamps.destroy(device);
        recorder.destroy(device);
    }
    result
}

/// Fill then copy to a readback buffer through the graph, the fill declared as `declared`.
fn fill_then_copy(declared: Access) -> (meadow::Result<Vec<u32>>, Option<u64>) {
    with_device(&options(), false, |device| {
        let bytes = 256;
        let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        let source = Buffer::new(device, &BufferDesc::gpu_only("graph test source", bytes, usage))?;
        let readback = Buffer::new(device, &BufferDesc::readback("graph test readback", bytes, usage))?;
        let mut graph = Graph::new();
        graph.add(FillPass { buffer: source.raw, declared });
        graph.add(CopyPass { from: source.raw, to: readback.raw, bytes });
        let ran = run(device, &mut graph, &[(Resource::Buffer(readback.raw), Access::HostRead)]);
        let words = bytemuck::cast_slice::<u8, u32>(readback.mapped()).to_vec();
        // SAFETY: run waited for the submission.
        unsafe {
            graph.destroy(device);
            source.destroy(device);
            readback.destroy(device);
        }
        ran.map(|()| words)
    })
}

#[test]
fn declared_accesses_give_the_barriers_and_a_wrong_one_is_caught() {
    let (words, messages) = fill_then_copy(Access::TransferWrite);
    assert_eq!(messages, Some(0), "the right declaration must be clean");
    assert!(words.expect("ran").iter().all(|&w| w == FILL), "the copy saw the fill");

    // Declared as a read, the fill gets no barrier before the copy reads it: synchronization
    // validation reports the read-after-write hazard, and a test under validation fails.
    let (ran, messages) = fill_then_copy(Access::ComputeShaderRead);
    ran.expect("recorded and submitted");
    assert!(messages.unwrap_or(0) >= 1, "a fill declared as a read went unreported");
}

#[test]
fn the_graph_refuses_unimported_images_and_two_layouts_in_one_pass() {
    let (result, messages) = with_device(&options(), false, |device| {
        let image = vk::Image::from_raw(0x1234);
        let mut outcomes = Vec::new();
        let sampled_too = vec![Access::TransferRead, Access::FragmentShaderSampledRead];
        for (imported, uses) in [(false, vec![Access::TransferRead]), (true, sampled_too)] {
            let mut graph = Graph::new();
            if imported {
                graph.import(Resource::color(image), &[Access::TransferRead]);
            }
            // A copy source never imported; then one imported but also sampled (two layouts).
            graph.add(DrawPass { image, uses });
            let outcome = run(device, &mut graph, &[]);
            // SAFETY: the passes own nothing.
            unsafe { graph.destroy(device) };
            outcomes.push(outcome.err().map(|e| e.to_string()));
        }
        Ok(outcomes)
    });
    let outcomes = result.expect("device");
    assert!(outcomes[0].as_deref().is_some_and(|e| e.contains("never imported")), "{outcomes:?}");
    assert!(outcomes[1].as_deref().is_some_and(|e| e.contains("two layouts")), "{outcomes:?}");
    assert_eq!(messages, Some(0));
}

/// Run `meadow ARGS` with the N-th submission failing; it must exit 1 with one error line, soon.
fn fails_cleanly(args: &[&str], nth: &str) {
    let started = Instant::now();
    let output = meadow().args(args).env("MEADOW_INJECT_SUBMIT_FAILURE", nth).output().expect("run meadow");
    assert!(started.elapsed() < Duration::from_secs(60), "took {:?}", started.elapsed());
    assert_eq!(output.status.code(), Some(1), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let lost = "error: vkQueueSubmit2 (injected failure): the GPU device was lost (VK_ERROR_DEVICE_LOST)";
    assert!(stderr.contains(lost) && stderr.lines().count() == 1, "{stderr}");
    assert!(String::from_utf8_lossy(&output.stdout).contains("validation: 0 messages"), "{}", transcript(&output));
}

#[test]
fn a_failed_submission_reports_an_error_and_never_hangs() {
    let dir = support::scratch("graph-submit-failure");
    let out = dir.join("x.png");
    let out = out.to_str().expect("utf-8");
    let common = ["--validation", "--device", support::DEVICE, "--blades", "500", "--size", "32x32"];
    let render: Vec<&str> = ["render"].iter().chain(&common).chain(&["--frames", "3", "--out", out]).copied().collect();
    fails_cleanly(&render, "2");
    assert!(!dir.join("x.png").exists(), "nothing written after a failed frame");
    // Frames in flight: the failing frame's slot is waited again while others are pending.
    let timing = dir.join("timing");
    let timing = timing.to_str().expect("utf-8");
    let args: Vec<&str> =
        ["timing"].iter().chain(&common).chain(&["--frames", "6", "--warmup", "0", "--out", timing]).copied().collect();
    fails_cleanly(&args, "3");
}

fn small_settings(frames_in_flight: usize) -> meadow::render::RenderSettings {
    use meadow::render::{culling::Culling, RenderSettings};
    RenderSettings { frames_in_flight, ..RenderSettings::offscreen(2, Culling::default_for(2)) }
}

#[test]
fn after_a_failed_submission_every_slot_can_be_waited_and_reused() {
    // Also multisampled: the failed first frame made the multisampled images, and the graph's
    // states went back to before it; the next frame must import them again.
    for samples in [1, 4] {
        failed_submission_then_reuse(samples);
    }
}

fn failed_submission_then_reuse(samples: u32) {
    use meadow::render::msaa::Msaa;
    use meadow::render::{OffscreenTarget, Renderer};
    let (result, messages) = with_device(&options(), false, |device| {
        let scene = meadow::scene::Scene::generate(300, 3);
        let settings =
            meadow::render::RenderSettings { msaa: Msaa { samples, alpha_to_coverage: true }, ..small_settings(2) };
        let mut renderer = Renderer::new(device.clone(), &scene, settings, Default::default())?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 16, height: 16 })?;
        let camera = meadow::scene::Camera::default_for(&scene.terrain);
        renderer.inject_submit_failure(1);
        let failed = renderer.render_offscreen(&mut target, &camera, 0.0);
        // Every slot, the failed one included, is waited without hanging, then renders again.
        for _ in 0..3 {
            renderer.begin_frame()?;
        }
        let again = renderer.render_offscreen(&mut target, &camera, 0.0).map(|t| t.gpu_ms);
        drop(renderer);
        // SAFETY: the renderer waited for the device on drop.
        unsafe { target.destroy(device) };
        Ok((failed.err().map(|e| e.to_string()), again))
    });
    let (failed, again) = result.expect("device");
    assert!(failed.is_some_and(|e| e.contains("ERROR_DEVICE_LOST")), "{samples} samples");
    assert!(again.expect("renders after the failure") > 0.0, "{samples} samples");
    assert_eq!(messages, Some(0));
}

#[test]
fn rebuilt_passes_are_freed_behind_the_frames_in_flight() {
    use meadow::render::animation::{AnimationSettings, Eval, Mode};
    use meadow::render::graph::Outputs;
    use meadow::render::renderer::FrameSync;
    use meadow::render::{OffscreenTarget, Renderer};
    let (result, messages) = with_device(&options(), false, |device| {
        let scene = meadow::scene::Scene::generate(2000, 5);
        let mut renderer = Renderer::new(device.clone(), &scene, small_settings(2), Default::default())?;
        let target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 48 })?;
        let camera = meadow::scene::Camera::default_for(&scene.terrain);
        let mut view = target.view();
        let frame = |renderer: &mut Renderer, view: &mut TargetView| -> meadow::Result<()> {
            let (slot, _) = renderer.begin_frame()?;
            renderer.submit_frame(slot, view, &camera, 0.5, FrameSync::default(), Outputs::default())?;
            view.color_previous = Access::ColorAttachmentWrite;
            view.depth_previous = Access::DepthAttachmentReadWrite;
            Ok(())
        };
        let mut pending = Vec::new();
        // Each switch while two frames are in flight with the old pipelines: the cluster-bounds
        // view (passes only: nothing is uploaded, so nothing waits for the queue), then texture
        // keyframes per blade (a compute pass appears), static blades, and the floor.
        let bounds = meadow::render::RenderSettings { debug_bounds: true, ..small_settings(2) };
        let per_blade = AnimationSettings { eval: Eval::Blade, ..Default::default() };
        let still = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let floor = meadow::render::RenderSettings { floor: true, ..small_settings(2) };
        let steps = [
            (bounds, AnimationSettings::default()),
            (small_settings(2), per_blade),
            (small_settings(2), still.clone()),
            (floor, still),
        ];
        for (settings, animation) in steps {
            frame(&mut renderer, &mut view)?;
            frame(&mut renderer, &mut view)?;
            renderer.rebuild(&scene, settings, animation)?;
            pending.push((renderer.pending_deletions(), renderer.pass_names()));
        }
        frame(&mut renderer, &mut view)?;
        renderer.wait_all_frames()?;
        let after = renderer.pending_deletions();
        // A change the frames depend on is refused, and the renderer keeps working.
        let refused = renderer.rebuild(&scene, small_settings(3), Default::default()).is_err();
        frame(&mut renderer, &mut view)?;
        drop(renderer);
        // SAFETY: the renderer waited for the device on drop.
        unsafe { target.destroy(device) };
        Ok((pending, after, refused))
    });
    let (pending, after, refused) = result.expect("device");
    // Destroying a pipeline a pending command buffer uses is a validation error: none.
    assert_eq!(messages, Some(0));
    for (queued, _) in &pending {
        assert_eq!(*queued, 1, "the old passes and model wait behind the frames in flight: {pending:?}");
    }
    let cull = ["depth pyramid", "cull tiles", "cull count", "cull scan", "cull emit"];
    let with_cull = |before: &[&'static str], after: &[&'static str]| [before, &cull[..], after].concat();
    // With the cull, a model that reads the wind (and the bounds view) has the wind field
    // evaluated on the GPU first (`render::wind`); static blades without the bounds view read none.
    assert_eq!(pending[0].1, [&["wind field"][..], &with_cull(&["terrain"], &["blades", "cluster bounds"])].concat());
    // With the cull, the per-blade evaluation reads its visible list: after it, and the drawn
    // blades' levels are placed from its records (bent by the pressed map, `press`, moved out of
    // any collider, `push-out`, and drawn by their interaction patches, `patches`) before the blade
    // pass.
    let per_blade = with_cull(&["terrain"], &["blade poses", "press", "push-out", "patches", "blade levels", "blades"]);
    assert_eq!(pending[1].1, [&["wind field"][..], &per_blade].concat());
    assert_eq!(pending[2].1, with_cull(&["terrain"], &["blades"]));
    assert_eq!(pending[3].1, ["terrain", "blades"], "the floor stands in for the blade pass");
    assert_eq!(after, 0, "freed once the frames finished");
    assert!(refused);
}

fn brute_force(frames_in_flight: usize) -> meadow::render::RenderSettings {
    use meadow::render::{culling::Culling, RenderSettings};
    let culling = Culling { enabled: false, ..Culling::default_for(2) };
    RenderSettings { frames_in_flight, ..RenderSettings::offscreen(2, culling) }
}

/// Fills its own buffer: one of many passes.
struct NumberedFill {
    name: &'static str,
    buffer: Buffer,
}

impl Pass for NumberedFill {
    fn name(&self) -> &'static str {
        self.name
    }
    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.buffer.raw, Access::TransferWrite))
    }
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        // SAFETY: recording outside a rendering instance; the buffer is live.
        unsafe { ctx.device.raw.cmd_fill_buffer(cmd, self.buffer.raw, 0, vk::WHOLE_SIZE, FILL) };
        Ok(())
    }
    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.buffer.destroy(device) };
    }
}

#[test]
fn a_graph_of_forty_passes_reports_forty_pass_times() {
    use meadow::render::{OffscreenTarget, Renderer};
    let (result, messages) = with_device(&options(), false, |device| {
        let scene = meadow::scene::Scene::generate(300, 3);
        let mut renderer = Renderer::new(device.clone(), &scene, brute_force(2), Default::default())?;
        let own = renderer.pass_names().len();
        let mut names = Vec::new();
        for i in 0..40 - own {
            let name: &'static str = Box::leak(format!("fill {i}").into_boxed_str());
            let usage = vk::BufferUsageFlags::TRANSFER_DST;
            let buffer = Buffer::new(device, &BufferDesc::gpu_only(name, 64, usage))?;
            renderer.add_pass(Box::new(NumberedFill { name, buffer }));
            names.push(name);
        }
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 16, height: 16 })?;
        let camera = meadow::scene::Camera::default_for(&scene.terrain);
        let timings = renderer.render_offscreen(&mut target, &camera, 0.0)?;
        let graph = renderer.pass_names();
        drop(renderer);
        // SAFETY: the renderer waited for the device on drop.
        unsafe { target.destroy(device) };
        Ok((names, graph, timings))
    });
    let (names, graph, timings) = result.expect("device");
    assert_eq!(messages, Some(0));
    assert_eq!(graph.len(), 40);
    let timed: Vec<&str> = timings.passes.iter().map(|p| p.name).collect();
    assert_eq!(timed, graph, "every pass of the graph is timed, in order");
    assert_eq!(&timed[..names.len()], &names[..], "passes added from outside run first");
    for pair in timings.passes.windows(2) {
        assert!(pair[1].start_ns >= pair[0].start_ns, "{pair:?}");
    }
    assert!(timings.passes.iter().all(|p| p.ms.is_finite() && p.ms >= 0.0));
}

/// A run-once pass: counts its runs on the GPU (`tests/shaders/count_runs.comp`) and its
/// recordings on the CPU; it runs again when its input changes.
struct CountRunsPass {
    input: Rc<Cell<u32>>,
    recorded: Rc<Cell<u32>>,
    runs: vk::Buffer,
    pipeline: glsl::ComputePipeline,
}

impl Pass for CountRunsPass {
    fn name(&self) -> &'static str {
        "count runs"
    }
    fn runs(&self, _: &PassContext) -> Runs {
        Runs::OnChange(u64::from(self.input.get()))
    }
    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        let declaration = Declaration::compute()
            .buffer(self.runs, Access::ComputeShaderRead)
            .buffer(self.runs, Access::ComputeShaderWrite)
            .step("to host")
            .buffer(self.runs, Access::HostRead);
        Some(declaration)
    }
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        if ctx.step == 0 {
            self.recorded.set(self.recorded.get() + 1);
            self.pipeline.dispatch(ctx.device, cmd, 0, bytemuck::bytes_of(&self.input.get()), 1);
        }
        Ok(())
    }
    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.pipeline.destroy(device) };
    }
}

#[test]
fn a_run_once_pass_runs_once_and_again_only_when_its_input_changes() {
    use meadow::render::{OffscreenTarget, Renderer};
    let (result, messages) = with_device(&options(), false, |device| {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let mut runs = Buffer::new(device, &BufferDesc::readback("runs", 8, usage))?;
        runs.write(0, &[0u32, 0]);
        let pipeline = glsl::ComputePipeline::new(device, "count_runs.comp", 1, 4, 1)?;
        pipeline.write(device, 0, &[runs.raw]);
        let (input, recorded) = (Rc::new(Cell::new(7)), Rc::new(Cell::new(0)));
        let scene = meadow::scene::Scene::generate(300, 3);
        let mut renderer = Renderer::new(device.clone(), &scene, brute_force(2), Default::default())?;
        let pass = CountRunsPass { input: input.clone(), recorded: recorded.clone(), runs: runs.raw, pipeline };
        renderer.add_pass(Box::new(pass));
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 16, height: 16 })?;
        let camera = meadow::scene::Camera::default_for(&scene.terrain);
        let mut seen = Vec::new();
        // Three frames with input 7; then input 9, whose first frame fails to submit; two more.
        for frame in 0..6 {
            if frame == 3 {
                input.set(9);
                renderer.inject_submit_failure(1);
            }
            let rendered = renderer.render_offscreen(&mut target, &camera, 0.0);
            assert_eq!(rendered.is_err(), frame == 3, "frame {frame}");
            renderer.wait_all_frames()?;
            let words = bytemuck::cast_slice::<u8, u32>(runs.mapped()).to_vec();
            seen.push((words[0], words[1], recorded.get()));
        }
        drop(renderer);
        // SAFETY: the renderer waited for the device on drop.
        unsafe {
            target.destroy(device);
            runs.destroy(device);
        }
        Ok(seen)
    });
    let seen = result.expect("device");
    assert_eq!(messages, Some(0));
    // (GPU runs, input of the last run, recordings) after each frame: the dropped frame's run is
    // recorded again by the next frame and counts once.
    assert_eq!(seen, [(1, 7, 1), (1, 7, 1), (1, 7, 1), (1, 7, 2), (2, 9, 3), (2, 9, 3)]);
}

/// 3 000 blades over 40 m of terrain: 80 cells a side, 5 × 5 chunks (`terrain_chunks`).
fn wide_sparse_field() -> meadow::scene::Scene {
    use meadow::scene::{blades, terrain::Terrain, tiles};
    let terrain = Terrain::generate(40.0, 5);
    let mut blades = blades::scatter(&terrain, 3000, 5);
    let tile_grid = tiles::TileGrid::new(terrain.size);
    let tiles = tiles::arrange(&tile_grid, &mut blades);
    meadow::scene::Scene {
        terrain,
        blades,
        tile_grid,
        tiles,
        field: None,
        cover: Default::default(),
        clumps: None,
        flowers: None,
    }
}

#[test]
fn a_prerecorded_replay_with_a_moving_camera_gives_the_pictures_of_recording_each_frame() {
    use meadow::render::submission::{Strategy, Submission};
    use meadow::render::{OffscreenTarget, Renderer};
    let (result, messages) = with_device(&options(), false, |device| {
        let scene = wide_sparse_field();
        let mut pictures = Vec::new();
        let mut replayed = Vec::new();
        for strategy in [Strategy::Instanced, Strategy::Prerecorded] {
            let settings =
                meadow::render::RenderSettings { submission: Submission { strategy, clusters: 1 }, ..brute_force(2) };
            let mut renderer = Renderer::new(device.clone(), &scene, settings, Default::default())?;
            let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 48 })?;
            // From the middle of the field: other terrain chunks in view whichever way it looks.
            let eye = glam::Vec3::new(0.0, scene.terrain.height_at(0.0, 0.0) + 1.7, 0.0);
            let start = meadow::scene::Camera { position: eye, yaw_deg: 0.0, pitch_deg: -20.0 };
            let mut frames = Vec::new();
            let mut replays = Vec::new();
            // Turning 40 degrees a frame (other terrain chunks in view each frame), then still.
            for frame in 0..12 {
                let turn = 40.0 * frame.min(8) as f32;
                let camera = meadow::scene::Camera { yaw_deg: start.yaw_deg + turn, ..start };
                let timings = renderer.render_offscreen(&mut target, &camera, 0.25)?;
                frames.push(target.pixels().to_vec());
                replays.push(timings.replayed);
            }
            drop(renderer);
            // SAFETY: the renderer waited for the device on drop.
            unsafe { target.destroy(device) };
            pictures.push(frames);
            replayed.push(replays);
        }
        Ok((pictures, replayed))
    });
    let (pictures, replayed) = result.expect("device");
    assert_eq!(messages, Some(0));
    for (frame, (recorded, replay)) in pictures[0].iter().zip(&pictures[1]).enumerate() {
        assert!(recorded == replay, "frame {frame}: the prerecorded picture differs");
    }
    let differing = |a: &[u8], b: &[u8]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    let turns: Vec<usize> = pictures[0][..9].windows(2).map(|pair| differing(&pair[0], &pair[1])).collect();
    assert!(turns.iter().all(|&d| d > 0), "the camera's turn changes the picture: {turns:?}");
    assert!(replayed[0].iter().all(|r| !r), "recorded every frame: {:?}", replayed[0]);
    // The still frames (past the first of each slot) replay the kept recordings.
    assert!(replayed[1][10..].iter().all(|&r| r), "{:?}", replayed[1]);
}
