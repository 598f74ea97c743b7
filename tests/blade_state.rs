//! State that lasts (issue #29 item 5), with a stateful response defined here
//! (`tests/shaders/blade_state/spring.comp`: each blade's tip is a damped spring pulled towards
//! the offset the wind asks for) on the library's blade-state store
//! (`render::animation::blade_state`). Through the cull, validation-clean:
//!
//! - one frame of k steps leaves the same state, to the bit, as k frames of one step, and the
//!   state is the spring's CPU reference of those steps;
//! - a blade inside the store's radius keeps bit-identical state across camera moves that scroll
//!   the store, against a run without the moves;
//! - one that leaves the radius and comes back, and one culled for a frame and drawn again,
//!   restart at the equilibrium under the wind (the documented policy: reset), where the blades
//!   of the run without the detour are still swinging;
//! - a stored field keeps state for its blades by index in the same way.

#[path = "support/steady_wind.rs"]
mod steady_wind;
mod support;

use std::cell::{Cell, RefCell};
use std::rc::Rc;

use ash::vk;
use glam::{Vec2, Vec3};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::blade_state::{self, BladeStateStore, StepSpan, StoreShape, HEADER_WORDS};
use meadow::render::animation::response::{
    BladeInput, BladeResponse, BuildResponse, ResponseContext, ResponseSetup, ResponseStep,
};
use meadow::render::culling::Culling;
use meadow::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use meadow::render::recording::{BladeDispatch, PassSet};
use meadow::render::specialization::Specialization;
use meadow::render::{Models, OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::{FieldSpec, BLOCK_SIZE};
use meadow::scene::{Camera, Scene};
use meadow::vk::descriptor::Resource as Descriptor;
use meadow::vk::profile::Shader;
use meadow::vk::{Access, Destroy, Device, DeviceSelector, Resource};
use steady_wind::{SteadyWind, Velocity};

const SPRING_COMP: Shader = meadow::spirv_shader!("tests/blade_state/spring.comp");

const EXTENT: vk::Extent2D = vk::Extent2D { width: 160, height: 90 };
/// The spring's state: offset x, z and velocity x, z (f32 bits), and the weight of the stateless
/// counterpart it was drawn with (for the test).
const WORDS: u32 = 5;
/// The block field's store: blocks within 2 of the camera's.
const RADIUS: u32 = 2;
/// spring.comp's constants.
const GAIN: f32 = 0.08;
const K: f32 = 40.0;
const C: f32 = 3.0;
const DT: f32 = 1.0 / 60.0;

/// The ramp's rise, seconds (`Velocity::Ramp`).
const RAMP_S: f64 = 0.05;

/// The spring response's builder, its store shared with the test.
fn spring(store: &SharedStore) -> Rc<BuildResponse> {
    let shared = store.clone();
    Rc::new(move |device: &Device, context: &ResponseContext| -> meadow::Result<Box<dyn BladeResponse>> {
        *shared.borrow_mut() = Some(BladeStateStore::new(device, context.scene, WORDS, RADIUS, true)?);
        Ok(Box::new(SpringResponse {
            store: shared.clone(),
            previous: Cell::new(None),
            span: Rc::new(Cell::new(StepSpan::between(None, 0))),
        }))
    })
}

/// The store, shared with the test, which reads it back between frames.
type SharedStore = Rc<RefCell<Option<BladeStateStore>>>;

/// The spring response: its store and the span of steps each frame takes.
struct SpringResponse {
    store: SharedStore,
    previous: Cell<Option<u64>>,
    span: Rc<Cell<StepSpan>>,
}

impl BladeResponse for SpringResponse {
    fn name(&self) -> &'static str {
        "spring"
    }

    fn specialize(&self, _: &mut Specialization) {}

    fn blade_input(&self) -> BladeInput {
        BladeInput::PoseRecords
    }

    fn tracked(&self) -> Vec<(Resource, Vec<Access>)> {
        Vec::new()
    }

    fn passes(&self, device: &Device, setup: &ResponseSetup) -> meadow::Result<Vec<Box<dyn Pass>>> {
        let store = self.store.borrow();
        let store = store.as_ref().expect("the store");
        Ok(vec![Box::new(SpringPass::new(device, setup, store, self.span.clone())?)])
    }

    fn step(&mut self, step: &ResponseStep) {
        self.span.set(StepSpan::between(self.previous.get(), step.step));
        self.previous.set(Some(step.step));
    }

    fn tip_offset(&self, wind: Vec3) -> Vec3 {
        let t = Vec2::new(wind.x, wind.z) * GAIN;
        Vec3::new(t.x, 0.0, t.y)
    }

    fn stateful(&self) -> bool {
        true
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        if let Some(store) = self.store.borrow_mut().take() {
            // SAFETY: per the contract.
            unsafe { store.destroy(device) };
        }
    }
}

