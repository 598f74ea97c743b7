//! Blade pass: every blade's strip expanded in the vertex shader (vertex pulling, thesis 4.1
//! Bézier strips, no vertex buffer), drawn with the submission strategy of `meadow overhead`: one
//! instanced draw by default, or per cluster, indirectly, or from secondary command buffers
//! recorded on worker threads (`render::submission`).

use ash::vk;

use crate::error::{Result, VkContext};
use crate::render::animation::BladeInput;
use crate::render::draw_rows::{DrawRows, TileRows};
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes::{self, PipelineTarget};
use crate::render::recording::{self, bucket_dispatch, PassSet, SceneSets};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::render::submission::{self, BladeDraws, IndirectDraws, SecondaryRecorders, Strategy};
use crate::scene::bezier::{self, Batching};
use crate::vk::profile::Shader;
use crate::vk::upload::UploadBatch;
use crate::vk::{pipeline, Access, Buffer, Device, Guard, Resource};

/// The blade pipeline and its draws.
pub struct BladePass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    color_format: vk::Format,
    /// Depth format and sample count of the attachments (secondary command buffers inherit them).
    depth_format: vk::Format,
    samples: vk::SampleCountFlags,
    strategy: Strategy,
    /// Vertices per instance (a strip, or K strips joined by degenerate triangles).
    vertices: u32,
    /// Instances of the instanced draw.
    instances: u32,
    /// Strip vertices of one blade.
    strip: u32,
    /// Blade ranges of the per-cluster and secondary strategies.
    ranges: Vec<(u32, u32)>,
    /// Commands of the indirect strategies.
    indirect: Option<IndirectDraws>,
    /// Worker command buffers of the `Secondary` strategy, one set per frame in flight.
    secondaries: Vec<SecondaryRecorders>,
    /// Buffers the vertex shader reads (for the declaration).
    reads: Vec<(vk::Buffer, Access)>,
    /// What a per-vertex response's include reads of its resources (for the declaration).
    response_reads: Vec<(Resource, Access)>,
    /// A per-vertex response's resources, in the pass's own set (`SET_PASS`), whose layout the
    /// pipelines are built on.
    own: Option<PassSet>,
    /// Each frame's wind at the cluster corners (`PassSetup::wind`).
    wind: Vec<vk::Buffer>,
    /// Set `SET_POSES`.
    poses: vk::DescriptorSet,
    /// With the cull: one pipeline per LOD bucket (its segment count compiled in) and the
    /// indirect draws the cull writes, one per bucket.
    buckets: Vec<vk::Pipeline>,
    draws: vk::Buffer,
    /// With the cull: the buckets' blade triangle lists (`bezier::bucket_indices`).
    indices: Option<Buffer>,
    /// With a row per visible tile: the cull's rows and their layout (`draw_rows::TileRows`).
    tile_rows: Option<(vk::Buffer, TileRows)>,
    /// Whether the scene's depth is stored after the pass: a further draw class's pass tests
    /// against it (otherwise its contents may be discarded, `DONT_CARE`).
    store_depth: bool,
}

/// The blade pass's vertex shader, its own set and what the shader reads of it.
type VertexInput = (Shader, Option<PassSet>, Vec<(Resource, Access)>);

/// How the blade pass is built.
pub struct BladeSetup<'a> {
    /// Layout and formats.
    pub target: PipelineTarget,
    /// Specialization constants.
    pub constants: &'a Specialization,
    /// Segments per blade.
    pub segments: u32,
    /// Blades per instance of the instanced draw.
    pub blades_per_instance: u32,
    /// The submission strategy and its clusters.
    pub submission: submission::Submission,
    /// Frames in flight (the secondary strategy records per frame).
    pub frames_in_flight: usize,
    /// How the blade response poses a blade.
    pub input: BladeInput,
    /// Set `SET_POSES` and its pose records and placed levels.
    pub poses: (vk::DescriptorSet, [vk::Buffer; 2]),
    /// The sets before a pass's own, for a per-vertex response's (`BladeInput::PerVertex`).
    pub sets: SceneSets<'a>,
    /// Segments of the LOD buckets the cull sorts blades into (`None`: brute force, every blade
    /// at `segments`).
    pub buckets: Option<&'a [u32]>,
    /// How the buckets are drawn: once each, or a row per visible tile (`draw_rows`).
    pub rows: DrawRows,
    /// Each frame's wind at the cluster corners (`PassSetup::wind`).
    pub wind: &'a [vk::Buffer],
    /// Whether a further draw class's pass follows and depth-tests against the blades
    /// (`render::draw_class`): the pass then stores the depth.
    pub depth_after: bool,
}

