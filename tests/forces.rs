//! Per-blade forces on the GPU (the vertex shader's `blade_force`) against the CPU reference,
//! and the cluster-discretisation experiment of thesis fig. 4.7/4.8.

#[path = "support/compute.rs"]
mod compute;
#[path = "support/probes.rs"]
mod probes;

use std::sync::Arc;

use ash::vk;
use glam::{UVec4, Vec2, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation;
use meadow::render::uniforms::FrameUniforms;
use meadow::scene::clusters::{BladeCluster, ClusterGrid};
use meadow::scene::{BladeInstance, Scene};
use meadow::vk::descriptor::{self, Binding, Resource};
use meadow::vk::{pipeline, Buffer, BufferDesc, Device, DeviceSelector};
use meadow::wind::{Attenuation, CalmArea, Collider, GlobalWind, PointSource, Wind};

fn options() -> GpuOptions {
    GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") }
}

struct Case<'a> {
    blades: &'a [BladeInstance],
    grid: ClusterGrid,
    wind: &'a Wind,
    attenuation: Attenuation,
    time: f32,
}

/// Run `blade_forces.comp` for a case; returns (GPU forces, CPU reference forces).
fn gpu_forces(device: &Arc<Device>, case: &Case) -> meadow::Result<(Vec<Vec2>, Vec<Vec2>)> {
    let clusters = case.grid.assign(case.blades);
    let corners = animation::corner_forces(&case.grid, case.wind, case.time, case.attenuation);
    let emitters = animation::emitters(case.wind, case.time);
    let uniforms = FrameUniforms {
        wind_counts: UVec4::new(
            case.wind.sources.len() as u32,
            case.wind.colliders.len() as u32,
            case.grid.corners_per_side(),
            0,
        ),
        ..bytemuck::Zeroable::zeroed()
    };
    let inputs = Inputs { blades: case.blades, clusters: &clusters, corners: &corners, emitters: &emitters, uniforms };
    let gpu = probe(device, &inputs, case.attenuation, 0)?;
    let cpu = cpu_forces(case, &clusters, &corners, &emitters);
    Ok((gpu, cpu))
}

/// What `blade_forces.comp` reads: the frame uniforms, the blades, their cluster records (unread
/// for a block field), the corners' wind and the emitters.
struct Inputs<'a> {
    blades: &'a [BladeInstance],
    clusters: &'a [BladeCluster],
    corners: &'a [Vec4],
    emitters: &'a [Vec4],
    uniforms: FrameUniforms,
}

/// The GPU's force of every blade of `inputs`, the probe specialised for `attenuation` and the
/// render flags `flags` (`FLAG_BLOCKS` for a block field's levels).
fn probe(device: &Arc<Device>, inputs: &Inputs, attenuation: Attenuation, flags: u32) -> meadow::Result<Vec<Vec2>> {
    let buffers = buffers(device, inputs)?;
    let compute = vk::ShaderStageFlags::COMPUTE;
    let mut bindings = vec![Binding { binding: 0, kind: vk::DescriptorType::UNIFORM_BUFFER, stages: compute }];
    bindings.extend((1..6).map(|b| Binding { binding: b, kind: vk::DescriptorType::STORAGE_BUFFER, stages: compute }));
    let set_layout = descriptor::set_layout(device, "forces set layout", &bindings)?;
    let layout = pipeline::layout(device, "forces layout", &[set_layout], &[])?;
    // The attenuation (0 cluster, 1 blade), as the blade pipelines are specialised; the texture
    // mode and encoding 1, the rest as `Specialization::new` (the shaders' defaults).
    let attenuation = u32::from(attenuation == Attenuation::Blade);
    let base = meadow::render::specialization::Specialization::new(false, 4, 1, false, true);
    let spec = meadow::render::specialization::Specialization {
        keyframe_uvec4s: 0,
        mode: 1,
        encoding: 1,
        attenuation,
        flags: base.flags | flags,
        ..base
    };
    let pipe = pipeline::compute(
        device,
        "blade forces",
        probes::BLADE_FORCES_COMP.code(device.profile),
        layout,
        &spec.named(),
    )?;
    let (pool, sets) = descriptor::allocate_sets(device, "forces", set_layout, &bindings, 1)?;
    let writes: Vec<_> = bindings
        .iter()
        .zip(&buffers)
        .map(|(b, buffer)| (b.binding, b.kind, Resource::Buffer(buffer.descriptor())))
        .collect();
    descriptor::write(device, sets[0], &writes);
    let out = buffers.last().expect("output").raw;
    let groups = (inputs.blades.len() as u32).div_ceil(64);
    let submitted = compute::dispatch(device, "forces", (pipe, layout), &sets, &[], groups, out);
    let gpu: Vec<Vec2> = bytemuck::cast_slice::<u8, [f32; 2]>(buffers.last().expect("output").mapped())
        .iter()
        .map(|f| Vec2::from(*f))
        .collect();
    // SAFETY: submit_and_wait waited for the dispatch.
    unsafe { compute::teardown(device, (pool, pipe, layout, set_layout), buffers) };
    submitted?;
    Ok(gpu)
}

