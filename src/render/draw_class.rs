//! Draw classes (issue #30 item 1): what the GPU-driven cull sorts its candidates into. A class
//! owns a range of the cull's buckets, a selection (the count pass's `class_bucket`, which puts a
//! candidate into one of its buckets or none), its rows of the indirect-draw buffer (a
//! `VkDrawIndexedIndirectCommand` per bucket, and with `DrawRows::PerTile` one per visible tile
//! and bucket), its order in the visible list (near to far, or far to near for blended classes)
//! and the pass that draws its buckets. The tiles, count, scan and emit passes are the same for
//! every class (`shaders/cull/`).
//!
//! The blade class comes first: its buckets are the `--lod-segments` buckets, its selection the
//! blade tests (`blade_bucket` in `shaders/cull/cull.glsl`), its pass `passes::blades`. Further
//! classes are given to the renderer as a [`DrawClasses`] (`render::Models::classes`): the classes
//! and the count shader that holds their selection (`cull_count.comp`'s `class_bucket`, then
//! `#include "cull/count_main.glsl"`). Their buckets follow the blade class's, at most
//! `MAX_LOD_BUCKETS` in all; [`ClassLayout`] places them and writes where they lie into the
//! frame's uniforms (`cull_classes`, `cull_class_first`, `cull_bucket_draws`), from which the
//! shaders read every class's buckets: no word of the draws buffer is laid out by hand per class.
//! `tests/draw_class.rs` adds a class from `tests/` this way.
//!
//! A class selects from the blade tiles' candidates (claiming blades, as the flowers do), or a set
//! of classes brings a candidate source of its own ([`CandidateSource`]): candidates a ring slot
//! holds besides its blades, ranked after them, with the tiles and count shaders that place and
//! select them.

use std::rc::Rc;

use ash::vk;
use glam::UVec4;

use crate::error::{Error, Result};
use crate::render::draw_rows::DrawRows;
use crate::render::gpu_constants as gpu;
use crate::render::graph::Pass;
use crate::render::passes::PipelineTarget;
use crate::render::recording::SceneSets;
use crate::render::scene_gpu::SceneGpu;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::profile::Shader;
use crate::vk::Device;

/// The order of a class's entries in the visible list, and of its rows: slot order (near to far)
/// for opaque classes, which early depth then rejects behind; reversed for blended classes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Order {
    /// Nearest slots first.
    #[default]
    NearToFar,
    /// Farthest slots first.
    FarToNear,
}

/// What a class's pass is built from.
pub struct ClassSetup<'a> {
    /// The scene pipelines' layout and attachments.
    pub target: PipelineTarget,
    /// The scene's set layouts and the frames in flight.
    pub sets: SceneSets<'a>,
    /// Specialization constants.
    pub constants: &'a Specialization,
    /// The scene on the GPU: the cull's `draws`, `tile_rows` and visible list.
    pub scene: &'a SceneGpu,
    /// The class's first bucket in the cull's bucket space: its draws are the
    /// `VkDrawIndexedIndirectCommand`s at words `DRAW_WORDS × (first + b)` of `scene.draws`.
    pub first_bucket: u32,
    /// Entries of the visible list per instance of its draws (`BLADES_PER_INSTANCE`).
    pub blades_per_instance: u32,
    /// The pose records' set (`SET_POSES`, bind with `recording::bind_pose_set`) and its buffers
    /// (the records, the placed levels): a posed class's entries' records, by entry
    /// (`DrawClass::posed`).
    pub poses: (vk::DescriptorSet, [vk::Buffer; 2]),
}

/// A class the cull sorts candidates into, besides the blades.
pub trait DrawClass {
    /// Its name, in the cull's counts (`render`, `timing`, the viewer, the bench JSON).
    fn name(&self) -> &'static str;
    /// Its buckets (at least one).
    fn buckets(&self) -> u32;
    /// The order of its entries.
    fn order(&self) -> Order {
        Order::NearToFar
    }
    /// Whether it draws once per bucket or once per visible tile and bucket.
    fn rows(&self) -> DrawRows {
        DrawRows::PerBucket
    }
    /// Bucket `bucket`'s draw of one instance of `blades_per_instance` entries: its index count
    /// and first index in its pass's index buffer.
    fn bucket_draw(&self, bucket: u32, blades_per_instance: u32) -> (u32, u32);
    /// The segments bucket `bucket`'s entries are posed with when the blade response poses them
    /// as blades (its pose pass covers the bucket too, `FLAG_POSE_CLASS`, writing records by
    /// entry, `ClassSetup::poses`); `None`, the default: not posed.
    fn posed(&self, _bucket: u32) -> Option<u32> {
        None
    }
    /// The pass that draws its buckets (after the blade pass).
    fn pass(&self, device: &Device, setup: &ClassSetup) -> Result<Box<dyn Pass>>;
}

