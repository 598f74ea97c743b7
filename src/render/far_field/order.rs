//! The far field's far-to-near order for `--fade blend` (Zhang Xia §5.4): blended plants must be
//! drawn from the farthest to the nearest, or a near plant's transparent texels hide the far ones
//! drawn after it.
//!
//! Zhang Xia sorts the grass grids by their offset from the camera's grid and draws the plants of
//! each grid in one of eight orders computed once (§5.4.2, Figure 16). meadow's rings are that in
//! one: every ring's lattice of `RING_SIDE`² points holds the camera at nearly the same place,
//! within half a step and a block of `eye_in_lattice` along each axis, whatever the ring and
//! wherever the camera stands. So one
//! order of the lattice, computed once per set of rings ([`far_to_near`]), sorts every ring's
//! points far to near, and the rings go outermost first:
//!
//! - **Across rings** the order is exact in Chebyshev distance (ring r holds `[r0 2^r, r0
//!   2^(r+1))`). Along one direction from the eye, the Chebyshev distance is the Euclidean one
//!   times a constant, so plants that can cover one another on screen (those in one direction)
//!   are in Euclidean order too.
//! - **Inside a ring**, by the Chebyshev distance from `eye_in_lattice`, within half a step and a
//!   block of the camera's place (0.83 of a step for 150 m of blades): along one direction from
//!   the eye every point's distance is off by the same amount, so points there keep their order.
//!
//! The placement (`shaders/far_field/far_place.comp`, variant `ordered`) visits the points in
//! this order and `far_order.comp` compacts the kept ones without reordering them. Each plant
//! keeps its key (its place in the order), which [`key_of`] recomputes on the CPU.

use glam::{IVec2, Vec2};

use crate::render::far_rings::{FarRings, RING_SIDE};
use crate::scene::field::BLOCK_SIZE;

/// Points of a ring's lattice.
pub const PER_RING: u32 = RING_SIDE * RING_SIDE;

/// Where the camera stands in every ring's lattice, in lattice steps from its first point, along
/// each axis: in `[K + 1, K + 2 + 1 / blocks)` for K = 2 r0 / s0 (the lattice's first point lies
/// one to two steps outside its square's corner, 2 r0 from the camera, floored to whole blocks),
/// taken as K + 1.5.
pub fn eye_in_lattice(rings: &FarRings) -> f64 {
    2.0 * f64::from(rings.start) / f64::from(rings.step) + 1.5
}

/// The lattice's points far to near: `order[rank]` is the index (`x + RING_SIDE z`) of the point
/// drawn `rank`-th in its ring. By Chebyshev distance from the camera's place
/// ([`eye_in_lattice`]), farthest first, then by Euclidean distance, then by index.
pub fn far_to_near(rings: &FarRings) -> Vec<u32> {
    let eye = eye_in_lattice(rings);
    let distances = |i: u32| {
        let (x, z) = (f64::from(i % RING_SIDE) - eye, f64::from(i / RING_SIDE) - eye);
        (x.abs().max(z.abs()), x.hypot(z))
    };
    let mut order: Vec<u32> = (0..PER_RING).collect();
    order.sort_by(|&a, &b| {
        let (da, db) = (distances(a), distances(b));
        db.0.total_cmp(&da.0).then(db.1.total_cmp(&da.1)).then(a.cmp(&b))
    });
    order
}

