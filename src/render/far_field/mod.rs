//! The far field (issue #37): past the blades, out to the view distance, a block field's grass is
//! drawn as far plants, Zhang Xia's billboards of six half-planes round a vertical axis (§4.1) or
//! Pelzer's stars of three crossed quads (§7.3), textured from an atlas that meadow bakes from its
//! own blades and leaning in the same wind as the blades.
//!
//! - **Rings** (Zhang Xia eq. 8–9). The plants stand on a world lattice whose step doubles with
//!   each ring: ring r holds Chebyshev distances `[r0 · 2^r, r0 · 2^(r+1))` from the camera on a
//!   lattice of `s0 · 2^r`, so every ring holds the same number of lattice points and the total
//!   grows with log(distance), as eq. 9's count of billboards per grid does. A plant's width grows
//!   with 2^λ, λ = log2(d / r0) its continuous ring, as eq. 8's length does; inside a ring the
//!   plants that the next ring's lattice does not hold fade out over its outer half (a hashed
//!   threshold per plant), so a ring boundary swaps nothing at once. The lattice is the world's:
//!   a plant keeps its place, hash and looks as the camera moves (`shaders/far_field/far_place.comp`).
//! - **Atlas** (`atlas`): patches of the block's own blades seen from the side, orthographic and
//!   supersampled, baked once by a run-once pass (and again when the blade look changes): the
//!   premultiplied albedo with the coverage, and the premultiplied height along the blade (for
//!   Belyaev's l⁶ terms), with box-filtered mips (the mean coverage kept at every level).
//! - **Wind**: the top edge of every rectangle leans by the blade response's tip offset
//!   (`BladeResponse::tip_offset`, tabulated by wind speed and averaged over the blades' facings,
//!   [`TipTable`]) for the wind the field gives at that place (`shaders/wind/wind_field.glsl`:
//!   the global wind and its gusts, sources, calm areas, Perlin or fluid wind), so near and far
//!   lean alike. Zhang Xia's speed-up of far animation (§4.2) is 1 everywhere: the far field moves
//!   at the wind's own pace, which keeps it in phase with the blades in the band and a gust
//!   visibly travelling from the blades to the horizon.
//! - **Fade** (a dither, Zhang Xia §6.1's fade as a hashed threshold): across the band from `BAND_START` of
//!   the blade range to the blade range, blades thin out by a hashed threshold per blade (the
//!   cull, `shaders/cull/cull.glsl`) while the far field's fragments fade in by a hashed threshold
//!   per stretch of a rectangle a blade wide; both thresholds are world-anchored, so a creeping
//!   camera changes only the few plants whose threshold it crosses. Both ramps are measured from
//!   the band's eye, the culling camera on a leash (`far_rings::BandEye`, the hysteresis: state,
//!   one point), so a camera jittering within the leash crosses none. `--fade blend` blends the
//!   far field instead (`order`).
//!   The coverage test is hashed too (a fragment is kept when a world-anchored hash lies under
//!   the atlas's coverage times the fades): every mip keeps the mean coverage, so no per-level
//!   alpha scaling is needed.

pub mod atlas;
pub mod order;
mod pass;
mod place_pass;

use std::rc::Rc;

use glam::Vec3;

pub use crate::render::far_rings::{
    FarFade, FarField, FarRings, BAND_START, CAPACITY, MAX_RINGS, RING_SIDE, RING_START, STEP_SHARE,
};
pub use pass::{FarPass, FarSetup};
pub use place_pass::FarPlacePass;

use crate::render::animation::response::BladeResponse;

/// A plant's rectangles are this many lattice steps wide (times 2^λ, λ its continuous ring): Zhang
/// Xia's billboards are as long as their spacing (eq. 8–9).
pub const WIDTH_STEPS: f32 = 1.0;
/// ... and in the first rings (λ under 1.5, then ramping to 1 at λ = 2.5) half that: there the
/// plants are a few pixels tall at grazing angles, where whole-length ones line up as horizontal
/// dashes, and the far field matches the blades drawn that far better half as long (`meadow bench
/// --preset far`'s band and past-the-band figures) at two thirds of the fragments. Past the ramp
/// the plants keep covering the ground to the horizon.
pub const NEAR_WIDTH: f32 = 0.5;
/// Invocations per workgroup of the placement.
pub const PLACE_GROUP: u32 = 64;
/// Invocations of the ordered compaction's one workgroup (`far_order.comp`).
pub const ORDER_GROUP: u32 = 256;
/// Wind speeds the tip table holds, from 0 to `TIP_TABLE_MAX` m/s.
pub const TIP_TABLE_SIZE: usize = 32;
/// The tip table's fastest wind (m/s); faster winds take its last entry.
pub const TIP_TABLE_MAX: f32 = 24.0;
/// Facings the tip table averages a response's tip offset over.
const TIP_FACINGS: u32 = 8;

