//! A draw class added from `tests/` (issue #30 item 1, `render::draw_class`), with no edit to the
//! library: a class of markers, its selection in its own count shader
//! (`tests/shaders/draw_class/markers_count.comp`: every seventh stored blade the blade tests keep
//! becomes a marker), its pass and its GLSL (`marker.vert`, `marker.frag`), drawn far to near.
//! Culled together with the blade class through the library's tiles, scan and emit passes, on
//! lavapipe with validation and synchronization validation:
//! - the counts of both classes equal the CPU reference (`cull_reference::reference_kept`, split
//!   by the same rule), and together the blades drawn without the class;
//! - the markers' entries in the visible list are the reference's claimed blades, farthest slot
//!   first, while the blade class's run nearest first;
//! - the markers are drawn (red squares in the picture), and the blades they took are not.
//!
//! And a class with a candidate source of its own (`render::draw_class::CandidateSource`):
//! beacons, a few per stored tile (`tests/shaders/draw_class/beacons.glsl`), placed by their own
//! tiles and count shaders. Their counts and visible entries equal the CPU reference's (the slots
//! the tile tests keep, `cull_reference::reference_slots`), the blades are culled as without them,
//! and they are drawn (blue squares).

mod support;

use std::rc::Rc;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::cull_reference::{reference_kept, reference_slots};
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::draw_class::{draw_word, CandidateSource, ClassSetup, DrawClass, DrawClasses, Order};
use meadow::render::graph::{Declaration, Pass, PassContext};
use meadow::render::passes::{self, PipelineTarget};
use meadow::render::uniforms::FrameUniforms;
use meadow::render::{Models, OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{Camera, Scene};
use meadow::vk::profile::Shader;
use meadow::vk::upload::UploadBatch;
use meadow::vk::{pipeline, Access, Buffer, Device, DeviceSelector, Guard};

const MARKERS_COUNT: Shader = meadow::spirv_shader!("tests/draw_class/markers_count.comp");
const MARKER_VERT: Shader = meadow::spirv_shader!("tests/draw_class/marker.vert");
const MARKER_FRAG: Shader = meadow::spirv_shader!("tests/draw_class/marker.frag");
const BEACONS_TILES: Shader = meadow::spirv_shader!("tests/draw_class/beacons_tiles.comp");
const BEACONS_COUNT: Shader = meadow::spirv_shader!("tests/draw_class/beacons_count.comp");
const BEACON_VERT: Shader = meadow::spirv_shader!("tests/draw_class/beacon.vert");

const EXTENT: vk::Extent2D = vk::Extent2D { width: 320, height: 180 };

/// The markers' claim (`markers_count.comp`).
fn claimed(blade: u32) -> bool {
    blade % 7 == 3
}

/// The class: one bucket, far to near, an upright square per entry.
struct Markers;

impl DrawClass for Markers {
    fn name(&self) -> &'static str {
        "markers"
    }

    fn buckets(&self) -> u32 {
        1
    }

    fn order(&self) -> Order {
        Order::FarToNear
    }

    fn bucket_draw(&self, _: u32, blades_per_instance: u32) -> (u32, u32) {
        (6 * blades_per_instance, 0)
    }

    fn pass(&self, device: &Device, setup: &ClassSetup) -> meadow::Result<Box<dyn Pass>> {
        Ok(Box::new(MarkerPass::new(device, setup, MARKER_VERT)?))
    }
}

/// The beacons: one bucket, near to far, from their own candidate source.
struct Beacons;

/// The beacons' source: most per slot (beacons.glsl places 2 to 7 a tile).
const BEACONS_MOST: u32 = 5;

impl DrawClass for Beacons {
    fn name(&self) -> &'static str {
        "beacons"
    }

    fn buckets(&self) -> u32 {
        1
    }

    fn bucket_draw(&self, _: u32, blades_per_instance: u32) -> (u32, u32) {
        (6 * blades_per_instance, 0)
    }

    fn pass(&self, device: &Device, setup: &ClassSetup) -> meadow::Result<Box<dyn Pass>> {
        Ok(Box::new(MarkerPass::new(device, setup, BEACON_VERT)?))
    }
}

