//! The renderer's graph: which passes a frame records, in order, for the settings.

use ash::vk;

use super::Renderer;
use crate::error::Result;
use crate::render::animation::patch_pass::PatchPass;
use crate::render::animation::patches::PatchClock;
use crate::render::animation::pressed::PressPass;
use crate::render::animation::push_out::PushOutPass;
use crate::render::animation::response::ResponseSetup;
use crate::render::draw_class::ClassSetup;
use crate::render::draw_rows::DrawRows;
use crate::render::far_field;
use crate::render::gpu_constants as gpu;
use crate::render::graph::Graph;
use crate::render::msaa::MSAA_COLOR_FORMAT;
use crate::render::passes::blades::BladeSetup;
use crate::render::passes::cull::{self, CullSetup};
use crate::render::passes::depth_pyramid::DepthPyramidPass;
use crate::render::passes::{
    BladeLevelsPass, BladePass, ClusterBoundsPass, FloorPass, GroundFillPass, PipelineTarget, ResolvePass, TerrainPass,
    WindArrowsPass,
};
use crate::render::recording::SceneSets;
use crate::render::scene_gpu::SceneGpu;
use crate::render::settings::sky_clear_color;
use crate::render::specialization::Specialization;
use crate::render::wind::WindSetup;
use crate::scene::Scene;
use crate::vk::descriptor::SetLayout;
use crate::vk::{Access, Device, Guard, Resource};

impl Renderer {
    /// The passes, in order: a block field's ground fill, terrain, the cull's passes, the
    /// blade response's compute passes (before the terrain without the cull), blades (or the floor), the debug views asked for,
    /// the resolve with `--msaa` or `--fade blend`, and the overlay's passes once there is an overlay.
    pub(super) fn build_graph(&mut self, cpu_scene: &Scene, polygon: vk::PolygonMode) -> Result<()> {
        // The far field's draw is the new graph's, if it has one.
        self.far = None;
        let device = &*self.device;
        let settings = &self.settings;
        let scene = self.scene.as_ref().expect("uploaded");
        let response = self.response.as_deref().expect("built");
        let constants = self.specialization();
        let msaa = settings.msaa;
        let target = PipelineTarget {
            layout: self.layouts.pipeline_layout,
            color: if self.linear_scene() { MSAA_COLOR_FORMAT } else { settings.color_format },
            depth: self.device.depth_format,
            polygon,
            samples: msaa.flag(),
            alpha_to_coverage: msaa.enabled() && msaa.alpha_to_coverage,
        };
        // Uploaded data, as the upload left it (a new kind of read will wait for the upload).
        self.graph.import(Resource::color(scene.blade_alpha.raw), &[Access::FragmentShaderSampledRead]);
        let vertex_compute = [Access::VertexShaderStorageRead, Access::ComputeShaderRead];
        self.graph.import(Resource::Buffer(scene.blades.raw), self.device.profile.fetches());
        self.graph.import(Resource::Buffer(scene.clusters.raw), &vertex_compute);
        if scene.ground.source.fill().is_none() {
            // A ground uploaded once (a stored terrain); a filled one is first written by its pass.
            self.graph.import(Resource::Buffer(scene.ground.texels.raw), self.device.profile.fetches());
            self.graph.import(Resource::Buffer(scene.ground.cover.0.raw), self.device.profile.fetches());
        }
        for (_, buffer) in &scene.ground.extra {
            self.graph.import(Resource::Buffer(buffer.raw), &[Access::ComputeShaderRead]);
        }
        self.graph.import(Resource::Buffer(scene.ground.indices.raw), &[Access::IndexRead]);
        self.graph.import(Resource::Buffer(scene.tiles.raw), &[Access::ComputeShaderRead]);
        // The response's resources, as their uploads left them.
        for (resource, uploaded) in response.tracked() {
            self.graph.import(resource, &uploaded);
        }
        if self.wind_passes_run() {
            // First: every blade response samples what it writes.
            let frames: Vec<_> =
                self.forces.iter().map(|f| (f.corners.descriptor(), f.emitters.descriptor())).collect();
            let setup = WindSetup { frames: &frames, corners: scene.wind_corner_count(), constants: &constants };
            for pass in self.wind.passes(device, &setup)? {
                self.graph.add_boxed(pass);
            }
            for (resource, accesses) in self.wind.tracked() {
                self.graph.import(resource, &accesses);
            }
        }
        if settings.floor {
            let sky = self.sky();
            let sets = ([&self.layouts.scene, &self.layouts.poses], self.ring.slots());
            add_terrain(&mut self.graph, device, (target, sets), &constants, scene, sky)?;
            self.graph.add(FloorPass::new(device, target, &constants, &cpu_scene.blades, settings.segments)?);
        } else {
            self.add_blade_passes(target, &constants)?;
            self.add_far_passes(target, &constants, cpu_scene)?;
        }
        if self.settings.debug_bounds {
            let (set_layout, scene) = (self.layouts.scene.raw, self.scene.as_ref().expect("uploaded"));
            let wind: Vec<vk::Buffer> = self.forces.iter().map(|f| f.corners.raw).collect();
            self.graph.add(ClusterBoundsPass::new(&self.device, (set_layout, target), &constants, scene, &wind)?);
        }
        if self.settings.debug_wind {
            let (set_layout, scene) = (self.layouts.scene.raw, self.scene.as_ref().expect("uploaded"));
            let wind: Vec<vk::Buffer> = self.forces.iter().map(|f| f.corners.raw).collect();
            self.graph.add(WindArrowsPass::new(&self.device, (set_layout, target), &constants, scene, &wind)?);
        }
        if self.linear_scene() {
            // The target's encoding, not the linear scene's.
            let resolve = Specialization { encode_srgb: u32::from(self.settings.encode_srgb), ..constants };
            let (format, samples) = (self.settings.color_format, msaa.samples);
            self.graph.add(ResolvePass::new(&self.device, (format, samples), &resolve, self.ring.slots())?);
        }
        // Last, over the frame's output (the resolved one with `--msaa` or `--fade blend`).
        self.add_overlay_passes();
        Ok(())
    }

