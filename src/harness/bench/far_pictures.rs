//! The far field's picture figures of `meadow bench --preset far` (issue #37), from the landscape
//! camera at the bench's size, static blades at t = 0, over the 8 × 8 blocks of the rows where
//! the flat ground ahead lies in the band (from its start to the blade range):
//!
//! - **in the band**: the far field (blades to 150 m, then plants to 500 m) against the blades
//!   alone to 500 m (a block field's farthest), 8 × 8 mean and 99th-percentile block;
//! - **past the band**: the same pictures over the rows from the blade range to `PAST_M`, where
//!   the far field stands alone (the blades alone to 500 m are what it stands for);
//! - **no seam**: the far field with its boundary moved 20 % nearer (blades to 120 m) against
//!   the same at 150 m, over both bands' rows;
//! - **no flicker**: a creep of `CREEP_M` a frame for `CREEP_FRAMES` frames towards the band,
//!   time fixed, after `PREROLL` unrecorded frames (the band's eye then trails the camera on its
//!   leash throughout): the mean frame-to-frame change of the band's 8 × 8-filtered picture, the
//!   far field's over the blades alone's.
//!
//! Each for the dither (`--fade dither`, the default) and again blended (`--fade blend`).

use std::sync::Arc;

use ash::vk;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::imagediff::box_filtered_difference;
use crate::render::animation::{AnimationSettings, Mode};
use crate::render::culling::Culling;
use crate::render::far_field::{FarFade, FarField};
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::camera::{rows_below_horizon, FOV_Y_DEG};
use crate::scene::{Camera, Scene};
use crate::vk::Device;

/// How far the far field reaches in these figures (m): a block field's blades reach 504 m.
pub const REACH_M: f32 = 500.0;
/// How far the figure past the band reaches (m): short of the far field's end, whose last tenth
/// fades into the haze.
pub const PAST_M: f32 = 400.0;
/// The creep a frame (m) and its frames.
pub const CREEP_M: f32 = 0.05;
pub const CREEP_FRAMES: u32 = 20;
/// Frames the creep runs before its first recorded one: 0.8 m, past the band's leash (0.6 m at
/// the default 150 m of blades).
pub const PREROLL: u32 = 16;

/// The picture figures, in % of full scale.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FarPictures {
    /// Rows of the band (first, last) at the bench's size.
    pub band_rows: [u32; 2],
    /// The far field against the blades alone, 8 × 8 mean and p99.
    pub band_mean: f64,
    pub band_p99: f64,
    /// The boundary moved by 20 %, 8 × 8 mean and p99.
    pub seam_mean: f64,
    pub seam_p99: f64,
    /// Rows past the band (first, last), and the far field against the blades alone over them,
    /// 8 × 8 mean and p99.
    pub past_rows: [u32; 2],
    pub past_mean: f64,
    pub past_p99: f64,
    /// The mean frame-to-frame change over the creep past the band (its rows cross the rings'
    /// edges at 170 and 340 m): the far field's, the blades alone's.
    pub past_flicker_far: f64,
    pub past_flicker_blades: f64,
    /// The mean frame-to-frame change over the creep: the far field's, the blades alone's.
    pub flicker_far: f64,
    pub flicker_blades: f64,
    /// The far field's figures blended (`--fade blend`).
    pub blend: FadeFigures,
}

/// The far field's own figures for one fade, in % of full scale (as `FarPictures`').
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FadeFigures {
    pub band_mean: f64,
    pub band_p99: f64,
    pub seam_mean: f64,
    pub seam_p99: f64,
    pub past_mean: f64,
    pub past_p99: f64,
    pub past_flicker_far: f64,
    pub flicker_far: f64,
}

/// The row of flat ground `distance` m ahead from `camera` in a picture `rows` high.
fn row_at(camera: &Camera, height: f32, distance: f32, rows: u32) -> f32 {
    let focal = 0.5 * rows as f32 / (0.5 * FOV_Y_DEG.to_radians()).tan();
    let horizon = 0.5 * rows as f32 - focal * (-camera.pitch_deg).to_radians().tan();
    horizon + rows_below_horizon(height, camera.pitch_deg, distance, rows)
}

/// The rows of whole blocks of 8 between `rows[0]` and `rows[1]` (none at a small size).
fn whole_blocks(rows: [u32; 2]) -> u32 {
    (rows[1] + 1).saturating_sub(rows[0]) / 8 * 8
}

