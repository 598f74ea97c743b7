//! CPU cost of the keyframe pipeline (thesis ch. 3–4): solving one pose, generating the table
//! (`--poses 1000` at 4, 8 and 16 segments, and the curve table), encoding it for the texture and
//! the uniform array, and the selection + blend the vertex shader mirrors.
//! `cargo bench --bench keyframes`.
//!
//! The compression figures (`CompressionReport::new`) are a handful of integer products with no
//! data to walk: nothing worth a benchmark.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode, Throughput};
use meadow::keyframes::encoding::{self, Encoding, Packing};
use meadow::keyframes::pose::{self, MAX_FORCE};
use meadow::keyframes::{BladeModel, KeyframeLayout, KeyframeTable, Smoothing};

/// The thesis' pose count.
const POSES: u32 = 1000;
const SEGMENTS: [u32; 3] = [4, 8, 16];

fn pose_solve(c: &mut Criterion) {
    let mut group = c.benchmark_group("keyframes/pose_solve");
    // A moderate oblique force: 60 % of the table's strongest, 30° from the normal.
    let (f, phi) = (0.6 * MAX_FORCE, 30f32.to_radians());
    for segments in SEGMENTS {
        let model = BladeModel::new(segments);
        group.bench_with_input(BenchmarkId::new("segments", segments), &model, |b, model| {
            b.iter(|| pose::solve(black_box(model), black_box(f * phi.sin()), black_box(f * phi.cos())))
        });
    }
    group.finish();
}

fn table_generation(c: &mut Criterion) {
    let layout = KeyframeLayout::for_poses(POSES);
    let mut group = c.benchmark_group("keyframes/generate");
    // Every stored pose is a full solve: tens to hundreds of milliseconds per table.
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    group.throughput(Throughput::Elements(u64::from(layout.stored())));
    for segments in SEGMENTS {
        let model = BladeModel::new(segments);
        group.bench_with_input(BenchmarkId::new("vertex/segments", segments), &model, |b, model| {
            b.iter(|| KeyframeTable::generate(black_box(model), layout))
        });
    }
    group.bench_function("curve", |b| b.iter(|| KeyframeTable::generate_curve(black_box(layout))));
    group.finish();
}

fn encode(c: &mut Criterion) {
    let table = KeyframeTable::generate(&BladeModel::new(8), KeyframeLayout::for_poses(POSES));
    let keyframes = table.frames.len() as u64;
    let mut group = c.benchmark_group("keyframes/encode");
    // One element per stored keyframe (one texel, two for rgba8x2; two uniform words).
    group.throughput(Throughput::Elements(keyframes));
    for (name, encoding) in
        [("rgba8x2", Encoding::Rgba8x2), ("unorm16", Encoding::Unorm16), ("float32", Encoding::Float32)]
    {
        group.bench_with_input(BenchmarkId::new("texture", name), &encoding, |b, &encoding| {
            b.iter(|| encoding::texture_texels(black_box(&table), encoding))
        });
    }
    for (name, packing) in [("thesis", Packing::Thesis), ("snorm", Packing::Snorm)] {
        group.bench_with_input(BenchmarkId::new("uniform", name), &packing, |b, &packing| {
            b.iter(|| encoding::uniform_words(black_box(&table), packing))
        });
    }
    group.finish();
}

/// `count` forces spread over the full circle and the table's magnitude range (a fixed
/// low-discrepancy pattern, so every quadrant and both ends of the table are hit).
fn forces(count: u32) -> Vec<(f32, f32)> {
    (0..count)
        .map(|i| {
            let angle = i as f32 * 2.399_963; // golden angle
            let magnitude = 1.1 * MAX_FORCE * ((i as f32 + 0.5) / count as f32).sqrt();
            (magnitude * angle.sin(), magnitude * angle.cos())
        })
        .collect()
}

fn select_blend(c: &mut Criterion) {
    const FORCES: u32 = 1024;
    let segments = 8;
    let table = KeyframeTable::generate(&BladeModel::new(segments), KeyframeLayout::for_poses(POSES));
    let forces = forces(FORCES);
    let mut group = c.benchmark_group("keyframes/select_blend");
    // One element per blade posed: a selection and a blend of every level, as the vertex
    // shader does for each of a blade's vertex pairs.
    group.throughput(Throughput::Elements(u64::from(FORCES)));
    for (name, smoothing) in
        [("nearest", Smoothing::Nearest), ("linear", Smoothing::Linear), ("slerp", Smoothing::Slerp)]
    {
        group.bench_with_input(BenchmarkId::new("segments_8", name), &smoothing, |b, &smoothing| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for &(fx, fz) in black_box(&forces) {
                    let selection = table.select(fx, fz, smoothing);
                    for level in 1..=segments {
                        let (p, twist) = table.blend(&selection, level, smoothing);
                        sum += p.x + p.y + p.z + twist;
                    }
                }
                sum
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    targets = pose_solve, table_generation, encode, select_blend
}
criterion_main!(benches);