/// A class's pass of squares (the markers', the beacons'): its pipeline, its index list (two
/// triangles per entry of an instance), and the cull's buffers it reads.
struct MarkerPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    indices: Buffer,
    draws: vk::Buffer,
    visible: vk::Buffer,
    bucket: u32,
}

impl MarkerPass {
    fn new(device: &Device, setup: &ClassSetup, vertex: Shader) -> meadow::Result<Self> {
        let quads: Vec<u32> =
            (0..setup.blades_per_instance).flat_map(|m| [0, 1, 2, 2, 1, 3].map(|v| 4 * m + v)).collect();
        let mut batch = UploadBatch::new(device);
        let indices =
            batch.buffer("marker indices", &quads, vk::BufferUsageFlags::INDEX_BUFFER, &[Access::IndexRead])?;
        // Not submitted yet: the batch waits for its submission, or never submits.
        let indices = Guard::new(device, indices);
        batch.submit()?;
        let target: PipelineTarget = setup.target;
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "markers",
                vertex: vertex.code(device.profile),
                fragment: MARKER_FRAG.code(device.profile),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                cull: vk::CullModeFlags::NONE,
                polygon: target.polygon,
                depth_compare: vk::CompareOp::GREATER,
                depth_write: true,
                color_format: target.color,
                depth_format: target.depth,
                layout: target.layout,
                constants: &setup.constants.named(),
                vertex_stride: 0,
                samples: target.samples,
                blend: pipeline::Blend::Opaque,
            },
        )?;
        let (draws, visible) = (setup.scene.draws.raw, setup.scene.visible.raw);
        Ok(Self {
            pipeline,
            layout: target.layout,
            indices: indices.take(),
            draws,
            visible,
            bucket: setup.first_bucket,
        })
    }
}

impl Pass for MarkerPass {
    fn name(&self) -> &'static str {
        "markers"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let rendering = passes::scene_rendering(ctx, self.pipeline, true, false);
        let declaration = Declaration::graphics(rendering)
            .buffer(self.visible, ctx.device.profile.vertex_fetch())
            .buffer(self.draws, Access::IndirectCommandRead);
        Some(declaration.buffer(self.indices.raw, Access::IndexRead))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.layout, self.pipeline);
        let (offset, stride) = draw_word(self.bucket);
        // SAFETY: cmd is recording inside this pass's rendering instance; set 0 is bound; the
        // scan wrote the bucket's draw before this pass (the graph's barrier).
        unsafe {
            device.raw.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
            device.raw.cmd_draw_indexed_indirect(cmd, self.draws, offset, 1, stride);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            meadow::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.indices.destroy(device);
        }
    }
}

/// One frame of `scene` from `camera`, with the markers or without: the picture (RGBA), the
/// cull's counts, the visible list and draws, and the frame's uniforms.
struct Frame {
    pixels: Vec<u8>,
    counts: CullCounts,
    visible: Vec<[u32; 2]>,
    draws: Vec<u32>,
    uniforms: FrameUniforms,
}

/// The classes a test culls besides the blades.
#[derive(Clone, Copy, PartialEq)]
enum With {
    Nothing,
    Markers,
    Beacons,
}