/// The classes a renderer culls besides the blades, the count shader that selects for them, and
/// their own candidate source.
#[derive(Clone, Default)]
pub struct DrawClasses {
    /// The further classes, in bucket order.
    pub classes: Vec<Rc<dyn DrawClass>>,
    /// `cull_count.comp` built with their selection (`class_bucket`, and with a source
    /// `source_bucket`); `None`: the library's, the blade class alone.
    pub count_shader: Option<Shader>,
    /// Candidates of their own, besides the blade tiles'; `None`: they select from the blades.
    pub source: Option<CandidateSource>,
}

/// The most candidates a source adds to a ring slot: a visible entry holds its rank in 16 bits
/// (`visible_source`, `shaders/cull/cull.glsl`).
pub const MOST_SOURCE_CANDIDATES: u32 = 1 << 16;

/// A set of draw classes' own candidate source (issue #30 item 1): candidates a ring slot holds
/// besides its blades, such as a flower's or a far cell's places, which the classes' selection
/// sorts into their buckets instead of claiming blades.
/// - **Where they are**: in the slots the tile tests keep, within the slot's box (the tests are
///   the blades' tile's: a source's candidates must lie in it). The tiles pass asks each kept slot
///   how many it holds (`source_candidates`, its shader's), clamped to `most_per_slot`.
/// - **Their ranks** follow the slot's blade candidates: their verdicts sit after the blades' in
///   the slot's room, the emit pass writes them after the slot's blades, and their visible entry
///   is (slot, rank in the source) in 16 bits each (`visible_source`), in either field. Their
///   class's pass finds the candidate from it (`source_entry` of `shaders/common/field.glsl`).
/// - **Their selection** is the count shader's `source_bucket` (after `#define CLASS_SOURCE`):
///   a bucket of a class or none, the fade and widening, the root's height. They are counted in
///   their buckets, and not in the blade tests' counts (considered, after each test). They go to
///   buckets of the further classes, never the blade class's, and a bucket that takes them is
///   not posed as blades (`DrawClass::posed`): their entries are not blades.
///
/// `tests/draw_class.rs` adds one from `tests/`.
#[derive(Clone, Copy, Debug)]
pub struct CandidateSource {
    /// `cull_tiles.comp` with the source's `source_candidates`: `#define CLASS_SOURCE`, include
    /// `cull/cull.glsl`, define it, include `cull/tiles_main.glsl`.
    pub tiles_shader: Shader,
    /// The most candidates it adds to a slot, at most `MOST_SOURCE_CANDIDATES`: a stored field's
    /// verdicts get that much more room per ring slot (a block field's share their room).
    pub most_per_slot: u32,
}

impl DrawClasses {
    /// The cull's count and tiles shaders for these classes (the library's where they bring none).
    pub fn cull_shaders(&self) -> (Shader, Shader) {
        let count = self.count_shader.unwrap_or(crate::render::shaders::CULL_COUNT_COMP);
        (count, self.source.map_or(crate::render::shaders::CULL_TILES_COMP, |s| s.tiles_shader))
    }

    /// The most candidates their own source adds to a slot (0: none), the frame's `cull_room.y`.
    pub fn source_room(&self) -> u32 {
        self.source.map_or(0, |s| s.most_per_slot)
    }
}

/// Where every class's buckets lie: the blade class's `blade_buckets` first, then each further
/// class's.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassLayout {
    /// The blade class's buckets.
    pub blade_buckets: u32,
    /// The blade class's rows.
    pub blade_rows: DrawRows,
    /// Per further class: its name, first bucket, buckets, order, rows and each bucket's draw.
    pub classes: Vec<PlacedClass>,
}

