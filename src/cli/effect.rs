//! No flag is silently ignored. A flag typed on the command line (clap's
//! `ValueSource::CommandLine`, not a default) that has no effect in the configuration the rest of
//! the command line chooses is refused, before any work, with exit 2 and one line
//! `error: --flag has no effect with <configuration>: <why>`.
//!
//! [`RULES`] is the one table of these cases: each row names the flags, the subcommands, the
//! configuration (a test of the parsed command line) and the reason. A new flag, or a new mode
//! that makes some flags moot, adds a row here; `tests/flag_effects.rs` runs every flag of every
//! subcommand through the binary and fails on one that neither changes the output nor is
//! refused.

use clap::parser::ValueSource;
use clap::ArgMatches;

use super::animation::{DebugViewArg, ModeArg};
use super::args::PresetArg;
use super::culling::{CullTest, LodKind};
use crate::render::submission::Strategy;

/// The subcommands that draw the scene of `SceneArgs`.
const SCENE: &[&str] = &["render", "view", "timing"];
/// The scene subcommands with a submission strategy (`SubmissionArgs`).
const SUBMITTED: &[&str] = &["render", "timing"];

/// The keyframe flags: what the keyframe table is and where it is evaluated.
const KEYFRAME_FLAGS: &[&str] = &["poses", "smoothing", "encoding", "packing", "keyframes", "eval"];
/// The forces on the blades (thesis ch. 4–5) and what they vary with.
const FORCE_FLAGS: &[&str] =
    &["wind", "no_gusts", "source", "calm", "collider", "attenuation", "cluster_size", "time", "dt"];
/// The GPU-driven path's flags: the cull, the LOD and what steers them.
const CULL_FLAGS: &[&str] =
    &["cull", "lod", "lod_segments", "view_distance", "blade_distance", "budget_ms", "lod_scale"];

/// A configuration in which some flags have no effect.
pub(crate) struct Rule {
    /// The flags (clap ids, the field names) that have no effect there.
    pub(crate) flags: &'static [&'static str],
    /// How the error names the flag, when it is one of its values rather than the flag (`--cull
    /// none`); `None`: `--long`.
    pub(crate) subject: Option<&'static str>,
    /// The subcommands it applies to.
    pub(crate) commands: &'static [&'static str],
    /// The configuration, as the error names it.
    pub(crate) with: &'static str,
    /// Whether the command line is in that configuration.
    pub(crate) when: fn(&Given) -> bool,
    /// Why the flags have no effect there.
    pub(crate) why: &'static str,
}

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
        with: "--mode static (without --debug-view force or bounds)",
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
        when: |g| !g.cull().contains(&CullTest::Distance) && !g.given("field"),
        why: "only the distance test reads it (a --field also sizes its ground and its blocks' rings by them)",
    },
    Rule {
        flags: &["view_distance"],
        subject: None,
        commands: SCENE,
        with: "--blade-distance on stored blades",
        when: |g| g.given("blade_distance") && !g.given("field"),
        why: "the stored terrain is drawn whole, and the blades end at --blade-distance",
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
        when: |g| !g.given("field"),
        why: "it is the blades per m² of a --field's blocks; stored blades are --blades",
    },
    Rule {
        flags: &["relief"],
        subject: None,
        commands: SCENE,
        with: "stored blades (no --field)",
        when: |g| !g.given("field"),
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

/// The parsed command line of one subcommand, as the rules read it. Reading an id the
/// subcommand does not have reads as absent (the unit test checks that every id a rule reads
/// exists where it applies).
pub(crate) struct Given<'a> {
    matches: &'a ArgMatches,
    #[cfg(test)]
    read: std::cell::RefCell<Vec<&'static str>>,
}

impl<'a> Given<'a> {
    fn new(matches: &'a ArgMatches) -> Self {
        Given {
            matches,
            #[cfg(test)]
            read: Default::default(),
        }
    }

    fn note(&self, _id: &'static str) {
        #[cfg(test)]
        self.read.borrow_mut().push(_id);
    }

    /// Whether `id` was typed on the command line.
    pub(crate) fn given(&self, id: &'static str) -> bool {
        self.note(id);
        self.matches.value_source(id) == Some(ValueSource::CommandLine)
    }

    /// A boolean flag's value (false when absent).
    pub(crate) fn flag(&self, id: &'static str) -> bool {
        self.one::<bool>(id).unwrap_or(false)
    }

