//! What `render` and `view` draw when no flag names a scene: the landscape (issue #37, item 6),
//! an unbounded field from the landscape camera with blades to 150 m and the far field to
//! `LANDSCAPE_VIEW_DISTANCE`. `--blades`, `--brute-force`, `--mode floor`, `--submission` and
//! `--debug-view bounds` keep the stored field of 100 000 blades (the reference paths and the
//! fixed cluster grid have no block field), and `timing` always draws stored blades unless given
//! `--field`, so its figures compare with the runs before.
//!
//! One decision, [`draws_landscape`], read from the parsed command line: the scene flags take it
//! (`SceneArgs::landscape`), and so do the rules of which flags have an effect (`effect`) and the
//! check of the blade distance against the view distance.

use clap::parser::ValueSource;
use clap::ArgMatches;

use super::animation::{DebugViewArg, ModeArg};

use crate::render::culling::{DEFAULT_VIEW_DISTANCE, LANDSCAPE_VIEW_DISTANCE};

/// Whether subcommand `command`, parsed as `m`, draws the landscape: `render` or `view` with none
/// of `--blades`, `--field`, `--brute-force`, `--mode floor`, `--submission` and `--debug-view
/// bounds` typed.
pub(crate) fn draws_landscape(command: &str, m: &ArgMatches) -> bool {
    let typed =
        |id: &str| m.try_contains_id(id).unwrap_or(false) && m.value_source(id) == Some(ValueSource::CommandLine);
    let brute_force = m.try_get_one::<bool>("brute_force").ok().flatten().copied().unwrap_or(false);
    let floor = m.try_get_one::<ModeArg>("mode").ok().flatten() == Some(&ModeArg::Floor);
    let bounds = m.try_get_one::<DebugViewArg>("debug_view").ok().flatten() == Some(&DebugViewArg::Bounds);
    matches!(command, "render" | "view")
        && !typed("blades")
        && !typed("field")
        && !typed("submission")
        && !brute_force
        && !floor
        && !bounds
}

/// The view distance of a scene: `--view-distance` if typed, else the landscape's or the default.
pub(crate) fn view_distance(typed: Option<f32>, landscape: bool) -> f32 {
    typed.unwrap_or(if landscape { LANDSCAPE_VIEW_DISTANCE } else { DEFAULT_VIEW_DISTANCE })
}
