//! The renderer: scene on the GPU, the passes, and the frames in flight. It records the same
//! passes into any [`TargetView`] — an offscreen image for `meadow render`, a swapchain image for
//! the viewer.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{UVec4, Vec4};

use crate::error::{Result, VkContext};
use crate::keyframes::Representation;
use crate::render::animation::Mode;
use crate::render::animation::{self, AnimationSettings};
use crate::render::frame::{look, Frame, FrameUniforms};
use crate::render::passes::{BladePass, BladePosePass, FloorPass, TerrainPass};
use crate::render::scene_gpu::{self, SceneGpu};
use crate::render::specialization::Specialization;
use crate::render::submission::{self, BladeDraws, IndirectDraws, SecondaryRecorders, Strategy, Submission};
use crate::render::target::{OffscreenTarget, TargetView, DEPTH_FORMAT};
use crate::scene::bezier::{self, Batching};
use crate::scene::{Camera, Scene};
use crate::vk::image::{COLOR_RANGE, DEPTH_RANGE};
use crate::vk::query::{span_ms, PipelineStatistics};
use crate::vk::upload::UploadBatch;
use crate::vk::{commands, debug, descriptor, pipeline, sync, Access, Device};

/// Blade segments allowed (thesis 4.1 levels of detail).
pub const SEGMENTS_RANGE: std::ops::RangeInclusive<u32> = 1..=crate::render::gpu_constants::MAX_SEGMENTS;

/// How the renderer is built.
#[derive(Clone, Copy, Debug)]
pub struct RenderSettings {
    /// Quads per blade.
    pub segments: u32,
    /// Colour attachment format of the targets.
    pub color_format: vk::Format,
    /// Whether the shaders encode sRGB (UNORM targets) or the format does (`*_SRGB`).
    pub encode_srgb: bool,
    /// Frames in flight (1 for headless rendering).
    pub frames_in_flight: usize,
    /// Blades drawn per instance of the blade draw (see `BladePass::record`).
    pub blades_per_instance: u32,
    /// Colour blades by the magnitude of their force (thesis fig. 4.5 / 6.1c).
    pub debug_force: bool,
    /// Draw triangle edges only (needs `fillModeNonSolid`).
    pub wireframe: bool,
    /// Count pipeline statistics per pass (when the device has `pipelineStatisticsQuery`).
    pub pipeline_statistics: bool,
    /// How the blade pass submits its draws (`meadow overhead`); the floor ignores it.
    pub submission: Submission,
}

/// Blades per instance allowed.
pub const BLADES_PER_INSTANCE_RANGE: std::ops::RangeInclusive<u32> = 1..=1024;
/// Default blades per instance.
pub const DEFAULT_BLADES_PER_INSTANCE: u32 = 1;

/// GPU time of one pass.
#[derive(Clone, Copy, Debug)]
pub struct PassTime {
    /// Pass name.
    pub name: &'static str,
    /// Milliseconds.
    pub ms: f64,
    /// Start, in nanoseconds of the device's timestamp clock (masked, scaled).
    pub start_ns: f64,
    /// What the pass made the pipeline do, when statistics were asked for and supported.
    pub statistics: Option<PipelineStatistics>,
}

/// What one frame cost.
#[derive(Clone, Debug, Default)]
pub struct FrameTimings {
    /// CPU time to record the command buffer.
    pub cpu_record_ms: f64,
    /// CPU time of `vkQueueSubmit2`.
    pub cpu_submit_ms: f64,
    /// CPU time blocked on the frame fence.
    pub cpu_wait_ms: f64,
    /// GPU time from the first to the last timestamp of the frame.
    pub gpu_ms: f64,
    /// GPU time per pass.
    pub passes: Vec<PassTime>,
    /// First and last timestamp of the frame, in nanoseconds of the device's timestamp clock.
    pub gpu_span_ns: (f64, f64),
    /// When recording started, ended, and submission returned (`None` only in `Default`).
    pub cpu_spans: Option<[Instant; 3]>,
    /// When the fence wait before reading these timings started and ended.
    pub cpu_wait: Option<[Instant; 2]>,
}

