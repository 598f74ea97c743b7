//! CPU cost of building the scene (terrain + blade scatter) at the thesis' blade counts.
//! `cargo bench --bench scene`. The GPU benchmarks come with `meadow bench`.

use std::hint::black_box;
use std::time::Instant;

use meadow::scene::Scene;

fn main() {
    println!("{:>10} {:>12} {:>12}", "blades", "median ms", "ns/blade");
    for blades in [40_000u32, 360_000, 1_000_000] {
        let mut samples: Vec<f64> = (0..7)
            .map(|seed| {
                let start = Instant::now();
                black_box(Scene::generate(blades, seed));
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        let median = meadow::app::median(&mut samples);
        println!("{blades:>10} {median:>12.2} {:>12.1}", median * 1e6 / f64::from(blades));
    }
}
