//! Flowers (issue #36 item 1, `scene::flowers`): the library's first draw class besides the blades
//! (`render::draw_class`). Its selection is `shaders/flowers/flowers_count.comp` (the cull claims
//! candidate blades for it by `scene::flowers::claimed`), its buckets are two levels of detail,
//! its entries are posed by the blade response as blades (`DrawClass::posed`: the stems), and its
//! pass ([`FlowerPass`], `pass.rs`) draws a head of petals on each stem.
//!
//! | bucket | stem segments | petals | vertices | triangles |
//! |---|---|---|---|---|
//! | near (head ≥ `NEAR_PIXELS` across) | `NEAR_STEM_SEGMENTS` (4) | `NEAR_PETALS` (6) | 23 | 20 |
//! | far | none (under a pixel wide) | a square (`FAR_SQUARE` of the radius) | 4 | 2 |
//!
//! A near head is a star: its centre, and around it per petal a notch and the petal's tip, two
//! triangles a petal; its vertices are shared between neighbouring petals. On lavapipe a visible
//! triangle is what costs: a far flower draws as many as the far blade it took.

mod pass;

use crate::error::Result;
use crate::render::draw_class::{ClassSetup, DrawClass, DrawClasses};
use crate::render::graph::Pass;
use crate::scene::flowers::{NEAR_PETALS, NEAR_STEM_SEGMENTS};
use crate::vk::profile::Shader;
use crate::vk::Device;

pub use pass::FlowerPass;

/// Index values per flower of an instance: flower k's vertex codes are `k · STRIDE + code`
/// (`shaders/flowers/flower.vert`).
pub const STRIDE: u32 = 32;
/// The far bucket's first vertex code (the near flower's codes come first).
pub const FAR_BASE: u32 = vertices(NEAR_STEM_SEGMENTS, NEAR_PETALS);
/// The far head's square: its corners at this share of the head's radius.
pub const FAR_SQUARE: f32 = 0.8;

// Both flowers' vertex codes fit a stride: the far square's four after the near flower's.
const _: () = assert!(FAR_BASE + 4 <= STRIDE);

/// Vertices of a flower with a stem of `segments` and `petals` petals: the stem's, two a level,
/// then the head's centre and two a petal.
const fn vertices(segments: u32, petals: u32) -> u32 {
    2 * (segments + 1) + 1 + 2 * petals
}

/// The count shader of the blade class and the flowers.
pub const COUNT_SHADER: Shader = crate::spirv_shader!("flowers/flowers_count.comp");

/// The triangle list of one near flower: a stem of `segments` segments, then a head of `petals`
/// petals, two triangles each about its centre: (centre, notch, tip) and (centre, tip, next notch).
fn flower_triangles(segments: u32, petals: u32) -> Vec<u32> {
    let stem = (0..segments).flat_map(|s| [2 * s, 2 * s + 1, 2 * s + 2, 2 * s + 2, 2 * s + 1, 2 * s + 3]);
    let centre = 2 * (segments + 1);
    let ring = move |k: u32| centre + 1 + k % (2 * petals);
    let head =
        (0..petals).flat_map(move |p| [centre, ring(2 * p), ring(2 * p + 1), centre, ring(2 * p + 1), ring(2 * p + 2)]);
    stem.chain(head).collect()
}

/// The pass's index list: the near bucket's `per_instance` flowers, then the far bucket's
/// squares.
pub fn flower_indices(per_instance: u32) -> Vec<u32> {
    let near = flower_triangles(NEAR_STEM_SEGMENTS, NEAR_PETALS);
    let near = (0..per_instance).flat_map(|k| near.iter().map(move |i| k * STRIDE + i).collect::<Vec<_>>());
    let square = (0..per_instance).flat_map(|k| [0, 1, 2, 0, 2, 3].map(|c| k * STRIDE + FAR_BASE + c));
    near.chain(square).collect()
}

/// Indices of one near and one far flower.
const NEAR_INDICES: u32 = 6 * (NEAR_STEM_SEGMENTS + NEAR_PETALS);
const FAR_INDICES: u32 = 6;

/// The flowers' draw class.
pub struct FlowerClass;

impl FlowerClass {
    /// The draw classes of a scene with flowers: this class and its count shader.
    pub fn classes() -> DrawClasses {
        DrawClasses { classes: vec![std::rc::Rc::new(FlowerClass)], count_shader: Some(COUNT_SHADER), source: None }
    }
}

impl DrawClass for FlowerClass {
    fn name(&self) -> &'static str {
        "flowers"
    }

    fn buckets(&self) -> u32 {
        2
    }

    fn bucket_draw(&self, bucket: u32, blades_per_instance: u32) -> (u32, u32) {
        match bucket {
            0 => (NEAR_INDICES * blades_per_instance, 0),
            _ => (FAR_INDICES * blades_per_instance, NEAR_INDICES * blades_per_instance),
        }
    }

    fn posed(&self, bucket: u32) -> Option<u32> {
        // The far head stands at the tip of a one-segment pose.
        Some(if bucket == 0 { NEAR_STEM_SEGMENTS } else { 1 })
    }

    fn pass(&self, device: &Device, setup: &ClassSetup) -> Result<Box<dyn Pass>> {
        Ok(Box::new(FlowerPass::new(device, setup)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shaders_integer_constants_are_these() {
        // flower.vert decodes the index list's codes by them, flowers.glsl hashes and claims by
        // them: a change on one side alone would draw the wrong vertices.
        let vert = include_str!("../../../shaders/flowers/flower.vert");
        let glsl = include_str!("../../../shaders/flowers/flowers.glsl");
        let checks = [
            (vert, format!("const uint FLOWER_STRIDE = {STRIDE}u;")),
            (vert, format!("const uint FLOWER_FAR_BASE = {FAR_BASE}u;")),
            (glsl, format!("const uint FLOWER_NEAR_PETALS = {NEAR_PETALS}u;")),
            (glsl, format!("const uint FLOWER_NEAR_STEM_SEGMENTS = {NEAR_STEM_SEGMENTS}u;")),
            (glsl, format!("const uint FLOWER_STORED_KEY = 0x{:x}u;", crate::scene::flowers::STORED_KEY)),
        ];
        for (source, line) in checks {
            assert!(source.contains(&line), "{line}");
        }
    }

    #[test]
    fn the_index_list_holds_each_buckets_flowers_in_their_codes() {
        let indices = flower_indices(2);
        assert_eq!(indices.len() as u32, 2 * (NEAR_INDICES + FAR_INDICES));
        let (near, far) = indices.split_at(2 * NEAR_INDICES as usize);
        // The near flowers' codes below the far base, each flower in its own stride.
        assert!(near.iter().all(|&i| i % STRIDE < FAR_BASE));
        assert!(far.iter().all(|&i| i % STRIDE >= FAR_BASE));
        assert_eq!(near.iter().filter(|&&i| i / STRIDE == 1).count() as u32, NEAR_INDICES);
        // Every vertex of a flower is used, and the head's ring closes on its first notch.
        let one: std::collections::BTreeSet<u32> =
            flower_triangles(NEAR_STEM_SEGMENTS, NEAR_PETALS).into_iter().collect();
        assert_eq!(one.len() as u32, FAR_BASE);
        let (_, first) = FlowerClass.bucket_draw(1, 2);
        assert_eq!(first, 2 * NEAR_INDICES);
    }
}
