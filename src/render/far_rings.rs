//! Where the far field stands (issue #37, `render::far_field` draws it): which plants, how they
//! meet the blades, and the rings of a world lattice whose step doubles per ring (Zhang Xia eq.
//! 8–9) from inside the band where the blades thin out to the view distance. Below the cull's
//! settings (`render::culling::Culling` holds the choice), above nothing of the render layer.

/// Which far plants stand past the blades (`--far-field`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FarField {
    /// Zhang Xia's billboards: six half-planes round a vertical axis (§4.1).
    #[default]
    Billboards,
    /// Pelzer's stars: three crossed quads (§7.3).
    Stars,
    /// No far field: the grass ends at the blade range.
    Off,
}

impl FarField {
    /// Rectangles per plant.
    pub fn rectangles(self) -> u32 {
        match self {
            FarField::Billboards => 6,
            FarField::Stars => 3,
            FarField::Off => 0,
        }
    }

    /// The mesh code the shaders read (`FAR_MESH_*` of `far_field.glsl`).
    pub fn mesh_code(self) -> u32 {
        match self {
            FarField::Stars => 1,
            _ => 0,
        }
    }
}

/// How the far field meets the blades across the band (`--fade`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FarFade {
    /// A hashed threshold per plant and per stretch of a rectangle: opaque, in any order.
    #[default]
    Dither,
    /// Alpha-blended into the linear RGBA16F scene (resolved as `--msaa` is), the plants placed
    /// far to near (Zhang Xia §5.4) and each plant's rectangles far to near.
    Blend,
}

/// How far the band's eye trails the culling camera, as a share of the band's width
/// (`Culling::band_leash`'s default): 0.6 m for the default 150 m of blades.
pub const BAND_LEASH: f32 = 0.02;

/// The point the band is measured from (the hysteresis of `--fade`): the culling camera on a
/// leash. It stays put while the camera moves within the leash of it and trails the camera at the
/// leash's length beyond, so a camera that creeps back and forth by less than the leash crosses no
/// plant's threshold twice, and one that moves on shifts the band with it. State, one point kept
/// by the renderer; a leash of 0 is the stateless band (the camera's own distances).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BandEye {
    at: Option<glam::DVec3>,
}

impl BandEye {
    /// Follow `eye` (world) on a leash of `leash` m; returns where the band's eye now is.
    pub fn follow(&mut self, eye: glam::DVec3, leash: f64) -> glam::DVec3 {
        let at = match self.at {
            Some(at) if at.distance(eye) <= leash => at,
            Some(at) => eye + (at - eye).normalize_or_zero() * leash,
            None => eye,
        };
        self.at = Some(at);
        at
    }

    /// Where it is, if it has followed a camera.
    pub fn at(&self) -> Option<glam::DVec3> {
        self.at
    }
}

/// The band where blades thin out and the far field fades in starts at this share of the blade
/// range and ends at the blade range.
pub const BAND_START: f32 = 0.8;
/// Ring 0 starts at this share of the band's start (Chebyshev): the band's corners, whose
/// Euclidean distance passes the band's start before their Chebyshev one does, have far plants.
pub const RING_START: f32 = std::f32::consts::FRAC_1_SQRT_2;
/// A ring's lattice step is at least this share of its inner distance (eq. 8–9: plants per ring
/// constant), rounded up to whole blocks (so the lattice is O's cells' in integers).
pub const STEP_SHARE: f32 = 0.125;
/// Lattice points per side of a ring's square (its outer half-width is twice its inner: 4 inner
/// distances across, at most `1 / STEP_SHARE` steps each, and two steps of margin either side).
pub const RING_SIDE: u32 = 4 * 8 + 4;
/// Rings at most: from a blade range of 5 m to the 10 km view distance.
pub const MAX_RINGS: u32 = 12;
/// Plants the placement can write at most: every ring's every lattice point.
pub const CAPACITY: u32 = MAX_RINGS * RING_SIDE * RING_SIDE;
/// Where the far field's rings lie, for a blade range and a view distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarRings {
    /// Ring 0's inner Chebyshev distance (m).
    pub start: f32,
    /// Ring 0's lattice step (m): whole blocks.
    pub step: f32,
    /// Rings out to the view distance.
    pub rings: u32,
    /// The band's start (m): blades thin out from here to the blade range.
    pub band_start: f32,
    /// The blade range (m).
    pub blade_range: f32,
    /// The view distance (m).
    pub view_distance: f32,
}