    /// The value of `id`, typed or default.
    pub(crate) fn one<T: Clone + Send + Sync + 'static>(&self, id: &'static str) -> Option<T> {
        self.note(id);
        self.matches.try_get_one::<T>(id).ok().flatten().cloned()
    }

    /// The values of a list flag `id`, typed or default.
    pub(crate) fn many<T: Clone + Send + Sync + 'static>(&self, id: &'static str) -> Vec<T> {
        self.note(id);
        self.matches.try_get_many::<T>(id).ok().flatten().map(|v| v.cloned().collect()).unwrap_or_default()
    }

    fn mode(&self) -> Option<ModeArg> {
        self.one("mode")
    }

    fn debug_view(&self) -> Option<DebugViewArg> {
        self.one("debug_view")
    }

    /// Whether a debug view shows the forces (force magnitude, or the clusters' corner forces).
    fn shows_forces(&self) -> bool {
        matches!(self.debug_view(), Some(DebugViewArg::Force | DebugViewArg::Bounds))
    }

    fn cull(&self) -> Vec<CullTest> {
        self.many("cull")
    }

    fn lod(&self) -> Vec<LodKind> {
        self.many("lod")
    }
}

/// The first flag of `command` (a subcommand's parsed matches) that the rules refuse, as the
/// message of its error line (without `error: `).
pub(crate) fn refused(command: &clap::Command, name: &str, matches: &ArgMatches) -> Option<String> {
    let given = Given::new(matches);
    for rule in RULES.iter().filter(|r| r.commands.contains(&name)) {
        let Some(flag) = rule.flags.iter().find(|f| given.given(f)) else { continue };
        if !(rule.when)(&given) {
            continue;
        }
        let subject = rule.subject.map(str::to_string).unwrap_or_else(|| long(command, flag));
        return Some(format!("{subject} has no effect with {}: {}", rule.with, rule.why));
    }
    None
}

/// `--long` of the argument `id` of `command`.
fn long(command: &clap::Command, id: &str) -> String {
    let arg = command.get_arguments().find(|a| a.get_id() == id);
    format!("--{}", arg.and_then(|a| a.get_long()).unwrap_or(id))
}

/// Apply the rule to a parsed command line: `Err(message)` for the first flag it refuses.
pub(crate) fn check(root: &clap::Command, matches: &ArgMatches) -> Result<(), String> {
    let Some((name, sub)) = matches.subcommand() else { return Ok(()) };
    let Some(command) = root.find_subcommand(name) else { return Ok(()) };
    match refused(command, name, sub) {
        Some(message) => Err(message),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    /// Every flag a rule names and every id its condition reads exists in each subcommand it
    /// applies to (a misspelt id would read as absent and the rule would never fire).
    #[test]
    fn every_rule_names_flags_its_subcommands_have() {
        let root = crate::cli::Cli::command();
        for (i, rule) in RULES.iter().enumerate() {
            assert!(!rule.flags.is_empty() && !rule.commands.is_empty(), "rule {i}");
            for name in rule.commands {
                let command = root.find_subcommand(name).unwrap_or_else(|| panic!("rule {i}: no subcommand {name}"));
                let ids: Vec<&str> = command.get_arguments().map(|a| a.get_id().as_str()).collect();
                for flag in rule.flags {
                    assert!(ids.contains(flag), "rule {i}: {name} has no flag {flag}");
                }
                let matches = root.clone().try_get_matches_from(["meadow", name]).expect("defaults parse");
                let (_, sub) = matches.subcommand().expect("a subcommand");
                let given = Given::new(sub);
                let _ = (rule.when)(&given);
                for id in given.read.borrow().iter() {
                    assert!(ids.contains(id), "rule {i}: its condition reads {id}, which {name} has not");
                }
            }
        }
    }

    fn refusal(args: &[&str]) -> Option<String> {
        let root = crate::cli::Cli::command();
        let matches = root.clone().try_get_matches_from(args).expect("parses");
        check(&root, &matches).err()
    }

    #[test]
    fn typed_flags_are_refused_and_defaults_are_not() {
        let message = refusal(&["meadow", "render", "--brute-force", "--lod-scale", "1"]).expect("refused");
        assert_eq!(
            message,
            "--lod-scale has no effect with --brute-force: it draws every stored blade at --segments in one instanced draw, with no cull and no LOD"
        );
        // The same configuration with every cull flag at its default is accepted.
        assert_eq!(refusal(&["meadow", "render", "--brute-force"]), None);
        assert_eq!(refusal(&["meadow", "render"]), None);
        assert_eq!(refusal(&["meadow", "render", "--lod-scale", "2"]), None);
        let none = refusal(&["meadow", "timing", "--cull", "none,frustum"]).expect("refused");
        assert!(none.starts_with("--cull none has no effect with other tests"), "{none}");
        assert_eq!(refusal(&["meadow", "render", "--cull", "none"]), None);
    }
}