/// Rows `rows` (whole blocks of 8 inside them) of an RGBA picture `width` wide, as RGB.
fn band(pixels: &[u8], width: u32, rows: [u32; 2]) -> Vec<u8> {
    let (first, last) = (rows[0], rows[0] + whole_blocks(rows));
    let line = 4 * width as usize;
    pixels[first as usize * line..last as usize * line].chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// Rows `r` of a crop of rows `span` (each as `band` keeps them) of a picture `width` wide.
fn sliced(crop: &[u8], width: u32, span: [u32; 2], r: [u32; 2]) -> &[u8] {
    let line = 3 * width as usize;
    let start = (r[0] - span[0]) as usize * line;
    &crop[start..start + whole_blocks(r) as usize * line]
}

/// A figure's renderer: blades to `blades` m, then `far_field` to `REACH_M` under `fog`.
fn settings(blades: f32, far_field: FarField, far_fade: FarFade, fog: f32) -> RenderSettings {
    let (view_distance, blade_distance) = (REACH_M, blades);
    let culling = Culling { view_distance, blade_distance, far_field, far_fade, ..Culling::default_for(4) };
    RenderSettings { fog_density: fog, ..RenderSettings::offscreen(4, culling) }
}

impl FarPictures {
    /// The figures of the band's and the past rows (`rows`), the dither's and the blend's, and
    /// the blades' own change over the creep in either.
    fn of(rows: [[u32; 2]; 2], dither: FadeFigures, blend: FadeFigures, flicker_blades: [f64; 2]) -> Self {
        Self {
            band_rows: rows[0],
            band_mean: dither.band_mean,
            band_p99: dither.band_p99,
            seam_mean: dither.seam_mean,
            seam_p99: dither.seam_p99,
            past_rows: rows[1],
            past_mean: dither.past_mean,
            past_p99: dither.past_p99,
            past_flicker_far: dither.past_flicker_far,
            past_flicker_blades: flicker_blades[1],
            flicker_far: dither.flicker_far,
            flicker_blades: flicker_blades[0],
            blend,
        }
    }
}

/// Measure the figures for `scene` from `camera`, `height` m above the ground, at `size`.
pub fn measure(
    device: &Arc<Device>,
    scene: &Scene,
    (camera, height): (Camera, f32),
    size: (u32, u32),
    fog: f32,
) -> Result<FarPictures> {
    let extent = vk::Extent2D { width: size.0, height: size.1 };
    let mut target = OffscreenTarget::new(device, extent)?;
    let result = (|| {
        let settings = |blades: f32, far_field: FarField, far_fade: FarFade| settings(blades, far_field, far_fade, fog);
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        // Pictures of `frames` frames creeping from `camera`, each its band's rows. A creep of more
        // than one frame starts `PREROLL` frames earlier, unrecorded, so that the band's eye trails
        // the camera on its leash (`far_rings::BandEye`) through every recorded frame.
        let mut frames = |settings: RenderSettings, frames: u32, rows: [u32; 2]| -> Result<Vec<Vec<u8>>> {
            let mut renderer = Renderer::new(device.clone(), scene, settings, animation.clone())?;
            let forward = glam::Vec3::new(0.0, 0.0, -1.0);
            let first = if frames > 1 { -(PREROLL as i32) } else { 0 };
            let mut pictures = Vec::new();
            for f in first..frames as i32 {
                let at = Camera { position: camera.position + forward * (CREEP_M * f as f32), ..camera };
                renderer.render_offscreen(&mut target, &at, 0.0)?;
                if f >= 0 {
                    pictures.push(band(target.pixels(), size.0, rows));
                }
            }
            Ok(pictures)
        };
        let rows_of = |near: f32, far: f32| {
            [row_at(&camera, height, far, size.1).ceil() as u32, row_at(&camera, height, near, size.1).floor() as u32]
        };
        let range = Culling::default_for(4).blade_range();
        let rows = rows_of(crate::render::far_field::BAND_START * range, range);
        let past = rows_of(range, PAST_M);
        // The creeps keep the rows past the band and the band's: `slice` takes either out.
        let span = [past[0].min(rows[0]), past[1].max(rows[1])];
        let slice = |picture: &[u8], r: [u32; 2]| sliced(picture, size.0, span, r).to_vec();
        let diff = |a: &[u8], b: &[u8], r: [u32; 2]| {
            box_filtered_difference(&slice(a, r), &slice(b, r), size.0, whole_blocks(r), 8)
        };
        let change = |pictures: &[Vec<u8>], r: [u32; 2]| {
            pictures.windows(2).map(|w| diff(&w[1], &w[0], r).mean_percent).sum::<f64>() / (pictures.len() - 1) as f64
        };
        let blades = frames(settings(REACH_M, FarField::Off, FarFade::Dither), CREEP_FRAMES, span)?;
        let blades_past = frames(settings(REACH_M, FarField::Off, FarFade::Dither), 1, past)?;
        let both = rows_of(0.8 * crate::render::far_field::BAND_START * range, range);
        let mut figures = |fade: FarFade| -> Result<FadeFigures> {
            let far = frames(settings(range, FarField::Billboards, fade), CREEP_FRAMES, span)?;
            let in_band = diff(&far[0], &blades[0], rows);
            let moved = frames(settings(0.8 * range, FarField::Billboards, fade), 1, both)?;
            let here = frames(settings(range, FarField::Billboards, fade), 1, both)?;
            let seam = box_filtered_difference(&moved[0], &here[0], size.0, whole_blocks(both), 8);
            let alone = frames(settings(range, FarField::Billboards, fade), 1, past)?;
            let beyond = box_filtered_difference(&alone[0], &blades_past[0], size.0, whole_blocks(past), 8);
            Ok(FadeFigures {
                band_mean: in_band.mean_percent,
                band_p99: in_band.p99_percent,
                seam_mean: seam.mean_percent,
                seam_p99: seam.p99_percent,
                past_mean: beyond.mean_percent,
                past_p99: beyond.p99_percent,
                past_flicker_far: change(&far, past),
                flicker_far: change(&far, rows),
            })
        };
        let dither = figures(FarFade::Dither)?;
        let blend = figures(FarFade::Blend)?;
        Ok(FarPictures::of([rows, past], dither, blend, [change(&blades, rows), change(&blades, past)]))
    })();
    // SAFETY: every renderer waited for its frames and is dropped.
    unsafe { target.destroy(device) };
    result
}