/// Everything the renderer owns. Filled step by step in `new`; null handles and `None`s are
/// skipped at destruction, so an error half-way frees exactly what exists.
#[derive(Default)]
struct Resources {
    scene: Option<SceneGpu>,
    set_layout: vk::DescriptorSetLayout,
    pipeline_layout: vk::PipelineLayout,
    descriptor_pool: vk::DescriptorPool,
    frames: Vec<Frame>,
    terrain: Option<TerrainPass>,
    blades: Option<BladePass>,
    floor: Option<FloorPass>,
    poses: Option<BladePosePass>,
    /// Blade ranges of the per-cluster and secondary strategies.
    ranges: Vec<(u32, u32)>,
    /// Commands of the indirect strategies.
    indirect: Option<IndirectDraws>,
}

/// Scene passes and frames in flight.
pub struct Renderer {
    device: Arc<Device>,
    settings: RenderSettings,
    animation: AnimationSettings,
    resources: Option<Resources>,
    frame_index: usize,
}

/// Pass names; a frame records the passes it runs in `Frame::passes`, timestamps `i` and `i + 1`
/// bracketing pass `i`.
const PASSES: [&str; 3] = ["blade poses", "terrain", "blades"];

impl Renderer {
    /// Upload `scene` and build the passes and frames.
    pub fn new(
        device: Arc<Device>,
        scene: &Scene,
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<Self> {
        let bindings = scene_gpu::bindings();
        let mut renderer =
            Self { device: device.clone(), settings, animation, resources: Some(Resources::default()), frame_index: 0 };
        let res = renderer.resources.as_mut().expect("just set");
        let scene_gpu = res.scene.insert(SceneGpu::upload(&device, scene, settings.segments, &renderer.animation)?);
        let corners = scene_gpu.grid.corner_count();
        let emitters = animation::MAX_EMITTERS as u32;
        res.set_layout = descriptor::set_layout(&device, "scene set layout", &bindings)?;
        res.pipeline_layout = pipeline::layout(
            &device,
            "scene pipeline layout",
            &[res.set_layout],
            &[submission::push_constant_range()],
        )?;
        let (pool, sets) = descriptor::allocate_sets(
            &device,
            "scene sets",
            res.set_layout,
            &bindings,
            settings.frames_in_flight as u32,
        )?;
        res.descriptor_pool = pool;
        for (index, set) in sets.into_iter().enumerate() {
            let frame = Frame::new(&device, index, set, corners, emitters, settings.pipeline_statistics)?;
            scene_gpu.write_descriptors(&device, set, &frame);
            res.frames.push(frame);
        }
        // Specialization constant 0: the size of the keyframe uniform array (bindings.glsl).
        let specialization = Specialization::new(
            &device,
            &renderer.animation,
            settings.debug_force,
            settings.segments,
            settings.blades_per_instance,
            settings.submission.strategy.pushes_first_blade(),
            settings.encode_srgb,
        );
        let constants = specialization.constants();
        let (layout, color) = (res.pipeline_layout, settings.color_format);
        let polygon = if settings.wireframe {
            if device.features.fill_mode_non_solid == vk::FALSE {
                return Err(crate::error::Error::Environment(format!(
                    "{} cannot draw wireframes (no fillModeNonSolid)",
                    device.info.name
                )));
            }
            vk::PolygonMode::LINE
        } else {
            vk::PolygonMode::FILL
        };
        res.terrain = Some(TerrainPass::new(&device, layout, color, DEPTH_FORMAT, &constants, polygon)?);
        if renderer.animation.mode == Mode::Floor {
            res.floor = Some(FloorPass::new(&device, layout, color, DEPTH_FORMAT, &constants, polygon)?);
        } else {
            res.blades = Some(BladePass::new(&device, layout, color, DEPTH_FORMAT, &constants, polygon)?);
        }
        if specialization.eval_blade() {
            res.poses = Some(BladePosePass::new(&device, layout, &constants)?);
        }
        let Submission { strategy, clusters } = settings.submission;
        if strategy != Strategy::Instanced && renderer.animation.mode != Mode::Floor {
            if let Some(why) = strategy.unsupported(&device, clusters) {
                return Err(crate::error::Error::Environment(format!(
                    "{} cannot submit `{}`: {why}",
                    device.info.name,
                    strategy.name()
                )));
            }
            if settings.blades_per_instance != 1 {
                return Err(crate::error::Error::bad_input(
                    "submission strategies draw one blade per instance: drop --blades-per-instance",
                ));
            }
            res.ranges = submission::ranges(scene.blades.len() as u32, clusters);
            if matches!(strategy, Strategy::Indirect | Strategy::Mdi | Strategy::MdiCount) {
                let mut batch = UploadBatch::new(&device);
                let vertices = bezier::strip_vertices(settings.segments);
                res.indirect = Some(IndirectDraws::upload(&mut batch, &res.ranges, vertices)?);
                batch.submit()?;
            }
            if strategy == Strategy::Secondary {
                let workers = std::thread::available_parallelism().map_or(2, |n| n.get()).min(res.ranges.len());
                for (i, frame) in res.frames.iter_mut().enumerate() {
                    frame.secondaries =
                        Some(SecondaryRecorders::new(&device, &format!("frame {i} secondary"), workers)?);
                }
            }
        }
        Ok(renderer)
    }

    fn scene_gpu(&self) -> &SceneGpu {
        self.resources().scene.as_ref().expect("scene uploaded in new")
    }

    /// The settings the renderer was built with.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    fn resources(&self) -> &Resources {
        self.resources.as_ref().expect("renderer resources exist after new")
    }

