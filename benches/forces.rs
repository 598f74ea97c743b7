//! CPU cost of the per-frame forces at cluster corners (thesis 3.2.2), which the thesis puts on
//! the CPU: `render::animation::corner_forces` over square grids of about 1k to 100k clusters,
//! under the default gusty global wind plus 0, 1, 8 or 64 point sources or calm areas (cluster
//! attenuation: sources are evaluated at every corner). Colliders are not in the corners: each
//! blade takes their shapes (`wind::Collider::blade_force`).
//! `cargo bench --bench forces`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec2;
use meadow::render::animation::corner_forces;
use meadow::scene::clusters::ClusterGrid;
use meadow::wind::{Attenuation, CalmArea, GlobalWind, PointSource, Wind};

/// Clusters per side: 1 024, 4 096, 16 384, 65 536 and 99 856 clusters.
const SIDES: [u32; 5] = [32, 64, 128, 256, 316];
const COUNTS: [usize; 3] = [1, 8, 64];

/// One-metre clusters over a `side` × `side` m field (what `--cluster-size 1` gives).
fn grid(side: u32) -> ClusterGrid {
    let grid = ClusterGrid::new(side as f32, 1.0);
    assert_eq!(grid.clusters, side);
    grid
}

/// A point on the field at fraction `(u, v)` of its side, each in [0, 1).
fn at(grid: &ClusterGrid, u: f32, v: f32) -> Vec2 {
    let side = grid.clusters as f32 * grid.cluster_size;
    Vec2::new(grid.origin + u * side, grid.origin + v * side)
}

/// Deterministic spread of `i` of `n` over the unit square.
fn spread(i: usize, n: usize) -> (f32, f32) {
    let u = (i as f32 + 0.5) / n as f32;
    let v = (i as f32 * 0.618_034).fract();
    (u, v)
}

#[derive(Clone, Copy, Debug)]
enum Extra {
    Sources,
    Calm,
}

/// The CLI's default wind (30°, 0.3, gusts) plus `count` of `extra` scattered over the field.
fn wind(grid: &ClusterGrid, extra: Extra, count: usize) -> Wind {
    let mut wind =
        Wind { global: Some(GlobalWind { direction_deg: 30.0, strength: 0.3, gusts: true }), ..Default::default() };
    let size = grid.cluster_size * grid.clusters as f32;
    for i in 0..count {
        let (u, v) = spread(i, count);
        let p = at(grid, u, v);
        match extra {
            Extra::Sources => wind.sources.push(PointSource {
                position: p,
                power: 0.5,
                sigma: 1.5,
                velocity: Vec2::new(0.5, -0.25),
                height: 0.5,
            }),
            Extra::Calm => {
                let half = Vec2::splat(0.02 * size);
                wind.calm.push(CalmArea { min: p - half, max: p + half })
            }
        }
    }
    wind
}

fn bench_corner_forces(c: &mut Criterion) {
    let cases = std::iter::once(("global_only", Extra::Sources, 0))
        .chain(COUNTS.iter().map(|&n| ("sources", Extra::Sources, n)))
        .chain(COUNTS.iter().map(|&n| ("calm", Extra::Calm, n)));
    for (name, extra, count) in cases {
        let mut group = c.benchmark_group(format!("corner_forces/{name}_{count}"));
        // The largest cases take a good part of a second per call: few samples; criterion's
        // automatic sampling turns flat (equal iterations per sample) for them.
        group.sample_size(20);
        for side in SIDES {
            let grid = grid(side);
            let wind = wind(&grid, extra, count);
            group.throughput(Throughput::Elements(u64::from(grid.corner_count())));
            group.bench_with_input(BenchmarkId::new("clusters", side * side), &(grid, wind), |b, (grid, wind)| {
                b.iter(|| corner_forces(black_box(grid), wind, black_box(1.25), Attenuation::Cluster))
            });
        }
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    targets = bench_corner_forces
}
criterion_main!(benches);
