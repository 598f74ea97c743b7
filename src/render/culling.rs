//! How the GPU-driven cull and LOD are set (`Culling`), and what they did in a frame
//! (`CullCounts`, read back after the frame's fence). The passes are `render::passes::cull`.

use glam::{UVec4, Vec4};

use crate::render::draw_rows::DrawRows;
use crate::render::gpu_constants as gpu;
use crate::render::uniforms::FrameUniforms;
use crate::scene::bezier::BladeMesh;
use crate::scene::blades;
use crate::scene::tiles::TileGrid;
use crate::scene::Camera;

/// Most LOD buckets (`--lod-segments`).
pub const MAX_LOD_BUCKETS: usize = gpu::MAX_LOD_BUCKETS as usize;
/// Default view distance in metres (`--view-distance`).
pub const DEFAULT_VIEW_DISTANCE: f32 = 150.0;
/// The view distance of the default landscape (`meadow render` and `view` with no scene flag), in
/// metres: the ground and the far field end there, in haze.
pub const LANDSCAPE_VIEW_DISTANCE: f32 = 2000.0;
/// Default blade distance in metres (`--blade-distance`): blades are drawn out to it, or to the
/// view distance when that is shorter (`Culling::blade_range`).
pub const DEFAULT_BLADE_DISTANCE: f32 = 150.0;
/// Distance in metres out to which the density LOD keeps every blade (Belyaev §2.2), at LOD
/// scale 1. It was 8 m; then fading blades kept their height, tiles took a progressive order
/// (`scene::tiles::progressive_order`), coarse strips were lit with the mean of l^6 over their
/// stretch (`height_six` in lighting.glsl) and widened blades with their patch's mean colour.
/// Measured at 1M blades from the default view (8x8 mean difference from brute force, blades
/// drawn): 8 m before, 0.455 % and 143 598; 6.5 m after, 0.405 % and 103 833; 6 m, 0.438 % and
/// 91 203; 5.5 m, 0.473 % and 78 991. With the widening cap raised from 6 to 12 (`bench --preset
/// lod`, mean / p99 block, blades drawn, unbounded frame against the 100k brute-force one): 6 m,
/// 0.42 % / 2.60 %, 91 266, 0.73x; 5.5 m, 0.45 % / 2.85 %, 79 057, 0.65x; 5 m, 0.50 % / 3.17 %,
/// 67 614, 0.64x. 5.5 m keeps the 1M bound (0.5 %) with a margin and is nearest the unbounded
/// field's 0.5x.
pub const FULL_DENSITY_DISTANCE: f32 = 5.5;
/// Where the density LOD's far field begins: past it the kept fraction falls as 1/d³ instead of
/// Belyaev's 1/d² (`far_field` and `density_keep` in cull.glsl). Belyaev's 1/d² is the screen
/// area of a square metre of ground seen face-on, and the survivors widen to keep the ground
/// covered, up to `max_widening`. Past the distance where a face-on patch's survivors reach that
/// cap, (1 − FADE_BAND / 2) keep = 1 / max_widening with keep = 1 / (A1 (1 + d²/d0²)), widening
/// no longer holds the coverage, and over a grazing view the ground one pixel row sees grows as
/// d³ (its width as d, its depth as d² / eye height): 1/d² keeps adding blades to pixels that
/// are already covered many times, 1/d³ keeps the drawn blades per pixel constant. At d0 = 5.5 m
/// and a cap of 12 it is 34.7 m.
pub fn far_field_distance(full_density_distance: f32, max_widening: f32) -> f32 {
    full_density_distance * (max_widening * (1.0 - 0.5 * FADE_BAND) / A1 - 1.0).sqrt()
}

