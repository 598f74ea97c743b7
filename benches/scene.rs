//! CPU cost of building the scene (terrain + blade scatter) at the thesis' blade counts.
//! `cargo bench --bench scene`. The GPU benchmarks come with `meadow bench`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode, Throughput};
use meadow::scene::Scene;

fn scene_generation(c: &mut Criterion) {
    let mut group = c.benchmark_group("scene/generate");
    // A million blades take a good fraction of a second: few samples of one iteration each.
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    for blades in [40_000u32, 360_000, 1_000_000] {
        group.throughput(Throughput::Elements(u64::from(blades)));
        group.bench_with_input(BenchmarkId::from_parameter(blades), &blades, |b, &blades| {
            b.iter(|| Scene::generate(black_box(blades), 7))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    targets = scene_generation
}
criterion_main!(benches);
