//! The GPU's keyframe selection and smoothing against the CPU's: `tests/shaders/probes/keyframe_pose.comp` runs
//! `kf_select` and `kf_level` (keyframes.glsl, as blade.vert and blade_pose.comp call them) on the
//! renderer's own animation model — its keyframe texture (unorm16, the default), frame uniforms
//! and specialization constants — for the pose-error report's forces, and every level is compared
//! with `KeyframeTable::pose_for`, the code the report measures. Then report entries are
//! recomputed from the GPU's poses: the report's numbers are those of the poses the renderer draws.

#[path = "support/compute.rs"]
mod compute;
#[path = "support/frame_uniforms.rs"]
mod frame_uniforms;
#[path = "support/probes.rs"]
mod probes;

use std::f32::consts::FRAC_PI_2;
use std::sync::Arc;

use ash::vk;
use glam::{Vec3, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::keyframes::encoding::{self as enc, Encoding};
use meadow::keyframes::pose::{self, Pose};
use meadow::keyframes::pose_error::{self, ErrorStats, PoseErrorReport, SMOOTHINGS};
use meadow::keyframes::{BladeModel, KeyframeLayout, KeyframeTable, Smoothing};
use meadow::render::animation::keyframed::KeyframeResponse;
use meadow::render::animation::response::BladeResponse;
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::render::specialization::Specialization;
use meadow::vk::descriptor::{Resource, SetLayout};
use meadow::vk::{pipeline, Buffer, BufferDesc, Device, DeviceSelector};

/// `meadow keyframes --report`'s default segments.
const SEGMENTS: u32 = 4;
/// The renderer's default pose count, a row of the report.
const POSES: u32 = 1000;

/// The largest unorm16 round-trip error of a stored component in [-1, 1]: half a step of
/// 2/65535 (`encoding::encode_unorm16` rounds to the nearest step; `tests/keyframe_decode.rs`
/// checks that `kf_fetch` decodes as the CPU does).
const UNORM16_HALF_STEP: f32 = 1.0 / 65535.0;
/// How far the GPU's `atan` may lie from Rust's `atan2` (radians): llvmpipe's measured up to
/// 3.0e-6 over the report's forces, about 25 ulp near π/2 (Vulkan allows 4096).
const ATAN_ERROR: f32 = 4e-6;
/// Rounding of f32 arithmetic on values of order 1: a few ulp, and the other functions
/// (`length`, SLERP's `acos` and `sin`) measured as close as that.
const ROUNDING: f32 = 1e-6;

/// Largest allowed GPU-vs-CPU difference of a backbone point (unit blade) and of a twist (radians).
#[derive(Clone, Copy, Debug)]
struct Tolerance {
    point: f32,
    twist: f32,
}

/// The tolerance against `pose_for` on `table` (f32) when `encoded`, else on the unorm16-decoded
/// table (the same keyframes the GPU reads).
///
/// Noise: the selection's angle parameter af = φ / (π/2) · (angles − 1) takes the `atan` error
/// times (angles − 1) / (π/2), and linear and SLERP blends move with af by at most the length of
/// the path between angle-neighbouring keyframes (SLERP's arc, no shorter than linear's chord).
/// Nearest's rounded rows do not move with it (no force of the report lies within the noise of a
/// rounding tie: the measured difference is 1 ulp).
/// Encoding: each decoded component is within half a step of the stored one; nearest and linear
/// take a convex combination of keyframes, so a point lies within √3 half steps; SLERP's result
/// moves by the error of its ends' lengths plus that of their directions, each within that
/// bound, so twice. The twist is stored divided by π/2 and blended linearly by every smoothing.
fn tolerance(table: &KeyframeTable, smoothing: Smoothing, encoded: bool) -> Tolerance {
    let (point_step, twist_step) = angle_neighbour_differences(table);
    let af_error = ATAN_ERROR * (table.layout.angles - 1) as f32 / FRAC_PI_2;
    let (point_noise, twist_noise) = match smoothing {
        Smoothing::Nearest => (ROUNDING, ROUNDING),
        Smoothing::Linear | Smoothing::Slerp => (af_error * point_step + ROUNDING, af_error * twist_step + ROUNDING),
    };
    if !encoded {
        return Tolerance { point: point_noise, twist: twist_noise };
    }
    let convex = 3f32.sqrt() * UNORM16_HALF_STEP;
    let point_encoding = if smoothing == Smoothing::Slerp { 2.0 * convex } else { convex };
    Tolerance { point: point_encoding + point_noise, twist: UNORM16_HALF_STEP * FRAC_PI_2 + twist_noise }
}

/// Longest SLERP path between the points (root-relative: the arc of the longer plus the change of
/// length), and largest difference between the twists, of keyframes of neighbouring angles (same
/// magnitude, same level).
fn angle_neighbour_differences(table: &KeyframeTable) -> (f32, f32) {
    let l = table.layout;
    let (mut point, mut twist) = (0.0f32, 0.0f32);
    for m in 0..l.magnitudes {
        for a in 0..l.angles - 1 {
            for level in 1..=table.records {
                let (k0, k1) = (table.keyframe(l.row(m, a), level), table.keyframe(l.row(m, a + 1), level));
                let straight = table.straight(level);
                let (p0, p1) = (straight + Vec3::from_slice(&k0[..3]), straight + Vec3::from_slice(&k1[..3]));
                let arc = p0.length().max(p1.length()) * p0.angle_between(p1) + (p1.length() - p0.length()).abs();
                point = point.max(arc);
                twist = twist.max((k1[3] - k0[3]).abs());
            }
        }
    }
    (point, twist)
}

/// The renderer's model for `smoothing` and its table's settings: texture, unorm16, vertex
/// representation, evaluated per vertex (blade_pose.comp calls the same functions).
fn settings(smoothing: Smoothing) -> AnimationSettings {
    let settings = AnimationSettings { smoothing, poses: POSES, eval: Eval::Vertex, ..Default::default() };
    assert_eq!((settings.mode, settings.encoding), (Mode::Texture, Encoding::Unorm16), "the default texture path");
    settings
}

/// Run `keyframe_pose.comp` for `forces` on the renderer's model for `smoothing`: the levels
/// 0..=SEGMENTS of each force, as poses of the unit blade.
fn poses_on_gpu(device: &Arc<Device>, smoothing: Smoothing, forces: &[(f32, f32)]) -> meadow::Result<Vec<Pose>> {
    // The renderer's keyframe response, its resources given by name to the probe's set 1.
    let model = KeyframeResponse::new(device, &settings(smoothing), SEGMENTS)?;
    // As `Renderer::specialization`: the blade geometry, then the response's constants.
    let mut specialization = Specialization::new(false, SEGMENTS, 1, false, true);
    model.specialize(&mut specialization);
    let frame = frame_uniforms::upload(device, "pose frame", &bytemuck::Zeroable::zeroed())?;
    let force_data: Vec<[f32; 2]> = forces.iter().map(|&(fx, fz)| [fx, fz]).collect();
    let forces_buffer = Buffer::with_data(
        device,
        &BufferDesc::upload("pose forces", 8 * forces.len() as u64, vk::BufferUsageFlags::STORAGE_BUFFER),
        &force_data,
    )?;
    let levels = (SEGMENTS as usize + 1) * forces.len();
    let out = Buffer::new(
        device,
        &BufferDesc::readback("pose levels", 16 * levels as u64, vk::BufferUsageFlags::STORAGE_BUFFER),
    )?;
    let code = probes::KEYFRAME_POSE_COMP.code(device.profile);
    let probe = SetLayout::reflected(device, "pose set layout", &[("keyframe_pose.comp", code)], 0)?;
    let tables = SetLayout::reflected(device, "keyframe set layout", &[("keyframe_pose.comp", code)], 1)?;
    let layout = pipeline::layout(device, "pose layout", &[probe.raw, tables.raw], &[])?;
    let constants = specialization.named();
    let pipe = pipeline::compute(device, "keyframe pose", code, layout, &constants)?;
    let (pool, sets) = probe.allocate(device, "pose", 1)?;
    let resources = [
        (0, Resource::Buffer(frame.descriptor())),
        (1, Resource::Buffer(forces_buffer.descriptor())),
        (2, Resource::Buffer(out.descriptor())),
    ];
    probe.write(device, sets[0], "pose set", &resources)?;
    let (table_pool, table_sets) = tables.allocate(device, "keyframes", 1)?;
    tables.write_named(device, table_sets[0], "keyframe set", &model.resources())?;
    let groups = (forces.len() as u32).div_ceil(64);
    let sets = [sets[0], table_sets[0]];
    let submitted = compute::dispatch(device, "keyframe pose", (pipe, layout), &sets, &[], groups, out.raw);
    let poses = bytemuck::cast_slice::<u8, Vec4>(out.mapped()).chunks(SEGMENTS as usize + 1).map(pose_of).collect();
    // SAFETY: submit_and_wait waited.
    unsafe {
        compute::teardown(device, (pool, pipe, layout, probe.raw), [frame, forces_buffer, out]);
        device.raw.destroy_descriptor_pool(table_pool, None);
        Box::new(model).destroy(device);
        tables.destroy(device);
    }
    submitted.map(|()| poses)
}

/// A pose from the shader's levels (xyz point, w twist).
fn pose_of(levels: &[Vec4]) -> Pose {
    Pose { backbone: levels.iter().map(|l| l.truncate()).collect(), twist: levels.iter().map(|l| l.w).collect() }
}

/// The table as the GPU reads it: every component through the unorm16 round trip of
/// `encoding::texture_texels` (the twist divided by π/2 there, multiplied back by `kf_fetch`).
fn unorm16_table(table: &KeyframeTable) -> KeyframeTable {
    let round_trip = |x: f32| enc::decode_unorm16(enc::encode_unorm16(x));
    let frames = table
        .frames
        .iter()
        .map(|k| [round_trip(k[0]), round_trip(k[1]), round_trip(k[2]), round_trip(k[3] / FRAC_PI_2) * FRAC_PI_2])
        .collect();
    KeyframeTable { frames, ..table.clone() }
}

/// Largest difference of backbone points (unit blade) and of twists (radians) between the GPU's
/// poses and `table.pose_for` for the same forces.
fn largest_differences(table: &KeyframeTable, forces: &[(f32, f32)], gpu: &[Pose], smoothing: Smoothing) -> (f32, f32) {
    assert_eq!(gpu.len(), forces.len());
    let (mut point, mut twist) = (0.0f32, 0.0f32);
    for (&(fx, fz), g) in forces.iter().zip(gpu) {
        let cpu = table.pose_for(fx, fz, smoothing);
        assert_eq!(g.backbone.len(), cpu.backbone.len());
        for level in 0..cpu.backbone.len() {
            let d: Vec3 = g.backbone[level] - cpu.backbone[level];
            point = point.max(d.length());
            twist = twist.max((g.twist[level] - cpu.twist[level]).abs());
        }
    }
    (point, twist)
}

#[test]
fn gpu_poses_match_pose_for_and_the_reports_entries() {
    let forces = pose_error::sample_forces(pose_error::SEED, pose_error::SAMPLES);
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, |device| {
        SMOOTHINGS.iter().map(|&smoothing| poses_on_gpu(device, smoothing, &forces)).collect::<meadow::Result<Vec<_>>>()
    });
    let gpu = result.expect("posed on the GPU");
    assert_eq!(messages, Some(0));
    // The report's table (`PoseErrorReport::measure_with`), which `KeyframeTexture::new` encodes.
    let model = BladeModel::new(SEGMENTS);
    let table = KeyframeTable::generate(&model, KeyframeLayout::for_poses(POSES));
    let decoded = unorm16_table(&table);
    for (&smoothing, poses) in SMOOTHINGS.iter().zip(&gpu) {
        let (against_table, against_decoded) =
            (tolerance(&table, smoothing, true), tolerance(&table, smoothing, false));
        let (point, twist) = largest_differences(&table, &forces, poses, smoothing);
        let (point_decoded, twist_decoded) = largest_differences(&decoded, &forces, poses, smoothing);
        eprintln!(
            "{smoothing:?}: GPU vs pose_for: point {point:.3e} (tolerance {:.3e}), twist {twist:.3e} rad ({:.3e}); \
             vs pose_for on the unorm16-decoded table: point {point_decoded:.3e} ({:.3e}), twist {twist_decoded:.3e} ({:.3e})",
            against_table.point, against_table.twist, against_decoded.point, against_decoded.twist
        );
        assert!(
            point <= against_table.point && twist <= against_table.twist,
            "{smoothing:?}: point {point}, twist {twist} over {against_table:?}"
        );
        // The same selection and blend on the same decoded keyframes: only the noise apart.
        assert!(
            point_decoded <= against_decoded.point && twist_decoded <= against_decoded.twist,
            "{smoothing:?}: point {point_decoded}, twist {twist_decoded} over {against_decoded:?}"
        );
    }
    recompute_report_entries(&table, &forces, &gpu);
}