/// `A1` and `FADE_BAND` of `shaders/cull/cull.glsl` (Belyaev's a1; the band of the kept fraction over
/// which blades fade).
pub const A1: f32 = 0.25;
/// See `A1`.
pub const FADE_BAND: f32 = 0.3;
/// Projected height in pixels one blade segment may span before the LOD picks more segments,
/// at LOD scale 1. llvmpipe pays per triangle (a visible blade triangle costs its setup, binning
/// and the 4x4 blocks it touches; the fragment shader's work hardly counts: a constant colour
/// changed nothing), and a blade of 4, 2 and 1 segments is 7, 3 and 1 triangles. Measured with
/// `bench --preset lod` (1M default view, 8x8 mean / p99 block against brute force, blade
/// triangles; unbounded field's GPU frame): 8 px, 0.45 % / 2.85 %, 277 745, 126 ms; 12 px,
/// 0.46 % / 2.94 %, 208 057, 108 ms; 16 px, 0.48 % / 2.98 %, 171 689, 108 ms; 20 px, 0.50 % /
/// 3.14 %, 149 351, 108 ms. 16 px keeps the 1M bound (0.5 %) with the unbounded field's blade
/// triangles down from 301 492 to 205 410.
pub const PIXELS_PER_SEGMENT: f32 = 16.0;

/// The segment counts of the LOD buckets, decreasing: bucket 0 is the nearest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LodSegments {
    counts: [u32; MAX_LOD_BUCKETS],
    len: usize,
}

impl LodSegments {
    /// Buckets of `counts` segments: 1 to `MAX_LOD_BUCKETS` counts in 1..=16, strictly
    /// decreasing. The error says why not.
    pub fn new(counts: &[u32]) -> Result<Self, String> {
        if counts.is_empty() || counts.len() > MAX_LOD_BUCKETS {
            return Err(format!("give 1 to {MAX_LOD_BUCKETS} segment counts"));
        }
        if let Some(bad) = counts.iter().find(|c| !crate::render::limits::SEGMENTS_RANGE.contains(c)) {
            return Err(format!("{bad} segments is outside 1..={}", gpu::MAX_SEGMENTS));
        }
        if counts.windows(2).any(|w| w[1] >= w[0]) {
            return Err(format!("{counts:?} must decrease (nearest bucket first)"));
        }
        let mut all = [0; MAX_LOD_BUCKETS];
        all[..counts.len()].copy_from_slice(counts);
        Ok(Self { counts: all, len: counts.len() })
    }

    /// Halvings of `segments` down to 1 that divide it (`--segments 8`: 8, 4, 2, 1; 6: 6, 3, 1;
    /// 7: 7, 1), so every bucket's levels are levels of the animation model: no bucket
    /// interpolates between them.
    pub fn halving(segments: u32) -> Self {
        let next = |s: &u32| (*s > 1).then(|| (1..=s / 2).rev().find(|d| s.is_multiple_of(*d)).expect("1 divides"));
        let counts: Vec<u32> = std::iter::successors(Some(segments.max(1)), next).collect();
        Self::new(&counts).expect("halvings of 1..=16 decrease and fit")
    }

    /// The counts, nearest bucket first.
    pub fn counts(&self) -> &[u32] {
        &self.counts[..self.len]
    }

    /// Packed for `FrameUniforms::cull_lod.y`: count − 1 in 4 bits per bucket.
    pub fn packed(&self) -> u32 {
        self.counts().iter().enumerate().fold(0, |acc, (i, c)| acc | ((c - 1) << (4 * i)))
    }
}

