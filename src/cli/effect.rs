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

use super::animation::{AnimationArg, DebugViewArg, ModeArg};
use super::culling::{CullTest, LodKind};

mod rules;

pub(crate) use rules::RULES;

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

/// The parsed command line of one subcommand, as the rules read it. Reading an id the
/// subcommand does not have reads as absent (the unit test checks that every id a rule reads
/// exists where it applies).
pub(crate) struct Given<'a> {
    matches: &'a ArgMatches,
    /// The command line draws the default landscape (`default_scene::draws_landscape`).
    landscape: bool,
    #[cfg(test)]
    read: std::cell::RefCell<Vec<&'static str>>,
}

impl<'a> Given<'a> {
    fn new(name: &str, matches: &'a ArgMatches) -> Self {
        Given {
            matches,
            landscape: super::default_scene::draws_landscape(name, matches),
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

    /// Whether the scene is stored blades: no `--field`, and not the default landscape.
    pub(crate) fn stored(&self) -> bool {
        !self.given("field") && !self.landscape
    }

    /// Whether the ground reaches past the blades (the view distance, typed or the scene's, over
    /// the blade distance): where a far field can stand.
    pub(crate) fn ground_past_blades(&self) -> bool {
        let view = super::default_scene::view_distance(self.one::<f32>("view_distance"), self.landscape);
        let blades = self.one::<f32>("blade_distance").unwrap_or(crate::render::culling::DEFAULT_BLADE_DISTANCE);
        view > blades + 1e-3
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

    /// The values of `id` as typed (the command line's text, typed or default).
    pub(crate) fn raw(&self, id: &'static str) -> Vec<String> {
        self.note(id);
        let values = self.matches.try_get_raw(id).ok().flatten();
        values.map(|v| v.map(|s| s.to_string_lossy().into_owned()).collect()).unwrap_or_default()
    }

    fn mode(&self) -> Option<ModeArg> {
        self.one("mode")
    }

    fn animation(&self) -> Option<AnimationArg> {
        self.one("animation")
    }

    fn wind_field(&self) -> Option<crate::cli::animation::WindFieldArg> {
        self.one("wind_field")
    }

    fn debug_view(&self) -> Option<DebugViewArg> {
        self.one("debug_view")
    }

    /// Whether a debug view shows the forces (force magnitude, the clusters' corner forces, or the
    /// wind's arrows).
    fn shows_forces(&self) -> bool {
        matches!(self.debug_view(), Some(DebugViewArg::Force | DebugViewArg::Bounds | DebugViewArg::Wind))
    }

    /// Whether the blades are posed from pose records, which the pressed map and push-out act on:
    /// every response but static blades and the keyframes per vertex (`--eval vertex`, or `auto`
    /// with `--brute-force`).
    fn pose_records(&self) -> bool {
        use crate::cli::animation::EvalArg;
        if matches!(self.mode(), Some(ModeArg::Floor | ModeArg::Static)) {
            return false;
        }
        match self.animation() {
            Some(AnimationArg::Static) => false,
            Some(AnimationArg::Keyframes) | None => match self.one::<EvalArg>("eval") {
                Some(EvalArg::Blade) => true,
                Some(EvalArg::Vertex) => false,
                _ => !self.flag("brute_force"),
            },
            Some(_) => true,
        }
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
    let given = Given::new(name, matches);
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
                let given = Given::new(name, sub);
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
    fn a_source_height_is_refused_only_without_the_fluid() {
        let height = ["meadow", "render", "--source", "0,0,1,2,0.8"];
        assert!(refusal(&height).is_some_and(|m| m.starts_with("--source …,HEIGHT has no effect")));
        let fluid = [&height[..], &["--wind-field", "fluid"]].concat();
        assert_eq!(refusal(&fluid), None);
        // Four numbers (no height) and six (a motion, no height) are every field's.
        assert_eq!(refusal(&["meadow", "render", "--source", "0,0,1,2"]), None);
        assert_eq!(refusal(&["meadow", "render", "--source", "0,0,1,2,1,0"]), None);
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
