//! The colliders binned over the ground (issue #34): a blade tests only the colliders whose ground
//! ellipse may hold its root, not all of them. Both the colliders' force (`blade_force`,
//! `shaders/animation/forces.glsl`: every response) and push-out act only on blades whose root lies
//! inside a collider's ground ellipse (and the interaction patches, `patches`, only within
//! `patches::REACH_M` of it), so a grid of `BIN_DIMS`² bins over the box of every
//! collider's ellipse, each with a 128-bit mask of the colliders whose ellipse's box, grown by that reach, overlaps it,
//! tells a blade the few it must test (`shaders/animation/collider_bins.glsl`). A blade outside the
//! grid tests none.
//!
//! The grid is written by the CPU each frame after the emitters, in the same buffer (set 0's
//! `Emitters`, from element `COLLIDER_BINS`): a header (the grid's first corner x, z relative to
//! O, its bin edge, `BIN_DIMS`; 0 there when no collider), then per bin its mask as eight 16-bit
//! integers in floats (two elements) (exact, and no bit pattern a float load may change). The bins are found with
//! the f32 positions the GPU reads, and the boxes padded by a millimetre more, so no root within
//! reach is missed; a blade's colliders are taken in ascending order, as before, so the forces
//! are the same to the bit.

use glam::{Vec2, Vec4};

/// Bins per side of the grid.
pub const BIN_DIMS: usize = 32;
/// The first element of the grid in the emitter buffer: after the emitters.
pub const COLLIDER_BINS: usize = super::EMITTER_ELEMENTS;
/// The emitter buffer's elements: the emitters, the grid's header and its bins (two each).
pub const EMITTER_BUFFER_ELEMENTS: usize = COLLIDER_BINS + 1 + 2 * BIN_DIMS * BIN_DIMS;
/// The smallest bin edge, in metres.
const MIN_BIN_M: f32 = 0.25;
/// The padding of each ellipse's box, in metres: the interaction patches' reach
/// (`patches::REACH_M`), and a millimetre.
const PAD_M: f32 = super::patches::REACH_M + 1e-3;

/// Pad `emitters` (the sources, then `(len − sources) / 2` colliders) to `COLLIDER_BINS` and
/// append the grid over its colliders.
pub fn append(emitters: &mut Vec<Vec4>, sources: usize) {
    let grounds: Vec<(Vec2, Vec2)> = emitters[sources.min(emitters.len())..]
        .chunks_exact(2)
        .map(|c| (Vec2::new(c[0].x, c[0].z), Vec2::new(c[1].x, c[1].z)))
        .collect();
    emitters.resize(COLLIDER_BINS, Vec4::ZERO);
    emitters.extend(bins(&grounds));
}

/// The grid over `colliders` (each its ground centre x, z relative to O and its radii x, z): the
/// header and the bins (`EMITTER_BUFFER_ELEMENTS - COLLIDER_BINS` elements).
pub fn bins(colliders: &[(Vec2, Vec2)]) -> Vec<Vec4> {
    let mut out = vec![Vec4::ZERO; 1 + 2 * BIN_DIMS * BIN_DIMS];
    if colliders.is_empty() {
        return out;
    }
    let boxes: Vec<(Vec2, Vec2)> = colliders.iter().map(|&(c, r)| (c - r - PAD_M, c + r + PAD_M)).collect();
    let lo = boxes.iter().fold(Vec2::MAX, |a, b| a.min(b.0));
    let hi = boxes.iter().fold(Vec2::MIN, |a, b| a.max(b.1));
    let edge = ((hi - lo).max_element() / BIN_DIMS as f32).max(MIN_BIN_M) * (1.0 + 1e-4);
    out[0] = Vec4::new(lo.x, lo.y, edge, BIN_DIMS as f32);
    let n = BIN_DIMS as i64;
    let bin = |p: Vec2| ((p - lo) / edge).floor().as_i64vec2().clamp(glam::I64Vec2::ZERO, glam::I64Vec2::splat(n - 1));
    let mut masks = vec![0u128; BIN_DIMS * BIN_DIMS];
    for (i, (a, b)) in boxes.iter().enumerate().take(super::MAX_COLLIDERS) {
        let (a, b) = (bin(*a), bin(*b));
        for y in a.y..=b.y {
            for x in a.x..=b.x {
                masks[(y * n + x) as usize] |= 1 << i;
            }
        }
    }
    let part = |mask: u128, k: u32| ((mask >> (16 * k)) & 0xffff) as f32;
    for (slots, mask) in out[1..].chunks_exact_mut(2).zip(masks) {
        slots[0] = Vec4::new(part(mask, 0), part(mask, 1), part(mask, 2), part(mask, 3));
        slots[1] = Vec4::new(part(mask, 4), part(mask, 5), part(mask, 6), part(mask, 7));
    }
    out
}

/// The colliders the grid `bins` names for a root at `root` (relative to O): the CPU mirror of
/// `colliders_near` in `collider_bins.glsl`.
pub fn near(bins: &[Vec4], root: Vec2) -> u128 {
    let head = bins[0];
    if head.w == 0.0 {
        return 0;
    }
    let b = ((root - Vec2::new(head.x, head.y)) / head.z).floor();
    if b.min_element() < 0.0 || b.max_element() >= BIN_DIMS as f32 {
        return 0;
    }
    let at = 1 + 2 * (b.y as usize * BIN_DIMS + b.x as usize);
    let parts = bins[at].to_array().into_iter().chain(bins[at + 1].to_array());
    parts.enumerate().fold(0, |mask, (k, v)| mask | (v as u128) << (16 * k))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_root_inside_an_ellipse_finds_its_collider() {
        let colliders: Vec<(Vec2, Vec2)> = (0..120)
            .map(|i| {
                let a = i as f32 * 0.7;
                (Vec2::new(30.0 * a.cos(), 20.0 * (1.3 * a).sin()), Vec2::new(0.3 + 0.05 * (i % 5) as f32, 0.4))
            })
            .collect();
        let grid = bins(&colliders);
        let mut inside = 0;
        for k in 0..20_000 {
            let p = Vec2::new((k % 200) as f32 * 0.33 - 33.0, (k / 200) as f32 * 0.45 - 22.5);
            let mask = near(&grid, p);
            for (i, &(c, r)) in colliders.iter().enumerate() {
                if ((p - c) / r).length_squared() < 1.0 {
                    inside += 1;
                    assert!(mask & (1u128 << i) != 0, "root {p} inside collider {i} not in its bin");
                }
            }
            // A bin names few: those whose box reaches it.
            assert!(mask.count_ones() <= 6, "{p}: {mask:b}");
        }
        assert!(inside > 50, "{inside} roots inside");
        assert_eq!(near(&bins(&[]), Vec2::ZERO), 0);
    }
}