impl BladePass {
    /// Build the pipeline (two-sided blades: no culling) and the draws of the strategy.
    pub fn new(device: &Device, scene: &SceneGpu, setup: &BladeSetup) -> Result<Self> {
        let mut target = setup.target;
        let tile_rows = (setup.buckets.is_some() && setup.rows == DrawRows::PerTile)
            .then_some((scene.tile_rows.raw, TileRows { capacity: scene.slot_capacity }));
        if let Some((_, rows)) = tile_rows {
            crate::render::draw_rows::check_capacity(device, rows.capacity)?;
        }
        let (vertex, own, response_reads) = Self::vertex_input(device, scene, setup, tile_rows)?;
        let own = Guard::new(device, own);
        if let Some(own) = own.as_ref() {
            target.layout = own.layout;
        }
        // With the cull, the buckets' pipelines draw (`build_buckets`): no pipeline of its own.
        let pipeline = match setup.buckets {
            Some(_) => vk::Pipeline::null(),
            None => {
                let strip = vk::PrimitiveTopology::TRIANGLE_STRIP;
                Self::pipeline(device, (target, vertex), setup.constants, "blades", strip)?
            }
        };
        let mut reads = vec![
            (scene.blades.raw, device.profile.vertex_fetch()),
            (scene.clusters.raw, Access::VertexShaderStorageRead),
        ];
        if setup.input.pose_records() {
            // With the cull, the placed levels stand for the records (`BladeLevelsPass`). The
            // shader names both (a specialization constant skips one), and synchronization
            // validation counts static use: both are declared, whichever path runs, so a
            // previous graph's write of either is ordered before this pass.
            let [poses, levels] = setup.poses.1;
            reads.push((poses, Access::VertexShaderStorageRead));
            reads.push((levels, device.profile.vertex_fetch()));
        }
        // The ground's normal under each root (per vertex without placed levels).
        reads.push((scene.ground.texels.raw, device.profile.vertex_fetch()));
        // And the cover there (`--debug-view cover` colours the blades by it).
        reads.push((scene.ground.cover.0.raw, device.profile.vertex_fetch()));
        let mut pass = Guard::new(
            device,
            Self {
                pipeline,
                layout: target.layout,
                color_format: target.color,
                depth_format: target.depth,
                samples: target.samples,
                strategy: setup.submission.strategy,
                vertices: Batching::new(setup.segments, setup.blades_per_instance).vertices_per_instance(),
                instances: scene.blade_count.div_ceil(setup.blades_per_instance),
                strip: bezier::strip_vertices(setup.segments),
                ranges: Vec::new(),
                indirect: None,
                secondaries: Vec::new(),
                reads,
                response_reads,
                own: own.take(),
                wind: setup.wind.to_vec(),
                poses: setup.poses.0,
                buckets: Vec::new(),
                draws: scene.draws.raw,
                indices: None,
                tile_rows,
                store_depth: setup.depth_after,
            },
        );
        match setup.buckets {
            Some(buckets) => pass.build_buckets(device, scene, (setup, target, vertex), buckets)?,
            None => pass.build_submission(device, scene.blade_count, setup)?,
        }
        Ok(pass.take())
    }

    /// The vertex shader, the pass's own set and what the shader reads of it: a per-vertex
    /// response's own shader and resources; or with a row per tile (`tile_rows`) the variant
    /// that reads its draw's record, the rows in its own set; else `blade.vert`, no own set.
    fn vertex_input(
        device: &Device,
        scene: &SceneGpu,
        setup: &BladeSetup,
        tile_rows: Option<(vk::Buffer, TileRows)>,
    ) -> Result<VertexInput> {
        let own = |vertex: Shader, resources: Vec<(&'static str, crate::vk::descriptor::Resource)>| {
            let code = [("blades", vertex.code(device.profile))];
            PassSet::new(device, &setup.sets.desc("blades", &code), |_| resources.clone())
        };
        Ok(match (&setup.input, tile_rows) {
            (BladeInput::PerVertex { .. }, Some(_)) => {
                return Err(crate::error::Error::bad_input(
                    "a row per tile draws pose records or neutral blades, not a per-vertex response",
                ))
            }
            (BladeInput::PerVertex { vertex, resources, reads }, None) => {
                (*vertex, Some(own(*vertex, resources.clone())?), reads.clone())
            }
            (_, Some((rows, _))) => {
                let vertex = shaders::BLADE_TILES_VERT;
                let resources =
                    vec![("TileRows", crate::vk::descriptor::Resource::Buffer(scene.tile_rows.descriptor()))];
                (vertex, Some(own(vertex, resources)?), vec![(Resource::Buffer(rows), Access::VertexShaderStorageRead)])
            }
            (_, None) => (shaders::BLADE_VERT, None, Vec::new()),
        })
    }

