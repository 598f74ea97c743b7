//! `meadow bench --preset far`: issue #37's cost side by side in one run (`pairs`). Renderers of
//! the default unbounded field (400 blades/m², the gentle relief) render in turn from the landscape
//! camera under one light fog (`FOG`, at 1 km a surface keeps 37 % of its colour), in pairs
//! against the blades alone to their 150 m (the ground to 150 m too):
//!
//! - **the landscape to 2 km with billboards** (the blades to 150 m, then the far field). Target:
//!   ≤ 1.10×.
//! - **the same with stars**. Target: ≤ 1.10×.
//! - **the same with billboards blended** (`--fade blend`: the ordered placement, the blended
//!   draw, the linear scene and its resolve). Target: ≤ 1.10×.
//! - **the ground to 2 km and no far field**: what the longer ground costs alone (no target of the
//!   issue; 1.10× as the others').
//!
//! Then the picture figures (`far_pictures`): the band against the blades alone, the boundary
//! moved, a creep. `far.json` holds every variant's GPU times, each pair's ratio and picture
//! difference and the figures; `table` prints them.

use std::path::Path;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::harness::bench::far_pictures;
use crate::harness::bench::pairs::{self, Pair, PairBenchOptions, PairSpec};
use crate::harness::document::{to_json, Header};
use crate::harness::measure::Schedule;
use crate::render::culling::Culling;
use crate::render::far_field::{FarFade, FarField};
use crate::render::RenderSettings;
use crate::scene::field::FieldSpec;
use crate::scene::{CameraChoice, Scene};
use crate::vk::Device;

/// The files of a run.
pub const FILES: [&str; 1] = ["far.json"];
/// The fog's density (1/m): the default's.
pub const FOG: f32 = crate::render::frame::look::FOG_DENSITY;
/// The landscape's view distance (m): the default landscape's.
pub const LANDSCAPE_M: f32 = crate::render::culling::LANDSCAPE_VIEW_DISTANCE;
/// The seed of the field.
pub const SEED: u64 = 1;

/// A `far.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FarDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// Rounds discarded, rounds measured.
    pub warmup: u32,
    pub frames: u32,
    /// The pairs, in order.
    pub pairs: Vec<Pair>,
    /// The picture figures (`far_pictures`).
    pub pictures: far_pictures::FarPictures,
}

/// The pairs' (label, reference name, subject name, target).
const PAIRS: [PairSpec; 4] = [
    ("landscape to 2 km, billboards / blades alone to 150 m", "blades to 150 m", "billboards to 2 km", 1.10),
    ("landscape to 2 km, stars / blades alone to 150 m", "blades to 150 m", "stars to 2 km", 1.10),
    (
        "landscape to 2 km, billboards blended / blades alone to 150 m",
        "blades to 150 m",
        "billboards blended to 2 km",
        1.10,
    ),
    ("ground to 2 km, no far field / blades alone to 150 m", "blades to 150 m", "ground to 2 km", 1.10),
];

/// Each variant's settings, in `PAIRS`' order.
fn settings() -> Vec<RenderSettings> {
    let base = pairs::default_settings();
    let with = |view_distance: f32, far_field: FarField, far_fade: FarFade| RenderSettings {
        culling: Culling { view_distance, far_field, far_fade, ..base.culling },
        fog_density: FOG,
        ..base
    };
    let alone = with(crate::render::culling::DEFAULT_VIEW_DISTANCE, FarField::Off, FarFade::Dither);
    let landscape = |far_field: FarField, fade: FarFade| with(LANDSCAPE_M, far_field, fade);
    vec![
        alone,
        landscape(FarField::Billboards, FarFade::Dither),
        alone,
        landscape(FarField::Stars, FarFade::Dither),
        alone,
        landscape(FarField::Billboards, FarFade::Blend),
        alone,
        landscape(FarField::Off, FarFade::Dither),
    ]
}

/// Run the benchmark; `progress(done, total)` after every frame.
pub fn run(device: &Arc<Device>, options: &PairBenchOptions, progress: impl FnMut(u64, u64)) -> Result<FarDocument> {
    let spec = FieldSpec { size: None, density: crate::scene::blades::DENSITY_PER_M2 };
    let scene = Scene::blocks(spec, SEED);
    let scenes = vec![scene.clone(); 2 * PAIRS.len()];
    let cameras = vec![scene.camera(Some(CameraChoice::Landscape)); scenes.len()];
    let schedule = Schedule { warmup: options.warmup, frames: options.frames };
    let animation = crate::render::animation::AnimationSettings::default();
    let settings = settings();
    let animated = pairs::Animated { settings: &settings, ..pairs::Animated::still(&animation) };
    let pairs = pairs::run(device, (&PAIRS, &scenes, &cameras, animated), options.size, schedule, progress)?;
    let height = crate::scene::camera::LANDSCAPE_HEIGHT;
    let pictures = far_pictures::measure(device, &scene, (cameras[0], height), options.size, FOG)?;
    let (header, warmup, frames) = (Header::new(device, "far", options.size), options.warmup, options.frames);
    Ok(FarDocument { header, warmup, frames, pairs, pictures })
}

/// Write `far.json` into `dir`.
pub fn write(doc: &FarDocument, dir: &Path) -> Result<()> {
    crate::app::write_text(&dir.join(FILES[0]), &to_json(doc))
}

/// The pairs as a text table.
pub fn table(doc: &FarDocument) -> String {
    let head = format!("far field, {} rounds after {} of warm-up\n", doc.frames, doc.warmup);
    let p = &doc.pictures;
    let pictures = format!(
        "band (rows {}-{}), 8x8 mean / p99: far field against blades alone {:.2} % / {:.2} %; boundary moved 20 % {:.2} % / {:.2} %\n\
         past the band (rows {}-{}, to {} m), 8x8 mean / p99: far field against blades alone {:.2} % / {:.2} %; creep {:.3} % against {:.3} % ({:.2}x)\n\
         creep of {} m a frame over {} frames, mean frame-to-frame change: far field {:.3} %, blades alone {:.3} % ({:.2}x)\n\
         blended (--fade blend): band {:.2} % / {:.2} %; boundary moved 20 % {:.2} % / {:.2} %; past the band {:.2} % / {:.2} %, creep {:.3} % ({:.2}x); creep {:.3} % ({:.2}x)\n",
        p.band_rows[0],
        p.band_rows[1],
        p.band_mean,
        p.band_p99,
        p.seam_mean,
        p.seam_p99,
        p.past_rows[0],
        p.past_rows[1],
        far_pictures::PAST_M,
        p.past_mean,
        p.past_p99,
        p.past_flicker_far,
        p.past_flicker_blades,
        p.past_flicker_far / p.past_flicker_blades.max(1e-9),
        far_pictures::CREEP_M,
        far_pictures::CREEP_FRAMES,
        p.flicker_far,
        p.flicker_blades,
        p.flicker_far / p.flicker_blades.max(1e-9),
        p.blend.band_mean,
        p.blend.band_p99,
        p.blend.seam_mean,
        p.blend.seam_p99,
        p.blend.past_mean,
        p.blend.past_p99,
        p.blend.past_flicker_far,
        p.blend.past_flicker_far / p.past_flicker_blades.max(1e-9),
        p.blend.flicker_far,
        p.blend.flicker_far / p.flicker_blades.max(1e-9)
    );
    head + &pairs::table_rows(&doc.pairs) + &pictures
}
