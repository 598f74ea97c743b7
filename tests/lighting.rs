//! Belyaev §2.3's Fresnel term: evaluated by the shader's own functions at read-back strip
//! vertices and checked against the formula on the CPU, and shown to grow towards contour areas.

#[path = "support/compute.rs"]
mod compute;
#[path = "support/probes.rs"]
mod probes;

mod support;

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use meadow::app::{with_device, GpuOptions};
use meadow::render::frame::look;
use meadow::scene::camera::Camera;
use meadow::scene::{bezier, Scene};
use meadow::vk::descriptor::{self, Binding, Resource};
use meadow::vk::{pipeline, Buffer, BufferDesc, Device, DeviceSelector};

/// Ks of lighting.glsl (`FRESNEL_KS`); `ks_is_the_shaders` keeps the two in step.
const KS: [f32; 3] = [0.26, 0.30, 0.34];
/// Floats per vertex the probe writes: world xyz, l, terrain normal xyz, Is rgb.
const PROBE_FLOATS: usize = 10;
const SEGMENTS: u32 = 4;

/// One probed strip vertex.
struct ProbedVertex {
    world: Vec3,
    l: f32,
    terrain_normal: Vec3,
    fresnel: Vec3,
}

/// Run fresnel_probe.comp over every strip vertex of `scene`'s blades seen from `camera`.
fn probe(device: &Arc<Device>, scene: &Scene, camera: Vec3) -> meadow::Result<Vec<ProbedVertex>> {
    let vertices = bezier::strip_vertices(SEGMENTS);
    let count = scene.blades.len() * vertices as usize;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let blades = Buffer::with_data(
        device,
        &BufferDesc::upload("probe blades", 32 * scene.blades.len() as u64, storage),
        &scene.blades,
    )?;
    let heights = &scene.terrain.heights;
    let heights =
        Buffer::with_data(device, &BufferDesc::upload("probe heights", 4 * heights.len() as u64, storage), heights)?;
    let output = Buffer::new(device, &BufferDesc::readback("probe", (4 * PROBE_FLOATS * count) as u64, storage))?;
    let bindings: Vec<Binding> = (0..3)
        .map(|binding| Binding {
            binding,
            kind: vk::DescriptorType::STORAGE_BUFFER,
            stages: vk::ShaderStageFlags::COMPUTE,
        })
        .collect();
    let set_layout = descriptor::set_layout(device, "probe set layout", &bindings)?;
    let push = vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 36 };
    let layout = pipeline::layout(device, "probe layout", &[set_layout], &[push])?;
    let pipe =
        pipeline::compute(device, "fresnel probe", probes::FRESNEL_PROBE_COMP.code(device.profile), layout, &[])?;
    let (pool, sets) = descriptor::allocate_sets(device, "probe", set_layout, &bindings, 1)?;
    let resources = [&blades, &heights, &output].map(|b| Resource::Buffer(b.descriptor()));
    let writes: Vec<_> =
        resources.into_iter().enumerate().map(|(i, r)| (i as u32, vk::DescriptorType::STORAGE_BUFFER, r)).collect();
    descriptor::write(device, sets[0], &writes);
    let t = &scene.terrain;
    let params: [f32; 9] =
        [camera.x, camera.y, camera.z, 0.0, t.origin(), t.cell_size(), t.cells as f32, 0.0, f32::from_bits(vertices)];
    let groups = (count as u32).div_ceil(64);
    let submitted =
        compute::dispatch(device, "probe", (pipe, layout), &sets, bytemuck::cast_slice(&params), groups, output.raw);
    let floats = bytemuck::cast_slice::<u8, f32>(output.mapped()).to_vec();
    // SAFETY: submit_and_wait waited for the dispatch.
    unsafe { compute::teardown(device, (pool, pipe, layout, set_layout), [blades, heights, output]) };
    submitted?;
    Ok(floats
        .chunks_exact(PROBE_FLOATS)
        .map(|f| ProbedVertex {
            world: Vec3::new(f[0], f[1], f[2]),
            l: f[3],
            terrain_normal: Vec3::new(f[4], f[5], f[6]),
            fresnel: Vec3::new(f[7], f[8], f[9]),
        })
        .collect())
}

/// Is = Ks · l⁶ · (1 − N_L·V)¹⁰ on the CPU (lighting.glsl's reading of Belyaev §2.3).
fn fresnel_formula(terrain_normal: Vec3, world: Vec3, camera: Vec3, l: f32) -> Vec3 {
    let v = (camera - world).normalize();
    let c = 1.0 - terrain_normal.dot(v).clamp(0.0, 1.0);
    Vec3::from(KS) * l.powi(6) * c.powi(10)
}

fn probe_views(scene: &Scene, cameras: &[Vec3]) -> Vec<Vec<ProbedVertex>> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) =
        with_device(&options, false, |device| cameras.iter().map(|&c| probe(device, scene, c)).collect());
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("probe ran")
}