/// The cull and LOD of the blade pass. `enabled: false` is `--brute-force`: every stored blade
/// at `--segments`, one instanced draw, no cull pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Culling {
    /// Run the cull passes and draw what they keep (false: `--brute-force`).
    pub enabled: bool,
    /// Tiles and blades outside the frustum.
    pub frustum: bool,
    /// Tiles and blades beyond `view_distance`.
    pub distance: bool,
    /// Blades seen edge-on.
    pub orientation: bool,
    /// Tiles and blades behind the terrain (this frame's depth pyramid).
    pub occlusion: bool,
    /// Belyaev's smooth density LOD.
    pub density: bool,
    /// Segment buckets by projected height (off: every blade in the first bucket).
    pub segment_lod: bool,
    /// The alpha-tested outline drawn as geometry (tapered strips, the rim computed): no discard,
    /// so early depth tests reject hidden fragments before shading.
    pub solid_outline: bool,
    /// The buckets.
    pub lod_segments: LodSegments,
    /// Metres beyond which nothing is drawn: the ground's extent.
    pub view_distance: f32,
    /// Metres beyond which no blade is drawn (`blade_range`: at most `view_distance`).
    pub blade_distance: f32,
    /// The plants drawn past the blade range out to the view distance (a block field's,
    /// `render::far_field`).
    pub far_field: crate::render::far_rings::FarField,
    /// How the far field meets the blades across the band.
    pub far_fade: crate::render::far_rings::FarFade,
    /// How far the band's eye trails the culling camera, as a share of the band's width
    /// (`far_rings::BandEye`, `FarRings::leash`; 0: stateless).
    pub band_leash: f32,
    /// Scales the full-density distance and divides the pixels per segment: above 1, more detail.
    pub lod_scale: f32,
    /// How the blade class issues its draws: once per LOD bucket, or once per visible tile and
    /// bucket (`draw_rows`; `--animation sine-cluster` draws a row per tile).
    pub rows: DrawRows,
    /// A block field's cell heights bounded by the clipmap's tiles under the cell
    /// (`render::ground::tiles`, `FLAG_GROUND_BOUNDS`; off: by the spread the ground's steepest
    /// slope allows alone). The tiles' cover skips bare cells either way. No effect on stored
    /// fields.
    pub ground_bounds: bool,
}

impl Culling {
    /// Culling and LOD on, buckets halving from `segments`.
    pub fn default_for(segments: u32) -> Self {
        Self {
            enabled: true,
            frustum: true,
            distance: true,
            orientation: true,
            occlusion: true,
            density: true,
            segment_lod: true,
            solid_outline: true,
            lod_segments: LodSegments::halving(segments),
            view_distance: DEFAULT_VIEW_DISTANCE,
            blade_distance: DEFAULT_BLADE_DISTANCE,
            far_field: Default::default(),
            far_fade: Default::default(),
            band_leash: crate::render::far_rings::BAND_LEASH,
            lod_scale: 1.0,
            rows: DrawRows::PerBucket,
            ground_bounds: true,
        }
    }

    /// `--brute-force`: no cull pass.
    pub fn brute_force(segments: u32) -> Self {
        Self { enabled: false, ..Self::default_for(segments) }
    }

    /// How far blades are drawn: the blade distance, or the view distance when it is shorter
    /// (the ground ends there). The cull's distance test and a block field's rings of blade
    /// cells and force corners are sized by it; the ground by `view_distance`.
    pub fn blade_range(&self) -> f32 {
        self.blade_distance.min(self.view_distance)
    }

    /// The far field's rings when it draws: a far field chosen and the ground reaching past the
    /// blades (a block field's; `Renderer` checks the field).
    pub fn far_rings(&self) -> Option<crate::render::far_rings::FarRings> {
        let on = self.enabled && self.far_field != crate::render::far_rings::FarField::Off;
        on.then(|| crate::render::far_rings::FarRings::new(self.blade_range(), self.view_distance)).flatten()
    }

    /// Whether the far field is blended (`FarFade::Blend`): the scene is then drawn in linear
    /// light into the RGBA16F intermediate a resolve encodes (`RenderSettings::linear_scene`).
    pub fn blends_far_field(&self) -> bool {
        self.far_rings().is_some() && self.far_fade == crate::render::far_rings::FarFade::Blend
    }

    /// How far a block field's wind reaches: the blades, or the far field's plants.
    pub fn wind_reach(&self) -> f32 {
        self.far_rings().map_or(self.blade_range(), |rings| rings.view_distance)
    }