/// A blade response's tip offset by wind speed, averaged over the blades' facings: per speed,
/// how far a unit blade's tip moves along the wind and up (m per m of height).
#[derive(Clone, Debug, PartialEq)]
pub struct TipTable(pub [[f32; 2]; TIP_TABLE_SIZE]);

impl TipTable {
    /// The table of `response` (`BladeResponse::tip_offset`).
    pub fn of(response: &dyn BladeResponse) -> Self {
        Self::from_offsets(|wind| response.tip_offset(wind))
    }

    /// The table of a tip offset `offset` (wind in the blade's frame → the tip's move in it).
    pub fn from_offsets(offset: impl Fn(Vec3) -> Vec3) -> Self {
        let mut table = [[0.0; 2]; TIP_TABLE_SIZE];
        for (i, entry) in table.iter_mut().enumerate() {
            let speed = TIP_TABLE_MAX * i as f32 / (TIP_TABLE_SIZE - 1) as f32;
            let (mut along, mut up) = (0.0, 0.0);
            for f in 0..TIP_FACINGS {
                // A blade facing `phi` about +y feels the wind (along world +x) turned by -phi.
                let phi = std::f32::consts::TAU * f as f32 / TIP_FACINGS as f32;
                let (s, c) = phi.sin_cos();
                let local = Vec3::new(c * speed, 0.0, s * speed);
                let moved = offset(local);
                // Back to the world: the part along the wind.
                along += moved.x * c + moved.z * s;
                up += moved.y;
            }
            *entry = [along / TIP_FACINGS as f32, up / TIP_FACINGS as f32];
        }
        Self(table)
    }
}

/// The far field a graph draws: the placement's indirect draw, read back for the counts, and
/// what it stands for.
#[derive(Clone, Copy, Debug)]
pub struct FarDraw {
    /// The placement's `VkDrawIndexedIndirectCommand`.
    pub draw: ash::vk::Buffer,
    /// The plants it placed, in their drawn order.
    pub plants: ash::vk::Buffer,
    /// Its mesh.
    pub mesh: FarField,
    /// Rectangles a plant is drawn as (`pieces`).
    pub pieces: u32,
    /// Its rings.
    pub rings: FarRings,
    /// Its atlas.
    pub atlas: atlas::AtlasHandles,
}

/// A placed plant as the placement wrote it (`FarPlant` of `far_field.glsl`; `Renderer::far_plants`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlacedPlant {
    /// Its centre on the ground, relative to O (m).
    pub centre: [f32; 3],
    /// Its rectangles' width (m).
    pub width: f32,
    /// Its identity's hash.
    pub hash: u32,
    /// Its turn about its axis (radians).
    pub turn: f32,
    /// Its continuous ring λ.
    pub ring: f32,
    /// With `--fade blend`, its key in the far-to-near order (`order::key_of`); 0 otherwise.
    pub key: u32,
}

/// What the far field drew in a frame (`Renderer::far_counts`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarCounts {
    /// Plants drawn.
    pub plants: u32,
    /// Their triangles.
    pub triangles: u32,
    /// Rings, and the distances they span (m).
    pub rings: FarRings,
}

/// The far field's parameters, one std140 block both its passes read (`FarParams` of
/// `shaders/far_field/far_field.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FarParams {
    /// x ring 0's inner distance, y its lattice step, z the band's start (m) (the band's ramp
    /// reads the blade range from the frame: `far_band_ramp` of `shaders/common/frame.glsl`), w
    /// the share of flowers the atlas's flower tiles are baked at (`atlas`; 0: none).
    pub rings: [f32; 4],
    /// x the view distance (m), y a plant's height (m), z, w unused.
    pub reach: [f32; 4],
    /// x rings, y the mesh (`FAR_MESH_*`), z plants the placement may write, w unused.
    pub counts: [u32; 4],
    /// Per wind speed: the tip's move along the wind and up per metre of height (`TipTable`).
    pub tips: [[f32; 4]; TIP_TABLE_SIZE],
}

