//! The CPU scene: terrain, blades, camera. Built once from a seed, then uploaded to GPU buffers.

pub mod alpha;
pub mod bezier;
pub mod blades;
pub mod camera;
pub mod clumps;
pub mod clusters;
pub mod cover;
pub mod field;
pub mod flowers;
pub mod heightmap;
pub mod rng;
pub mod terrain;
pub mod tiles;

pub use blades::BladeInstance;
pub use camera::{Camera, CameraChoice, OrthographicCamera};
pub use terrain::Terrain;

/// Terrain and blades of one field.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The height field.
    pub terrain: Terrain,
    /// Every blade, tile by tile (`tiles::arrange`).
    pub blades: Vec<BladeInstance>,
    /// The tiles over the field.
    pub tile_grid: tiles::TileGrid,
    /// One record per tile of `tile_grid`, row-major.
    pub tiles: Vec<tiles::BladeTile>,
    /// A block field (`--field`): `blades` is its stored block, placed in every cell around the
    /// camera on the relief; `terrain`, `tile_grid` and `tiles` are a one-cell stand-in the GPU
    /// never draws.
    pub field: Option<Field>,
    /// Where grass grows: a stored field's blades were scattered by it, a block field's cull and
    /// every terrain read it (`cover`).
    pub cover: cover::Cover,
    /// Blades in clumps: a stored field's blades were clumped when scattered, a block field's
    /// are where the GPU places them (`clumps`).
    pub clumps: Option<clumps::Clumps>,
    /// Flowers among the blades (`flowers`): the cull claims some of its candidate blades.
    pub flowers: Option<flowers::Flowers>,
}

/// A block field's size and density and the ground under it.
#[derive(Clone, Debug)]
pub struct Field {
    /// Size and density.
    pub spec: field::FieldSpec,
    /// The ground, evaluated anywhere.
    pub ground: FieldGround,
}

/// What a block field stands on.
#[derive(Clone, Debug)]
pub enum FieldGround {
    /// The procedural relief (`--relief`).
    Relief(field::Relief),
    /// A heightmap (`--heightmap`).
    Heightmap(std::sync::Arc<heightmap::Heightmap>),
}

impl FieldGround {
    /// Height at world (x, z), in f64.
    pub fn height(&self, x: f64, z: f64) -> f64 {
        match self {
            FieldGround::Relief(relief) => relief.height(x, z),
            FieldGround::Heightmap(map) => map.height_at(x, z),
        }
    }

    /// The lowest and highest height the ground can reach.
    pub fn height_range(&self) -> (f32, f32) {
        match self {
            FieldGround::Relief(relief) => (-relief.height_bound(), relief.height_bound()),
            FieldGround::Heightmap(map) => (0.0, map.scale.y as f32),
        }
    }

    /// The steepest slope the ground can have: bounds a cell's heights.
    pub fn slope_bound(&self) -> f32 {
        match self {
            FieldGround::Relief(relief) => relief.slope_bound(),
            FieldGround::Heightmap(map) => map.slope_bound() as f32,
        }
    }

    /// The relief, when the ground is one.
    pub fn relief(&self) -> Option<&field::Relief> {
        match self {
            FieldGround::Relief(relief) => Some(relief),
            FieldGround::Heightmap(_) => None,
        }
    }
}

impl Scene {
    /// Build the field for `blade_count` blades from `seed`.
    pub fn generate(blade_count: u32, seed: u64) -> Self {
        let terrain = Terrain::generate(blades::field_size(blade_count), seed);
        Self::stored_on(terrain, blade_count, seed, (cover::Cover::default(), None))
    }

    /// `blade_count` blades from `seed` scattered over `terrain` where `cover` lets them grow
    /// (`cover::kept` by the density under each), in `clumps` if any, tiled once.
    pub fn stored_on(
        terrain: Terrain,
        blade_count: u32,
        seed: u64,
        (cover, clumps): (cover::Cover, Option<clumps::Clumps>),
    ) -> Self {
        let mut blades = blades::scatter(&terrain, blade_count, seed);
        if cover.active() {
            let mut index = 0;
            blades.retain(|b| {
                let (x, z) = (b.position[0], b.position[2]);
                let normal = terrain.normal_at(x, z);
                let slope = glam::Vec2::new(-normal.x, -normal.z) / normal.y;
                index += 1;
                cover::kept(index - 1, seed, cover.density(f64::from(x), f64::from(z), slope))
            });
        }
        if let Some(clumps) = clumps {
            for blade in &mut blades {
                *blade = clumps.apply(blade, glam::Vec2::new(blade.position[0], blade.position[2])).1;
            }
        }
        let tile_grid = tiles::TileGrid::new(terrain.size);
        let tiles = tiles::arrange(&tile_grid, &mut blades);
        Self { terrain, blades, tile_grid, tiles, field: None, cover, clumps, flowers: None }
    }

    /// A block field of `spec` from `seed` on the gentle relief: its stored block and its relief.
    pub fn blocks(spec: field::FieldSpec, seed: u64) -> Self {
        Self::blocks_on(spec, field::ReliefKind::Gentle, seed)
    }