/// The shader's inputs (frame uniforms, blades, their clusters, corner forces, emitters) and its
/// host-visible output, in binding order.
fn buffers(device: &Arc<Device>, inputs: &Inputs) -> meadow::Result<Vec<Buffer>> {
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let upload = |name: &str, bytes: &[u8], usage| {
        Buffer::with_data(device, &BufferDesc::upload(name, bytes.len() as u64, usage), bytes)
    };
    let mut buffers = vec![
        upload("frame", bytemuck::bytes_of(&inputs.uniforms), vk::BufferUsageFlags::UNIFORM_BUFFER)?,
        upload("blades", bytemuck::cast_slice(inputs.blades), storage)?,
        upload("clusters", bytemuck::cast_slice(inputs.clusters), storage)?,
        upload("corners", bytemuck::cast_slice(inputs.corners), storage)?,
        upload("emitters", bytemuck::cast_slice(inputs.emitters), storage)?,
    ];
    buffers.push(Buffer::new(device, &BufferDesc::readback("forces", 8 * inputs.blades.len() as u64, storage))?);
    Ok(buffers)
}

/// The CPU reference of every blade's force.
fn cpu_forces(case: &Case, clusters: &[BladeCluster], corners: &[Vec4], emitters: &[Vec4]) -> Vec<Vec2> {
    let sources = case.wind.sources.len();
    case.blades
        .iter()
        .zip(clusters)
        .map(|(b, c)| animation::blade_force(&case.grid, c, corners, emitters, sources, case.attenuation, b))
        .collect()
}

fn assert_close(gpu: &[Vec2], cpu: &[Vec2], what: &str) {
    for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        assert!((*g - *c).length() <= 1e-4 * (1.0 + c.length()), "{what}: blade {i}: GPU {g:?} CPU {c:?}");
    }
}

#[test]
fn gpu_blade_forces_equal_the_cpu_reference() {
    let scene = Scene::generate(3000, 5);
    let wind = Wind {
        global: Some(GlobalWind { direction_deg: 20.0, strength: 0.4, gusts: true }),
        sources: vec![PointSource {
            position: Vec2::new(0.5, -0.5),
            power: 0.3,
            sigma: 2.0,
            velocity: Vec2::new(0.1, 0.0),
            height: 0.5,
        }],
        calm: vec![CalmArea { min: Vec2::new(-1.0, 0.5), max: Vec2::new(0.5, 1.5) }],
        colliders: vec![Collider::at_rest(glam::Vec3::new(-1.0, 0.2, -1.0), glam::Vec3::new(0.3, 0.2, 0.5))],
        cuts: Vec::new(),
    };
    let (result, messages) = with_device(&options(), false, |device| {
        for attenuation in [Attenuation::Cluster, Attenuation::Blade] {
            let case = Case {
                blades: &scene.blades,
                grid: ClusterGrid::new(scene.terrain.size, 0.5),
                wind: &wind,
                attenuation,
                time: 1.25,
            };
            let (gpu, cpu) = gpu_forces(device, &case)?;
            assert_close(&gpu, &cpu, &format!("{attenuation:?}"));
        }
        Ok(())
    });
    result.expect("forces computed");
    assert_eq!(messages, Some(0));
}

