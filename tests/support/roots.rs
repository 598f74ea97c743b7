//! The roots the cull placed on a block field, read from its visible list: where each drawn
//! blade stands (`field_blade` of `shaders/common/field.glsl`) and the root height its entry
//! carries (`visible_scale`: a half float above the camera's height). Used by `tests/ground.rs`
//! and `tests/heightmap.rs` to hold roots to the drawn ground.

use glam::{DVec2, IVec2};
use meadow::render::gpu_constants as gpu;
use meadow::scene::field::BLOCK_SIZE;
use meadow::scene::{tiles, BladeInstance, Scene};

/// A visible entry that draws nothing (a bucket's padding).
const VISIBLE_PADDING: u32 = 0xffff_ffff;

/// A half float's value.
pub fn half(bits: u32) -> f32 {
    let (sign, exponent, mantissa) = ((bits >> 15) & 1, (bits >> 10) & 31, bits & 1023);
    let magnitude = match exponent {
        0 => mantissa as f32 * 2f32.powi(-24),
        e => (1.0 + mantissa as f32 / 1024.0) * 2f32.powi(e as i32 - 15),
    };
    if sign == 1 {
        -magnitude
    } else {
        magnitude
    }
}

/// `cell_hash` of `shaders/common/field.glsl`.
fn cell_hash(cell: IVec2) -> u32 {
    let c = cell.rem_euclid(IVec2::splat(gpu::PERIOD_CELLS as i32));
    let mut h = (c.x as u32).wrapping_mul(0x8da6_b343) ^ (c.y as u32).wrapping_mul(0xd816_3841);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^ (h >> 12)
}

/// Where blade `blade` of the stored block stands in world cell `cell` (`field_blade` of
/// `shaders/common/field.glsl`), in the world's x and z.
pub fn placed(blade: &BladeInstance, cell: IVec2) -> DVec2 {
    let edge = f64::from(BLOCK_SIZE);
    let h = cell_hash(cell);
    let mut p = DVec2::new(f64::from(blade.position[0]), f64::from(blade.position[2])) - DVec2::splat(0.5 * edge);
    if h & 4 != 0 {
        p.x = -p.x;
    }
    for _ in 0..h & 3 {
        p = DVec2::new(p.y, -p.x);
    }
    cell.as_dvec2() * edge + p + DVec2::splat(0.5 * edge)
}

/// Every drawn root of the blade class's buckets (the `draws` words' first buckets, entries of
/// `blades_per_instance`): its place in the world (x, z) and its height, for a frame whose O is
/// `origin` and whose camera stood `eye_y` up.
pub fn roots(
    scene: &Scene,
    (visible, draws): (&[[u32; 2]], &[u32]),
    (origin, eye_y): (IVec2, f32),
    blades_per_instance: u32,
) -> Vec<(DVec2, f64)> {
    let mut out = Vec::new();
    for bucket in 0..gpu::MAX_LOD_BUCKETS as usize {
        let draw = &draws[bucket * gpu::DRAW_WORDS as usize..];
        let first = draw[gpu::DRAW_FIRST_INSTANCE as usize] * blades_per_instance;
        let count = draw[gpu::DRAW_INSTANCES as usize] * blades_per_instance;
        for entry in &visible[first as usize..(first + count) as usize] {
            if entry[0] == VISIBLE_PADDING {
                continue;
            }
            let (x, z) = tiles::ring_cell(entry[0] >> 16);
            let p = placed(&scene.blades[(entry[0] & 0xffff) as usize], origin + IVec2::new(x, z));
            out.push((p, f64::from(half(entry[1] & 0xffff) + eye_y)));
        }
    }
    out
}