/// A placed plant's key on the CPU, as the ordered placement computes it: its ring counted from
/// the outside times `PER_RING`, plus its point's rank in [`far_to_near`] (`ranks`: its
/// inverse). `centre`: the plant's (x, z) relative to O, as placed; `eye`: the culling camera's
/// relative to O; `origin`: O's cell. `None` for a place no ring holds.
pub fn key_of(rings: &FarRings, ranks: &[u32], (centre, eye, origin): (Vec2, Vec2, IVec2)) -> Option<u32> {
    let offset = (centre - eye).abs();
    let cheb = offset.x.max(offset.y);
    let ring = (0..rings.rings).find(|&r| {
        let start = rings.start * (1u32 << r) as f32;
        cheb >= start && cheb < 2.0 * start
    })?;
    let start = rings.start * (1u32 << ring) as f32;
    let blocks = ((rings.step / BLOCK_SIZE + 0.5) as i32) << ring;
    // The ring's first point (far_place.comp), and the plant's point: its jitter is under half a step.
    let corner = origin + ((eye - Vec2::splat(2.0 * start)) / BLOCK_SIZE).floor().as_ivec2();
    let first = IVec2::new(corner.x.div_euclid(blocks), corner.y.div_euclid(blocks)) - 1;
    let world = centre / BLOCK_SIZE + origin.as_vec2();
    let point = (world / blocks as f32).round().as_ivec2() - first;
    let side = RING_SIDE as i32;
    if point.cmplt(IVec2::ZERO).any() || point.cmpge(IVec2::splat(side)).any() {
        return None;
    }
    let rank = ranks[(point.x + side * point.y) as usize];
    Some((rings.rings - 1 - ring) * PER_RING + rank)
}

/// The inverse of an order: `ranks[point]` is the point's rank.
pub fn ranks(order: &[u32]) -> Vec<u32> {
    let mut ranks = vec![0; order.len()];
    for (rank, &point) in order.iter().enumerate() {
        ranks[point as usize] = rank as u32;
    }
    ranks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_order_is_a_permutation_far_to_near_from_the_eyes_cell() {
        let rings = FarRings::new(150.0, 2000.0).expect("a far field");
        let order = far_to_near(&rings);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..PER_RING).collect::<Vec<_>>());
        // From any place of the camera's cell, a point two steps farther along one direction
        // comes first.
        let eye = eye_in_lattice(&rings);
        let rank = ranks(&order);
        let at = |x: f64, z: f64| rank[(x as u32 + RING_SIDE * z as u32) as usize];
        for (dx, dz) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (1.0, -1.0)] {
            let near = (eye.floor() + 4.0 * dx, eye.floor() + 4.0 * dz);
            let far = (near.0 + 2.0 * dx, near.1 + 2.0 * dz);
            assert!(at(far.0, far.1) < at(near.0, near.1), "({dx}, {dz})");
        }
        // The first point is a corner, the last the one nearest the eye's place.
        let first = order[0];
        assert!([0, RING_SIDE - 1, PER_RING - RING_SIDE, PER_RING - 1].contains(&first), "{first}");
        let last = order[PER_RING as usize - 1];
        assert_eq!((last % RING_SIDE, last / RING_SIDE), (eye.round() as u32, eye.round() as u32));
    }

    #[test]
    fn every_ring_holds_the_eye_at_the_same_place() {
        // far_place.comp's first point of a ring, for cameras across a few cells and rings.
        let rings = FarRings::new(150.0, 2000.0).expect("a far field");
        let lattice = eye_in_lattice(&rings) - 0.5;
        for ring in 0..rings.rings {
            let start = rings.start * (1u32 << ring) as f32;
            let blocks = ((rings.step / BLOCK_SIZE + 0.5) as i32) << ring;
            for i in 0..200 {
                let eye = Vec2::new(0.37 * i as f32, -0.61 * i as f32) + Vec2::new(1.7, 3.1);
                let corner = ((eye - Vec2::splat(2.0 * start)) / BLOCK_SIZE).floor().as_ivec2();
                let first = IVec2::new(corner.x.div_euclid(blocks), corner.y.div_euclid(blocks)) - 1;
                let at = eye / (BLOCK_SIZE * blocks as f32) - first.as_vec2();
                for a in [at.x, at.y] {
                    let a = f64::from(a);
                    assert!(
                        a >= lattice - 1e-3 && a < lattice + 1.0 + 1.0 / f64::from(blocks) + 1e-3,
                        "ring {ring}: {a}"
                    );
                }
            }
        }
    }
}