impl FarRings {
    /// How far the band's eye trails the culling camera (m) on a leash of `share` of the band's
    /// width (`BandEye`).
    pub fn leash(&self, share: f32) -> f32 {
        share * (self.blade_range - self.band_start)
    }

    /// The rings for blades out to `blade_range` and the ground out to `view_distance`; `None`
    /// when the ground ends where the blades do.
    pub fn new(blade_range: f32, view_distance: f32) -> Option<Self> {
        if view_distance <= blade_range + 1e-3 {
            return None;
        }
        let band_start = BAND_START * blade_range;
        let start = RING_START * band_start;
        let block = crate::scene::field::BLOCK_SIZE;
        let step = block * (STEP_SHARE * start / block).ceil().max(1.0);
        // The outermost ring's outer edge, in Chebyshev distance, reaches the view distance.
        let rings = ((view_distance / start).log2().ceil().max(1.0) as u32).min(MAX_RINGS);
        Some(Self { start, step, rings, band_start, blade_range, view_distance })
    }

    /// How far `MAX_RINGS` rings reach from a blade range of `blade_range` m: the outermost ring's
    /// outer Chebyshev distance (2 317 times the blade range).
    pub fn reach(blade_range: f32) -> f32 {
        RING_START * BAND_START * blade_range * (1u32 << MAX_RINGS) as f32
    }

    /// Lattice points the placement visits: `RING_SIDE`² per ring.
    pub fn points(&self) -> u32 {
        self.rings * RING_SIDE * RING_SIDE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_band_eye_stays_within_its_leash_and_trails_beyond_it() {
        use glam::DVec3;
        let mut eye = BandEye::default();
        let start = DVec3::new(10.0, 2.0, -5.0);
        assert_eq!(eye.follow(start, 0.5), start, "the first camera is where it starts");
        // Back and forth within the leash: it stays.
        for x in [0.3, -0.2, 0.45, 0.0] {
            assert_eq!(eye.follow(start + DVec3::X * x, 0.5), start);
        }
        // On past the leash: it trails at the leash's length.
        let far = start + DVec3::new(3.0, 0.0, 4.0);
        let at = eye.follow(far, 0.5);
        assert!((at.distance(far) - 0.5).abs() < 1e-12 && at.distance(start) > 4.0, "{at}");
        // A leash of 0 is the camera itself.
        assert_eq!(eye.follow(start, 0.0), start);
    }

    #[test]
    fn rings_keep_their_plants_and_reach_the_view_distance() {
        let rings = FarRings::new(150.0, 10_000.0).expect("a far field");
        assert!((rings.band_start - 120.0).abs() < 1e-3);
        // The step is whole blocks and at least the share of ring 0's start.
        let blocks = rings.step / crate::scene::field::BLOCK_SIZE;
        assert_eq!(blocks.fract(), 0.0);
        assert!(rings.step >= STEP_SHARE * rings.start - 1e-3, "{rings:?}");
        let outer = rings.start * 2f32.powi(rings.rings as i32);
        assert!(outer >= 10_000.0 && outer / 2.0 < 10_000.0, "{rings:?}");
        // A ring's square spans 4 inner distances: RING_SIDE points cover it at ring 0's step
        // (every ring holds the same count at its own step).
        assert!(4.0 * rings.start / rings.step + 2.0 <= RING_SIDE as f32, "{rings:?}");
        assert!(FarRings::new(150.0, 150.0).is_none());
        // The rings' reach: 5 m of blades (the viewer's least) reach past 10 km, 4 m do not.
        assert!(FarRings::reach(5.0) > 10_000.0 && FarRings::reach(4.0) < 10_000.0);
        let short = FarRings::new(4.0, 10_000.0).expect("a far field");
        assert!(short.rings == MAX_RINGS && short.start * 2f32.powi(MAX_RINGS as i32) < 10_000.0);
    }
}