    /// The terrain's clear colour as the scene's colour attachment stores it: encoded for an
    /// UNORM target the shaders encode for, linear for the multisampled scene or an sRGB format.
    fn sky(&self) -> [f32; 4] {
        sky_clear_color(self.settings.encode_srgb && !self.linear_scene())
    }

    /// The specialization constants of every scene pipeline for the settings and the response.
    fn specialization(&self) -> Specialization {
        let settings = &self.settings;
        let mut specialization = Specialization::new(
            settings.debug_force,
            settings.segments,
            settings.blades_per_instance,
            settings.submission.strategy.pushes_first_blade(),
            // Multisampled or blended, the scene is drawn in linear light; the resolve pass encodes.
            settings.encode_srgb && !self.linear_scene(),
        );
        specialization.msaa_samples = settings.msaa.samples;
        if settings.debug_lod {
            specialization.flags |= crate::render::specialization::FLAG_DEBUG_LOD;
        }
        if self.scene.as_ref().is_some_and(|scene| scene.field.is_some()) {
            specialization.flags |= crate::render::gpu_constants::FLAG_BLOCKS;
        }
        if let Some(scene) = &self.scene {
            // The ground's clipmap for the view distance (`shaders/common/ground.glsl`).
            let distances = (settings.culling.view_distance, settings.culling.blade_range());
            specialization.ground_cells = scene.ground.source.cells();
            specialization.ground_levels = scene.ground.source.levels(distances);
            specialization.ground_cover = u32::from(scene.ground.source.cover().active());
            specialization.clump_size_mm = scene.clump_size_mm;
            specialization.flower_share = scene.flower_share.to_bits();
            if settings.culling.ground_bounds {
                specialization.flags |= gpu::FLAG_GROUND_BOUNDS;
            }
        }
        if settings.debug_tiles {
            specialization.flags |= crate::render::gpu_constants::FLAG_DEBUG_TILES;
        }
        if settings.debug_fresnel {
            specialization.flags |= crate::render::gpu_constants::FLAG_DEBUG_FRESNEL;
        }
        if settings.debug_pressed {
            specialization.flags |= crate::render::gpu_constants::FLAG_DEBUG_PRESSED;
        }
        if settings.debug_far {
            specialization.flags |= crate::render::gpu_constants::FLAG_DEBUG_FAR;
        }
        if settings.debug_patches {
            specialization.flags |= crate::render::gpu_constants::FLAG_DEBUG_PATCHES;
        }
        if settings.debug_cover {
            specialization.flags |= crate::render::gpu_constants::FLAG_DEBUG_COVER;
        }
        // Where point sources are attenuated (thesis 4.5): the wind field's sampling, whichever
        // response reads it (`wind/wind_field.glsl`).
        specialization.attenuation = match self.animation.attenuation {
            crate::wind::Attenuation::Cluster => gpu::ATTENUATION_CLUSTER,
            crate::wind::Attenuation::Blade => gpu::ATTENUATION_BLADE,
        };
        if let (false, Some(response), Some(poses)) = (settings.floor, self.response.as_deref(), self.poses.as_ref()) {
            response.specialize(&mut specialization);
            if response.blade_input().pose_records() {
                specialization.flags |= gpu::FLAG_EVAL_BLADE;
                // With the cull, the drawn blades' levels are placed and lit once (`BladeLevelsPass`).
                if settings.culling.enabled && poses.level_records > 0 {
                    specialization.flags |= gpu::FLAG_LEVELS;
                }
            }
        }
        if settings.culling.enabled && settings.culling.solid_outline {
            // The buckets' pipelines draw the outline as geometry; the cull's scan sizes their
            // index lists by it (a collapsed tip, `bezier::BladeMesh`).
            specialization.flags |= gpu::FLAG_SOLID_OUTLINE;
        }
        specialization.cull_group = cull::workgroup_size(self.device.subgroup_size);
        // Rows per tile when the blade class or a further one draws so (`render::draw_class`).
        let rows = settings.culling.rows == DrawRows::PerTile
            || self.builders.classes.classes.iter().any(|class| class.rows() == DrawRows::PerTile);
        if let (true, true, Some(scene)) = (settings.culling.enabled, rows, &self.scene) {
            specialization.tile_rows_capacity = scene.slot_capacity;
        }
        specialization
    }