/// The report's 1000-pose row, recomputed from the GPU's poses against `pose::solve`: a max or a
/// mean of per-pose errors moves by at most the largest per-pose change, 100 × the point
/// tolerance in % of the blade's length (the twist's in degrees).
fn recompute_report_entries(table: &KeyframeTable, forces: &[(f32, f32)], gpu: &[Vec<Pose>]) {
    let model = BladeModel::new(SEGMENTS);
    let report = PoseErrorReport::measure(SEGMENTS);
    let row = report.rows.iter().find(|row| row.poses == POSES).expect("the report measures 1000 poses");
    let direct: Vec<Pose> = forces.iter().map(|&(fx, fz)| pose::solve(&model, fx, fz)).collect();
    for ((&smoothing, poses), printed) in SMOOTHINGS.iter().zip(gpu).zip(row.errors) {
        let backbone = ErrorStats::of(poses.iter().zip(&direct).map(|(g, d)| pose_error::backbone_error(g, d)));
        let twist = ErrorStats::of(poses.iter().zip(&direct).map(|(g, d)| pose_error::twist_error(g, d)));
        let bound = tolerance(table, smoothing, true);
        let (point_bound, twist_bound) = (100.0 * bound.point, bound.twist.to_degrees());
        eprintln!(
            "{smoothing:?} at {POSES} poses: backbone mean/max {:.4}/{:.4} % from the GPU, {:.4}/{:.4} % reported; \
             twist max {:.4}° vs {:.4}°",
            backbone.mean, backbone.max, printed.backbone.mean, printed.backbone.max, twist.max, printed.twist.max
        );
        assert!(
            (backbone.max - printed.backbone.max).abs() <= point_bound,
            "{smoothing:?}: {backbone:?} vs {printed:?}"
        );
        assert!(
            (backbone.mean - printed.backbone.mean).abs() <= point_bound,
            "{smoothing:?}: {backbone:?} vs {printed:?}"
        );
        assert!((twist.max - printed.twist.max).abs() <= twist_bound, "{smoothing:?}: {twist:?} vs {printed:?}");
    }
}