#[test]
fn fresnel_term_matches_the_cpu_formula_at_read_back_vertices() {
    let scene = Scene::generate(1500, 11);
    // Low over the field's edge, so the far blades are seen nearly edge-on.
    let camera = Camera::default_for(&scene.terrain).position - 1.4 * Vec3::Y;
    let probed = probe_views(&scene, &[camera]).remove(0);
    let vertices = bezier::strip_vertices(SEGMENTS) as usize;
    assert_eq!(probed.len(), scene.blades.len() * vertices);
    let mut lit = 0;
    for (i, p) in probed.iter().enumerate() {
        let blade = &scene.blades[i / vertices];
        // The probe placed the vertex where the CPU's strip does, over the CPU terrain's normal.
        let cpu_world = bezier::strip_vertex(blade, SEGMENTS, (i % vertices) as u32);
        assert!(p.world.distance(cpu_world) < 1e-4, "vertex {i}: {} against {cpu_world}", p.world);
        let cpu_normal = scene.terrain.normal_at(blade.position[0], blade.position[2]);
        assert!(p.terrain_normal.distance(cpu_normal) < 1e-5, "normal {i}: {} against {cpu_normal}", p.terrain_normal);
        let expected = fresnel_formula(cpu_normal, p.world, camera, p.l);
        let error = (p.fresnel - expected).abs().max_element();
        assert!(error < 1e-5 + 1e-4 * expected.max_element(), "vertex {i}: Is {} against {expected}", p.fresnel);
        lit += usize::from(expected.x > 0.01);
    }
    // The comparison is not of zeros: the far blades' tips carry the term.
    assert!(lit > probed.len() / 100, "only {lit} of {} vertices have Is > 0.01", probed.len());
}

#[test]
fn fresnel_term_grows_towards_contour_areas() {
    let scene = Scene::generate(1500, 12);
    let grazing = Camera::default_for(&scene.terrain).position;
    let steep = Vec3::new(0.0, scene.terrain.height_at(0.0, 0.0) + 25.0, 0.0);
    let views = probe_views(&scene, &[grazing, steep]);
    let tips = |view: &[ProbedVertex], keep: &dyn Fn(&ProbedVertex) -> bool| {
        let chosen: Vec<f32> = view.iter().filter(|p| p.l == 1.0 && keep(p)).map(|p| p.fresnel.y).collect();
        chosen.iter().sum::<f32>() / chosen.len().max(1) as f32
    };
    let all = |_: &ProbedVertex| true;
    let (grazing_mean, steep_mean) = (tips(&views[0], &all), tips(&views[1], &all));
    assert!(grazing_mean > 20.0 * steep_mean, "grazing {grazing_mean} against steep {steep_mean}");
    // Within the grazing view, the farther (more edge-on) half of the field gets more of it.
    let distance = |p: &ProbedVertex| p.world.distance(grazing);
    let near = tips(&views[0], &|p| distance(p) < 0.5 * scene.terrain.size);
    let far = tips(&views[0], &|p| distance(p) >= 0.5 * scene.terrain.size);
    assert!(far > 2.0 * near, "far {far} against near {near}");
    // And it grows with the edge-on-ness itself: the tip vertices sorted by N_L·V.
    let mut by_cos: Vec<(f32, f32)> = views[0]
        .iter()
        .filter(|p| p.l == 1.0)
        .map(|p| (p.terrain_normal.dot((grazing - p.world).normalize()), p.fresnel.y))
        .collect();
    by_cos.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = by_cos.len() / 2;
    let mean = |s: &[(f32, f32)]| s.iter().map(|p| p.1).sum::<f32>() / s.len() as f32;
    assert!(mean(&by_cos[..half]) > 4.0 * mean(&by_cos[half..]), "edge-on half against facing half");
}

#[test]
fn ks_is_the_shaders() {
    let source = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/common/lighting.glsl")).unwrap();
    let declared = format!("const vec3 FRESNEL_KS = vec3({:.2}, {:.2}, {:.2});", KS[0], KS[1], KS[2]);
    assert!(source.contains(&declared), "lighting.glsl does not declare {declared}");
}

#[test]
fn the_fresnel_debug_view_shows_the_term_alone() {
    let dir = support::scratch("fresnel_view");
    let args = ["--blades", "3000", "--size", "160x96"];
    let lit = dir.join("lit.png");
    let term = dir.join("term.png");
    support::render(&args, &lit);
    let with_view: Vec<&str> = args.iter().copied().chain(["--debug-view", "fresnel"]).collect();
    support::render(&with_view, &term);
    let (lit, term) = (support::Picture::load(&lit), support::Picture::load(&term));
    // Blades lose their diffuse light: the view is darker wherever grass is.
    let sum = |p: &support::Picture| -> u64 { p.rgb.iter().skip(1).step_by(3).map(|&g| u64::from(g)).sum() };
    assert!(sum(&term) < sum(&lit), "the debug view is not darker than the lit picture");
}