impl FarParams {
    /// The block for `rings`, drawing `mesh`, leaning by `tips`, the atlas's flower tiles baked at
    /// `flower_tiles` (`scene::Scene::far_flower_share`).
    pub fn new(rings: &FarRings, mesh: FarField, tips: &TipTable, flower_tiles: f32) -> Self {
        let mut block = Self {
            rings: [rings.start, rings.step, rings.band_start, flower_tiles],
            reach: [rings.view_distance, atlas::TILE_HEIGHT_M, 0.0, 0.0],
            counts: [rings.rings, mesh.mesh_code(), CAPACITY, 0],
            tips: [[0.0; 4]; TIP_TABLE_SIZE],
        };
        for (to, from) in block.tips.iter_mut().zip(&tips.0) {
            *to = [from[0], from[1], 0.0, 0.0];
        }
        block
    }
}

/// Rectangles one plant of `mesh` is drawn as: its own, but with `--fade blend` a star's three
/// crossed quads as their six halves from the axis (the billboard's half-planes, the same
/// surface), which, unlike whole crossed quads, have an order far to near (`far.vert`).
pub fn pieces(mesh: FarField, fade: FarFade) -> u32 {
    match (mesh, fade) {
        (FarField::Off, _) => 0,
        (_, FarFade::Blend) => 6,
        (_, FarFade::Dither) => mesh.rectangles(),
    }
}

/// The index list of one plant of `pieces` rectangles: two triangles per rectangle, its vertices
/// `4 · rectangle + corner` (corner 0, 1 at the root, 2, 3 at the top).
pub fn plant_indices(pieces: u32) -> Vec<u32> {
    (0..pieces).flat_map(|r| [0, 1, 2, 2, 1, 3].map(|c| 4 * r + c)).collect()
}

/// The far field's passes and what the renderer keeps of them.
pub struct FarPasses {
    /// In order: the atlas's bake and mips (run once), the placement, the draw.
    pub passes: Vec<Box<dyn crate::render::graph::Pass>>,
    /// The resources they made, never written yet (the graph imports them so: a handle a
    /// destroyed resource had carries no state over).
    pub fresh: Vec<crate::vk::Resource>,
    /// The draw, for the counts.
    pub draw: FarDraw,
    /// The atlas the draw samples, for a rebuilt graph to keep (`Atlas::baked`).
    pub atlas: std::rc::Weak<atlas::Atlas>,
}