    /// Number of blades drawn.
    pub fn blade_count(&self) -> u32 {
        self.scene_gpu().blade_count
    }

    /// Triangles of one frame: (blades, terrain).
    pub fn triangles(&self) -> (u64, u64) {
        let scene = self.scene_gpu();
        (BladePass::triangles(scene, self.settings.segments), TerrainPass::triangles(scene))
    }

    /// The uniforms of a frame seen from `camera` at simulation time `time` into `extent`.
    pub fn frame_uniforms(&self, camera: &Camera, time: f32, extent: vk::Extent2D) -> FrameUniforms {
        let scene = self.scene_gpu();
        let aspect = extent.width as f32 / extent.height as f32;
        FrameUniforms {
            view_proj: camera.view_projection(aspect),
            camera_position: camera.position.extend(time),
            sun_direction: look::sun_direction().extend(0.0),
            sky_color: look::SKY.extend(look::FOG_DENSITY),
            terrain: Vec4::new(scene.terrain_origin, scene.terrain_cell_size, 0.0, 0.0),
            params: UVec4::new(self.settings.segments, scene.blade_count, scene.terrain_cells, 0),
            keyframes: UVec4::new(
                scene.keyframes.layout.magnitudes,
                scene.keyframes.layout.angles,
                self.emitter_counts().0,
                scene.grid.corners_per_side(),
            ),
            keyframe_shape: UVec4::new(
                match self.animation.representation {
                    Representation::Vertex => self.settings.segments,
                    Representation::Curve => 3,
                },
                self.emitter_counts().1,
                0,
                0,
            ),
        }
    }