    /// A block field of `spec` from `seed` on a relief of `relief`.
    pub fn blocks_on(spec: field::FieldSpec, relief: field::ReliefKind, seed: u64) -> Self {
        let mut blades = field::block_blades(&spec, seed);
        let terrain = Terrain::generate(field::BLOCK_SIZE, seed);
        let tile_grid = tiles::TileGrid { origin: 0.0, tile_size: field::BLOCK_SIZE, tiles: 1 };
        let tiles = tiles::arrange(&tile_grid, &mut blades);
        Self {
            terrain,
            blades,
            tile_grid,
            tiles,
            field: Some(Field { spec, ground: FieldGround::Relief(field::Relief::of_kind(relief, seed)) }),
            cover: cover::Cover::default(),
            clumps: None,
            flowers: None,
        }
    }

    /// A block field of `spec` from `seed` on the heightmap `map` (its blades as `blocks_on`'s).
    pub fn blocks_on_map(spec: field::FieldSpec, map: std::sync::Arc<heightmap::Heightmap>, seed: u64) -> Self {
        let mut scene = Self::blocks(spec, seed);
        scene.field = Some(Field { spec, ground: FieldGround::Heightmap(map) });
        scene
    }

    /// `generate`'s field of `blade_count` blades on the heightmap `map`, over its centre: the
    /// stored terrain samples the map (`Terrain::from_heightmap`) and the blades stand on it.
    pub fn generate_on_map(blade_count: u32, map: &heightmap::Heightmap, seed: u64) -> Self {
        let terrain = Terrain::from_heightmap(blades::field_size(blade_count), map);
        Self::stored_on(terrain, blade_count, seed, (cover::Cover::default(), None))
    }

    /// The same scene with `cover`: a stored field's blades scattered again under it, a block
    /// field's cull to thin by it.
    pub fn with_cover(self, cover: cover::Cover, blade_count: u32, seed: u64) -> Self {
        match self.field {
            Some(_) => Self { cover, ..self },
            None => Self::stored_on(self.terrain, blade_count, seed, (cover, self.clumps)),
        }
    }

    /// The same scene with its blades in `clumps` (a stored field already in clumps keeps its
    /// blades: build it with `stored_on` instead): a stored field's clumped now (each blade by
    /// the clump at its root, its tiles arranged again), a block field's by the GPU.
    pub fn with_clumps(mut self, clumps: clumps::Clumps) -> Self {
        if self.field.is_none() && self.clumps.is_none() {
            for blade in &mut self.blades {
                let at = glam::Vec2::new(blade.position[0], blade.position[2]);
                *blade = clumps.apply(blade, at).1;
            }
            // The tiles' bounds and facing ranges from the clumped blades.
            self.tiles = tiles::arrange(&self.tile_grid, &mut self.blades);
        }
        Self { clumps: Some(clumps), ..self }
    }

    /// The same scene with `flowers` among its blades; refused (bad input) when they are denser
    /// than its blades (`flowers::Flowers::share`).
    pub fn with_flowers(self, flowers: flowers::Flowers) -> crate::error::Result<Self> {
        flowers.share(self.blade_density())?;
        Ok(Self { flowers: Some(flowers), ..self })
    }

    /// Blades per m² before any cover: a block field's density, a stored field's scatter's.
    pub fn blade_density(&self) -> f32 {
        self.field.as_ref().map_or(blades::DENSITY_PER_M2, |f| f.spec.density)
    }

    /// The share of candidate blades the flowers claim under full green and grass (0: none).
    pub fn flower_share(&self) -> f32 {
        self.flowers.and_then(|f| f.share(self.blade_density()).ok()).unwrap_or(0.0)
    }

    /// The share of the blades the flowers claim where the cover grows the most flowers for its
    /// grass (`cover::Cover::flower_ratio_bound`), at most 1: the far field's flower tiles are
    /// baked at it, and a far plant takes them where the share there calls for it (0: no flowers).
    pub fn far_flower_share(&self) -> f32 {
        (self.flower_share() * self.cover.flower_ratio_bound()).min(1.0)
    }

    /// The ground's height at world (x, z).
    pub fn ground(&self, x: f32, z: f32) -> f32 {
        match &self.field {
            Some(field) => field.ground.height(f64::from(x), f64::from(z)) as f32,
            None => self.terrain.height_at(x, z),
        }
    }

    /// The default camera: at the stored field's edge looking across it, or in a block field
    /// at the origin looking along -z; 1.7 m above the ground, slightly down.
    pub fn default_camera(&self) -> Camera {
        match &self.field {
            Some(_) => Camera {
                position: glam::Vec3::new(0.0, self.ground(0.0, 0.0) + camera::EYE_HEIGHT, 0.0),
                yaw_deg: 0.0,
                pitch_deg: -12.0,
            },
            None => Camera::default_for(&self.terrain),
        }
    }

    /// The camera `choice` names in this scene: the landscape preset stands
    /// `camera::LANDSCAPE_HEIGHT` above the ground where the default camera stands.
    pub fn camera(&self, choice: Option<CameraChoice>) -> Camera {
        match choice {
            Some(CameraChoice::At(camera)) => camera,
            Some(CameraChoice::Landscape) => {
                let at = self.default_camera().position;
                let y = self.ground(at.x, at.z) + camera::LANDSCAPE_HEIGHT;
                Camera {
                    position: glam::Vec3::new(at.x, y, at.z),
                    pitch_deg: camera::LANDSCAPE_PITCH_DEG,
                    yaw_deg: 0.0,
                }
            }
            None => self.default_camera(),
        }
    }
}