/// The far field's passes. `bake_key`: `atlas::bake_key` of the blades the bake draws; `baked`: an
/// atlas that holds that bake already (a rebuilt graph's), drawn from with no bake passes.
pub fn passes(
    device: &crate::vk::Device,
    setup: &FarSetup,
    (rings, (mesh, fade), tips): (&FarRings, (FarField, FarFade), &TipTable),
    (bake_key, baked): (u64, Option<std::rc::Rc<atlas::Atlas>>),
) -> crate::error::Result<FarPasses> {
    let params = FarParams::new(rings, mesh, tips, setup.scene.far_flower_share);
    let mut passes: crate::vk::Guard<Vec<Box<dyn crate::render::graph::Pass>>> =
        crate::vk::Guard::new(device, Vec::new());
    let baked = baked.filter(|atlas| atlas.baked() == Some(bake_key));
    let fresh_atlas = baked.is_none();
    // Shared by the bakes, the mips and the draw: the last owner to go destroys it, the guard too
    // if the passes are not all built.
    let shared = crate::vk::Guard::new(device, baked.map_or_else(|| atlas::Atlas::new(device).map(Rc::new), Ok)?);
    let (atlas, depth) = (shared.handles(), shared.depth());
    if fresh_atlas {
        let target = (setup.target, setup.constants);
        for output in 0..2 {
            let bake = atlas::AtlasBakePass::new(device, target, setup.scene, ((*shared).clone(), output), bake_key)?;
            passes.push(Box::new(bake));
        }
        passes.push(Box::new(atlas::AtlasMipsPass::new(device, (*shared).clone(), bake_key)?));
    }
    let blend = fade == FarFade::Blend;
    let index_count = 6 * pieces(mesh, fade);
    let counts = (rings.points(), index_count);
    let place = FarPlacePass::new(device, (setup.sets, setup.constants), setup.scene, (params, rings, blend), counts)?;
    let placed = (place.plants(), place.draw());
    let staged = place.staged();
    passes.push(Box::new(place));
    passes.push(Box::new(FarPass::new(device, setup, (placed, (*shared).clone()), (mesh, fade), params)?));
    // A kept atlas's levels keep the states the old graph left them in.
    let mut fresh: Vec<crate::vk::Resource> = match fresh_atlas {
        true => atlas.levels().chain([depth]).collect(),
        false => Vec::new(),
    };
    fresh.extend([placed.0.buffer, placed.1].into_iter().chain(staged).map(crate::vk::Resource::Buffer));
    let weak = Rc::downgrade(&shared);
    drop(shared.take());
    let draw =
        FarDraw { draw: placed.1, plants: placed.0.buffer, mesh, pieces: pieces(mesh, fade), rings: *rings, atlas };
    Ok(FarPasses { passes: passes.take(), fresh, draw, atlas: weak })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shaders_integer_constants_are_these() {
        // far_field.glsl sizes its tables and loops by them: a change on one side alone would
        // read the wrong plants, tip entries or tiles.
        let glsl = include_str!("../../../shaders/far_field/far_field.glsl");
        for line in [
            format!("const uint FAR_TIP_TABLE = {TIP_TABLE_SIZE}u;"),
            format!("const uint FAR_RING_SIDE = {RING_SIDE}u;"),
            format!("const uint FAR_TILES = {}u;", atlas::TILES),
            format!("const uint FAR_MIPS = {}u;", atlas::MIPS),
            format!(
                "const vec2 FAR_TILE_TEXELS = vec2({:.1}, {:.1});",
                atlas::TILE_TEXELS.0 as f32,
                atlas::TILE_TEXELS.1 as f32
            ),
        ] {
            assert!(glsl.contains(&line), "{line}");
        }
        let place = include_str!("../../../shaders/far_field/far_place.comp");
        assert!(place.contains(&format!("layout(local_size_x = {PLACE_GROUP}) in;")));
        let compact = include_str!("../../../shaders/far_field/far_order.comp");
        assert!(compact.contains(&format!("const uint GROUP = {ORDER_GROUP}u;")));
        assert!(compact.contains(&format!("layout(local_size_x = {ORDER_GROUP}) in;")));
        let bake = include_str!("../../../shaders/far_field/atlas_bake.vert");
        assert!(bake.contains(&format!("const uint BAKE_SEGMENTS = {}u;", atlas::BAKE_SEGMENTS)));
    }

    #[test]
    fn the_tip_table_follows_the_offsets_it_is_built_from() {
        // A blade whose tip moves along the wind by a tenth of its speed and drops by a hundredth.
        let table = TipTable::from_offsets(|w| Vec3::new(0.1 * w.x, -0.01 * w.length(), 0.1 * w.z));
        assert_eq!(table.0[0], [0.0, 0.0]);
        let last = table.0[TIP_TABLE_SIZE - 1];
        assert!((last[0] - 0.1 * TIP_TABLE_MAX).abs() < 1e-4 && (last[1] + 0.01 * TIP_TABLE_MAX).abs() < 1e-4);
    }

    #[test]
    fn the_meshes_are_six_and_three_rectangles() {
        let indices = |mesh, fade| plant_indices(pieces(mesh, fade)).len();
        assert_eq!(indices(FarField::Billboards, FarFade::Dither), 36);
        assert_eq!(indices(FarField::Stars, FarFade::Dither), 18);
        // Blended, a star is drawn as the six halves of its quads.
        assert_eq!(indices(FarField::Billboards, FarFade::Blend), 36);
        assert_eq!(indices(FarField::Stars, FarFade::Blend), 36);
        assert_eq!(std::mem::size_of::<FarParams>(), 48 + 16 * TIP_TABLE_SIZE);
    }
}