/// spring.comp over the drawn blades: the store's clear on its first frame, the steps, and the
/// store handed to the host for the test.
struct SpringPass {
    set: PassSet,
    dispatch: BladeDispatch,
    uniforms: PassUniforms,
    span: Rc<Cell<StepSpan>>,
    store: vk::Buffer,
    /// What the store's records are (its frame block, `StoreShape::frame_block`).
    shape: StoreShape,
    cleared: Cell<bool>,
    poses: (vk::DescriptorSet, vk::Buffer),
    reads: [vk::Buffer; 2],
    wind: Vec<vk::Buffer>,
}

impl SpringPass {
    fn new(
        device: &Device,
        setup: &ResponseSetup,
        store: &BladeStateStore,
        span: Rc<Cell<StepSpan>>,
    ) -> meadow::Result<Self> {
        let scene = setup.scene;
        let spirv = SPRING_COMP.code(device.profile);
        let uniforms = PassUniforms::new(device, "spring", 48, setup.sets.frames)?;
        let shaders = [("spring.comp", spirv)];
        let set = PassSet::new(device, &setup.sets.desc("spring", &shaders), |slot| {
            vec![
                ("Draws", Descriptor::Buffer(scene.draws.descriptor())),
                store.resource(),
                ("BladeStateFrame", uniforms.resource(slot)),
                ("BladeStateControl", uniforms.resource(slot)),
            ]
        })?;
        let dispatch = BladeDispatch::new(device, "spring", spirv, set.layout, setup.constants, setup.blade_source())?;
        Ok(Self {
            set,
            dispatch,
            uniforms,
            span,
            store: store.buffer.raw,
            shape: store.shape,
            cleared: Cell::new(false),
            poses: setup.poses,
            reads: [scene.blades.raw, scene.clusters.raw],
            wind: setup.wind.to_vec(),
        })
    }
}

impl Pass for SpringPass {
    fn name(&self) -> &'static str {
        "spring"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let fetch = ctx.device.profile.compute_fetch();
        let mut declaration = Declaration::compute();
        if !self.cleared.get() {
            declaration = declaration.step("clear").buffer(self.store, Access::TransferWrite).step("springs");
        }
        let declaration = declaration
            .buffer(self.store, Access::ComputeShaderRead)
            .buffer(self.store, Access::ComputeShaderWrite)
            .buffer(self.poses.1, Access::ComputeShaderWrite)
            .buffer(self.reads[0], fetch)
            .buffer(self.reads[1], Access::ComputeShaderRead)
            .buffer(self.wind[ctx.slot], Access::ComputeShaderRead);
        let declaration = self.dispatch.declare(ctx, declaration);
        // No commands: the barrier that makes the store readable by the test.
        Some(declaration.step("to host").buffer(self.store, Access::HostRead))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        let device = ctx.device;
        let first = !self.cleared.get();
        if first && ctx.step == 0 {
            blade_state::record_clear(device, cmd, self.store);
            return Ok(());
        }
        if ctx.step == if first { 2 } else { 1 } {
            self.cleared.set(true);
            return Ok(());
        }
        self.set.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        self.dispatch.record(ctx, cmd, self.set.layout, self.poses.0);
        Ok(())
    }

    fn uniforms(&self, _: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        Some((&self.uniforms, bytemuck::cast_slice(&self.shape.frame_block(self.span.get(), DT)).to_vec()))
    }

    fn frame_dropped(&self) {
        self.cleared.set(false);
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.set.destroy(device);
            self.uniforms.destroy(device);
            self.dispatch.destroy(device);
        }
    }
}