    /// Record the scene passes of `frame` into `target`, with timestamps around each pass.
    ///
    /// Each pass is its own rendering instance, so a binning rasteriser (lavapipe) finishes a
    /// pass before the next timestamp and per-pass times mean what they say. Between the two, an
    /// explicit attachment barrier orders the blade pass's loads after the terrain's stores.
    fn record_scene(&self, frame: &mut Frame, cmd: vk::CommandBuffer, target: &TargetView) -> Result<()> {
        let device = &*self.device;
        let res = self.resources();
        let scene = self.scene_gpu();
        frame.timestamps.reset(device, cmd);
        if let Some(statistics) = &mut frame.statistics {
            statistics.reset(device, cmd);
        }
        frame.timestamps.write(device, cmd);
        frame.passes.clear();
        // Statistics queries bracket each pass outside its rendering instance, like the timestamps.
        // The pass's pipeline is bound first: lavapipe (Mesa 22.3) emits the bound graphics state
        // at vkCmdBeginQuery and crashes when there is none yet.
        let begin_statistics = |frame: &mut Frame, pipeline: vk::Pipeline| {
            frame.statistics.as_mut().map(|s| {
                // SAFETY: cmd is recording, outside a rendering instance.
                unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
                s.begin(device, cmd)
            })
        };
        let end_statistics = |frame: &Frame, query: Option<u32>| {
            if let (Some(statistics), Some(query)) = (&frame.statistics, query) {
                statistics.end(device, cmd, query);
            }
        };
        // SAFETY: cmd is recording; the set is compatible with both bind points' layouts.
        unsafe {
            for bind_point in [vk::PipelineBindPoint::GRAPHICS, vk::PipelineBindPoint::COMPUTE] {
                device.raw.cmd_bind_descriptor_sets(
                    cmd,
                    bind_point,
                    res.pipeline_layout,
                    0,
                    &[frame.descriptor_set],
                    &[],
                );
            }
            // Defined for every draw: per-cluster draws push their own first blade.
            let push = submission::ClusterPush { first_blade: 0 };
            device.raw.cmd_push_constants(
                cmd,
                res.pipeline_layout,
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(&push),
            );
        }
        if let Some(poses) = &res.poses {
            debug::begin_label(device, cmd, PASSES[0], [0.7, 0.5, 0.2, 1.0]);
            poses.record(device, cmd, &scene.poses, scene.blade_count);
            debug::end_label(device, cmd);
            frame.timestamps.write(device, cmd);
            frame.passes.push((PASSES[0], None));
        }
        let attachment_barriers = |previous_color: Access, previous_depth: Access| {
            sync::cmd_barriers(
                device,
                cmd,
                &[],
                &[
                    sync::image_barrier(target.color, COLOR_RANGE, &[previous_color], &[Access::ColorAttachmentWrite]),
                    sync::image_barrier(
                        target.depth,
                        DEPTH_RANGE,
                        &[previous_depth],
                        &[Access::DepthAttachmentReadWrite],
                    ),
                ],
            )
        };
        attachment_barriers(target.color_previous, target.depth_previous);

        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: target.extent };
        let viewport = full_viewport(target.extent);
        // SAFETY: cmd is recording; dynamic state and bound sets persist across rendering instances.
        unsafe {
            device.raw.cmd_set_viewport(cmd, 0, &[viewport]);
            device.raw.cmd_set_scissor(cmd, 0, &[area]);
        }

        // Terrain: clears colour to the sky and depth to the far plane (0, reversed Z).
        let terrain = res.terrain.as_ref().expect("built in new");
        let query = begin_statistics(frame, terrain.pipeline());
        self.begin_pass(cmd, target, PASSES[1], true, false);
        terrain.record(device, cmd, scene);
        self.end_pass(cmd);
        end_statistics(frame, query);
        frame.timestamps.write(device, cmd);
        frame.passes.push((PASSES[1], query));

