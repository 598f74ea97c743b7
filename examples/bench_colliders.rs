//! Print `meadow bench --preset interaction`'s colliders as `--collider` flags, so `meadow timing`
//! can measure the same scene pass by pass: `cargo run --release --example bench_colliders --
//! stored|infinite`.
use meadow::harness::bench::interaction::{colliders, SEED, STORED_BLADES};
use meadow::scene::field::FieldSpec;
use meadow::scene::Scene;

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "infinite".into());
    let scene = if which == "stored" {
        Scene::generate(STORED_BLADES, SEED)
    } else {
        Scene::blocks(FieldSpec { size: None, density: meadow::scene::blades::DENSITY_PER_M2 }, SEED)
    };
    let camera = scene.default_camera();
    for c in colliders(&scene, &camera) {
        let (p, r, v) = (c.center, c.radii.x, c.velocity);
        print!(" --collider sphere:{},{},{},{},{},{},{}", p.x, p.y, p.z, r, v.x, v.y, v.z);
    }
    println!();
}