    /// A block field's ground fill, terrain, the cull (depth pyramid, tiles, count, scan, emit),
    /// the response's passes (after the cull, whose visible list they read; before the terrain
    /// without it) and the blade pass.
    fn add_blade_passes(&mut self, target: PipelineTarget, constants: &Specialization) -> Result<()> {
        let device = &*self.device;
        let settings = &self.settings;
        let scene = self.scene.as_ref().expect("uploaded");
        let response = self.response.as_deref().expect("built");
        let poses = self.poses.as_ref().expect("built");
        let culled = settings.culling.enabled;
        let layout = self.class_layout()?;
        let buckets = culled.then(|| settings.culling.buckets());
        let sets = SceneSets {
            before: [&self.layouts.scene, &self.layouts.poses],
            push: crate::render::submission::push_constant_range(),
            frames: self.ring.slots(),
        };
        let wind: Vec<vk::Buffer> = self.forces.iter().map(|f| f.corners.raw).collect();
        let posed = if culled { layout.posed() } else { Vec::new() };
        let poses_of = (poses.set, poses.poses.raw);
        let setup = ResponseSetup { sets, constants, scene, poses: poses_of, buckets, posed: &posed, wind: &wind };
        // Never recorded until the graph holds them.
        let mut response_passes = Guard::new(device, response.passes(device, &setup)?);
        self.response_passes = response_passes.iter().map(|pass| pass.name()).collect();
        if let (true, Some(map)) = (response.blade_input().pose_records(), self.pressed.as_ref()) {
            let clock = PatchClock::new(self.animation.clock, self.animation.chain);
            response_passes.extend(interaction_passes(device, &setup, map, clock)?);
        }
        if constants.flags & gpu::FLAG_LEVELS != 0 {
            response_passes.push(Box::new(BladeLevelsPass::new(device, &setup, poses)?));
        }
        let response_passes = response_passes.take();
        let (before, after) = if culled { (Vec::new(), response_passes) } else { (response_passes, Vec::new()) };
        before.into_iter().for_each(|pass| self.graph.add_boxed(pass));
        let sky = self.sky();
        let (graph, slots) = (&mut self.graph, self.ring.slots());
        // The response's passes are not in the graph yet: the graph's teardown would miss them.
        let after = Guard::new(device, after);
        (|| -> Result<()> {
            add_terrain(graph, device, (target, (sets.before, slots)), constants, scene, sky)?;
            if culled && settings.culling.occlusion {
                graph.add(DepthPyramidPass::new(device, scene, slots, settings.msaa.enabled())?);
            }
            if culled {
                let stats = self.cull_frames.iter().map(|frame| frame.stats.raw).collect();
                let (count_shader, tiles_shader) = self.builders.classes.cull_shaders();
                let setup = CullSetup { sets, constants, frame_stats: stats, count_shader, tiles_shader };
                cull::add_passes(graph, device, &setup, scene)?;
            }
            Ok(())
        })()?;
        after.take().into_iter().for_each(|pass| self.graph.add_boxed(pass));
        let setup = BladeSetup {
            target,
            constants,
            segments: settings.segments,
            blades_per_instance: settings.blades_per_instance,
            submission: settings.submission,
            frames_in_flight: settings.frames_in_flight,
            input: response.blade_input(),
            poses: (poses.set, poses.buffers()),
            sets,
            buckets: culled.then(|| settings.culling.buckets()),
            rows: settings.culling.rows,
            wind: &wind,
            depth_after: culled && !self.builders.classes.classes.is_empty(),
        };
        self.graph.add(BladePass::new(device, scene, &setup)?);
        if culled {
            // Each further draw class's pass, after the blades (`render::draw_class`).
            for (class, placed) in self.builders.classes.classes.iter().zip(&layout.classes) {
                let (target, blades_per_instance) = (target, settings.blades_per_instance);
                let (first_bucket, poses) = (placed.first, (poses.set, poses.buffers()));
                let setup = ClassSetup { target, sets, constants, scene, first_bucket, blades_per_instance, poses };
                self.graph.add_boxed(class.pass(device, &setup)?);
            }
        }
        Ok(())
    }
}