/// One frame of a run: the step it draws, the camera and the wind.
#[derive(Clone, Copy)]
struct Frame {
    step: u64,
    camera: Camera,
    wind: Vec3,
}

/// The store's words after each frame of `frames`, on `scene` through the cull.
fn run(scene: &Scene, frames: &[Frame]) -> Vec<Vec<u32>> {
    run_with(scene, frames, None).0
}

/// `run`, and with `ramp` = `Some(first)` under the ramp wind, after `app::warm_up` to step
/// `first`: also the steps it took.
fn run_with(scene: &Scene, frames: &[Frame], ramp: Option<u64>) -> (Vec<Vec<u32>>, u64) {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let store: SharedStore = Rc::new(RefCell::new(None));
        let (field, wind) = SteadyWind::shared();
        let field = match ramp {
            Some(_) => SteadyWind(Velocity::Ramp { to: WIND, rise: RAMP_S }),
            None => field,
        };
        let models = Models { wind: Box::new(field), response: spring(&store), ..Models::default() };
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::with_models(device.clone(), scene, settings, Default::default(), models)?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut words = Vec::new();
        let warmed = match ramp {
            Some(first) => meadow::app::warm_up(&mut renderer, &mut target, &frames[0].camera, first)?,
            None => 0,
        };
        for frame in frames {
            wind.set(frame.wind);
            let time = frame.step as f32 * DT;
            renderer.render_offscreen(&mut target, &frame.camera, time)?;
            let store = store.borrow();
            let bytes = store.as_ref().expect("the store").buffer.mapped();
            words.push(bytemuck::cast_slice::<u8, u32>(bytes).to_vec());
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok((words, warmed))
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// One record of a snapshot: its world cell key, the step it holds plus one, and the spring's
/// offset and velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Record {
    key: u32,
    stamp: u32,
    x: Vec2,
    v: Vec2,
    stateless: f32,
}

fn records(words: &[u32]) -> Vec<Record> {
    let f = |w: u32| f32::from_bits(w);
    words
        .chunks_exact((HEADER_WORDS + WORDS) as usize)
        .map(|r| Record {
            key: r[0],
            stamp: r[1],
            x: Vec2::new(f(r[2]), f(r[3])),
            v: Vec2::new(f(r[4]), f(r[5])),
            stateless: f(r[6]),
        })
        .collect()
}

/// The records written by frame `step` (they hold that step).
fn stamped(snapshot: &[u32], step: u64) -> Vec<(usize, Record)> {
    records(snapshot).into_iter().enumerate().filter(|(_, r)| r.stamp == step as u32 + 1).collect()
}

/// Indices of the records every frame of `frames` wrote (drawn, and so stepped, in each).
fn drawn_throughout(snapshots: &[Vec<u32>], frames: &[Frame]) -> Vec<usize> {
    let mut kept: Option<Vec<usize>> = None;
    for (snapshot, frame) in snapshots.iter().zip(frames) {
        let now: Vec<usize> = stamped(snapshot, frame.step).into_iter().map(|(i, _)| i).collect();
        kept = Some(match kept {
            None => now,
            Some(before) => before.into_iter().filter(|i| now.binary_search(i).is_ok()).collect(),
        });
    }
    kept.unwrap_or_default()
}

/// The spring's `steps` steps from rest at the origin towards `target`, as spring.comp takes them
/// (its wind rounded to 1/1024 m/s: `WIND` is a multiple).
fn spring_reference(target: Vec2, steps: u32) -> (Vec2, Vec2) {
    let (mut x, mut v) = (Vec2::ZERO, Vec2::ZERO);
    for _ in 0..steps {
        let a = K * (target - x) - C * v;
        v += a * DT;
        x += v * DT;
    }
    (x, v)
}

const WIND: Vec3 = Vec3::new(5.0, 0.0, 0.0);

fn block_scene() -> Scene {
    Scene::blocks(FieldSpec { size: None, density: 100.0 }, 1)
}

/// Above block (0, 0) of `scene`, looking down at it.
fn over_block(scene: &Scene, x: f32) -> Camera {
    let ground = scene.field.as_ref().expect("a field").ground.height(f64::from(x), 2.0) as f32;
    Camera { position: Vec3::new(x, ground + 5.0, 2.0), yaw_deg: 0.0, pitch_deg: -75.0 }
}

/// Frames at `steps`, from calm air at the first to `WIND` after, from `camera(step)`.
fn frames(steps: &[u64], camera: impl Fn(u64) -> Camera) -> Vec<Frame> {
    steps
        .iter()
        .enumerate()
        .map(|(i, &step)| Frame { step, camera: camera(step), wind: if i == 0 { Vec3::ZERO } else { WIND } })
        .collect()
}

/// One frame of k steps leaves the state k frames of one step leave, and both are the spring's.
fn k_steps_equal_k_frames(scene: &Scene, camera: Camera) {
    let k = 3u64;
    let one_by_one = run(scene, &frames(&[0, 1, 2, 3], |_| camera));
    let at_once = run(scene, &frames(&[0, k], |_| camera));
    let (a, b) = (stamped(&one_by_one[3], k), stamped(&at_once[1], k));
    assert!(a.len() > 500, "{} blades stepped", a.len());
    assert_eq!(a, b, "one frame of {k} steps against {k} frames of one");
    // A uniform wind gives every blade the same target: the CPU's steps from rest.
    let (x, v) = spring_reference(Vec2::new(WIND.x, WIND.z) * GAIN, k as u32);
    assert!(v.length() > 0.1, "the reference moves: {v}");
    for (_, r) in &a {
        assert!((r.x - x).length() < 1e-5 && (r.v - v).length() < 1e-4, "{r:?} against x {x}, v {v}");
    }
}

#[test]
fn on_a_block_field_one_frame_of_k_steps_is_k_frames_of_one_step() {
    let scene = block_scene();
    k_steps_equal_k_frames(&scene, over_block(&scene, 2.0));
}

#[test]
fn on_a_stored_field_one_frame_of_k_steps_is_k_frames_of_one_step() {
    let scene = Scene::generate(5000, 3);
    k_steps_equal_k_frames(&scene, Camera::default_for(&scene.terrain));
}

#[test]
fn a_blade_inside_the_store_keeps_its_state_across_camera_moves() {
    let scene = block_scene();
    let steps: Vec<u64> = (0..=8).collect();
    let still = frames(&steps, |_| over_block(&scene, 2.0));
    // Back and forth across the line between blocks 0 and 1: the store scrolls each frame.
    let moving = frames(&steps, |s| over_block(&scene, if s % 2 == 0 { 2.0 } else { 5.0 }));
    let (a, b) = (run(&scene, &still), run(&scene, &moving));
    let both: Vec<usize> = {
        let in_b = drawn_throughout(&b, &moving);
        drawn_throughout(&a, &still).into_iter().filter(|i| in_b.binary_search(i).is_ok()).collect()
    };
    assert!(both.len() > 200, "{} blades drawn in every frame of both runs", both.len());
    let (ra, rb) = (records(&a[8]), records(&b[8]));
    for &i in &both {
        assert_eq!(ra[i], rb[i], "record {i}");
    }
    // They are swinging, not at rest: the comparison is of a moving state.
    assert!(both.iter().all(|&i| ra[i].v.length() > 1e-3), "not moving");
}

/// Steps 0..=6 from above block 0, step 7 from `away`, step 8 from above block 0 again: the
/// blades drawn at steps 6 and 8 have restarted at equilibrium, where without the detour they
/// are still swinging.
fn restarts_after(away: Camera) -> usize {
    let scene = block_scene();
    let steps: Vec<u64> = (0..=8).collect();
    let home = over_block(&scene, 2.0);
    let still = frames(&steps, |_| home);
    let detour = frames(&steps, |s| if s == 7 { away } else { home });
    let (a, b) = (run(&scene, &still), run(&scene, &detour));
    let back: Vec<usize> = stamped(&b[8], 8).into_iter().map(|(i, _)| i).collect();
    let before: Vec<usize> = stamped(&b[6], 6).into_iter().map(|(i, _)| i).collect();
    let returned: Vec<usize> = back.into_iter().filter(|i| before.binary_search(i).is_ok()).collect();
    assert!(returned.len() > 200, "{} blades drawn before and after the detour", returned.len());
    // At step 7 their records were not stepped as theirs: not written, or written for another
    // block (a block `dims` blocks away shares their slots).
    let (r6, r7) = (records(&b[6]), records(&b[7]));
    let theirs = |i: usize| r7[i].stamp == 8 && r7[i].key == r6[i].key;
    assert!(returned.iter().all(|&i| !theirs(i)), "the detour stepped them");
    let reused = returned.iter().filter(|&&i| r7[i].stamp == 8).count();
    println!("{} of {} slots held another block's blades at step 7", reused, returned.len());
    let target = Vec2::new(WIND.x, WIND.z) * GAIN;
    let (ra, rb) = (records(&a[8]), records(&b[8]));
    for &i in &returned {
        assert_eq!(rb[i].v, Vec2::ZERO, "record {i} restarted: {:?}", rb[i]);
        assert!((rb[i].x - target).length() < 1e-5, "record {i} at equilibrium: {:?}", rb[i]);
        assert!(ra[i].v.length() > 1e-3, "record {i} without the detour: {:?}", ra[i]);
    }
    reused
}

#[test]
fn a_blade_that_leaves_the_store_and_comes_back_restarts_at_equilibrium() {
    // Ten blocks away: block 0's slots hold block 10's blades for a frame.
    let scene = block_scene();
    let reused = restarts_after(over_block(&scene, 2.0 + 10.0 * BLOCK_SIZE));
    assert!(reused > 0, "block 10 took none of block 0's slots");
}

#[test]
fn a_blade_culled_for_a_frame_restarts_at_equilibrium() {
    // The camera looks at the sky for one frame: every blade is culled, and reset when drawn again.
    let scene = block_scene();
    let reused = restarts_after(Camera { pitch_deg: 80.0, ..over_block(&scene, 2.0) });
    assert_eq!(reused, 0, "nothing is drawn looking at the sky");
}

#[test]
fn a_block_field_keeps_state_only_within_the_stores_radius() {
    // A low camera looking along the ground draws blades many blocks out; only those within
    // RADIUS blocks of the camera's block get records.
    let scene = block_scene();
    let camera = Camera { pitch_deg: -8.0, ..over_block(&scene, 2.0) };
    let snapshot = &run(&scene, &frames(&[0], |_| camera))[0];
    let written = stamped(snapshot, 0);
    let cells: Vec<(i32, i32)> = written
        .iter()
        .map(|(_, r)| ((r.key >> 16) as u16 as i16 as i32, (r.key & 0xffff) as u16 as i16 as i32))
        .collect();
    // Each record sits where the CPU's mirror of the addressing puts its (cell, blade): slot
    // `cell mod dims` (`camera_grid::world_slot`), then the blade in the block.
    let per_block = scene.blades.len() as u32;
    let shape = StoreShape { words: WORDS, blocks: Some((RADIUS, per_block)) };
    for ((i, _), &(x, z)) in written.iter().zip(&cells) {
        let blade = *i as u32 % per_block;
        let base = shape.record_base(glam::I64Vec2::new(i64::from(x), i64::from(z)), blade);
        assert_eq!(base, (*i as u64) * u64::from(HEADER_WORDS + WORDS), "cell ({x}, {z}) blade {blade}");
    }
    assert!(cells.len() > 1000, "{} records", cells.len());
    let reach = |&(x, z): &(i32, i32)| x.abs().max(z.abs());
    assert!(cells.iter().all(|c| reach(c) <= RADIUS as i32), "a record past the radius");
    assert!(cells.iter().any(|c| reach(c) == RADIUS as i32), "none at the radius: {:?}", cells.first());
    // The hand-over to the stateless counterpart: none inside the outermost ring of blocks, and
    // across it from about 0 to about 1.
    let ring: Vec<f32> =
        written.iter().zip(&cells).filter(|(_, c)| reach(c) == RADIUS as i32).map(|((_, r), _)| r.stateless).collect();
    let inner = written.iter().zip(&cells).filter(|(_, c)| reach(c) < RADIUS as i32);
    assert!(inner.clone().count() > 100 && inner.clone().all(|((_, r), _)| r.stateless == 0.0), "inside the ring");
    let (low, high) = ring.iter().fold((1.0f32, 0.0f32), |(lo, hi), &w| (lo.min(w), hi.max(w)));
    assert!(ring.iter().all(|w| (0.0..=1.0).contains(w)), "weights in [0, 1]");
    assert!(low < 0.1 && high > 0.9, "the ring's weights span {low}..{high}");
}

#[test]
fn a_stateful_response_warms_up_from_t_0_one_step_a_frame() {
    // Under a wind rising from calm: the state at step 6 after warming up to step 5 and drawing 5
    // and 6 is the state of drawing every step from 0, to the bit.
    let scene = block_scene();
    let camera = over_block(&scene, 2.0);
    let every: Vec<u64> = (0..=6).collect();
    let (a, none) = run_with(&scene, &frames(&every, |_| camera), Some(0));
    let (b, warmed) = run_with(&scene, &frames(&[5, 6], |_| camera), Some(5));
    assert_eq!((none, warmed), (0, 5), "warm-up steps");
    let (ra, rb) = (stamped(&a[6], 6), stamped(&b[1], 6));
    assert!(ra.len() > 500, "{} blades", ra.len());
    assert_eq!(ra, rb, "warmed up against every step drawn");
    assert!(ra.iter().all(|(_, r)| r.v.length() > 1e-3), "not moving");
    // A stateless response takes no warm-up steps.
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (steps, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::new(device.clone(), &scene, settings, Default::default())?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let steps = meadow::app::warm_up(&mut renderer, &mut target, &camera, 5);
        drop(renderer);
        // SAFETY: nothing was rendered into it.
        unsafe { target.destroy(device) };
        steps
    });
    assert_eq!(messages, Some(0));
    assert_eq!(steps.expect("warm-up"), 0);
}

