//! The fluid wind (`render::wind::fluid`, `--wind-field fluid`; Zhang Xia §2 after Stam) on
//! lavapipe and against its CPU reference (`fluid::scheme`, the same scheme and order):
//! - three steps of an 8³ grid on the GPU (read back) match the CPU's within 1e-4, with a
//!   source, a collider and gusts at the inflow;
//! - the projection at `PRESSURE_ITERATIONS` cuts the RMS divergence (the solver's own operator)
//!   by 20× or more, and 500 iterations bring it to 1e-3 of the injected velocity scale;
//! - injected velocity moves downstream;
//! - the jet under a source keeps its world cell when the camera moves 5 cells (the window
//!   scrolls by whole cells, toroidally);
//! - the corners' wind is continuous across the grid's edge (no step past what the blend band
//!   allows), equals the analytic field past it, and leans towards +x under a wind towards +x.

mod support;

use ash::vk;
use glam::{DVec2, IVec3, UVec3, Vec2, Vec3, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::AnimationSettings;
use meadow::render::culling::Culling;
use meadow::render::wind::fluid::scheme::{project_only, FluidState};
use meadow::render::wind::fluid::{self, FluidWind, PRESSURE_ITERATIONS};
use meadow::render::wind::params::Params;
use meadow::render::wind::{FieldKind, WindInput};
use meadow::render::{Models, OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::clusters::ClusterGrid;
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Attenuation, Collider, FluidGrid, GlobalWind, PointSource, Wind};

/// What a GPU run read after each frame: the grid in local cells, and the corners.
struct Frame {
    params: Params,
    window: IVec3,
    velocity: Vec<Vec3>,
    corners: Vec<Vec4>,
}

/// Each of `frames`' steps against the CPU reference stepped alongside from the first frame's
/// entered grid: within 1e-4 m/s everywhere.
fn assert_steps_match_the_cpu(frames: &[Frame]) {
    let mut cpu = FluidState::entered(&frames[0].params);
    for (k, frame) in frames.iter().enumerate() {
        cpu.step(&frame.params);
        let worst =
            cpu.velocity.iter().zip(&frame.velocity).map(|(a, b)| (*a - *b).abs().max_element()).fold(0.0, f32::max);
        assert!(worst <= 1e-4, "step {k}: the GPU's grid differs from the CPU's by {worst} m/s");
    }
}

/// Render one culled frame per camera of `cameras` under `wind` with the fluid on `grid`, and
/// read the fluid's grid (reordered from its toroidal slots to local cells) and the corners.
fn run(scene: &Scene, grid: FluidGrid, wind: &Wind, cameras: &[Camera]) -> Vec<Frame> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let animation =
            AnimationSettings { wind: wind.clone(), wind_field: FieldKind::Fluid, fluid: grid, ..Default::default() };
        let field = FluidWind::new(grid)?;
        let probe = field.probe();
        let models = Models { wind: Box::new(field), ..Models::default() };
        let mut renderer = Renderer::with_models(device.clone(), scene, settings, animation, models)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
        let mut frames = Vec::new();
        for (k, camera) in cameras.iter().enumerate() {
            renderer.render_offscreen(&mut target, camera, (k as f32 + 0.5) / 60.0)?;
            let (texels, extent, base) = renderer.read_wind_state()?.expect("the fluid has a grid");
            let dims = UVec3::new(extent.width, extent.height, extent.depth);
            let local = |c: UVec3| meadow::render::camera_grid::slot(c, base, dims) as usize;
            let mut velocity = Vec::new();
            for z in 0..dims.z {
                for y in 0..dims.y {
                    for x in 0..dims.x {
                        velocity.push(Vec4::from(texels[local(UVec3::new(x, y, z))]).truncate());
                    }
                }
            }
            let window = probe.window().expect("a window").as_ivec3();
            let corners = renderer.read_wind_corners(0)?.into_iter().map(Vec4::from).collect();
            frames.push(Frame { params: probe.params(), window, velocity, corners });
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frames; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(frames)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// A frame's parameters on the CPU for a window of `grid` whose first cell is the origin's.
fn cpu_params(grid: &FluidGrid, wind: &Wind, time: f64) -> Params {
    let clusters = ClusterGrid::new(8.0, 1.0);
    let input = WindInput {
        grid: &clusters,
        levels: 1,
        wind,
        attenuation: Attenuation::Cluster,
        time,
        origin: DVec2::ZERO,
        cpu_corners: false,
        camera: glam::DVec3::ZERO,
        dt: 1.0 / 60.0,
        ground: None,
    };
    let mut params = Params::new(&input);
    fluid::fill_params(&mut params, grid, (glam::I64Vec3::ZERO, UVec3::ZERO), &input);
    params
}

fn source(x: f32, z: f32, power: f32, height: f32) -> PointSource {
    PointSource { position: Vec2::new(x, z), power, sigma: 2.0, velocity: Vec2::ZERO, height }
}

#[test]
fn three_steps_of_an_8_cubed_grid_match_the_cpu_reference() {
    let scene = Scene::generate(2000, 3);
    let camera = Camera::default_for(&scene.terrain);
    let (cx, cz) = (camera.position.x, camera.position.z);
    let wind = Wind {
        global: Some(GlobalWind { direction_deg: 30.0, strength: 0.3, gusts: true }),
        sources: vec![source(cx + 1.0, cz + 0.5, 0.4, 1.0)],
        colliders: vec![Collider::at_rest(Vec3::new(cx - 1.5, 0.8, cz - 1.0), Vec3::splat(0.9))],
        ..Default::default()
    };
    let grid = FluidGrid { dims: [8, 8, 8], cell: [1.0, 0.5] };
    let frames = run(&scene, grid, &wind, &[camera, camera, camera]);
    assert_steps_match_the_cpu(&frames);
    // The step did something: the jet, the collider's solid cells.
    let last = &frames[2].velocity;
    assert!(last.iter().any(|v| v.y < -0.5), "the source's jet blows down");
    assert!(last.iter().filter(|v| **v == Vec3::ZERO).count() > 0, "the collider's cells are solid");
}

/// The same against the CPU with the wind from the other side, on a grid longer in z than in x:
/// the upwind ghosts are the far faces' (x = nx, z = nz), the inflow's rows 1 and 3, which the
/// 8³ case's wind never reads.
#[test]
fn the_far_faces_inflow_on_an_uneven_grid_matches_the_cpu_reference() {
    let scene = Scene::generate(2000, 3);
    let camera = Camera::default_for(&scene.terrain);
    let wind =
        Wind { global: Some(GlobalWind { direction_deg: 210.0, strength: 0.3, gusts: true }), ..Default::default() };
    let grid = FluidGrid { dims: [5, 4, 9], cell: [1.0, 0.5] };
    let frames = run(&scene, grid, &wind, &[camera, camera]);
    let faces = frames[0].params.fluid_dims[3];
    assert_eq!(faces, 2 | 8, "the wind blows in through the x+ and z+ faces only");
    assert_steps_match_the_cpu(&frames);
}

/// A divergent field on `grid`: the analytic wind plus a hashed, smooth-ish perturbation.
fn perturbed(params: &Params) -> FluidState {
    let mut state = FluidState::entered(params);
    let dims = state.dims;
    for (i, v) in state.velocity.iter_mut().enumerate() {
        let (x, y, z) = (i as i32 % dims.x, i as i32 / dims.x % dims.y, i as i32 / (dims.x * dims.y));
        let s = |a: f32| a.sin();
        *v += Vec3::new(
            s(0.9 * x as f32 + 0.3 * z as f32),
            0.5 * s(1.3 * y as f32 + x as f32),
            s(0.7 * z as f32 - y as f32),
        );
    }
    state
}

#[test]
fn the_projection_cuts_the_divergence_20_times_and_converges_with_more_iterations() {
    for grid in [FluidGrid { dims: [8, 8, 8], cell: [1.0, 1.0] }, FluidGrid::default()] {
        let wind = Wind {
            global: Some(GlobalWind { direction_deg: 30.0, strength: 0.3, gusts: false }),
            ..Default::default()
        };
        let params = cpu_params(&grid, &wind, 0.0);
        let mut state = perturbed(&params);
        let (before, after) = project_only(&mut state, &params, PRESSURE_ITERATIONS);
        eprintln!("{:?}: RMS divergence {before} → {after} ({}×)", grid.dims, before / after);
        assert!(before / after >= 20.0, "{:?}: {before} → {after}", grid.dims);
    }
    // 500 iterations on 8³: to 1e-3 of the injected scale (1 m/s over a 1 m cell).
    let grid = FluidGrid { dims: [8, 8, 8], cell: [1.0, 1.0] };
    let wind =
        Wind { global: Some(GlobalWind { direction_deg: 30.0, strength: 0.3, gusts: false }), ..Default::default() };
    let params = cpu_params(&grid, &wind, 0.0);
    let mut state = perturbed(&params);
    let (_, after) = project_only(&mut state, &params, 500);
    assert!(after <= 1e-3, "500 iterations leave an RMS divergence of {after} /s against 1 /s injected");
}

#[test]
fn injected_velocity_moves_downstream() {
    let grid = FluidGrid { dims: [24, 8, 12], cell: [1.0, 0.5] };
    let blowing = Wind {
        global: Some(GlobalWind { direction_deg: 0.0, strength: 0.5, gusts: false }),
        sources: vec![source(5.0, 6.0, 0.4, 1.0)],
        ..Default::default()
    };
    let still_source = Wind { sources: Vec::new(), ..blowing.clone() };
    let mut state = FluidState::entered(&cpu_params(&grid, &blowing, 0.0));
    // Where the jet's downward velocity is, by x: its centroid.
    let centroid = |s: &FluidState| {
        let (mut sum, mut weight) = (0.0, 0.0);
        for (i, v) in s.velocity.iter().enumerate() {
            let x = (i as i32 % s.dims.x) as f32 + 0.5;
            sum += x * v.y.min(0.0).abs();
            weight += v.y.min(0.0).abs();
        }
        (sum / weight, weight)
    };
    for k in 0..20 {
        state.step(&cpu_params(&grid, &blowing, f64::from(k) / 60.0));
    }
    let (start, injected) = centroid(&state);
    assert!(injected > 1.0, "the source injected a jet");
    for k in 20..50 {
        state.step(&cpu_params(&grid, &still_source, f64::from(k) / 60.0));
    }
    let (end, _) = centroid(&state);
    // 4 m/s for half a second: about 2 m downstream (the jet also spreads and leaves).
    assert!(end - start > 1.0, "the jet's centroid moved from x = {start} to {end} m");
}

#[test]
fn the_jet_keeps_its_world_cell_when_the_camera_moves_five_cells() {
    let scene = Scene::generate(2000, 3);
    let camera = Camera::default_for(&scene.terrain);
    let grid = FluidGrid { dims: [16, 8, 16], cell: [1.0, 0.5] };
    let (cx, cz) = (camera.position.x, camera.position.z);
    let wind = Wind { global: None, sources: vec![source(cx + 0.5, cz - 0.5, 0.5, 1.0)], ..Default::default() };
    let mut moved = camera;
    moved.position.x += 5.0;
    let mut cameras = vec![camera; 30];
    cameras.push(moved);
    let frames = run(&scene, grid, &wind, &cameras);
    // The world cell of the jet's core (its strongest downward velocity).
    let core = |f: &Frame| {
        let (i, _) = f.velocity.iter().enumerate().fold((0, 0.0), |b, (i, v)| if v.y < b.1 { (i, v.y) } else { b });
        let d = IVec3::from_array(grid.dims.map(|n| n as i32));
        f.window + IVec3::new(i as i32 % d.x, i as i32 / d.x % d.y, i as i32 / (d.x * d.y))
    };
    let (before, after) = (&frames[29], &frames[30]);
    assert_eq!(after.window - before.window, IVec3::new(5, 0, 0), "the window scrolled five cells");
    let (a, b) = (core(before), core(after));
    assert!((a - b).abs().max_element() <= 1, "the jet's core moved from world cell {a} to {b}");
}

#[test]
fn the_corners_are_continuous_across_the_edge_and_lean_downwind() {
    let scene = Scene::generate(100_000, 4);
    let camera = Camera::default_for(&scene.terrain);
    let (cx, cz) = (camera.position.x, camera.position.z);
    let grid = FluidGrid { dims: [8, 4, 8], cell: [1.0, 0.5] };
    let steady = GlobalWind { direction_deg: 0.0, strength: 0.5, gusts: false };
    let wind = Wind {
        global: Some(steady),
        sources: vec![source(cx + 1.0, cz, 0.5, 0.5)],
        colliders: vec![Collider::at_rest(Vec3::new(cx - 1.0, 0.5, cz + 1.0), Vec3::splat(1.0))],
        ..Default::default()
    };
    let frames = run(&scene, grid, &wind, &[camera; 12]);
    let last = frames.last().expect("frames");
    let clusters = ClusterGrid::new(scene.terrain.size, 1.0);
    let n = clusters.corners_per_side() as usize;
    let p = &last.params;
    let inside = |q: Vec2| {
        let g = (q - Vec2::new(p.fluid_corner[0], p.fluid_corner[1])) / p.fluid_cell[0];
        g.min(Vec2::splat(grid.dims[0] as f32) - g).min_element()
    };
    // The analytic field past the grid is the global wind plus the source's eq. 4.1.
    let mut outside = 0;
    let mut largest_step = 0.0f32;
    for (i, c) in last.corners.iter().enumerate() {
        let q = clusters.corner_position(i as u32);
        if inside(q) <= 0.0 {
            let analytic =
                Vec2::new(4.0, 0.0) + meadow::wind::PointSource::force_from(Vec2::new(cx + 1.0, cz), 0.5, 2.0, q) * 8.0;
            assert!((Vec2::new(c.x, c.z) - analytic).length() < 1e-3 * analytic.length().max(1.0), "corner {q}");
            outside += 1;
        }
        // The step to the next corner along x, against the analytic field's own.
        if (i + 1) % n != 0 {
            let next = last.corners[i + 1];
            let (ea, eb) = (inside(q), inside(clusters.corner_position(i as u32 + 1)));
            if (ea <= 0.0) != (eb <= 0.0) || (ea > 0.0 && ea < 2.0) || (eb > 0.0 && eb < 2.0) {
                largest_step = largest_step.max((next - *c).truncate().length());
            }
        }
    }
    assert!(outside > 100, "the field reaches past the grid ({outside} corners)");
    let mean = last.corners.iter().map(|c| c.x).sum::<f32>() / last.corners.len() as f32;
    assert!(mean > 2.0, "the corners lean towards +x under a 4 m/s wind towards +x: {mean} m/s on average");
    // Inside the blend band a corner moves at most half the way (1 m of a 2-cell band) from the
    // analytic field to the fluid's per metre; the two differ by at most a jet's speed here.
    let difference = last
        .corners
        .iter()
        .enumerate()
        .filter(|(i, _)| inside(clusters.corner_position(*i as u32)) > 0.0)
        .map(|(i, c)| {
            let q = clusters.corner_position(i as u32);
            let analytic = Vec2::new(4.0, 0.0) + PointSource::force_from(Vec2::new(cx + 1.0, cz), 0.5, 2.0, q) * 8.0;
            (Vec2::new(c.x, c.z) - analytic).length()
        })
        .fold(0.0f32, f32::max);
    assert!(difference > 0.1, "the fluid differs from the analytic field inside the grid");
    assert!(
        largest_step <= 0.5 * difference + 1.0,
        "a step of {largest_step} m/s at the edge (fields differ by {difference})"
    );
}

#[test]
fn a_steady_wind_with_nothing_in_it_stays_as_it_entered() {
    // Uniform flow is a solution of the scheme with these boundaries: inflow, outflow, ground
    // and top leave it as it is, step after step.
    let grid = FluidGrid { dims: [12, 6, 10], cell: [1.0, 0.5] };
    let wind =
        Wind { global: Some(GlobalWind { direction_deg: 30.0, strength: 0.5, gusts: false }), ..Default::default() };
    let params = cpu_params(&grid, &wind, 0.0);
    let mut state = FluidState::entered(&params);
    let entered = state.velocity[0];
    assert!((entered.length() - 4.0).abs() < 1e-5, "4 m/s entered: {entered}");
    for _ in 0..60 {
        state.step(&params);
    }
    let worst = state.velocity.iter().map(|v| (*v - entered).abs().max_element()).fold(0.0, f32::max);
    assert!(worst < 1e-4, "a steady wind drifted by {worst} m/s in 60 steps");
}