/// A further class placed in the bucket space.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedClass {
    /// Its name.
    pub name: &'static str,
    /// Its first bucket.
    pub first: u32,
    /// Its buckets.
    pub buckets: u32,
    /// Its order.
    pub order: Order,
    /// Its rows.
    pub rows: DrawRows,
    /// Per bucket: index count and first index of one instance's draw.
    pub draws: Vec<(u32, u32)>,
    /// Per bucket: the segments its entries are posed with (`DrawClass::posed`).
    pub posed: Vec<Option<u32>>,
}

impl ClassLayout {
    /// Place `classes` after `blade_buckets` buckets of blades drawn by `blade_rows`; refused
    /// when they need more than the cull's `MAX_LOD_BUCKETS` or more classes than it holds.
    pub fn new(
        blade_buckets: u32,
        blade_rows: DrawRows,
        classes: &DrawClasses,
        blades_per_instance: u32,
    ) -> Result<Self> {
        let further = gpu::MAX_DRAW_CLASSES - 1;
        if let Some(source) = classes.source {
            if !(1..=MOST_SOURCE_CANDIDATES).contains(&source.most_per_slot) {
                return Err(Error::Internal(format!(
                    "a candidate source of {} a slot: 1 to {MOST_SOURCE_CANDIDATES}",
                    source.most_per_slot
                )));
            }
        }
        if classes.classes.len() > further as usize {
            return Err(Error::Internal(format!(
                "{} draw classes besides the blades: the cull holds {further}",
                classes.classes.len()
            )));
        }
        let mut first = blade_buckets;
        let mut placed = Vec::new();
        for class in &classes.classes {
            let buckets = class.buckets();
            let draws = (0..buckets).map(|b| class.bucket_draw(b, blades_per_instance)).collect();
            let posed = (0..buckets).map(|b| class.posed(b)).collect();
            let (name, order, rows) = (class.name(), class.order(), class.rows());
            placed.push(PlacedClass { name, first, buckets, order, rows, draws, posed });
            first += buckets;
        }
        if first > gpu::MAX_LOD_BUCKETS || placed.iter().any(|c| c.buckets == 0) {
            let names: Vec<String> = placed.iter().map(|c| format!("{} {}", c.name, c.buckets)).collect();
            // Bad input: the blade class's buckets are `--lod-segments`', the others' the classes'.
            return Err(Error::BadInput(format!(
                "the draw classes need {first} buckets (blades {blade_buckets}, {}): the cull holds {} (fewer --lod-segments)",
                names.join(", "),
                gpu::MAX_LOD_BUCKETS
            )));
        }
        Ok(Self { blade_buckets, blade_rows, classes: placed })
    }

    /// Buckets of every class.
    pub fn buckets(&self) -> u32 {
        self.classes.last().map_or(self.blade_buckets, |c| c.first + c.buckets)
    }

    /// The frame's draw-class uniforms (`shaders/common/common.glsl`).
    pub fn fill_uniforms(&self, uniforms: &mut FrameUniforms) {
        let bits = |pick: &dyn Fn(Order, DrawRows) -> bool| {
            let blades = if pick(Order::NearToFar, self.blade_rows) { (1u32 << self.blade_buckets) - 1 } else { 0 };
            self.classes
                .iter()
                .filter(|c| pick(c.order, c.rows))
                .fold(blades, |mask, c| mask | (((1u32 << c.buckets) - 1) << c.first))
        };
        let far = bits(&|order, _| order == Order::FarToNear);
        let rows = bits(&|_, rows| rows == DrawRows::PerTile);
        uniforms.cull_classes = UVec4::new(self.buckets(), far, rows, self.classes.len() as u32);
        let mut first = [self.buckets(); 4];
        for (k, class) in self.classes.iter().enumerate() {
            first[k] = class.first;
        }
        uniforms.cull_class_first = UVec4::from(first);
        let mut draws = [[0u32; 2]; gpu::MAX_LOD_BUCKETS as usize];
        for class in &self.classes {
            for (b, &(count, first)) in class.draws.iter().enumerate() {
                draws[(class.first as usize) + b] = [count, first];
            }
        }
        uniforms.cull_bucket_draws = std::array::from_fn(|i| {
            UVec4::new(draws[2 * i][0], draws[2 * i][1], draws[2 * i + 1][0], draws[2 * i + 1][1])
        });
    }