    /// The `CULL_*` / `LOD_*` bits of the tests that are on.
    pub fn bits(&self) -> u32 {
        [
            (self.frustum, gpu::CULL_FRUSTUM),
            (self.distance, gpu::CULL_DISTANCE),
            (self.orientation, gpu::CULL_ORIENTATION),
            (self.occlusion, gpu::CULL_OCCLUSION),
            (self.density, gpu::LOD_DENSITY),
            (self.segment_lod, gpu::LOD_SEGMENTS),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .fold(0, |acc, (_, bit)| acc | bit)
    }

    /// The cull's part of the frame's uniforms: the culling camera, the LOD settings and the
    /// rings of tiles around the culling camera's tile. A frozen culling camera turns the
    /// occlusion test off: the depth pyramid is the view's. `lens` is the view's aspect ratio and
    /// near plane (`scene::camera::near_plane`).
    pub fn fill_uniforms(
        &self,
        uniforms: &mut FrameUniforms,
        grid: &TileGrid,
        camera: &Camera,
        frozen: bool,
        (aspect, near): (f32, f32),
        height: u32,
    ) {
        let p11 = 1.0 / (0.5 * crate::scene::camera::FOV_Y_DEG.to_radians()).tan();
        let pixels_per_metre = 0.5 * height as f32 * p11;
        let eye = camera.position;
        let centre = grid.cell(eye.x, eye.z);
        let scale = self.lod_scale;
        uniforms.cull_view_proj = camera.view_projection_near(aspect, near);
        uniforms.cull_eye = eye.extend(pixels_per_metre);
        uniforms.lod = Vec4::new(
            self.blade_range(),
            FULL_DENSITY_DISTANCE * scale,
            PIXELS_PER_SEGMENT / scale,
            blades::MAX_WIDENING,
        );
        uniforms.tile_grid = Vec4::new(grid.origin, grid.tile_size, p11 / aspect, p11);
        uniforms.cull_tiles = UVec4::new(grid.tiles, grid.ring_slots(centre), centre.0, centre.1);
        let bits = if frozen { self.bits() & !gpu::CULL_OCCLUSION } else { self.bits() };
        uniforms.cull_lod =
            UVec4::new(self.buckets().len() as u32, self.lod_segments.packed(), bits, uniforms.cull_lod.w);
    }

    /// The buckets drawn: all of them with segment LOD, else the first only.
    pub fn buckets(&self) -> &[u32] {
        let counts = self.lod_segments.counts();
        if self.segment_lod {
            counts
        } else {
            &counts[..1]
        }
    }
}

/// What the cull did in one frame (`shaders/common/shared.glsl`, `STAT_*`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CullCounts {
    /// Blades drawn per LOD bucket.
    pub drawn: [u32; MAX_LOD_BUCKETS],
    /// Segments of each bucket (0 past the last).
    pub segments: [u32; MAX_LOD_BUCKETS],
    /// Whether the buckets' blades end in one tip vertex (`bezier::BladeMesh`, the outline as
    /// geometry).
    pub collapsed_tip: bool,
    /// Blades of every tile.
    pub considered: u32,
    /// Blades of the tiles that passed the tile tests.
    pub after_tiles: u32,
    /// ... then kept by the density LOD.
    pub after_density: u32,
    /// ... then inside the frustum and the view distance.
    pub after_frustum: u32,
    /// ... then not seen edge-on.
    pub after_orientation: u32,
    /// ... then not behind the terrain.
    pub after_occlusion: u32,
    /// Tiles that passed the tile tests.
    pub tiles_visible: u32,
    /// Tiles.
    pub tiles: u32,
    /// Blades the blade tests kept, before the visible list's capacity thinned them (`drawn`
    /// sums to this when the scale is one).
    pub wanted: u32,
    /// The capacity scale the emit pass thinned every bucket by, 0.32 fixed point
    /// (`SCALE_ONE`: all kept; `capacity_scale`).
    pub scale: u32,
    /// Candidates of a block field's slots that found no room for their verdicts
    /// (`scene_gpu::FIELD_VERDICTS`): neither tested nor drawn.
    pub no_room: u32,
    /// With per-tile rows (`draw_rows::DrawRows::PerTile`): the draws of the classes drawn so,
    /// one per visible tile and bucket that draws (0 with one draw per bucket).
    pub tile_draws: u32,
    /// The further draw classes' entries drawn (`render::draw_class`; a class of no name is
    /// none), after the blade class's `drawn`.
    pub classes: [ClassCount; gpu::MAX_DRAW_CLASSES as usize - 1],
}

