//! The cull and LOD flags shared by `render`, `view` and `timing`, and their conversion into
//! [`Culling`].

use clap::{Args, ValueEnum};

use crate::app::values;
use crate::render::culling::{Culling, LodSegments, DEFAULT_BLADE_DISTANCE};
use crate::render::far_field::{FarFade, FarField};

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum CullTest {
    /// Tiles and blades outside the frustum.
    Frustum,
    /// Tiles and blades beyond --view-distance.
    Distance,
    /// Blades seen edge-on.
    Orientation,
    /// Tiles and blades behind the terrain of the frame (a depth pyramid of its depth).
    Occlusion,
    /// No test: every tile and blade goes on to the LOD.
    None,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum LodKind {
    /// Belyaev's smooth density F(z, φ): far tiles keep a thinning of their blades, widened.
    Density,
    /// Segment buckets (--lod-segments) by projected height.
    Segments,
    /// The blade outline as geometry instead of an alpha test (early depth rejects overdraw).
    Outline,
    /// Every kept blade at --segments.
    None,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum FarFieldArg {
    /// Zhang Xia's billboards: six half-planes round a vertical axis (§4.1).
    Billboards,
    /// Pelzer's stars: three crossed quads (§7.3).
    Stars,
    /// None: the grass ends at the blade distance.
    Off,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum FadeArg {
    /// A hashed threshold per plant: opaque, in any order.
    Dither,
    /// The far field alpha-blended far to near into a linear RGBA16F scene, resolved as --msaa is.
    Blend,
}

#[derive(Args)]
pub(crate) struct CullArgs {
    /// Draw every stored blade at --segments in one instanced draw: no cull pass, no LOD (the
    /// reference, and the thesis benchmark's path).
    #[arg(long)]
    pub(crate) brute_force: bool,
    /// Cull tests, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "frustum,distance,orientation,occlusion")]
    pub(crate) cull: Vec<CullTest>,
    /// Levels of detail, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "density,segments,outline")]
    pub(crate) lod: Vec<LodKind>,
    /// Segments of the LOD buckets, decreasing, the first at most --segments (default: the
    /// halvings of --segments down to 1 that divide it: 8,4,2,1; 6,3,1; 7,1).
    #[arg(long, value_name = "N,N,…", value_parser = values::lod_segments)]
    pub(crate) lod_segments: Option<LodSegments>,
    /// Nothing beyond this many metres is drawn: the ground's extent (at most 10 000 m; default
    /// 150, and 2000 for the landscape `render` and `view` draw with no scene flag).
    #[arg(long, value_name = "M", value_parser = values::view_distance, allow_hyphen_values = true)]
    pub(crate) view_distance: Option<f32>,
    /// Blades are drawn out to this many metres (default 150, or the view distance when it is
    /// shorter; at most the view distance): it sizes a block field's rings of blade cells.
    #[arg(long, value_name = "M", value_parser = values::positive_f32, allow_hyphen_values = true)]
    pub(crate) blade_distance: Option<f32>,
    /// The plants past the blades, out to --view-distance (a --field's): textured from an atlas
    /// of meadow's own blades, leaning in the same wind.
    #[arg(long, value_enum, default_value = "billboards")]
    pub(crate) far_field: FarFieldArg,
    /// How the far field meets the blades across the band where the blades thin out.
    #[arg(long, value_enum, default_value = "dither")]
    pub(crate) fade: FadeArg,
    /// Hold the GPU frame near this many milliseconds by adjusting the LOD scale each frame from
    /// the measured GPU time (a closed loop; needs the GPU-driven path).
    #[arg(long, value_name = "MS", value_parser = values::positive_f32, allow_hyphen_values = true)]
    pub(crate) budget_ms: Option<f32>,
    /// Detail of the LOD: above 1 keeps more blades and segments, below 1 fewer.
    #[arg(long, default_value = "1", value_parser = values::positive_f32, allow_hyphen_values = true)]
    pub(crate) lod_scale: f32,
}

impl CullArgs {
    /// The cull of these flags; `landscape`: the command line draws the default landscape.
    pub(crate) fn culling(&self, segments: u32, landscape: bool) -> Culling {
        let tests = |t: CullTest| self.cull.contains(&t);
        let lod = |l: LodKind| self.lod.contains(&l);
        Culling {
            enabled: !self.brute_force,
            frustum: tests(CullTest::Frustum),
            distance: tests(CullTest::Distance),
            orientation: tests(CullTest::Orientation),
            occlusion: tests(CullTest::Occlusion),
            density: lod(LodKind::Density),
            segment_lod: lod(LodKind::Segments),
            solid_outline: lod(LodKind::Outline),
            lod_segments: self.lod_segments.unwrap_or_else(|| LodSegments::halving(segments)),
            view_distance: super::default_scene::view_distance(self.view_distance, landscape),
            blade_distance: self.blade_distance.unwrap_or(DEFAULT_BLADE_DISTANCE),
            far_field: match self.far_field {
                FarFieldArg::Billboards => FarField::Billboards,
                FarFieldArg::Stars => FarField::Stars,
                FarFieldArg::Off => FarField::Off,
            },
            far_fade: match self.fade {
                FadeArg::Dither => FarFade::Dither,
                FadeArg::Blend => FarFade::Blend,
            },
            band_leash: crate::render::far_rings::BAND_LEASH,
            lod_scale: self.lod_scale,
            // A row per tile only where the animation needs it (`--animation sine-cluster`,
            // `Mode::draw_rows`).
            rows: crate::render::draw_rows::DrawRows::PerBucket,
            // A heightmap's cells are always bounded by its pyramid from the command line.
            ground_bounds: true,
        }
    }
}

/// Refuse a `--blade-distance` over the view distance of the same command line (typed, or the
/// scene's default; one line, before any work): blades stand on the ground, which ends at the
/// view distance.
pub(crate) fn check_distances(matches: &clap::ArgMatches) -> Result<(), String> {
    let Some((name, sub)) = matches.subcommand() else {
        return Ok(());
    };
    let has = |id: &str| sub.try_contains_id(id).unwrap_or(false);
    let Some(&blades) = sub.try_get_one::<f32>("blade_distance").ok().flatten() else {
        return Ok(());
    };
    let typed = if has("view_distance") { sub.get_one::<f32>("view_distance").copied() } else { None };
    let view = super::default_scene::view_distance(typed, super::default_scene::draws_landscape(name, sub));
    match typed {
        Some(view) if blades > view => {
            Err(format!("--blade-distance {blades} is over --view-distance {view}: blades end where the ground does"))
        }
        None if blades > view => Err(format!(
            "--blade-distance {blades} is over the view distance, {view} m by default: blades end where the ground does (give --view-distance)"
        )),
        _ => Ok(()),
    }
}