    /// The blade pipeline (two-sided blades: no culling) for `constants`. With alpha to coverage
    /// (`--msaa`), an alpha-tested outline is shaded by `blade.frag`'s variant `coverage`, which writes the
    /// outline's coverage of each sample as the sample mask; an outline drawn as geometry has no
    /// alpha test to replace.
    fn pipeline(
        device: &Device,
        (target, vertex): (PipelineTarget, Shader),
        constants: &Specialization,
        name: &str,
        topology: vk::PrimitiveTopology,
    ) -> Result<vk::Pipeline> {
        let flags = constants.flags;
        let per_sample = target.alpha_to_coverage && flags & gpu::FLAG_SOLID_OUTLINE == 0;
        pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name,
                vertex: vertex.code(device.profile),
                fragment: if per_sample {
                    shaders::BLADE_COVERAGE_FRAG.code(device.profile)
                } else {
                    shaders::BLADE_FRAG.code(device.profile)
                },
                topology,
                cull: vk::CullModeFlags::NONE,
                polygon: target.polygon,
                depth_compare: vk::CompareOp::GREATER,
                depth_write: true,
                color_format: target.color,
                depth_format: target.depth,
                layout: target.layout,
                constants: &constants.named(),
                vertex_stride: 0,
                samples: target.samples,
                blend: pipeline::Blend::Opaque,
            },
        )
    }

    /// One pipeline per LOD bucket, reading the cull's visible list, its index list and the
    /// reads of its draws. Each bucket draws indexed triangle lists (`bezier::BladeMesh`): the
    /// strips' triangles without their joins, and with the outline as geometry one tip vertex.
    fn build_buckets(
        &mut self,
        device: &Device,
        scene: &SceneGpu,
        (setup, target, vertex): (&BladeSetup, PipelineTarget, Shader),
        buckets: &[u32],
    ) -> Result<()> {
        // The outline as geometry, no alpha test: early depth rejects the overdraw. The cull's
        // scan reads the same flag (`FLAG_SOLID_OUTLINE` in every pipeline's constants) for the
        // lists' lengths.
        let collapsed_tip = setup.constants.flags & gpu::FLAG_SOLID_OUTLINE != 0;
        for (b, &segments) in buckets.iter().enumerate() {
            let constants =
                Specialization { lod_bucket: b as u32, ..bucket_dispatch::bucket_constants(setup.constants, segments) };
            let name = format!("blades, LOD bucket {b} ({segments} segments)");
            let list = vk::PrimitiveTopology::TRIANGLE_LIST;
            self.buckets.push(Self::pipeline(device, (target, vertex), &constants, &name, list)?);
        }
        let indices = bezier::bucket_indices(buckets, collapsed_tip, setup.blades_per_instance);
        let mut batch = UploadBatch::new(device);
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        let buffer = batch.buffer("blade bucket indices", &indices, usage, &[Access::IndexRead])?;
        self.reads.push((buffer.raw, Access::IndexRead));
        self.indices = Some(buffer);
        batch.submit()?;
        self.reads.push((scene.visible.raw, device.profile.vertex_fetch()));
        self.reads.push((scene.draws.raw, Access::IndirectCommandRead));
        if let Some((rows, _)) = self.tile_rows {
            self.reads.push((rows, Access::IndirectCommandRead));
        }
        Ok(())
    }

    /// Bind the pose records' set and a per-vertex response's own set (set 0 and the pipeline
    /// are bound).
    fn bind_sets(&self, ctx: &PassContext, cmd: vk::CommandBuffer) {
        let graphics = vk::PipelineBindPoint::GRAPHICS;
        recording::bind_pose_set(ctx.device, cmd, self.layout, graphics, self.poses);
        if let Some(own) = &self.own {
            own.bind(ctx.device, cmd, graphics, ctx.slot);
        }
    }

    /// The ranges, indirect commands and secondary recorders of a non-instanced strategy.
    fn build_submission(&mut self, device: &Device, blades: u32, setup: &BladeSetup) -> Result<()> {
        if matches!(self.strategy, Strategy::Instanced | Strategy::Prerecorded) {
            return Ok(());
        }
        self.ranges = submission::ranges(blades, setup.submission.clusters);
        if matches!(self.strategy, Strategy::Indirect | Strategy::Mdi | Strategy::MdiCount) {
            let mut batch = UploadBatch::new(device);
            let indirect = IndirectDraws::upload(&mut batch, &self.ranges, self.strip)?;
            self.reads.push((indirect.commands.raw, Access::IndirectCommandRead));
            self.reads.push((indirect.count.raw, Access::IndirectCommandRead));
            self.indirect = Some(indirect);
            batch.submit()?;
        }
        if self.strategy == Strategy::Secondary {
            let workers = std::thread::available_parallelism().map_or(2, |n| n.get()).min(self.ranges.len());
            for i in 0..setup.frames_in_flight {
                let name = format!("frame {i} secondary");
                self.secondaries.push(SecondaryRecorders::new(device, &name, workers)?);
            }
        }
        Ok(())
    }

    /// Triangles drawn.
    pub fn triangles(scene: &SceneGpu, segments: u32) -> u64 {
        2 * u64::from(segments) * u64::from(scene.blade_count)
    }

    /// The draws of the strategy (all but `Secondary`, recorded on worker threads).
    fn draws(&self) -> BladeDraws<'_> {
        let indirect = || self.indirect.as_ref().expect("built in new for the indirect strategies");
        match self.strategy {
            Strategy::Instanced | Strategy::Prerecorded => {
                BladeDraws::Instanced { vertices: self.vertices, instances: self.instances }
            }
            Strategy::PerCluster | Strategy::Secondary => {
                BladeDraws::PerCluster { vertices: self.strip, ranges: &self.ranges, layout: self.layout }
            }
            Strategy::Indirect => BladeDraws::IndirectLoop(indirect()),
            Strategy::Mdi => BladeDraws::MultiDraw(indirect()),
            Strategy::MdiCount => BladeDraws::MultiDrawCount(indirect()),
        }
    }

    /// The per-cluster draws as secondary command buffers, one per worker thread, executed by
    /// `cmd` (inside a rendering instance begun for secondary contents). Threads are scoped to the
    /// call: their start-up is part of the measured recording time.
    fn record_secondaries(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let workers = &self.secondaries[ctx.slot].workers;
        let per_worker = self.ranges.len().div_ceil(workers.len());
        let results: Vec<Result<vk::CommandBuffer>> = std::thread::scope(|scope| {
            let handles: Vec<_> = workers
                .iter()
                .zip(self.ranges.chunks(per_worker))
                .map(|(&(pool, secondary), ranges)| {
                    scope.spawn(move || self.record_worker(ctx, pool, secondary, ranges))
                })
                .collect();
            handles.into_iter().map(|h| h.join().expect("a recording thread panicked")).collect()
        });
        let secondaries: Vec<vk::CommandBuffer> = results.into_iter().collect::<Result<_>>()?;
        // SAFETY: cmd is inside a rendering instance begun for secondary command buffers with the
        // formats the secondaries inherit.
        unsafe { device.raw.cmd_execute_commands(cmd, &secondaries) };
        Ok(())
    }

    /// One worker's secondary command buffer: its share of the per-cluster draws.
    fn record_worker(
        &self,
        ctx: &PassContext,
        pool: vk::CommandPool,
        secondary: vk::CommandBuffer,
        ranges: &[(u32, u32)],
    ) -> Result<vk::CommandBuffer> {
        let device = ctx.device;
        let formats = [self.color_format];
        let mut rendering = vk::CommandBufferInheritanceRenderingInfo::default()
            .color_attachment_formats(&formats)
            .depth_attachment_format(self.depth_format)
            .rasterization_samples(self.samples);
        let inheritance = vk::CommandBufferInheritanceInfo::default().push_next(&mut rendering);
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT | vk::CommandBufferUsageFlags::RENDER_PASS_CONTINUE)
            .inheritance_info(&inheritance);
        // SAFETY: each worker owns its pool; the frame's fence was waited, so the previous
        // recording is not pending. Dynamic state and bindings are not inherited: each secondary
        // sets its own.
        unsafe {
            device.raw.reset_command_pool(pool, vk::CommandPoolResetFlags::empty()).vk("vkResetCommandPool")?;
            device.raw.begin_command_buffer(secondary, &begin).vk("vkBeginCommandBuffer")?;
        }
        passes::bind_graphics(device, ctx, secondary, self.layout, self.pipeline);
        self.bind_sets(ctx, secondary);
        let draws = BladeDraws::PerCluster { vertices: self.strip, ranges, layout: self.layout };
        submission::record_draws(device, secondary, &draws);
        // SAFETY: recording.
        unsafe { device.raw.end_command_buffer(secondary) }.vk("vkEndCommandBuffer")?;
        Ok(secondary)
    }
}

