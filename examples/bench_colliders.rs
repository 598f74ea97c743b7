//! Print `meadow bench --preset interaction`'s colliders as `--collider` flags, so `meadow timing`
//! can measure the same scene pass by pass: `cargo run --release --example bench_colliders --
//! stored|infinite`.
use meadow::harness::bench::interaction::{colliders, scenes};

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "infinite".into());
    let (stored, block) = scenes();
    let scene = if which == "stored" { stored } else { block };
    let camera = scene.default_camera();
    for c in colliders(&scene, &camera) {
        let (p, r, v) = (c.center, c.radii.x, c.velocity);
        print!(" --collider sphere:{},{},{},{},{},{},{}", p.x, p.y, p.z, r, v.x, v.y, v.z);
    }
    println!();
}