/// What the cull drew of a draw class besides the blades.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClassCount {
    /// Its name (empty: no class).
    pub name: &'static str,
    /// Entries of its buckets in the visible list.
    pub drawn: u32,
}

/// The capacity scale that keeps every blade (`SCALE_ONE`, `shaders/cull/cull.glsl`).
pub const SCALE_ONE: u32 = u32::MAX;

impl CullCounts {
    /// Decode the `SLOT_WORDS` words the scan wrote, for buckets of `segments` (their blades'
    /// tips collapsed or not).
    pub fn from_words(words: &[u32], segments: &[u32], collapsed_tip: bool) -> Self {
        let stat = |i: u32| words[i as usize];
        let mut counts = Self {
            considered: stat(gpu::STAT_CONSIDERED),
            after_tiles: stat(gpu::STAT_TILES),
            after_density: stat(gpu::STAT_DENSITY),
            after_frustum: stat(gpu::STAT_FRUSTUM),
            after_orientation: stat(gpu::STAT_ORIENTATION),
            after_occlusion: stat(gpu::STAT_OCCLUSION),
            tiles_visible: stat(gpu::STAT_TILES_VISIBLE),
            tiles: stat(gpu::STAT_TILES_TOTAL),
            wanted: stat(gpu::STAT_WANTED),
            scale: stat(gpu::STAT_SCALE),
            no_room: stat(gpu::STAT_NO_ROOM),
            tile_draws: stat(gpu::STAT_TILE_DRAWS),
            collapsed_tip,
            ..Self::default()
        };
        for (b, &s) in segments.iter().enumerate() {
            counts.drawn[b] = words[b];
            counts.segments[b] = s;
        }
        counts
    }