fn render(scene: &Scene, camera: &Camera, with: With) -> Frame {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let classes = match with {
            With::Markers => {
                DrawClasses { classes: vec![Rc::new(Markers)], count_shader: Some(MARKERS_COUNT), source: None }
            }
            With::Beacons => DrawClasses {
                classes: vec![Rc::new(Beacons)],
                count_shader: Some(BEACONS_COUNT),
                source: Some(CandidateSource { tiles_shader: BEACONS_TILES, most_per_slot: BEACONS_MOST }),
            },
            With::Nothing => DrawClasses::default(),
        };
        let models = Models { classes, ..Models::default() };
        // No occlusion test: the CPU reference has no depth pyramid.
        let culling = Culling { occlusion: false, ..Culling::default_for(4) };
        let settings = RenderSettings::offscreen(4, culling);
        let mut renderer = Renderer::with_models(device.clone(), scene, settings, Default::default(), models)?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        // Two frames: the second one's barriers follow the first one's accesses.
        renderer.render_offscreen(&mut target, camera, 0.0)?;
        let timings = renderer.render_offscreen(&mut target, camera, 0.0)?;
        let (visible, draws) = renderer.read_visible_list()?;
        let uniforms = renderer.frame_uniforms(camera, 0.0, EXTENT);
        let pixels = target.pixels().to_vec();
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(Frame { pixels, counts: timings.cull.expect("culled"), visible, draws, uniforms })
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// Pixels of one saturated channel (0 the markers' red, 2 the beacons' blue), the others dark.
fn saturated(pixels: &[u8], channel: usize) -> usize {
    pixels.chunks(4).filter(|p| (0..3).all(|c| if c == channel { p[c] > 200 } else { p[c] < 40 })).count()
}

/// Pixels of `channel` with the class and without it; the picture with it saved to the path in
/// the environment variable `save`, if set.
fn class_pixels(with: &Frame, without: &Frame, channel: usize, save: &str) -> (usize, usize) {
    if let Ok(path) = std::env::var(save) {
        image::save_buffer(path, &with.pixels, EXTENT.width, EXTENT.height, image::ColorType::Rgba8).expect("saved");
    }
    (saturated(&with.pixels, channel), saturated(&without.pixels, channel))
}

/// The entries of bucket `bucket` (its draw's instances, padding left out).
fn bucket_entries(frame: &Frame, bucket: u32, blades_per_instance: u32) -> Vec<u32> {
    let draw = &frame.draws[(bucket * meadow::render::gpu_constants::DRAW_WORDS) as usize..];
    let first = draw[meadow::render::gpu_constants::DRAW_FIRST_INSTANCE as usize] * blades_per_instance;
    let count = draw[meadow::render::gpu_constants::DRAW_INSTANCES as usize] * blades_per_instance;
    frame.visible[first as usize..(first + count) as usize].iter().map(|e| e[0]).filter(|&b| b != u32::MAX).collect()
}

#[test]
fn a_class_from_tests_culls_with_the_blades_counts_as_the_reference_and_draws_far_to_near() {
    let scene = Scene::generate(20_000, 1);
    let camera = scene.default_camera();
    let with = render(&scene, &camera, With::Markers);
    let without = render(&scene, &camera, With::Nothing);
    let kept = reference_kept(&scene, &with.uniforms);
    let (marked, blades): (Vec<&(u32, u32, usize)>, Vec<_>) = kept.iter().partition(|(_, blade, _)| claimed(*blade));
    assert!(marked.len() > 100 && blades.len() > 1000, "{} markers, {} blades", marked.len(), blades.len());

    // Counts: each class as the reference splits it, the stats of the candidates unchanged.
    let buckets = with.counts.segments.iter().filter(|&&s| s > 0).count();
    for b in 0..buckets {
        let reference = blades.iter().filter(|k| k.2 == b).count() as u32;
        assert_eq!(with.counts.drawn[b], reference, "bucket {b}: {}", with.counts.summary());
    }
    assert_eq!(with.counts.classes[0].name, "markers");
    assert_eq!(with.counts.classes[0].drawn as usize, marked.len(), "{}", with.counts.summary());
    assert_eq!(with.counts.total_drawn(), without.counts.total_drawn(), "the markers are blades taken from the class");
    assert_eq!(with.counts.after_occlusion, without.counts.after_occlusion);
    assert!(with.counts.summary().contains(&format!("{} markers drawn", marked.len())), "{}", with.counts.summary());

    // The markers' bucket, after the blades': the reference's claimed blades, farthest slot first
    // (stored order inside a slot); the blade buckets nearest first.
    let batch = RenderSettings::offscreen(4, Culling::default_for(4)).blades_per_instance;
    let slot_of: std::collections::HashMap<u32, u32> = kept.iter().map(|&(slot, blade, _)| (blade, slot)).collect();
    let entries = bucket_entries(&with, buckets as u32, batch);
    let mut expected: Vec<(u32, u32)> = marked.iter().map(|&&(slot, blade, _)| (slot, blade)).collect();
    expected.sort_by_key(|&(slot, blade)| (std::cmp::Reverse(slot), blade));
    assert_eq!(entries, expected.iter().map(|e| e.1).collect::<Vec<_>>(), "the markers' entries, far to near");
    let slots: Vec<u32> = entries.iter().map(|b| slot_of[b]).collect();
    assert!(slots.first() > slots.last(), "the markers span slots: {:?}..{:?}", slots.first(), slots.last());
    let near: Vec<u32> = bucket_entries(&with, 0, batch).iter().map(|b| slot_of[b]).collect();
    assert!(near.windows(2).all(|w| w[0] <= w[1]) && near.first() < near.last(), "the blades run near to far");

    // Drawn: red squares where there were none, and the pictures differ only through them.
    let (red_with, red_without) = class_pixels(&with, &without, 0, "MEADOW_DRAW_CLASS_PNG");
    assert!(red_without == 0 && red_with > 200, "red pixels: {red_with} with the markers, {red_without} without");
}

#[test]
fn a_class_with_its_own_candidate_source_culls_with_the_blades_as_the_reference() {
    let scene = Scene::generate(20_000, 1);
    let camera = scene.default_camera();
    let with = render(&scene, &camera, With::Beacons);
    let without = render(&scene, &camera, With::Nothing);

    // The reference: in each slot the tile tests keep, near to far, its beacons (beacons.glsl:
    // 2 to 7 a tile, clamped to the source's most), those kept in their order.
    let slots = reference_slots(&scene, &with.uniforms);
    let mut expected = Vec::new();
    let mut clamped = 0;
    for (slot, tile) in &slots {
        let placed = 2 + (tile.first / 7) % 6;
        clamped += usize::from(placed > BEACONS_MOST);
        let kept = (0..placed.min(BEACONS_MOST)).filter(|rank| (tile.first + rank) % 3 != 0);
        expected.extend(kept.map(|rank| (slot << 16) | rank));
    }
    assert!(expected.len() > 15 && clamped > 0, "{} beacons, {clamped} slots clamped", expected.len());

    // Counts: the beacons in their class, the blades' buckets and tests as without the class.
    let buckets = with.counts.segments.iter().filter(|&&s| s > 0).count();
    assert_eq!(with.counts.classes[0].name, "beacons");
    assert_eq!(with.counts.classes[0].drawn as usize, expected.len(), "{}", with.counts.summary());
    assert_eq!(with.counts.drawn[..buckets], without.counts.drawn[..buckets], "the blades' buckets");
    assert_eq!(with.counts.considered, without.counts.considered);
    assert_eq!(with.counts.after_occlusion, without.counts.after_occlusion);

    // The beacons' entries: (slot, rank) near to far, after the blades' buckets.
    let batch = RenderSettings::offscreen(4, Culling::default_for(4)).blades_per_instance;
    assert_eq!(bucket_entries(&with, buckets as u32, batch), expected, "the beacons' entries");
    assert_eq!(bucket_entries(&with, 0, batch), bucket_entries(&without, 0, batch), "the blades' entries");

    // Drawn: blue squares where there were none.
    let (blue_with, blue_without) = class_pixels(&with, &without, 2, "MEADOW_SOURCE_CLASS_PNG");
    assert!(blue_without == 0 && blue_with > 200, "blue pixels: {blue_with} with the beacons, {blue_without} without");
}

#[test]
fn more_buckets_than_the_cull_holds_are_refused() {
    struct Wide;
    impl DrawClass for Wide {
        fn name(&self) -> &'static str {
            "wide"
        }
        fn buckets(&self) -> u32 {
            8
        }
        fn bucket_draw(&self, _: u32, _: u32) -> (u32, u32) {
            (6, 0)
        }
        fn pass(&self, _: &Device, _: &ClassSetup) -> meadow::Result<Box<dyn Pass>> {
            unreachable!("refused before its pass is built")
        }
    }
    let scene = Scene::generate(2_000, 1);
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let classes = DrawClasses { classes: vec![Rc::new(Wide)], count_shader: Some(MARKERS_COUNT), source: None };
        let models = Models { classes, ..Models::default() };
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        Ok(Renderer::with_models(device.clone(), &scene, settings, Default::default(), models).err())
    });
    assert_eq!(messages, Some(0), "validation messages");
    let error = result.expect("ran").expect("refused").to_string();
    assert!(error.contains("buckets") && error.contains("wide 8"), "{error}");
}
