//! The table of [`RULES`]: every configuration in which some flags have no effect, with the
//! flags, the subcommands, the test of the parsed command line and the reason
//! (`cli::effect` applies it). A new flag, or a new mode that makes some flags moot, adds a row.

use super::Rule;
use crate::cli::animation::{AnimationArg, DebugViewArg, ModeArg};
use crate::cli::args::PresetArg;
use crate::cli::culling::{CullTest, FarFieldArg, LodKind};
use crate::render::submission::Strategy;

/// The subcommands that draw the scene of `SceneArgs`.
pub(super) const SCENE: &[&str] = &["render", "view", "timing"];
/// The scene subcommands with a submission strategy (`SubmissionArgs`).
const SUBMITTED: &[&str] = &["render", "timing"];
/// The keyframe flags: what the keyframe table is and where it is evaluated.
const KEYFRAME_FLAGS: &[&str] = &["poses", "smoothing", "encoding", "packing", "keyframes", "eval"];
/// The keyframe flags and the keyframe table's place (`--mode texture|uniform`), which only
/// `--animation keyframes` has.
const KEYFRAME_AND_MODE_FLAGS: &[&str] = &["mode", "poses", "smoothing", "encoding", "packing", "keyframes", "eval"];
/// The forces on the blades (thesis ch. 4–5) and what they vary with.
const FORCE_FLAGS: &[&str] =
    &["wind", "wind_field", "no_gusts", "source", "calm", "collider", "attenuation", "cluster_size", "time", "dt"];
/// The GPU-driven path's flags: the cull, the LOD and what steers them.
const CULL_FLAGS: &[&str] =
    &["cull", "lod", "lod_segments", "view_distance", "blade_distance", "far_field", "fade", "budget_ms", "lod_scale"];