    /// The drawn counts of further `classes` (name, first bucket, buckets) from the scan's words.
    pub fn with_classes(mut self, words: &[u32], classes: &[(&'static str, u32, u32)]) -> Self {
        for (count, &(name, first, buckets)) in self.classes.iter_mut().zip(classes) {
            let drawn = words[first as usize..(first + buckets) as usize].iter().sum();
            *count = ClassCount { name, drawn };
        }
        self
    }

    /// Blades drawn, all buckets.
    pub fn blades_drawn(&self) -> u64 {
        self.drawn.iter().map(|&d| u64::from(d)).sum()
    }

    /// Entries drawn: the blades and every further class's.
    pub fn total_drawn(&self) -> u64 {
        self.blades_drawn() + self.classes.iter().map(|c| u64::from(c.drawn)).sum::<u64>()
    }

    /// The further classes drawn, for the summary line: empty with none.
    fn class_list(&self) -> String {
        self.classes.iter().filter(|c| !c.name.is_empty()).map(|c| format!("; {} {} drawn", c.drawn, c.name)).collect()
    }

    /// The fraction of the kept blades the visible list's capacity let through: exactly 1 when
    /// they all fit, else the scale each bucket was thinned by (`scale` / 2^32).
    pub fn capacity_scale(&self) -> f64 {
        if self.scale == SCALE_ONE {
            1.0
        } else {
            f64::from(self.scale) / 4_294_967_296.0
        }
    }

    /// What the cull could not keep, for the summary line: empty when nothing was dropped.
    fn drops(&self) -> String {
        let mut text = String::new();
        if self.scale != SCALE_ONE {
            text += &format!(
                "; thinned to {} of {} (visible list full, scale {:.4})",
                self.total_drawn(),
                self.wanted,
                self.capacity_scale()
            );
        }
        if self.tile_draws > 0 {
            text += &format!("; {} draws (a row per visible tile and bucket)", self.tile_draws);
        }
        if self.no_room > 0 {
            text += &format!("; {} candidates not tested (verdict buffer full)", self.no_room);
        }
        text
    }

    /// One line: the blades after each test, drawn per bucket, tiles.
    pub fn summary(&self) -> String {
        let buckets: Vec<String> = (0..MAX_LOD_BUCKETS)
            .filter(|&b| self.segments[b] > 0)
            .map(|b| format!("{} x {} seg", self.drawn[b], self.segments[b]))
            .collect();
        format!(
            "{} considered, {} in visible tiles ({} of {}), {} after density, {} in frustum, {} not edge-on, {} not occluded; drawn {} ({}), {} triangles{}{}",
            self.considered,
            self.after_tiles,
            self.tiles_visible,
            self.tiles,
            self.after_density,
            self.after_frustum,
            self.after_orientation,
            self.after_occlusion,
            self.blades_drawn(),
            buckets.join(", "),
            self.triangles(),
            self.class_list(),
            self.drops()
        )
    }

    /// Blade triangles drawn (`bezier::BladeMesh::triangles` per blade).
    pub fn triangles(&self) -> u64 {
        let per_blade = |segments| u64::from(BladeMesh { segments, collapsed_tip: self.collapsed_tip }.triangles());
        self.drawn.iter().zip(self.segments).filter(|(_, s)| *s > 0).map(|(&d, s)| u64::from(d) * per_blade(s)).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_far_field_begins_where_the_survivors_reach_the_widening_cap() {
        for (d0, cap) in [(5.5, 12.0), (2.0, 6.0), (8.0, 24.0)] {
            let d = far_field_distance(d0, cap);
            let keep = 1.0 / (A1 + A1 * (d * d) / (d0 * d0));
            let widening = 1.0 / (keep * (1.0 - 0.5 * FADE_BAND));
            assert!((widening - cap).abs() < 1e-3 * cap, "d0 {d0}, cap {cap}: {d} m, widening {widening}");
        }
        assert!((far_field_distance(FULL_DENSITY_DISTANCE, blades::MAX_WIDENING) - 34.7).abs() < 0.05);
    }

    #[test]
    fn the_summary_says_when_the_visible_list_thinned_the_field() {
        let mut counts = CullCounts { wanted: 10, scale: SCALE_ONE, ..CullCounts::default() };
        counts.drawn[0] = 10;
        counts.segments[0] = 4;
        assert_eq!(counts.capacity_scale(), 1.0);
        assert!(!counts.summary().contains("thinned") && !counts.summary().contains("not tested"));
        counts.scale = 1 << 31;
        counts.drawn[0] = 5;
        assert_eq!(counts.capacity_scale(), 0.5);
        assert!(
            counts.summary().ends_with("; thinned to 5 of 10 (visible list full, scale 0.5000)"),
            "{}",
            counts.summary()
        );
        counts.no_room = 7;
        assert!(counts.summary().ends_with("; 7 candidates not tested (verdict buffer full)"), "{}", counts.summary());
    }

    #[test]
    fn lod_segments_are_checked() {
        assert!(LodSegments::new(&[]).is_err());
        assert!(LodSegments::new(&[0]).is_err());
        assert!(LodSegments::new(&[17]).is_err());
        assert!(LodSegments::new(&[2, 4]).is_err());
        assert!(LodSegments::new(&[4, 4]).is_err());
        assert_eq!(LodSegments::new(&[8, 4, 2, 1]).map(|l| l.packed()), Ok(0x0137));
        assert_eq!(LodSegments::halving(8).counts(), &[8, 4, 2, 1]);
        assert_eq!(LodSegments::halving(6).counts(), &[6, 3, 1]);
        assert_eq!(LodSegments::halving(7).counts(), &[7, 1]);
        assert_eq!(LodSegments::halving(12).counts(), &[12, 6, 3, 1]);
        assert_eq!(LodSegments::halving(1).counts(), &[1]);
    }
}