/// Thesis fig. 4.7/4.8: with a concentrated source, interpolating attenuated corner forces
/// (cluster) gets worse as clusters grow; delaying the attenuation to the blade does not.
#[test]
fn delayed_attenuation_removes_cluster_artefacts() {
    let scene = Scene::generate(4000, 8);
    let source =
        PointSource { position: Vec2::new(0.3, -0.2), power: 0.05, sigma: 2.0, velocity: Vec2::ZERO, height: 0.5 };
    let wind = Wind { sources: vec![source], ..Default::default() };
    // Blades between 0.3 m and 1.5 m from the source, where the force changes fast.
    let near: Vec<BladeInstance> = scene
        .blades
        .iter()
        .copied()
        .filter(|b| (Vec2::new(b.position[0], b.position[2]) - source.position).length() > 0.3)
        .filter(|b| (Vec2::new(b.position[0], b.position[2]) - source.position).length() < 1.5)
        .collect();
    assert!(near.len() > 500);
    let truth: Vec<Vec2> = near.iter().map(|b| wind.force_at(Vec2::new(b.position[0], b.position[2]), 0.0)).collect();
    let mean_relative_error = |forces: &[Vec2]| {
        forces.iter().zip(&truth).map(|(f, t)| (*f - *t).length() / t.length()).sum::<f32>() / truth.len() as f32
    };
    let (result, messages) = with_device(&options(), false, |device| {
        let mut cluster_errors = Vec::new();
        for size in [0.25f32, 0.5, 1.0, 2.0] {
            let grid = ClusterGrid::new(scene.terrain.size, size);
            let mut errors = [0.0f32; 2];
            for (i, attenuation) in [Attenuation::Cluster, Attenuation::Blade].into_iter().enumerate() {
                let case = Case { blades: &near, grid, wind: &wind, attenuation, time: 0.0 };
                let (gpu, cpu) = gpu_forces(device, &case)?;
                assert_close(&gpu, &cpu, &format!("{attenuation:?} {size} m"));
                errors[i] = mean_relative_error(&gpu);
            }
            eprintln!("cluster {size:>4} m: cluster attenuation error {:.4}, blade {:.2e}", errors[0], errors[1]);
            assert!(errors[1] < 1e-3, "blade attenuation error {} at {size} m", errors[1]);
            cluster_errors.push(errors[0]);
        }
        assert!(
            cluster_errors.windows(2).all(|w| w[1] > w[0]),
            "cluster attenuation error must grow with cluster size: {cluster_errors:?}"
        );
        Ok(())
    });
    result.expect("experiment ran");
    assert_eq!(messages, Some(0));
}

#[test]
fn corner_forces_are_what_the_cluster_grid_interpolates() {
    // Exposure of a corner inside a calm area is 0, elsewhere 1 (the w of each corner); the wind
    // in m/s, `KEYFRAME_WIND_SCALE` times the keyframe force.
    let grid = ClusterGrid::new(4.0, 1.0);
    let wind = Wind {
        global: Some(GlobalWind { direction_deg: 0.0, strength: 0.5, gusts: false }),
        calm: vec![CalmArea { min: Vec2::new(-2.0, -2.0), max: Vec2::new(-1.0, -1.0) }],
        ..Default::default()
    };
    let corners = animation::corner_forces(&grid, &wind, 0.0, Attenuation::Cluster);
    assert_eq!(corners[0], Vec4::new(0.0, 0.0, 0.0, 0.0));
    assert_eq!(corners[24], Vec4::new(0.5 * meadow::wind::KEYFRAME_WIND_SCALE, 0.0, 0.0, 1.0));
}