#[test]
fn a_thousand_frames_of_the_stateful_response_leave_memory_flat() {
    // The camera crosses blocks back and forth, and looks away now and then: the store scrolls,
    // blades reset, and nothing grows.
    let scene = block_scene();
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let store: SharedStore = Rc::new(RefCell::new(None));
        let field = SteadyWind(Velocity::Ramp { to: WIND, rise: RAMP_S });
        let models = Models { wind: Box::new(field), response: spring(&store), ..Models::default() };
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let mut renderer = Renderer::with_models(device.clone(), &scene, settings, Default::default(), models)?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut samples = Vec::new();
        for step in 0..1000u64 {
            let x = 2.0 + 3.0 * ((step / 7) % 2) as f32;
            let camera = Camera { pitch_deg: if step % 50 == 49 { 80.0 } else { -75.0 }, ..over_block(&scene, x) };
            renderer.render_offscreen(&mut target, &camera, step as f32 * DT)?;
            if step == 100 || step == 999 {
                let bytes = device.allocator().generate_report().total_allocated_bytes;
                // (Not `vk::live::total`: it counts every device of the process, and this file's
                // tests run side by side.)
                samples.push((bytes, renderer.pending_deletions()));
            }
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(samples)
    });
    assert_eq!(messages, Some(0), "validation messages");
    let samples = result.expect("rendered");
    assert_eq!(samples[0], samples[1], "allocated bytes, pending deletions at frames 100 and 1000");
}