    /// The further classes' buckets the blade response poses, and their segments.
    pub fn posed(&self) -> Vec<(u32, u32)> {
        self.classes
            .iter()
            .flat_map(|c| c.posed.iter().enumerate().filter_map(|(b, s)| s.map(|s| (c.first + b as u32, s))))
            .collect()
    }

    /// Per class, blades first: its name and its buckets (first, count), for the cull's counts.
    pub fn ranges(&self) -> Vec<(&'static str, u32, u32)> {
        std::iter::once(("blades", 0, self.blade_buckets))
            .chain(self.classes.iter().map(|c| (c.name, c.first, c.buckets)))
            .collect()
    }
}

/// The indirect-draw buffer's word of bucket `bucket`'s `VkDrawIndexedIndirectCommand`, and its
/// stride: what a class's pass draws with `vkCmdDrawIndexedIndirect`.
pub fn draw_word(bucket: u32) -> (u64, u32) {
    (4 * u64::from(gpu::DRAW_WORDS * bucket), std::mem::size_of::<vk::DrawIndexedIndirectCommand>() as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Markers(u32, Order);

    impl DrawClass for Markers {
        fn name(&self) -> &'static str {
            "markers"
        }
        fn buckets(&self) -> u32 {
            self.0
        }
        fn order(&self) -> Order {
            self.1
        }
        fn bucket_draw(&self, bucket: u32, batch: u32) -> (u32, u32) {
            (6 * batch, 100 * bucket)
        }
        fn pass(&self, _: &Device, _: &ClassSetup) -> Result<Box<dyn Pass>> {
            Err(Error::Internal("not drawn in this test".into()))
        }
    }

    #[test]
    fn further_classes_follow_the_blades_and_their_bits_say_how_they_draw() {
        let classes = DrawClasses {
            classes: vec![Rc::new(Markers(2, Order::FarToNear)), Rc::new(Markers(1, Order::NearToFar))],
            count_shader: None,
            source: None,
        };
        let layout = ClassLayout::new(3, DrawRows::PerTile, &classes, 32).unwrap();
        assert_eq!(layout.buckets(), 6);
        assert_eq!(layout.ranges(), vec![("blades", 0, 3), ("markers", 3, 2), ("markers", 5, 1)]);
        let mut u: FrameUniforms = bytemuck::Zeroable::zeroed();
        layout.fill_uniforms(&mut u);
        // Far to near: buckets 3 and 4; rows per tile: the blades' 0..3.
        assert_eq!(u.cull_classes, UVec4::new(6, 0b11000, 0b111, 2));
        assert_eq!(u.cull_class_first, UVec4::new(3, 5, 6, 6));
        assert_eq!(u.cull_bucket_draws[1], UVec4::new(0, 0, 6 * 32, 0));
        assert_eq!(u.cull_bucket_draws[2], UVec4::new(6 * 32, 100, 6 * 32, 0));
        // More buckets than the cull holds, or a class of none, are refused.
        let many =
            DrawClasses { classes: vec![Rc::new(Markers(6, Order::NearToFar))], count_shader: None, source: None };
        assert!(ClassLayout::new(3, DrawRows::PerBucket, &many, 32).is_err());
        let none =
            DrawClasses { classes: vec![Rc::new(Markers(0, Order::NearToFar))], count_shader: None, source: None };
        assert!(ClassLayout::new(3, DrawRows::PerBucket, &none, 32).is_err());
        // A source's room per slot: 1 to MOST_SOURCE_CANDIDATES (a rank is 16 bits of an entry).
        let with_room = |most_per_slot| DrawClasses {
            classes: vec![Rc::new(Markers(1, Order::NearToFar))],
            count_shader: None,
            source: Some(CandidateSource { tiles_shader: crate::render::shaders::CULL_TILES_COMP, most_per_slot }),
        };
        assert!(ClassLayout::new(3, DrawRows::PerBucket, &with_room(0), 32).is_err());
        assert!(ClassLayout::new(3, DrawRows::PerBucket, &with_room(MOST_SOURCE_CANDIDATES + 1), 32).is_err());
        let layout = ClassLayout::new(3, DrawRows::PerBucket, &with_room(MOST_SOURCE_CANDIDATES), 32).unwrap();
        assert_eq!(layout.buckets(), 4);
        assert_eq!(with_room(5).source_room(), 5);
    }
}