/// Issue 29 item 3: a collider's Y is a world height, and a blade feels the reach-weighted force
/// of the part of it inside the collider. A sphere whose lowest point is 0.35 m above the ground
/// pushes the tallest blades (0.55 m) under it outwards and leaves every blade under 0.3 m (tip
/// 0.29 m above the ground: roots sink 1 cm) bit-identical to a run without it; 50 m up it leaves
/// every blade bit-identical. On the GPU, under both attenuations.
#[test]
fn a_sphere_above_the_ground_bends_only_the_blades_that_reach_it() {
    let scene = Scene::generate(12000, 5);
    let (x, z, radius) = (0.2f32, -0.3f32, 1.0f32);
    let lowest = scene.terrain.height_at(x, z) + 0.35;
    let sphere =
        |lift: f32| Collider::at_rest(glam::Vec3::new(x, lowest + radius + lift, z), glam::Vec3::splat(radius));
    let global = Some(GlobalWind { direction_deg: 20.0, strength: 0.4, gusts: true });
    let bare = Wind { global, ..Default::default() };
    let low = Wind { colliders: vec![sphere(0.0)], ..bare.clone() };
    let high = Wind { colliders: vec![sphere(50.0)], ..bare.clone() };
    let (result, messages) = with_device(&options(), false, |device| {
        for attenuation in [Attenuation::Cluster, Attenuation::Blade] {
            let grid = ClusterGrid::new(scene.terrain.size, 0.5);
            let run = |wind: &Wind| {
                let case = Case { blades: &scene.blades, grid, wind, attenuation, time: 0.75 };
                gpu_forces(device, &case)
            };
            let (without, _) = run(&bare)?;
            let (with_low, cpu_low) = run(&low)?;
            let (with_high, _) = run(&high)?;
            assert_close(&with_low, &cpu_low, &format!("{attenuation:?} sphere"));
            let (mut tall, mut short) = (0, 0);
            for (i, b) in scene.blades.iter().enumerate() {
                let away = Vec2::new(b.position[0] - x, b.position[2] - z);
                let push = with_low[i] - without[i];
                if b.height < 0.3 {
                    short += usize::from(away.length() < radius);
                    assert_eq!(
                        with_low[i].to_array().map(f32::to_bits),
                        without[i].to_array().map(f32::to_bits),
                        "blade {i}, {} m",
                        b.height
                    );
                } else if b.height > 0.5 && away.length() > 0.05 && away.length() < 0.3 * radius {
                    tall += 1;
                    assert!(
                        push.dot(away.normalize()) > 0.05,
                        "{attenuation:?}: blade {i} ({} m) at {away}: push {push}",
                        b.height
                    );
                }
                assert_eq!(
                    with_high[i].to_array().map(f32::to_bits),
                    without[i].to_array().map(f32::to_bits),
                    "blade {i} under the sphere 50 m up"
                );
            }
            eprintln!("{attenuation:?}: {tall} tall blades pushed, {short} short ones under the sphere unchanged");
            assert!(tall >= 10 && short >= 20, "{tall} tall, {short} short blades under the sphere");
        }
        Ok(())
    });
    result.expect("forces computed");
    assert_eq!(messages, Some(0));
}