impl Renderer {
    /// The far field's passes after the blades (`render::far_field`): a block field's, when a far
    /// field is chosen and the ground reaches past the blades.
    fn add_far_passes(&mut self, target: PipelineTarget, constants: &Specialization, cpu_scene: &Scene) -> Result<()> {
        let scene = self.scene.as_ref().expect("uploaded");
        let culling = &self.settings.culling;
        let Some(rings) = culling.far_rings().filter(|_| scene.field.is_some()) else {
            return Ok(());
        };
        let response = self.response.as_deref().expect("built");
        let tips = far_field::TipTable::of(response);
        let sets = SceneSets {
            before: [&self.layouts.scene, &self.layouts.poses],
            push: crate::render::submission::push_constant_range(),
            frames: self.ring.slots(),
        };
        let wind: Vec<vk::Buffer> = self.forces.iter().map(|f| f.corners.raw).collect();
        // The pressed map, where the blades read it (the push-out pass is in the graph).
        let pressed = self.pressed.as_ref().filter(|_| response.blade_input().pose_records()).map(|map| map.reader());
        let setup = far_field::FarSetup { target, sets, constants, scene, wind: &wind, pressed };
        let key = far_field::atlas::bake_key(&cpu_scene.blades, scene.far_flower_share);
        let kept = (key, self.far_atlas.upgrade());
        let built =
            far_field::passes(&self.device, &setup, (&rings, (culling.far_field, culling.far_fade), &tips), kept)?;
        self.far = Some(built.draw);
        self.far_atlas = built.atlas;
        for pass in built.passes {
            self.graph.add_boxed(pass);
        }
        for resource in built.fresh {
            self.graph.import(resource, &[Access::Nothing]);
        }
        Ok(())
    }
}

/// The terrain pass, after the ground-fill pass that a filled ground's terrain reads (together, so
/// no path draws the clipmap unwritten). `sets`: the scene's set layouts and the frames in
/// flight, for the fill's own layout.
fn add_terrain(
    graph: &mut Graph,
    device: &Device,
    (target, sets): (PipelineTarget, ([&SetLayout; 2], usize)),
    constants: &Specialization,
    scene: &SceneGpu,
    sky: [f32; 4],
) -> Result<()> {
    if let Some(fill) = GroundFillPass::new(device, sets, constants, scene)? {
        graph.add(fill);
    }
    graph.add(TerrainPass::new(device, target, constants, scene, sky)?);
    Ok(())
}

/// Whatever the response wrote, bent by the pressed map and moved out of the colliders (Zhang Xia
/// §6.2), after the colliders and cuts are swept into the map; the blades a collider reaches, or
/// whose patch still lives, listed by the push-out walk and drawn by their patches' chains
/// (Belyaev §3.4, stepped by `clock`).
fn interaction_passes(
    device: &Device,
    setup: &ResponseSetup,
    map: &crate::render::animation::pressed::PressedMap,
    clock: PatchClock,
) -> Result<Vec<Box<dyn crate::render::graph::Pass>>> {
    let clock = std::rc::Rc::new(clock);
    let mut passes: Guard<Vec<Box<dyn crate::render::graph::Pass>>> = Guard::new(device, Vec::new());
    passes.push(Box::new(PressPass::new(device, setup, map.reader())?));
    passes.push(Box::new(PushOutPass::new(device, setup, map.reader(), clock.clone())?));
    passes.push(Box::new(PatchPass::new(device, setup, map.reader(), clock)?));
    Ok(passes.take())
}
