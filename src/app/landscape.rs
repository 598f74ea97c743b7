//! The ground and its cover from the command line (`--heightmap`, `--terrain-scale`, `--cover`,
//! `--slope-limit`): where the maps lie, loaded with the scene (`RenderOptions::scene`). A bad
//! map or a bad placement is bad input, refused in one line before anything is allocated for it.

use std::path::PathBuf;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::scene::cover::{Cover, CoverMap, MapPlacement};
use crate::scene::field::FieldSpec;
use crate::scene::heightmap::{Heightmap, TerrainScale, DEFAULT_SCALE};

/// The maps and rules of the command line.
#[derive(Clone, Debug, Default)]
pub struct Landscape {
    /// `--heightmap`: the ground from a greyscale PNG.
    pub heightmap: Option<PathBuf>,
    /// `--terrain-scale`: where the maps lie and how high white is.
    pub terrain_scale: Option<TerrainScale>,
    /// `--cover`: the covering map.
    pub cover: Option<PathBuf>,
    /// `--slope-limit`: the steepest slope covered, in degrees.
    pub slope_limit_deg: Option<f32>,
}

impl Landscape {
    /// Where the maps lie over `field` (or stored blades): a bounded field's square, held past
    /// its edges (a `--terrain-scale` must then give X and Z its size); otherwise the scale's
    /// extent repeated mirrored, its period dividing the world's under an unbounded field.
    pub fn scale(&self, field: Option<FieldSpec>) -> Result<(TerrainScale, bool)> {
        let scale = self.terrain_scale.unwrap_or(DEFAULT_SCALE);
        match field {
            Some(FieldSpec { size: Some(size), .. }) => {
                let size = f64::from(size);
                if self.terrain_scale.is_some() && (scale.x != size || scale.z != size) {
                    return Err(Error::bad_input(format!(
                        "--terrain-scale {},{},{} with --field {size}: the maps cover the field's square (give X and Z {size})",
                        scale.x, scale.y, scale.z
                    )));
                }
                Ok((TerrainScale { x: size, z: size, ..scale }, false))
            }
            Some(_) => {
                scale.check_period()?;
                Ok((scale, true))
            }
            None => Ok((scale, true)),
        }
    }

    /// The `--heightmap`, loaded and placed over `field`.
    pub fn heightmap(&self, field: Option<FieldSpec>) -> Result<Option<Heightmap>> {
        let Some(path) = &self.heightmap else {
            return Ok(None);
        };
        let (scale, mirrored) = self.scale(field)?;
        Ok(Some(Heightmap { mirrored, ..Heightmap::load(path, scale)? }))
    }

    /// The cover rules over `field`: the slope limit, and the `--cover` map loaded and placed as
    /// the heightmap is (it needs a `--heightmap` or a `--terrain-scale` to lie over).
    pub fn cover(&self, field: Option<FieldSpec>) -> Result<Cover> {
        let map = match &self.cover {
            None => None,
            Some(_) if self.heightmap.is_none() && self.terrain_scale.is_none() => {
                return Err(Error::bad_input(
                    "--cover needs --heightmap or --terrain-scale: the map is stretched over their extent",
                ))
            }
            Some(path) => {
                let (scale, mirrored) = self.scale(field)?;
                Some(Arc::new(CoverMap::load(path, MapPlacement { x: scale.x, z: scale.z, mirrored })?))
            }
        };
        Ok(Cover { slope_limit_deg: self.slope_limit_deg, map })
    }
}