/// Issue 29 item 1: a block field's wind lives in `WIND_LEVELS` nested levels around O's cell
/// (`field_gpu::wind_level`), and a blade takes the finest level that holds it, blended into the
/// next over the outer quarter of its half-extent. The GPU's interpolation (`levels_wind` of
/// `shaders/wind/wind_field.glsl`, through the keyframes' `blade_force`) against its CPU mirror
/// (`animation::levels_wind`), for blades from O's cell out past the outermost level (clamped),
/// across every level and every blend band; the corners as the analytic field writes them.
#[test]
fn a_block_fields_wind_levels_are_sampled_as_the_cpu_mirror_samples_them() {
    use meadow::render::gpu_constants::{FLAG_BLOCKS, WIND_LEVELS, WIND_LEVEL_CLUSTERS};
    let cluster_size = 1.0f32;
    let wind = Wind {
        global: Some(GlobalWind { direction_deg: 35.0, strength: 0.6, gusts: true }),
        sources: vec![PointSource {
            position: Vec2::new(40.0, -30.0),
            power: 2.0,
            sigma: 1.0,
            velocity: Vec2::ZERO,
            height: 0.5,
        }],
        calm: vec![CalmArea { min: Vec2::new(-300.0, 100.0), max: Vec2::new(-100.0, 400.0) }],
        ..Default::default()
    };
    let time = 1.75;
    let corners: Vec<Vec4> = (0..WIND_LEVELS)
        .flat_map(|l| {
            let grid = meadow::render::field_gpu::wind_level(cluster_size, l);
            animation::corner_forces_at(&grid, Vec2::ZERO, &wind, time, Attenuation::Cluster)
        })
        .collect();
    // Blades on a spiral out to 6 km (relative to O), upright, so no collider or pose matters.
    let blades: Vec<BladeInstance> = (0..4000)
        .map(|i| {
            let t = i as f32 / 4000.0;
            let p = Vec2::splat(4.0) + Vec2::from_angle(t * 211.0) * 6000.0 * t * t;
            BladeInstance { position: [p.x, 0.0, p.y], height: 0.4, stiffness: 1.0, ..bytemuck::Zeroable::zeroed() }
        })
        .collect();
    let uniforms = FrameUniforms {
        wind_counts: UVec4::new(wind.sources.len() as u32, 0, WIND_LEVEL_CLUSTERS + 1, WIND_LEVELS),
        terrain: Vec4::new(0.0, cluster_size, 0.0, 0.0),
        field: Vec4::new(meadow::scene::field::BLOCK_SIZE, 0.0, 0.0, 0.0),
        ..bytemuck::Zeroable::zeroed()
    };
    let emitters = animation::emitters(&wind, time);
    let clusters = vec![BladeCluster { corner: 0, weights: 0 }; blades.len()];
    let inputs = Inputs { blades: &blades, clusters: &clusters, corners: &corners, emitters: &emitters, uniforms };
    let (result, messages) =
        with_device(&options(), false, |device| probe(device, &inputs, Attenuation::Cluster, FLAG_BLOCKS));
    let gpu = result.expect("forces computed");
    assert_eq!(messages, Some(0));
    let half0 = 0.5 * WIND_LEVEL_CLUSTERS as f32 * cluster_size;
    let (mut levels, mut blended) = (vec![0usize; WIND_LEVELS as usize], 0);
    for (b, g) in blades.iter().zip(&gpu) {
        let root = Vec2::new(b.position[0], b.position[2]);
        let cpu = animation::levels_wind(cluster_size, &corners, root);
        let cpu = Vec2::new(cpu.x, cpu.z) / meadow::wind::KEYFRAME_WIND_SCALE;
        assert!((*g - cpu).length() <= 1e-4 * (1.0 + cpu.length()), "blade at {root}: GPU {g}, CPU {cpu}");
        let ratio = (root - Vec2::splat(4.0)).abs().max_element() / half0;
        let level = if ratio <= 1.0 { 0 } else { (ratio.log2().ceil() as usize).min(WIND_LEVELS as usize - 1) };
        levels[level] += 1;
        blended += usize::from(ratio / (1u32 << level) as f32 > 0.75 && level + 1 < WIND_LEVELS as usize);
    }
    eprintln!("blades per level {levels:?}, {blended} in a blend band");
    assert!(levels.iter().all(|&n| n >= 20) && blended >= 200, "{levels:?}, {blended} blended");
}

/// A block field holds only the wind levels its blades read (`field_gpu::wind_levels`): for every
/// root over the cull's rings about O's cell, the levels held give the wind all eight would, on
/// the CPU mirror of the GPU's sampling (`animation::levels_wind`).
#[test]
fn the_levels_a_block_field_holds_give_every_blade_in_range_the_wind_all_eight_would() {
    use meadow::render::field_gpu::{ring_radius, wind_level, wind_levels};
    use meadow::render::gpu_constants::{WIND_LEVELS, WIND_LEVEL_CLUSTERS};
    use meadow::scene::field::BLOCK_SIZE;
    let wind =
        Wind { global: Some(GlobalWind { direction_deg: 35.0, strength: 0.6, gusts: true }), ..Default::default() };
    let corners: Vec<Vec4> = (0..WIND_LEVELS)
        .flat_map(|l| animation::corner_forces_at(&wind_level(1.0, l), Vec2::ZERO, &wind, 1.75, Attenuation::Cluster))
        .collect();
    let per_level = (WIND_LEVEL_CLUSTERS as usize + 1).pow(2);
    for range in [20.0, 60.0, 150.0, 300.0, 504.0] {
        let levels = wind_levels(1.0, range) as usize;
        let held = &corners[..levels * per_level];
        // Roots on a spiral over the cull's rings about O's cell.
        let reach = (ring_radius(range) as f32 + 0.5) * BLOCK_SIZE;
        for i in 0..2000 {
            let t = i as f32 / 2000.0;
            let root = Vec2::splat(0.5 * BLOCK_SIZE) + Vec2::from_angle(t * 97.0) * reach * t.sqrt();
            let (few, all) = (animation::levels_wind(1.0, held, root), animation::levels_wind(1.0, &corners, root));
            assert_eq!(few, all, "{range} m, {levels} levels, root {root}");
        }
    }
}