        attachment_barriers(Access::ColorAttachmentWrite, Access::DepthAttachmentReadWrite);
        let secondary = frame.secondaries.is_some() && res.blades.is_some();
        let pipeline = match (&res.blades, &res.floor) {
            (Some(blades), _) => blades.pipeline(),
            (None, Some(floor)) => floor.pipeline(),
            _ => unreachable!("new builds the blade or the floor pass"),
        };
        // Secondary command buffers would need `inheritedQueries` to run inside a statistics
        // query: that pass goes uncounted.
        let query = if secondary { None } else { begin_statistics(frame, pipeline) };
        self.begin_pass(cmd, target, PASSES[2], false, secondary);
        // A failed secondary recording fails the frame (after the rendering instance is closed):
        // a frame without its blades must not be measured.
        let mut recorded = Ok(());
        match (&res.blades, &res.floor, &scene.floor) {
            (Some(_), _, _) if secondary => recorded = self.record_secondary_blades(frame, cmd, target),
            (Some(blades), _, _) => blades.record(device, cmd, &self.blade_draws()),
            (None, Some(floor), Some(vertices)) => floor.record(device, cmd, vertices),
            _ => unreachable!("new builds the blade or the floor pass"),
        }
        self.end_pass(cmd);
        end_statistics(frame, query);
        frame.timestamps.write(device, cmd);
        frame.passes.push((PASSES[2], query));
        recorded
    }

    /// The blade draws of the submission strategy (all but `Secondary`, which records
    /// per-cluster draws on worker threads).
    fn blade_draws(&self) -> BladeDraws<'_> {
        let res = self.resources();
        let scene = self.scene_gpu();
        let vertices = Batching::new(self.settings.segments, self.settings.blades_per_instance).vertices_per_instance();
        let indirect = || res.indirect.as_ref().expect("built in new for the indirect strategies");
        match self.settings.submission.strategy {
            Strategy::Instanced | Strategy::Prerecorded => BladeDraws::Instanced {
                vertices,
                instances: scene.blade_count.div_ceil(self.settings.blades_per_instance),
            },
            Strategy::PerCluster | Strategy::Secondary => {
                BladeDraws::PerCluster { vertices, ranges: &res.ranges, layout: res.pipeline_layout }
            }
            Strategy::Indirect => BladeDraws::IndirectLoop(indirect()),
            Strategy::Mdi => BladeDraws::MultiDraw(indirect()),
            Strategy::MdiCount => BladeDraws::MultiDrawCount(indirect()),
        }
    }

    /// The blade pass as secondary command buffers, one per worker thread, each drawing a share
    /// of the clusters with push constants, executed by `cmd` (inside a rendering instance begun
    /// for secondary contents). Threads are scoped to the call: their start-up is part of the
    /// measured recording time.
    fn record_secondary_blades(&self, frame: &Frame, cmd: vk::CommandBuffer, target: &TargetView) -> Result<()> {
        let device = &*self.device;
        let res = self.resources();
        let workers = &frame.secondaries.as_ref().expect("checked by the caller").workers;
        let pipeline = res.blades.as_ref().expect("checked by the caller").pipeline();
        let vertices = bezier::strip_vertices(self.settings.segments);
        let per_worker = res.ranges.len().div_ceil(workers.len());
        let formats = [self.settings.color_format];
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: target.extent };
        let viewport = full_viewport(target.extent);
        let results: Vec<Result<vk::CommandBuffer>> = std::thread::scope(|scope| {
            let handles: Vec<_> = workers
                .iter()
                .zip(res.ranges.chunks(per_worker))
                .map(|(&(pool, secondary), ranges)| {
                    scope.spawn(move || {
                        let mut rendering = vk::CommandBufferInheritanceRenderingInfo::default()
                            .color_attachment_formats(&formats)
                            .depth_attachment_format(DEPTH_FORMAT)
                            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
                        let inheritance = vk::CommandBufferInheritanceInfo::default().push_next(&mut rendering);
                        let begin = vk::CommandBufferBeginInfo::default()
                            .flags(
                                vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT
                                    | vk::CommandBufferUsageFlags::RENDER_PASS_CONTINUE,
                            )
                            .inheritance_info(&inheritance);
                        // SAFETY: each worker owns its pool; the frame's fence was waited, so
                        // the previous recording is not pending. Dynamic state and bindings are
                        // not inherited: each secondary sets its own.
                        unsafe {
                            device
                                .raw
                                .reset_command_pool(pool, vk::CommandPoolResetFlags::empty())
                                .vk("vkResetCommandPool")?;
                            device.raw.begin_command_buffer(secondary, &begin).vk("vkBeginCommandBuffer")?;
                            device.raw.cmd_set_viewport(secondary, 0, &[viewport]);
                            device.raw.cmd_set_scissor(secondary, 0, &[area]);
                            device.raw.cmd_bind_descriptor_sets(
                                secondary,
                                vk::PipelineBindPoint::GRAPHICS,
                                res.pipeline_layout,
                                0,
                                &[frame.descriptor_set],
                                &[],
                            );
                            device.raw.cmd_bind_pipeline(secondary, vk::PipelineBindPoint::GRAPHICS, pipeline);
                        }
                        let draws = BladeDraws::PerCluster { vertices, ranges, layout: res.pipeline_layout };
                        submission::record_draws(device, secondary, &draws);
                        // SAFETY: recording.
                        unsafe { device.raw.end_command_buffer(secondary) }.vk("vkEndCommandBuffer")?;
                        Ok(secondary)
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().expect("a recording thread panicked")).collect()
        });
        let secondaries: Vec<vk::CommandBuffer> = results.into_iter().collect::<Result<_>>()?;
        // SAFETY: cmd is inside a rendering instance begun for secondary command buffers with
        // the formats the secondaries inherit.
        unsafe { device.raw.cmd_execute_commands(cmd, &secondaries) };
        Ok(())
    }

    /// Open a labelled rendering instance on `target`; `clear` clears colour and depth, otherwise
    /// both are loaded. Depth is stored only when a later pass reads it. `secondary`: the
    /// contents come from secondary command buffers.
    fn begin_pass(&self, cmd: vk::CommandBuffer, target: &TargetView, name: &str, clear: bool, secondary: bool) {
        let device = &*self.device;
        let sky = look::SKY;
        let clear_color = if self.settings.encode_srgb {
            [look::encode_srgb(sky.x), look::encode_srgb(sky.y), look::encode_srgb(sky.z), 1.0]
        } else {
            [sky.x, sky.y, sky.z, 1.0]
        };
        let load = if clear { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::LOAD };
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(target.color_view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: clear_color } })];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(target.depth_view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(load)
            .store_op(if clear { vk::AttachmentStoreOp::STORE } else { vk::AttachmentStoreOp::DONT_CARE })
            .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 } });
        let flags = if secondary {
            vk::RenderingFlags::CONTENTS_SECONDARY_COMMAND_BUFFERS
        } else {
            vk::RenderingFlags::empty()
        };
        let rendering = vk::RenderingInfo::default()
            .flags(flags)
            .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent: target.extent })
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        debug::begin_label(device, cmd, name, [0.3, 0.6, 0.2, 1.0]);
        // SAFETY: cmd is recording; the attachments are in the layouts set by the barriers.
        unsafe { device.raw.cmd_begin_rendering(cmd, &rendering) };
    }

    /// Close the rendering instance and its label.
    fn end_pass(&self, cmd: vk::CommandBuffer) {
        // SAFETY: matches begin_pass.
        unsafe { self.device.raw.cmd_end_rendering(cmd) };
        debug::end_label(&self.device, cmd);
    }

    /// Compute this frame's corner forces and emitters on the CPU (thesis 3.2.2) and write them
    /// into the frame's host-visible buffers; they are visible to the GPU at submission.
    fn write_forces(&self, frame: &mut Frame, time: f32) {
        let grid = &self.scene_gpu().grid;
        let wind = &self.animation.wind;
        frame.corners.write(0, &animation::corner_forces(grid, wind, time, self.animation.attenuation));
        let mut emitters = animation::emitters(wind, time);
        emitters.truncate(animation::MAX_EMITTERS);
        frame.emitters.write(0, &emitters);
    }

    /// Sources and colliders the shaders read: the first `MAX_EMITTERS` of them, sources first
    /// (the emitter buffers hold no more).
    fn emitter_counts(&self) -> (u32, u32) {
        let max = animation::MAX_EMITTERS;
        let sources = self.animation.wind.sources.len().min(max);
        let colliders = self.animation.wind.colliders.len().min(max - sources);
        (sources as u32, colliders as u32)
    }

    /// The animation the renderer was built with.
    pub fn animation(&self) -> &AnimationSettings {
        &self.animation
    }

    /// The forces, editable between frames (they are uploaded per frame). At most
    /// `MAX_EMITTERS` sources and colliders together are used; extra ones are ignored.
    pub fn wind_mut(&mut self) -> &mut crate::wind::Wind {
        &mut self.animation.wind
    }

    /// Wait until the next frame slot is free (its fence signalled) and return the slot with
    /// the timings of the frame it rendered last, if any. Only that slot's fence is waited: the
    /// other frames in flight keep running.
    pub fn begin_frame(&mut self) -> Result<(usize, Option<FrameTimings>)> {
        let slot = self.frame_index;
        self.frame_index = (self.frame_index + 1) % self.settings.frames_in_flight;
        Ok((slot, self.collect(slot)?))
    }

    /// Wait for `slot`'s fence and read the timings of its last submission, if any.
    fn collect(&mut self, slot: usize) -> Result<Option<FrameTimings>> {
        let device = self.device.clone();
        let frame = &mut self.resources.as_mut().expect("resources").frames[slot];
        let wait_started = Instant::now();
        sync::wait_fence(&device, frame.fence)?;
        let wait_ended = Instant::now();
        let waited = (wait_ended - wait_started).as_secs_f64() * 1e3;
        let timings = match frame.pending.take() {
            Some(spans @ [started, recorded, submitted]) => {
                let copied = frame.query_results.mapped();
                let stamps = frame.timestamps.read_ns(copied);
                let statistics = match &frame.statistics {
                    Some(queries) => queries.read(&copied[frame.statistics_offset as usize..]),
                    None => Vec::new(),
                };
                let passes = frame
                    .passes
                    .iter()
                    .enumerate()
                    .map(|(i, &(name, query))| PassTime {
                        name,
                        ms: span_ms(stamps[i], stamps[i + 1]),
                        start_ns: stamps[i],
                        statistics: query.and_then(|q| statistics.get(q as usize).copied()),
                    })
                    .collect();
                Some(FrameTimings {
                    cpu_record_ms: (recorded - started).as_secs_f64() * 1e3,
                    cpu_submit_ms: (submitted - recorded).as_secs_f64() * 1e3,
                    cpu_wait_ms: waited,
                    gpu_ms: span_ms(stamps[0], stamps[stamps.len() - 1]),
                    passes,
                    gpu_span_ns: (stamps[0], stamps[stamps.len() - 1]),
                    cpu_spans: Some(spans),
                    cpu_wait: Some([wait_started, wait_ended]),
                })
            }
            None => None,
        };
        Ok(timings)
    }

    /// The semaphore a swapchain image for `slot` is acquired with.
    pub fn acquire_semaphore(&self, slot: usize) -> vk::Semaphore {
        self.resources().frames[slot].acquire
    }

    /// The CPU side of a frame in `frame`: uniforms and corner forces written, then the command
    /// buffer recorded (passes, `finish`, the closing timestamp) or, for a pre-recorded
    /// submission already recorded for `target`, reused as is. Returns it and when recording began.
    fn prepare_frame(
        &self,
        frame: &mut Frame,
        target: &TargetView,
        camera: &Camera,
        time: f32,
        finish: impl FnOnce(&Device, vk::CommandBuffer),
    ) -> Result<(vk::CommandBuffer, Instant)> {
        let device = &*self.device;
        frame.uniforms.write(0, &[self.frame_uniforms(camera, time, target.extent)]);
        self.write_forces(frame, time);
        let started = Instant::now();
        let prerecorded = self.settings.submission.strategy == Strategy::Prerecorded;
        // The recording's first barriers assume how the target was last accessed: reuse it only
        // for the same image in the same state (e.g. not for frame 0's discard once frames queue
        // up behind each other on one image).
        let key = (target.color_view, target.extent, target.color_previous, target.depth_previous);
        if prerecorded && frame.recorded_for == Some(key) {
            // Recorded once for this target: uniforms and forces live in buffers written above,
            // so the same commands render this frame.
            return Ok((frame.recorder.cmd, started));
        }
        frame.recorded_for = None;
        let cmd = if prerecorded { frame.recorder.begin_reusable(device)? } else { frame.recorder.begin(device)? };
        self.record_scene(frame, cmd, target)?;
        finish(device, cmd);
        frame.timestamps.write(device, cmd);
        // The queries' results, copied on the GPU for the host to read after the fence.
        let results = frame.query_results.raw;
        frame.timestamps.record_copy(device, cmd, results, 0);
        if let Some(statistics) = &frame.statistics {
            statistics.record_copy(device, cmd, results, frame.statistics_offset);
        }
        let to_host = sync::buffer_barrier(results, &[Access::TransferWrite], &[Access::HostRead]);
        sync::cmd_barriers(device, cmd, &[to_host], &[]);
        frame.recorder.end(device)?;
        if prerecorded {
            frame.recorded_for = Some(key);
        }
        Ok((cmd, started))
    }

    /// Record and submit the frame of `slot` (after `begin_frame`) into `target`: uniforms and
    /// corner forces written, passes recorded, then `finish` records whatever follows the scene
    /// (the colour image's last barrier, a copy), and the submission waits and signals the given
    /// semaphores (a swapchain's acquire and present) and the slot's fence.
    pub fn submit_frame(
        &mut self,
        slot: usize,
        target: &TargetView,
        camera: &Camera,
        time: f32,
        sync: FrameSync,
        finish: impl FnOnce(&Device, vk::CommandBuffer),
    ) -> Result<()> {
        let device = self.device.clone();
        let mut frame = self.resources.as_mut().expect("resources").frames.swap_remove(slot);
        let result = (|| {
            let (cmd, started) = self.prepare_frame(&mut frame, target, camera, time, finish)?;
            let recorded = Instant::now();
            let info = |semaphore: Option<vk::Semaphore>, stage| {
                semaphore.map(|s| vk::SemaphoreSubmitInfo::default().semaphore(s).stage_mask(stage))
            };
            // The acquire semaphore is waited where the image is first written.
            let wait: Vec<_> = info(sync.wait, vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT).into_iter().collect();
            let signal: Vec<_> = info(sync.signal, vk::PipelineStageFlags2::ALL_COMMANDS).into_iter().collect();
            // Reset only now: if recording failed, the fence stays signalled and nobody waits forever.
            // SAFETY: begin_frame waited for this fence; nothing pending uses the frame.
            unsafe { device.raw.reset_fences(&[frame.fence]) }.vk("vkResetFences")?;
            commands::submit(&device, cmd, &wait, &signal, frame.fence)?;
            let submitted = Instant::now();
            frame.pending = Some([started, recorded, submitted]);
            Ok(())
        })();
        let frames = &mut self.resources.as_mut().expect("resources").frames;
        frames.push(frame);
        let last = frames.len() - 1;
        frames.swap(slot, last);
        result
    }

    /// Wait for every frame in flight (before rebuilding targets; never inside a frame).
    pub fn wait_all_frames(&self) -> Result<()> {
        for frame in &self.resources().frames {
            sync::wait_fence(&self.device, frame.fence)?;
        }
        Ok(())
    }

    /// Render one frame into `target` and copy it to the target's readback buffer; returns when
    /// the GPU is done, so `target.pixels()` holds the picture.
    pub fn render_offscreen(
        &mut self,
        target: &mut OffscreenTarget,
        camera: &Camera,
        time: f32,
    ) -> Result<FrameTimings> {
        let (slot, _) = self.begin_frame()?;
        let view = target.view();
        self.submit_frame(slot, &view, camera, time, FrameSync::default(), |device, cmd| {
            target.record_readback(device, cmd)
        })?;
        // Headless: wait right away, so the picture and the timings are ready.
        Ok(self.collect(slot)?.expect("the frame was submitted"))
    }

    /// The CPU side of one frame without its submission, for benchmarks (`benches/recording.rs`):
    /// take the next slot (`begin_frame`), write its uniforms and corner forces, and record the
    /// scene passes into `target` with the slot's recorder as `submit_frame` does (nothing
    /// follows the scene). The command buffer is left executable and is never submitted: nothing
    /// is pending, the slot's fence stays signalled and the slot's next `begin` resets the buffer.
    /// The timings of a frame the slot still had in flight are waited for and dropped.
    pub fn record_only(&mut self, target: &TargetView, camera: &Camera, time: f32) -> Result<()> {
        let (slot, _) = self.begin_frame()?;
        let mut frame = self.resources.as_mut().expect("resources").frames.swap_remove(slot);
        let result = self.prepare_frame(&mut frame, target, camera, time, |_, _| {}).map(|_| ());
        let frames = &mut self.resources.as_mut().expect("resources").frames;
        frames.push(frame);
        let last = frames.len() - 1;
        frames.swap(slot, last);
        result
    }
}