/// Every case of the rule. Order matters only for which of several violations is reported.
pub(crate) const RULES: &[Rule] = &[
    Rule {
        flags: &["brute_force", "blades_per_instance", "no_alpha_to_coverage"],
        subject: None,
        commands: SCENE,
        with: "--mode floor",
        when: |g| g.mode() == Some(ModeArg::Floor),
        why: "the floor is one draw of pre-expanded static triangles, with no cull",
    },
    Rule {
        flags: &["submission", "clusters"],
        subject: None,
        commands: SUBMITTED,
        with: "--mode floor",
        when: |g| g.mode() == Some(ModeArg::Floor),
        why: "the floor is one draw of pre-expanded static triangles",
    },
    Rule {
        flags: CULL_FLAGS,
        subject: None,
        commands: SCENE,
        with: "--mode floor",
        when: |g| g.mode() == Some(ModeArg::Floor),
        why: "the floor draws every stored blade, with no cull and no LOD",
    },
    Rule {
        flags: KEYFRAME_AND_MODE_FLAGS,
        subject: None,
        commands: SCENE,
        with: "an --animation other than keyframes",
        when: |g| g.animation().is_some_and(|a| a != AnimationArg::Keyframes),
        why: "they choose the keyframe table and where it is evaluated (--animation keyframes)",
    },
    Rule {
        flags: &["stiffness", "damping"],
        subject: None,
        commands: SCENE,
        with: "an --animation other than verlet, inertial or virtual-inertial",
        when: |g| {
            !matches!(g.animation(), Some(AnimationArg::Verlet | AnimationArg::Inertial | AnimationArg::VirtualInertial))
                || matches!(g.mode(), Some(ModeArg::Floor | ModeArg::Static))
        },
        why: "they are the Verlet blades' and the inertial chains' constants",
    },
    Rule {
        flags: &["animation"],
        subject: None,
        commands: SCENE,
        with: "--mode floor or static",
        when: |g| matches!(g.mode(), Some(ModeArg::Floor | ModeArg::Static)),
        why: "--mode floor and --mode static draw neutral blades, with no response (drop --animation)",
    },
    Rule {
        flags: FORCE_FLAGS,
        subject: None,
        commands: SCENE,
        with: "--animation static (without --debug-view force, bounds or wind)",
        when: |g| g.animation() == Some(AnimationArg::Static) && !g.shows_forces(),
        why: "static blades feel no force, and no debug view shows the forces",
    },
    Rule {
        flags: KEYFRAME_FLAGS,
        subject: None,
        commands: SCENE,
        with: "--mode floor",
        when: |g| g.mode() == Some(ModeArg::Floor),
        why: "the floor draws static blades, with no keyframes",
    },
    Rule {
        flags: FORCE_FLAGS,
        subject: None,
        commands: SCENE,
        with: "--mode floor (without --debug-view bounds)",
        when: |g| g.mode() == Some(ModeArg::Floor) && g.debug_view() != Some(DebugViewArg::Bounds),
        why: "the floor's static blades feel no force, and no debug view shows the forces",
    },
    Rule {
        flags: &["debug_view"],
        subject: None,
        commands: SCENE,
        with: "--mode floor",
        when: |g| g.mode() == Some(ModeArg::Floor) && g.debug_view() != Some(DebugViewArg::Bounds),
        why: "the floor's triangles are flat-coloured (only bounds draws over them)",
    },
    Rule {
        flags: KEYFRAME_FLAGS,
        subject: None,
        commands: SCENE,
        with: "--mode static",
        when: |g| g.mode() == Some(ModeArg::Static),
        why: "static blades read no keyframes",
    },
    Rule {
        flags: FORCE_FLAGS,
        subject: None,
        commands: SCENE,
        with: "--mode static (without --debug-view force, bounds or wind)",
        when: |g| g.mode() == Some(ModeArg::Static) && !g.shows_forces(),
        why: "static blades feel no force, and no debug view shows the forces",
    },
    Rule {
        flags: &["packing"],
        subject: None,
        commands: SCENE,
        with: "--mode texture",
        when: |g| g.mode() == Some(ModeArg::Texture),
        why: "the packing is the uniform array's (--mode uniform); the texture has --encoding",
    },
    Rule {
        flags: &["encoding"],
        subject: None,
        commands: SCENE,
        with: "--mode uniform",
        when: |g| g.mode() == Some(ModeArg::Uniform),
        why: "the encoding is the keyframe texture's (--mode texture); the uniform array has --packing",
    },
    Rule {
        flags: &["no_gusts"],
        subject: None,
        commands: SCENE,
        with: "--wind-field perlin",
        when: |g| g.wind_field() == Some(crate::cli::animation::WindFieldArg::Perlin),
        why: "the gusts are the analytic field's; the Perlin field's noise takes the global wind's place",
    },
    Rule {
        flags: &["cut", "recovery_s", "regrow_s"],
        subject: None,
        commands: SCENE,
        with: "blades posed per vertex or neutral (--eval vertex, --brute-force's keyframes, static blades, the floor)",
        when: |g| !g.pose_records(),
        why: "the pressed map bends and cuts the blades' pose records, which those do not write",
    },
    Rule {
        flags: &["recovery_s"],
        subject: None,
        commands: SUBMITTED,
        with: "no --collider",
        when: |g| !g.given("collider"),
        why: "it times how trampled blades recover, and nothing tramples them (the viewer's Shift + click and F7 can)",
    },
    Rule {
        flags: &["regrow_s"],
        subject: None,
        commands: SCENE,
        with: "no --cut",
        when: |g| !g.given("cut"),
        why: "it times how cut blades regrow, and nothing cuts them",
    },
    Rule {
        flags: &["fluid_grid", "fluid_cell"],
        subject: None,
        commands: SCENE,
        with: "a --wind-field other than fluid",
        when: |g| g.wind_field() != Some(crate::cli::animation::WindFieldArg::Fluid),
        why: "it shapes the fluid wind's grid (--wind-field fluid)",
    },
    Rule {
        flags: &["source"],
        subject: Some("--source …,HEIGHT"),
        commands: SCENE,
        with: "a --wind-field other than fluid",
        // Five numbers give the height, seven the motion and the height (`values::source`).
        when: |g| {
            g.wind_field() != Some(crate::cli::animation::WindFieldArg::Fluid)
                && g.raw("source").iter().any(|s| matches!(s.split(',').count(), 5 | 7))
        },
        why: "the height is where the fluid wind injects a source; the analytic and Perlin fields' sources blow at every height",
    },
    Rule {
        flags: &["attenuation"],
        subject: None,
        commands: SCENE,
        with: "--wind-field fluid",
        when: |g| g.wind_field() == Some(crate::cli::animation::WindFieldArg::Fluid),
        why: "the fluid injects the sources into its grid; the analytic field past it attenuates them at the corners",
    },
    Rule {
        flags: &["wind_field"],
        subject: Some("--wind-field fluid"),
        commands: SCENE,
        with: "--brute-force",
        when: |g| g.wind_field() == Some(crate::cli::animation::WindFieldArg::Fluid) && g.flag("brute_force"),
        why: "the fluid is stepped on the GPU with the cull; --brute-force keeps the thesis' CPU corners",
    },
    Rule {
        flags: &["attenuation"],
        subject: None,
        commands: SCENE,
        with: "no --source",
        when: |g| !g.given("source"),
        why: "it places the attenuation of point sources (thesis 4.5)",
    },
    Rule {
        flags: CULL_FLAGS,
        subject: None,
        commands: SCENE,
        with: "--brute-force",
        when: |g| g.flag("brute_force"),
        why: "it draws every stored blade at --segments in one instanced draw, with no cull and no LOD",
    },
    Rule {
        flags: &["cull"],
        subject: Some("--cull none"),
        commands: SCENE,
        with: "other tests",
        when: |g| g.cull().contains(&CullTest::None) && g.cull().len() > 1,
        why: "the other tests run: give none alone, or the tests alone",
    },
    Rule {
        flags: &["lod"],
        subject: Some("--lod none"),
        commands: SCENE,
        with: "other levels of detail",
        when: |g| g.lod().contains(&LodKind::None) && g.lod().len() > 1,
        why: "the other levels run: give none alone, or the levels alone",
    },
    Rule {
        flags: &["lod_scale", "budget_ms"],
        subject: None,
        commands: SCENE,
        with: "a --lod without density or segments",
        when: |g| !g.lod().iter().any(|l| matches!(l, LodKind::Density | LodKind::Segments)),
        why: "the LOD scale scales the density and segment LOD's distances",
    },
    Rule {
        flags: &["lod_segments"],
        subject: None,
        commands: SCENE,
        with: "a --lod without segments",
        when: |g| !g.lod().contains(&LodKind::Segments),
        why: "they are the segment LOD's buckets",
    },
    Rule {
        flags: &["view_distance", "blade_distance"],
        subject: None,
        commands: SCENE,
        with: "a --cull without distance on stored blades",
        when: |g| !g.cull().contains(&CullTest::Distance) && g.stored(),
        why: "only the distance test reads it (a --field also sizes its ground and its blocks' rings by them)",
    },
    Rule {
        flags: &["view_distance"],
        subject: None,
        commands: SCENE,
        with: "--blade-distance on stored blades",
        when: |g| g.given("blade_distance") && g.stored(),
        why: "the stored terrain is drawn whole, and the blades end at --blade-distance",
    },
    Rule {
        flags: &["far_field", "fade"],
        subject: None,
        commands: SCENE,
        with: "stored blades or no ground past the blades",
        when: |g| g.stored() || (!g.ground_past_blades() && g.one::<FarFieldArg>("far_field") != Some(FarFieldArg::Off)),
        why: "the far field stands past a --field's blades, on its ground out to a longer --view-distance",
    },
    Rule {
        flags: &["fade"],
        subject: None,
        commands: SCENE,
        with: "--far-field off",
        when: |g| g.one::<FarFieldArg>("far_field") == Some(FarFieldArg::Off),
        why: "the fade is where the blades meet the far field",
    },
    Rule {
        flags: &["no_alpha_to_coverage"],
        subject: None,
        commands: SCENE,
        with: "--msaa 1",
        when: |g| g.one::<u32>("msaa") == Some(1),
        why: "alpha to coverage needs samples: add --msaa 4",
    },
    Rule {
        flags: &["no_alpha_to_coverage"],
        subject: None,
        commands: SCENE,
        with: "the outline LOD (--lod with outline, the default)",
        when: |g| !g.flag("brute_force") && g.lod().contains(&LodKind::Outline),
        why: "the culled blades' outline is geometry, with no alpha to turn into coverage: add --brute-force or leave outline out of --lod",
    },
    Rule {
        flags: &["clusters"],
        subject: None,
        commands: SUBMITTED,
        with: "--submission instanced or prerecorded",
        when: |g| g.one::<Strategy>("submission").is_some_and(|s| !uses_clusters(s)),
        why: "these submissions draw the blades in one draw",
    },
    Rule {
        flags: &["density"],
        subject: None,
        commands: SCENE,
        with: "stored blades (no --field)",
        when: |g| g.stored(),
        why: "it is the blades per m² of a --field's blocks; stored blades are --blades",
    },
    Rule {
        flags: &["relief"],
        subject: None,
        commands: SCENE,
        with: "--heightmap",
        when: |g| g.given("heightmap"),
        why: "the ground is the heightmap",
    },
    Rule {
        flags: &["terrain_scale"],
        subject: None,
        commands: SCENE,
        with: "neither --heightmap nor --cover",
        when: |g| !g.given("heightmap") && !g.given("cover"),
        why: "it places a --heightmap or a --cover map",
    },
    Rule {
        flags: &["relief"],
        subject: None,
        commands: SCENE,
        with: "stored blades (no --field)",
        when: |g| g.stored(),
        why: "it is the relief under a --field's blocks; stored blades lie on their stored terrain",
    },
    Rule {
        flags: &["screenshot_ui"],
        subject: None,
        commands: &["view"],
        with: "no --screenshot and no --script (whose screenshots it also chooses)",
        when: |g| !g.given("screenshot") && !g.given("script"),
        why: "it chooses what the screenshot shows",
    },
    Rule {
        flags: &["capture_dir"],
        subject: None,
        commands: &["view"],
        with: "--no-ui",
        when: |g| g.flag("no_ui"),
        why: "the capture button is on the overlay",
    },
    Rule {
        flags: &[
            "preset",
            "blades",
            "segments",
            "modes",
            "eval",
            "size",
            "warmup",
            "frames",
            "out",
            "validation",
            "device",
        ],
        subject: None,
        commands: &["bench"],
        with: "--compare",
        when: |g| g.given("compare"),
        why: "it compares two bench.json files, measuring nothing and writing nothing",
    },
    Rule {
        flags: &["threshold"],
        subject: None,
        commands: &["bench"],
        with: "no --compare",
        when: |g| !g.given("compare"),
        why: "it is the noise threshold of --compare",
    },
    Rule {
        flags: &["preset"],
        subject: None,
        commands: &["bench"],
        with: "--blades, --segments, --size, --warmup and --frames all given",
        when: |g| {
            matches!(g.one::<PresetArg>("preset"), Some(PresetArg::Thesis | PresetArg::Quick))
                && ["blades", "segments", "size", "warmup", "frames"].iter().all(|f| g.given(f))
        },
        why: "they replace everything the thesis and quick presets set differently (both run every mode and placement)",
    },
    Rule {
        flags: &["device"],
        subject: None,
        commands: &["devices"],
        with: "devices",
        when: |_| true,
        why: "it lists every device (the other subcommands take --device to pick one)",
    },
    Rule {
        flags: &["modes", "eval"],
        subject: None,
        commands: &["bench"],
        with: "--preset lod",
        when: |g| g.one::<PresetArg>("preset") == Some(PresetArg::Lod),
        why: "it renders texture keyframes, brute force and GPU-driven",
    },
    Rule {
        flags: &["modes", "eval", "segments"],
        subject: None,
        commands: &["bench"],
        with: "--preset animations",
        when: |g| g.one::<PresetArg>("preset") == Some(PresetArg::Animations),
        why: "it renders each response with its own defaults, on its fixed rows",
    },
    Rule {
        flags: &["animations"],
        subject: None,
        commands: &["bench"],
        with: "a --preset other than animations or response",
        when: |g| !matches!(g.one::<PresetArg>("preset"), Some(PresetArg::Animations | PresetArg::Response)),
        why: "it picks the responses --preset animations compares and --preset response traces",
    },
    Rule {
        flags: &["wind_fields"],
        subject: None,
        commands: &["bench"],
        with: "a --preset other than animations",
        when: |g| g.one::<PresetArg>("preset") != Some(PresetArg::Animations),
        why: "it picks the wind fields --preset animations measures the keyframes and Verlet under",
    },
    Rule {
        flags: &["blades", "segments", "modes", "eval", "size", "warmup", "frames"],
        subject: None,
        commands: &["bench"],
        with: "--preset response",
        when: |g| g.one::<PresetArg>("preset") == Some(PresetArg::Response),
        why: "it traces a fixed field of 2000 blades through a fixed 3 s gust, one step a frame",
    },
    Rule {
        flags: &["blades", "modes", "eval", "segments"],
        subject: None,
        commands: &["bench"],
        with: "--preset landscape or far",
        when: |g| matches!(g.one::<PresetArg>("preset"), Some(PresetArg::Landscape | PresetArg::Far)),
        why: "it renders fixed unbounded fields: 400 blades/m², 4 segments, the default keyframes",
    },
    Rule {
        flags: &["blades", "modes", "eval", "segments"],
        subject: None,
        commands: &["bench"],
        with: "--preset plants or interaction",
        when: |g| matches!(g.one::<PresetArg>("preset"), Some(PresetArg::Plants | PresetArg::Interaction)),
        why: "it renders the default block field and the default 100 000-blade field, 4 segments, the default keyframes",
    },
    Rule {
        flags: &["modes", "eval", "segments"],
        subject: None,
        commands: &["bench"],
        with: "--preset msaa",
        when: |g| g.one::<PresetArg>("preset") == Some(PresetArg::Msaa),
        why: "it renders the default scene",
    },
    Rule {
        flags: &["eval"],
        subject: None,
        commands: &["bench"],
        with: "--modes without texture or uniform",
        when: |g| {
            g.given("modes")
                && !g.many::<ModeArg>("modes").iter().any(|m| matches!(m, ModeArg::Texture | ModeArg::Uniform))
        },
        why: "it places the keyframe evaluation, and the static blades and the floor have none",
    },
    Rule {
        flags: &["clusters"],
        subject: None,
        commands: &["overhead"],
        with: "--strategies of one draw (instanced, prerecorded)",
        when: |g| g.many::<Strategy>("strategies").iter().all(|s| !uses_clusters(*s)),
        why: "the cluster count splits the draws of the other strategies",
    },
];

/// Whether `strategy` splits the blades into `--clusters` draws.
fn uses_clusters(strategy: Strategy) -> bool {
    strategy.gpu_draws(2) > 1
}