/// Run a probe shader (`spirv`) of one dispatch of `groups` workgroups that writes `values` floats
/// to the storage buffer at set 0, binding 0.
fn float_probe(device: &Arc<Device>, name: &str, spirv: &[u8], values: usize, groups: u32) -> meadow::Result<Vec<f32>> {
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let output = Buffer::new(device, &BufferDesc::readback(name, 4 * values as u64, storage))?;
    let bindings =
        [Binding { binding: 0, kind: vk::DescriptorType::STORAGE_BUFFER, stages: vk::ShaderStageFlags::COMPUTE }];
    let set_layout = descriptor::set_layout(device, name, &bindings)?;
    let layout = pipeline::layout(device, name, &[set_layout], &[])?;
    let pipe = pipeline::compute(device, name, spirv, layout, &[])?;
    let (pool, sets) = descriptor::allocate_sets(device, name, set_layout, &bindings, 1)?;
    descriptor::write(
        device,
        sets[0],
        &[(0, vk::DescriptorType::STORAGE_BUFFER, Resource::Buffer(output.descriptor()))],
    );
    let submitted = compute::dispatch(device, name, (pipe, layout), &sets, &[], groups, output.raw);
    let floats = bytemuck::cast_slice::<u8, f32>(output.mapped()).to_vec();
    // SAFETY: submit_and_wait waited for the dispatch.
    unsafe { compute::teardown(device, (pool, pipe, layout, set_layout), [output]) };
    submitted?;
    Ok(floats)
}

/// Run height_six_probe.comp: `height_six` at levels 0..=s of strips of s = 1..=16 segments of a
/// 16-segment model, strip after strip.
fn height_six_probe(device: &Arc<Device>) -> meadow::Result<Vec<f32>> {
    let values = (1..=16).map(|s| s + 1).sum::<usize>();
    float_probe(device, "height six probe", probes::HEIGHT_SIX_PROBE_COMP.code(device.profile), values, 1)
}

#[test]
fn coarse_strips_are_lit_with_the_mean_of_l6_over_each_level() {
    // A strip interpolates its per-level colour linearly. For the l^6 height terms to come out
    // as they do on the full blade, each level of a coarser strip takes the mean of l^6 over the
    // stretch it stands for: the strip's piecewise-linear l^6 then integrates to exactly 1/7 (the
    // trapezoid rule over stretch means), where the point values integrate to more (1 segment:
    // 1/2, several times too bright). The model's own strip keeps the point values.
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, height_six_probe);
    let values = result.expect("probe");
    assert_eq!(messages, Some(0), "validation messages");
    let mut at = 0;
    for s in 1..=16usize {
        let levels = &values[at..at + s + 1];
        at += s + 1;
        let h = 0.5 / s as f64;
        for (level, &value) in levels.iter().enumerate() {
            let t = level as f64 / s as f64;
            let expected = if s == 16 {
                t.powi(6)
            } else {
                let (a, b) = ((t - h).max(0.0), (t + h).min(1.0));
                (b.powi(7) - a.powi(7)) / (7.0 * (b - a))
            };
            assert!((f64::from(value) - expected).abs() < 2e-6, "{s} segments, level {level}: {value} vs {expected}");
        }
        let trapezoid: f64 =
            levels.windows(2).map(|w| 0.5 * (f64::from(w[0]) + f64::from(w[1]))).sum::<f64>() / s as f64;
        if s < 16 {
            assert!((trapezoid - 1.0 / 7.0).abs() < 1e-5, "{s} segments integrate to {trapezoid}");
        }
    }
}

#[test]
fn the_srgb_encoding_is_within_half_a_level_of_the_exact_curve() {
    // The UNORM targets are encoded in the shaders by a three-square-root fit of the sRGB curve
    // (`encode_output`), and the clear colour by its CPU mirror: within half a level of 8 bits of
    // the exact transfer everywhere, so at most one level off after rounding, and the mirror
    // agrees with the shader.
    const VALUES: usize = 4096; // SRGB_PROBE_VALUES of srgb_probe.comp
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, |device| {
        float_probe(device, "srgb probe", probes::SRGB_PROBE_COMP.code(device.profile), VALUES, 64)
    });
    let encoded = result.expect("probe");
    assert_eq!(messages, Some(0), "validation messages");
    let mut worst: f32 = 0.0;
    for (i, &gpu) in encoded.iter().enumerate() {
        let linear = i as f32 / (VALUES - 1) as f32;
        let exact = look::encode_srgb_exact(linear);
        worst = worst.max((gpu - exact).abs() * 255.0);
        assert!((gpu - look::encode_srgb(linear)).abs() < 2e-6, "{linear}: shader {gpu}, CPU mirror");
    }
    assert!(worst < 0.45, "largest error {worst} of a level");
    // The probe reads what it should: the ends are exact, the middle is the sRGB curve, not linear.
    assert_eq!((encoded[0], encoded[VALUES - 1]), (0.0, 1.0));
    assert!((encoded[VALUES / 2] - 0.7353).abs() < 1e-3, "{}", encoded[VALUES / 2]);
}