/// The viewport covering `extent`, depth 0..1.
fn full_viewport(extent: vk::Extent2D) -> vk::Viewport {
    vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    }
}

/// Semaphores a frame's submission waits on (at colour output) and signals.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameSync {
    /// E.g. the swapchain image's acquire semaphore.
    pub wait: Option<vk::Semaphore>,
    /// E.g. the swapchain image's present semaphore.
    pub signal: Option<vk::Semaphore>,
}

impl Drop for Renderer {
    fn drop(&mut self) {
        if let Some(res) = self.resources.take() {
            // Teardown, not a frame: waiting for the whole device is the point.
            let _ = self.device.wait_idle();
            // SAFETY: the device is idle.
            unsafe { destroy_resources(&self.device, res) };
        }
    }
}

/// # Safety
/// The device must be idle.
unsafe fn destroy_resources(device: &Device, res: Resources) {
    // SAFETY: per the contract; destroying a null handle is a no-op.
    unsafe {
        if let Some(poses) = res.poses {
            poses.destroy(device);
        }
        if let Some(floor) = res.floor {
            floor.destroy(device);
        }
        if let Some(blades) = res.blades {
            blades.destroy(device);
        }
        if let Some(terrain) = res.terrain {
            terrain.destroy(device);
        }
        if let Some(indirect) = res.indirect {
            indirect.destroy(device);
        }
        for frame in res.frames {
            frame.destroy(device);
        }
        device.raw.destroy_descriptor_pool(res.descriptor_pool, None);
        device.raw.destroy_pipeline_layout(res.pipeline_layout, None);
        device.raw.destroy_descriptor_set_layout(res.set_layout, None);
        if let Some(scene) = res.scene {
            scene.destroy(device);
        }
    }
}
