//! Blades in clumps (issue #36 item 2, `--clumps SIZE_M`), after Ghost of Tsushima's grass: clump
//! centres on a jittered grid of `SIZE_M` over the world, each blade belonging to the nearest, and
//! the blades of a clump leaning outwards together (each faces away from its centre, leaning the
//! more the farther out it stands), sharing a tint and a height (each clump scales its blades by
//! 0.7 to 1, so no blade outgrows `blades::TALLEST`, which the cull's bounds pad by).
//!
//! Blades are not moved: the field keeps its even density, the cull's cells and tiles their
//! bounds, and the LOD its thinning. A stored field's blades are clumped when scattered; a block
//! field's are clumped where the GPU places them (`shaders/common/clumps.glsl`, the same function
//! on a lattice that repeats with the world, so the clumps 100 km out are the ones at the origin).

use glam::Vec2;

use crate::scene::blades::BladeInstance;
use crate::scene::field::WORLD_PERIOD;

/// The smallest and largest clump (m).
pub const SIZE_RANGE_M: (f32, f32) = (0.1, 50.0);
/// How far a clump's centre strays from its grid cell's centre, as a share of the cell.
pub const JITTER: f32 = 0.7;
/// How much of a blade's hue is its clump's.
pub const TINT: f32 = 0.75;

/// `--clumps SIZE_M`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clumps {
    /// The clump grid's cell (m).
    pub size_m: f32,
}

impl Clumps {
    /// The clump size in millimetres, as the shaders' `CLUMP_SIZE_MM` holds it.
    pub fn size_mm(&self) -> u32 {
        (self.size_m * 1000.0).round() as u32
    }

    /// The grid cell of the clump `blade` at world (x, z) belongs to, and the blade clumped.
    pub fn apply(&self, blade: &BladeInstance, world: Vec2) -> ([i32; 2], BladeInstance) {
        let lattice = Vec2::new(world.x.rem_euclid(WORLD_PERIOD), world.y.rem_euclid(WORLD_PERIOD));
        let size = self.size_mm() as f32 * 0.001;
        let (k, centre) = nearest(lattice, size);
        let h = clump_hash(k);
        let d = lattice - centre;
        let mut out = *blade;
        let spare = blade.variation(3);
        out.facing = d.x.atan2(d.y) + (spare - 0.5) * 0.5;
        out.height *= 0.7 + 0.3 * ((h >> 8) & 0xff) as f32 / 255.0;
        let hue = blade.variation(0) + TINT * ((h & 0xff) as f32 / 255.0 - blade.variation(0));
        let lean = (0.35 + 0.65 * d.length() / size).clamp(0.0, 1.0);
        out.variation = with_byte(with_byte(blade.variation, 0, hue), 2, lean);
        ([k.0, k.1], out)
    }
}

/// `variation` with byte `i` set to `value` (in [0, 1]).
fn with_byte(variation: u32, i: u32, value: f32) -> u32 {
    let byte = (value.clamp(0.0, 1.0) * 255.0).round() as u32;
    (variation & !(0xff << (8 * i))) | (byte << (8 * i))
}

/// The clump grid cell's hash (`clump_hash` in clumps.glsl).
fn clump_hash(k: (i32, i32)) -> u32 {
    let mut h = (k.0 as u32).wrapping_mul(0x27d4_eb2d) ^ (k.1 as u32).wrapping_mul(0x1656_67b1);
    h ^= h >> 15;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^ (h >> 13)
}

/// The centre of grid cell `k`'s clump.
fn centre(k: (i32, i32), size: f32) -> Vec2 {
    let h = clump_hash(k);
    let jitter = Vec2::new(((h >> 16) & 0xff) as f32, ((h >> 24) & 0xff) as f32) / 255.0;
    (Vec2::new(k.0 as f32, k.1 as f32) + Vec2::splat(0.5) + (jitter - Vec2::splat(0.5)) * JITTER) * size
}

/// The nearest clump centre to `p` among the 3 × 3 grid cells around it.
fn nearest(p: Vec2, size: f32) -> ((i32, i32), Vec2) {
    let k0 = ((p.x / size).floor() as i32, (p.y / size).floor() as i32);
    let mut best = (k0, centre(k0, size));
    for dz in -1..=1 {
        for dx in -1..=1 {
            let k = (k0.0 + dx, k0.1 + dz);
            let c = centre(k, size);
            if (p - c).length_squared() < (p - best.1).length_squared() {
                best = (k, c);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clumps_blades_share_its_tint_and_lean_away_from_its_centre() {
        let clumps = Clumps { size_m: 1.5 };
        let blade = BladeInstance {
            position: [0.0; 3],
            facing: 0.0,
            height: 0.5,
            width: 0.01,
            stiffness: 1.0,
            variation: 0x80_40_c0_20,
        };
        let mut seen = std::collections::HashMap::new();
        for i in 0..2000 {
            let world = Vec2::new((i % 50) as f32 * 0.13 - 3.0, (i / 50) as f32 * 0.11 - 2.0);
            let (k, out) = clumps.apply(&blade, world);
            let tint = out.variation & 0xff;
            assert_eq!(*seen.entry(k).or_insert(tint), tint, "clump {k:?}: two tints");
            assert!(out.height <= blade.height && out.height >= 0.7 * blade.height);
            // Its normal (sin f, cos f) points away from the centre (within the jitter of ±0.25).
            let c = centre((k[0], k[1]), 1.5);
            let d = Vec2::new(world.x.rem_euclid(WORLD_PERIOD), world.y.rem_euclid(WORLD_PERIOD)) - c;
            if d.length() > 0.05 {
                let n = Vec2::new(out.facing.sin(), out.facing.cos());
                assert!(n.dot(d.normalize()) > 0.95, "{world}: {n} against {d}");
            }
        }
        assert!(seen.len() > 10, "{} clumps", seen.len());
        // A world period away: the same clump.
        let far = Vec2::new(0.25 + WORLD_PERIOD * 5.0, -1.25);
        assert_eq!(clumps.apply(&blade, far).1, clumps.apply(&blade, Vec2::new(0.25, -1.25)).1);
    }
}
