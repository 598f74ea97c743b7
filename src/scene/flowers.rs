//! Flowers among the blades (issue #36 item 1, `--flowers PER_M2`), after Zhang Xia §3.3–3.4: a
//! draw class of its own (`render::flowers`), a head of petals on a stem.
//!
//! - **Where.** A flower takes a blade's place: the cull's count pass claims a candidate blade for
//!   the flowers when a hash of its identity (a stored blade's index; a block field's world cell,
//!   modulo the world's period, and its blade in the block) falls under the local share,
//!   `PER_M2 × green / (blade density × grass cover)` (`claimed`). The covering map's green
//!   channel (`scene::cover`) so sets the flowers' density where a map is given, and the grass's
//!   cover is divided out, so a patch of thin grass keeps its flowers. Flowers grow among the
//!   grass: on bare ground (no candidates) there are none, and `PER_M2` is at most the field's
//!   blade density (`check`).
//! - **Its stem** is the blade it took, posed by the blade response like any blade (its pose
//!   records written by the response's pose pass over the flower buckets too), so it bends under
//!   the same wind and response, stateful ones included: its state is keyed on the same identity
//!   in the blade-state store. It is drawn `STEM_WIDTH_M` wide, `STEM_SHORTEST_M` to
//!   `STEM_TALLEST_M` tall.
//! - **Its head** sits at the stem's tip, facing along the stem's tangent, so it nods with the
//!   stem: petals around a yellow centre. Its colour (one of `HEAD_COLORS`) and size
//!   (`HEAD_SMALLEST_M` to `HEAD_LARGEST_M`) vary per flower by the same hash.
//! - **LOD.** Flowers thin with distance with the blades (a claimed blade the density LOD drops is
//!   no flower), are never dropped for facing edge-on (a head shows from every side), and draw in
//!   two buckets: `NEAR_PETALS` petals on a stem of `NEAR_STEM_SEGMENTS` segments while the head
//!   spans `NEAR_PIXELS` pixels or more (20 triangles); past that the head alone, a square of two
//!   triangles at the posed stem's tip (the stem is under a pixel wide there): on lavapipe a
//!   visible triangle is what costs, and a far flower then costs what the far blade it took did.

use crate::error::{Error, Result};
use crate::scene::blades::TALLEST;

/// The densest flowers (per m²) `--flowers` takes, before the field's own blade density bounds it.
pub const MOST_PER_M2: f32 = 10_000.0;
/// A flower's shortest stem (m); the tallest is the tallest blade's (`TALLEST`, which the cull's
/// boxes pad by, and by a head's reach past it with flowers on: `HEAD_REACH_M`), and each
/// flower's lies between by its hash.
pub const STEM_SHORTEST_M: f32 = 0.40;
/// The tallest stem (m).
pub const STEM_TALLEST_M: f32 = TALLEST;
/// A head's smallest radius (m).
pub const HEAD_SMALLEST_M: f32 = 0.025;
/// A head's largest radius (m).
pub const HEAD_LARGEST_M: f32 = 0.045;
/// A stem's width (m).
pub const STEM_WIDTH_M: f32 = 0.004;
/// How far a head reaches past its stem's tip (m): the largest radius, and its cup above, with a
/// margin. The cull's boxes pad by it with flowers on (`plant_up` and `plant_across` in `shaders/common/field.glsl`).
pub const HEAD_REACH_M: f32 = 0.06;
/// The heads' colours (linear RGB): white, yellow, violet, red, blue.
pub const HEAD_COLORS: [[f32; 3]; 5] =
    [[0.80, 0.80, 0.74], [0.85, 0.62, 0.06], [0.38, 0.16, 0.62], [0.75, 0.10, 0.16], [0.18, 0.28, 0.78]];
/// The near bucket's petals and stem segments.
pub const NEAR_PETALS: u32 = 6;
/// The near bucket's stem segments.
pub const NEAR_STEM_SEGMENTS: u32 = 4;
/// A head drawn this many pixels across or more is in the near bucket.
pub const NEAR_PIXELS: f32 = 8.0;

/// `--flowers PER_M2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flowers {
    /// Flowers per square metre where the covering map's green is full.
    pub per_m2: f32,
}

impl Flowers {
    /// `PER_M2` checked: finite, positive, at most `MOST_PER_M2`.
    pub fn new(per_m2: f32) -> std::result::Result<Self, String> {
        if !per_m2.is_finite() || per_m2 <= 0.0 || per_m2 > MOST_PER_M2 {
            return Err(format!("{per_m2} flowers per m²: give more than 0 and at most {MOST_PER_M2}"));
        }
        Ok(Self { per_m2 })
    }

    /// The share of a field's candidate blades that are flowers under full green and full grass:
    /// `per_m2` over the field's `blades_per_m2`; refused (bad input) past 1, since a flower takes
    /// a blade's place.
    pub fn share(&self, blades_per_m2: f32) -> Result<f32> {
        if self.per_m2 > blades_per_m2 {
            return Err(Error::BadInput(format!(
                "--flowers {} per m²: more than the field's {blades_per_m2} blades per m² (a flower takes a blade's place)",
                self.per_m2
            )));
        }
        Ok(self.per_m2 / blades_per_m2)
    }
}

/// The hash of a candidate blade's identity (`flower_hash` in `shaders/flowers/flowers.glsl`):
/// `a` the block's cell hash (`cell_hash` in `shaders/common/field.glsl`, which repeats with the world) or
/// `STORED_KEY` for a stored blade, `b` its blade in the block or its index.
pub fn flower_hash(a: u32, b: u32) -> u32 {
    let mut h = a.wrapping_mul(0x9e37_79b1) ^ b.wrapping_add(0x7f4a_7c15).wrapping_mul(0x85eb_ca77);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^ (h >> 16)
}

/// `flower_hash`'s `a` for a stored field's blades.
pub const STORED_KEY: u32 = 0x5157;

/// Whether a candidate of hash `hash` is a flower where the flowers' share is `share` and the
/// covers there are `grass` and `flowers` (`flower_claimed` in `shaders/flowers/flowers.glsl`).
pub fn claimed(hash: u32, share: f32, grass: f32, flowers: f32) -> bool {
    let q = (share * flowers / grass.max(1.0 / 255.0)).min(1.0);
    ((hash >> 8) as f32 / (1u32 << 24) as f32) < q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_density_is_checked_and_bounded_by_the_blades() {
        assert!(Flowers::new(-1.0).is_err() && Flowers::new(f32::NAN).is_err() && Flowers::new(0.0).is_err());
        assert!(Flowers::new(1e9).is_err());
        let flowers = Flowers::new(20.0).unwrap();
        assert_eq!(flowers.share(400.0).unwrap(), 0.05);
        assert!(flowers.share(10.0).unwrap_err().to_string().contains("a flower takes a blade's place"));
    }

    #[test]
    fn the_claim_follows_the_share_and_the_covers() {
        let count = |share, grass, flowers| {
            (0..100_000u32).filter(|&i| claimed(flower_hash(STORED_KEY, i), share, grass, flowers)).count()
        };
        let full = count(0.05, 1.0, 1.0);
        assert!((4_700..5_300).contains(&full), "{full}");
        assert_eq!(count(0.05, 1.0, 0.0), 0, "no green, no flowers");
        // Half the grass: twice the share of its candidates, the same flowers per m².
        let thin = count(0.05, 0.5, 1.0);
        assert!((9_400..10_600).contains(&thin), "{thin}");
    }
}