impl Pass for BladePass {
    fn name(&self) -> &'static str {
        "blades"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let secondary = self.strategy == Strategy::Secondary;
        let first = self.buckets.first().copied().unwrap_or(self.pipeline);
        let rendering = passes::scene_rendering(ctx, first, self.store_depth, secondary);
        // The frame's wind (per vertex without pose records; the shader names it either way).
        let declaration = Declaration::graphics(rendering).buffer(self.wind[ctx.slot], Access::VertexShaderStorageRead);
        let declaration = self.response_reads.iter().fold(declaration, |d, &(r, a)| d.uses(r, a));
        Some(self.reads.iter().fold(declaration, |d, &(b, a)| d.buffer(b, a)))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        if self.strategy == Strategy::Secondary {
            return self.record_secondaries(ctx, cmd);
        }
        let device = ctx.device;
        let first = self.buckets.first().copied().unwrap_or(self.pipeline);
        passes::bind_graphics(device, ctx, cmd, self.layout, first);
        self.bind_sets(ctx, cmd);
        // Defined for every draw: per-cluster draws push their own first blade.
        let push = submission::ClusterPush { first_blade: 0 };
        // SAFETY: cmd is recording inside this pass's rendering instance; the layout has the range.
        unsafe {
            device.raw.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::VERTEX, 0, bytemuck::bytes_of(&push));
        }
        if self.buckets.is_empty() {
            submission::record_draws(device, cmd, &self.draws());
            return Ok(());
        }
        // Nearest bucket first: with the list near to far inside each bucket, early depth rejects
        // what the near blades hide.
        let stride = std::mem::size_of::<vk::DrawIndexedIndirectCommand>() as u32;
        let indices = self.indices.as_ref().expect("built with the buckets");
        // SAFETY: cmd is recording inside the rendering instance; the buffer holds u32 indices.
        unsafe { device.raw.cmd_bind_index_buffer(cmd, indices.raw, 0, vk::IndexType::UINT32) };
        for (b, &pipeline) in self.buckets.iter().enumerate() {
            // SAFETY: cmd is recording inside the rendering instance; the cull wrote the commands
            // (a row per tile: as many as the count word says, at most the layout's capacity).
            unsafe {
                device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                match self.tile_rows {
                    None => {
                        device.raw.cmd_draw_indexed_indirect(cmd, self.draws, u64::from(stride) * b as u64, 1, stride)
                    }
                    Some((rows, layout)) => device.raw.cmd_draw_indexed_indirect_count(
                        cmd,
                        rows,
                        4 * u64::from(layout.commands_word(b as u32)),
                        rows,
                        4 * u64::from(TileRows::count_word(b as u32)),
                        layout.capacity,
                        stride,
                    ),
                }
            }
        }
        Ok(())
    }

    fn replay_key(&self, _: &PassContext) -> Option<u64> {
        // The same draws every frame for a strategy (the cull's are indirect, read on the GPU).
        Some(0)
    }

    unsafe fn destroy(mut self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            for mut recorders in self.secondaries.drain(..) {
                recorders.destroy(device);
            }
            if let Some(indirect) = self.indirect.take() {
                indirect.destroy(device);
            }
            if let Some(indices) = self.indices.take() {
                indices.destroy(device);
            }
            for pipeline in self.buckets.drain(..) {
                crate::vk::live::destroyed(pipeline);
                device.raw.destroy_pipeline(pipeline, None);
            }
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            if let Some(own) = self.own.take() {
                own.destroy(device);
            }
        }
    }
}