/// `BladeResponse::tip_offset` (what a far field's billboard leans by) is the tip of the pose the
/// keyframes select for the wind over `KEYFRAME_WIND_SCALE`: none in calm air, along the wind,
/// further in a stronger wind, and the table's own tip.
#[test]
fn the_keyframe_responses_tip_offset_is_its_poses_tip() {
    use meadow::wind::KEYFRAME_WIND_SCALE;
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, |device| {
        let animation = settings(Smoothing::Nearest);
        let response = KeyframeResponse::new(device, &animation, SEGMENTS)?;
        let offsets: Vec<Vec3> =
            [0.0, 2.0, 6.0, -6.0].iter().map(|&w| response.tip_offset(Vec3::new(w, 0.0, 0.0))).collect();
        let across = response.tip_offset(Vec3::new(0.0, 0.0, 6.0));
        // SAFETY: nothing used it on the GPU but its upload, which was waited.
        unsafe { Box::new(response).destroy(device) };
        Ok((offsets, across))
    });
    assert_eq!(messages, Some(0));
    let (offsets, across) = result.expect("built");
    assert!(offsets[0].length() < 1e-6, "calm air: {:?}", offsets[0]);
    assert!(offsets[1].x > 0.01 && offsets[2].x > offsets[1].x, "along +x, further in more wind: {offsets:?}");
    assert!(offsets[3].x < -0.01, "along -x: {:?}", offsets[3]);
    assert!(across.z > 0.01 && across.x.abs() < 0.5 * across.z, "along +z: {across:?}");
    // The table's tip for the same force, on the CPU.
    let table = KeyframeTable::generate(&BladeModel::new(SEGMENTS), KeyframeLayout::for_poses(POSES));
    let pose = table.pose_for(6.0 / KEYFRAME_WIND_SCALE, 0.0, Smoothing::Nearest);
    let tip = *pose.backbone.last().expect("levels") - Vec3::Y;
    assert!((offsets[2] - tip).length() < 1e-6, "{:?} against the table's {tip:?}", offsets[2]);
}
