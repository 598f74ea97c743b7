//! No flag is silently ignored (`cli::effect`): every flag of every subcommand, read from the
//! clap definition so that a new flag cannot be forgotten, either changes what the command
//! outputs or is refused with exit 2 and one `error:` line, in each configuration below. The
//! output is the exit code, stdout and the files written, with measured numbers masked; pictures
//! (`render`'s, `keyframes --export`) are compared by their pixels. Each configuration's own
//! output is produced twice and must be the same, so that a difference can only be the flag's.
//!
//! Scenes are tiny (64x36, a few thousand blades, 1 frame). Cheaper proofs, where they hold:
//! - `view` and `timing` share `render`'s scene flags (`SceneArgs`, converted by the same
//!   `SceneArgs::options`), so those are proven through `render`'s pictures; `view` and `timing`
//!   are run on each of them only where `render` refuses it, to show that they refuse it too (a
//!   refusal is made at parse time, before any device or window, so these runs are cheap).
//! - A "focus" configuration (e.g. `--msaa 4`) runs only the flags whose consumer it changes;
//!   the "full" configurations run every flag.

mod support;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Output;
use std::sync::Mutex;

use clap::CommandFactory;
use support::xvfb::Xvfb;
use support::{meadow, scratch, transcript};

/// One way to set a flag away from its default: `context` goes into the configuration's own run
/// too (what the flag needs to act, e.g. `--screenshot` for `--screenshot-ui`), `args` only into
/// the flag's run. A later group replaces a group of the same flag.
#[derive(Clone, Copy)]
struct Alt {
    context: &'static [&'static str],
    args: &'static [&'static str],
}

const fn alt(args: &'static [&'static str]) -> Alt {
    Alt { context: &[], args }
}

const fn with(context: &'static [&'static str], args: &'static [&'static str]) -> Alt {
    Alt { context, args }
}

/// The ways of a flag (clap id), tried in order until one changes the output.
type Case = (&'static str, &'static [Alt]);

/// A configuration of a subcommand: its args, and the flags run in it (`None`: all of them).
struct Config {
    name: &'static str,
    args: &'static [&'static str],
    only: Option<&'static [&'static str]>,
}

/// How a subcommand is run and observed.
struct Subcommand {
    name: &'static str,
    configs: &'static [Config],
    cases: &'static [Case],
    /// Whether its PNGs are pictures to compare by pixels (not charts of measured numbers).
    pictures: bool,
    /// Under a display (`view`).
    display: bool,
}

const D: &str = support::DEVICE;

const RENDER_CASES: &[Case] = &[
    ("blades", &[alt(&["--blades", "2000"])]),
    ("field", &[alt(&["--field", "24"])]),
    ("density", &[alt(&["--density", "40"])]),
    ("segments", &[alt(&["--segments", "2"]), alt(&["--segments", "8"])]),
    ("size", &[alt(&["--size", "48x32"])]),
    ("seed", &[alt(&["--seed", "7"])]),
    ("camera", &[alt(&["--camera", "0.5,1,-1,70,-25"]), alt(&["--camera", "landscape"])]),
    ("relief", &[alt(&["--relief", "hills"])]),
    ("heightmap", &[alt(&["--heightmap", "map.png"])]),
    ("terrain_scale", &[with(&["--heightmap", "map.png"], &["--terrain-scale", "1000,20,1000"])]),
    ("cover", &[with(&["--heightmap", "map.png"], &["--cover", "cover.png"])]),
    ("slope_limit", &[with(&["--heightmap", "map.png"], &["--slope-limit", "3"])]),
    ("clumps", &[alt(&["--clumps", "1"])]),
    ("flowers", &[alt(&["--flowers", "100"])]),
    ("fog", &[alt(&["--fog", "0.5"])]),
    ("blades_per_instance", &[alt(&["--blades-per-instance", "4"])]),
    ("animation", &[alt(&["--animation", "sine-object"]), alt(&["--animation", "static"])]),
    ("stiffness", &[alt(&["--stiffness", "20"])]),
    ("damping", &[alt(&["--damping", "12"])]),
    ("mode", &[alt(&["--mode", "uniform"]), alt(&["--mode", "static"])]),
    ("poses", &[alt(&["--poses", "16"])]),
    ("smoothing", &[alt(&["--smoothing", "linear"]), with(&["--time", "1.3"], &["--smoothing", "slerp"])]),
    ("encoding", &[alt(&["--encoding", "rgba8x2"]), alt(&["--encoding", "float32"])]),
    ("packing", &[alt(&["--packing", "thesis"])]),
    ("keyframes", &[alt(&["--keyframes", "curve"])]),
    ("eval", &[alt(&["--eval", "vertex"]), alt(&["--eval", "blade"])]),
    ("attenuation", &[alt(&["--attenuation", "blade"])]),
    ("cluster_size", &[alt(&["--cluster-size", "0.3"]), with(&["--debug-view", "bounds"], &["--cluster-size", "0.3"])]),
    ("wind", &[alt(&["--wind", "200,0.9"])]),
    ("no_gusts", &[alt(&["--no-gusts"]), with(&["--time", "2.5"], &["--no-gusts"])]),
    ("wind_field", &[alt(&["--wind-field", "perlin"])]),
    ("fluid_grid", &[with(&["--wind-field", "fluid", "--source", "0,0,3,1"], &["--fluid-grid", "16,8,16"])]),
    ("fluid_cell", &[with(&["--wind-field", "fluid", "--source", "0,0,3,1"], &["--fluid-cell", "2,1"])]),
    ("source", &[alt(&["--source", "0,0,3,1"])]),
    ("calm", &[alt(&["--calm", "-9,-9,9,9"])]),
    ("collider", &[alt(&["--collider", "sphere:0,0,0,1.2"])]),
    ("cut", &[alt(&["--cut", "sphere:0,0,0,1.2"])]),
    // A sphere rolling across the field leaves a trail that recovers, or a cut that regrows, the
    // faster the shorter the time.
    ("recovery_s", &[with(&["--collider", "sphere:-1,0,0,0.6,1,0,0", "--time", "2"], &["--recovery-s", "0.5"])]),
    ("regrow_s", &[with(&["--cut", "sphere:-1,0,0,0.6,1,0,0", "--time", "2"], &["--regrow-s", "1"])]),
    ("time", &[alt(&["--time", "2.5"])]),
    // A frame draws the last completed step: at 0.03 s, step 1 of 1/60 s, step 0 of 1/20 s.
    ("dt", &[alt(&["--dt", "1/20"]), with(&["--time", "0.03"], &["--dt", "1/20"])]),
    ("brute_force", &[alt(&["--brute-force"])]),
    ("cull", &[alt(&["--cull", "frustum"]), alt(&["--cull", "orientation"])]),
    ("lod", &[alt(&["--lod", "segments"]), alt(&["--lod", "density"])]),
    ("lod_segments", &[alt(&["--lod-segments", "2,1"])]),
    ("view_distance", &[alt(&["--view-distance", "1"])]),
    ("blade_distance", &[alt(&["--blade-distance", "1"])]),
    ("far_field", &[alt(&["--far-field", "off"]), alt(&["--far-field", "stars"])]),
    ("fade", &[alt(&["--fade", "blend"])]),
    ("budget_ms", &[alt(&["--budget-ms", "5"])]),
    ("lod_scale", &[alt(&["--lod-scale", "0.2"])]),
    (
        "debug_view",
        &[alt(&["--debug-view", "force"]), alt(&["--debug-view", "bounds"]), alt(&["--debug-view", "wind"])],
    ),
    ("msaa", &[alt(&["--msaa", "4"])]),
    ("no_alpha_to_coverage", &[alt(&["--no-alpha-to-coverage"])]),
    ("out", &[alt(&["--out", "other.png"])]),
    ("frames", &[alt(&["--frames", "2"])]),
    ("submission", &[alt(&["--submission", "per-cluster"])]),
    ("clusters", &[alt(&["--clusters", "3"])]),
    ("validation", &[alt(&["--validation"])]),
    ("device", &[alt(&["--device", "no-such-device"])]),
];

/// `render`'s configurations. Every one names the device and the picture.
const RENDER_CONFIGS: &[Config] = &[
    Config {
        name: "culled",
        args: &["--blades", "3000", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: None,
    },
    Config {
        name: "brute force",
        args: &["--blades", "3000", "--brute-force", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: None,
    },
    Config {
        name: "floor",
        args: &["--blades", "3000", "--mode", "floor", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: None,
    },
    Config {
        name: "static",
        args: &["--blades", "3000", "--mode", "static", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: Some(&[
            "poses",
            "smoothing",
            "encoding",
            "packing",
            "keyframes",
            "eval",
            "attenuation",
            "cluster_size",
            "wind",
            "wind_field",
            "no_gusts",
            "source",
            "calm",
            "collider",
            "time",
            "dt",
            "debug_view",
            "mode",
        ]),
    },
    Config {
        name: "sine per vertex",
        args: &["--blades", "3000", "--animation", "sine-vertex", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: Some(&[
            "animation",
            "mode",
            "poses",
            "smoothing",
            "encoding",
            "packing",
            "keyframes",
            "eval",
            "attenuation",
            "wind",
            "wind_field",
            "no_gusts",
            "source",
            "calm",
            "collider",
            "time",
            "dt",
            "debug_view",
        ]),
    },
    Config {
        name: "verlet",
        args: &[
            "--blades",
            "3000",
            "--animation",
            "verlet",
            "--time",
            "0.5",
            "--size",
            "64x36",
            "--device",
            D,
            "--out",
            "out.png",
        ],
        only: Some(&[
            "animation",
            "stiffness",
            "damping",
            "mode",
            "eval",
            "wind",
            "wind_field",
            "time",
            "dt",
            "collider",
        ]),
    },
    Config {
        name: "inertial",
        args: &[
            "--blades",
            "3000",
            "--animation",
            "inertial",
            "--time",
            "0.5",
            "--size",
            "64x36",
            "--device",
            D,
            "--out",
            "out.png",
        ],
        only: Some(&["animation", "stiffness", "damping", "mode", "eval", "wind", "time", "dt", "collider"]),
    },
    Config {
        name: "virtual-inertial",
        args: &[
            "--blades",
            "3000",
            "--animation",
            "virtual-inertial",
            "--time",
            "0.5",
            "--size",
            "64x36",
            "--device",
            D,
            "--out",
            "out.png",
        ],
        only: Some(&["animation", "stiffness", "damping", "mode", "eval", "wind", "time", "dt", "collider"]),
    },
    Config {
        name: "block field",
        args: &["--field", "16", "--density", "20", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: Some(&[
            "blades",
            "field",
            "density",
            "view_distance",
            "blade_distance",
            "cull",
            "seed",
            "relief",
            "fog",
            "brute_force",
            "mode",
            "debug_view",
            "budget_ms",
            "segments",
        ]),
    },
    Config {
        name: "a far field",
        args: &[
            "--field",
            "infinite",
            "--camera",
            "landscape",
            "--view-distance",
            "600",
            "--fog",
            "0.001",
            "--size",
            "64x36",
            "--device",
            D,
            "--out",
            "out.png",
        ],
        only: Some(&["far_field", "fade"]),
    },
    Config {
        name: "uniform keyframes",
        args: &["--blades", "3000", "--mode", "uniform", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: Some(&["packing", "encoding", "keyframes"]),
    },
    Config {
        name: "msaa by brute force",
        args: &[
            "--blades",
            "3000",
            "--brute-force",
            "--msaa",
            "4",
            "--size",
            "64x36",
            "--device",
            D,
            "--out",
            "out.png",
        ],
        only: Some(&["no_alpha_to_coverage"]),
    },
    Config {
        name: "a point source",
        args: &["--blades", "3000", "--source", "0,0,3,1", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: Some(&["attenuation"]),
    },
    Config {
        name: "per-cluster submission",
        args: &[
            "--blades",
            "3000",
            "--brute-force",
            "--submission",
            "per-cluster",
            "--size",
            "64x36",
            "--device",
            D,
            "--out",
            "out.png",
        ],
        only: Some(&["clusters", "blades_per_instance"]),
    },
    Config {
        name: "no LOD",
        args: &["--blades", "3000", "--lod", "none", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: Some(&["lod_scale", "budget_ms", "lod_segments", "lod"]),
    },
    Config {
        name: "no cull test",
        args: &["--blades", "3000", "--cull", "none", "--size", "64x36", "--device", D, "--out", "out.png"],
        only: Some(&["view_distance", "blade_distance", "cull"]),
    },
];

const VIEW_BASE: &[&str] = &["--blades", "2000", "--brute-force", "--size", "64x36", "--device", D, "--frames", "3"];

/// `view`'s own flags (its scene flags are `render`'s).
const VIEW_CASES: &[Case] = &[
    ("present", &[alt(&["--present", "immediate"]), alt(&["--present", "mailbox"])]),
    ("frames_in_flight", &[alt(&["--frames-in-flight", "1"])]),
    ("frames", &[alt(&["--frames", "4"])]),
    ("script", &[alt(&["--script", "quit.txt"])]),
    ("screenshot", &[alt(&["--screenshot", "shot.png"])]),
    ("inject_out_of_date", &[alt(&["--inject-out-of-date", "1"])]),
    ("sample_every", &[alt(&["--sample-every", "1"])]),
    ("no_ui", &[alt(&["--no-ui"])]),
    ("screenshot_ui", &[alt(&["--screenshot-ui"]), with(&["--screenshot", "shot.png"], &["--screenshot-ui"])]),
    (
        "capture_dir",
        &[
            alt(&["--capture-dir", "."]),
            with(&["--script", "capture.txt", "--frames", "200", "--size", "640x480"], &["--capture-dir", "."]),
        ],
    ),
    ("validation", &[alt(&["--validation"])]),
    ("device", &[alt(&["--device", "no-such-device"])]),
];

const TIMING_CASES: &[Case] = &[
    ("frames", &[alt(&["--frames", "3"])]),
    ("warmup", &[alt(&["--warmup", "1"])]),
    ("trace", &[alt(&["--trace", "trace.json"])]),
    ("fly", &[alt(&["--fly", "30"])]),
    ("out", &[alt(&["--out", "other"])]),
    ("submission", &[alt(&["--submission", "per-cluster"])]),
    ("clusters", &[alt(&["--clusters", "3"]), with(&["--submission", "per-cluster"], &["--clusters", "3"])]),
    ("validation", &[alt(&["--validation"])]),
    ("device", &[alt(&["--device", "no-such-device"])]),
];

const BENCH_BASE: &[&str] = &[
    "--blades",
    "500",
    "--segments",
    "1",
    "--modes",
    "texture",
    "--size",
    "64x36",
    "--warmup",
    "0",
    "--frames",
    "1",
    "--out",
    "out",
    "--device",
    D,
];

const BENCH_CASES: &[Case] = &[
    ("preset", &[alt(&["--preset", "thesis"])]),
    ("blades", &[alt(&["--blades", "400"])]),
    ("segments", &[alt(&["--segments", "2"])]),
    ("modes", &[alt(&["--modes", "static"])]),
    ("eval", &[alt(&["--eval", "blade"])]),
    ("animations", &[alt(&["--animations", "sine-object"])]),
    ("wind_fields", &[alt(&["--wind-fields", "perlin"])]),
    ("size", &[alt(&["--size", "48x32"])]),
    ("warmup", &[alt(&["--warmup", "1"])]),
    ("frames", &[alt(&["--frames", "2"])]),
    ("out", &[alt(&["--out", "other"])]),
    ("compare", &[alt(&["--compare", "old.json", "new.json"]), alt(&["--compare", "new.json", "old.json"])]),
    ("threshold", &[alt(&["--threshold", "50"])]),
    ("validation", &[alt(&["--validation"])]),
    ("device", &[alt(&["--device", "no-such-device"])]),
];

const OVERHEAD_CASES: &[Case] = &[
    ("blades", &[alt(&["--blades", "400"])]),
    ("segments", &[alt(&["--segments", "2"])]),
    ("clusters", &[alt(&["--clusters", "3"])]),
    ("strategies", &[alt(&["--strategies", "instanced,indirect"])]),
    ("size", &[alt(&["--size", "48x32"])]),
    ("warmup", &[alt(&["--warmup", "1"])]),
    ("frames", &[alt(&["--frames", "2"])]),
    ("out", &[alt(&["--out", "other"])]),
    ("validation", &[alt(&["--validation"])]),
    ("device", &[alt(&["--device", "no-such-device"])]),
];

const KEYFRAMES_CASES: &[Case] = &[
    ("poses", &[alt(&["--poses", "16"])]),
    ("segments", &[alt(&["--segments", "2"])]),
    ("report", &[alt(&["--report"])]),
    ("export", &[alt(&["--export", "k.png"])]),
];

const DEVICES_CASES: &[Case] = &[("validation", &[alt(&["--validation"])]), ("device", &[alt(&["--device", "0"])])];

/// `completions SHELL`: the shell is its one argument (a positional, replaced as a flag's group).
const COMPLETIONS_CASES: &[Case] = &[("shell", &[alt(&["zsh"])])];

const SUBCOMMANDS: &[Subcommand] = &[
    Subcommand { name: "render", configs: RENDER_CONFIGS, cases: RENDER_CASES, pictures: true, display: false },
    Subcommand {
        name: "view",
        configs: &[Config { name: "brute force", args: VIEW_BASE, only: None }],
        cases: VIEW_CASES,
        pictures: false,
        display: true,
    },
    Subcommand {
        name: "timing",
        configs: &[Config {
            name: "brute force",
            args: &[
                "--blades",
                "2000",
                "--brute-force",
                "--size",
                "64x36",
                "--device",
                D,
                "--frames",
                "2",
                "--warmup",
                "0",
                "--out",
                "out",
            ],
            only: None,
        }],
        cases: TIMING_CASES,
        pictures: false,
        display: false,
    },
    Subcommand {
        name: "bench",
        configs: &[
            Config { name: "quick", args: BENCH_BASE, only: None },
            Config {
                name: "quick at the preset's size",
                args: &[
                    "--blades",
                    "500",
                    "--segments",
                    "1",
                    "--modes",
                    "texture",
                    "--eval",
                    "vertex",
                    "--warmup",
                    "0",
                    "--frames",
                    "1",
                    "--out",
                    "out",
                    "--device",
                    D,
                ],
                only: Some(&["preset"]),
            },
            Config { name: "compare", args: &["--compare", "old.json", "new.json"], only: None },
            Config {
                name: "animations",
                args: &[
                    "--preset",
                    "animations",
                    "--blades",
                    "300",
                    "--size",
                    "32x18",
                    "--warmup",
                    "0",
                    "--frames",
                    "1",
                    "--out",
                    "out",
                    "--device",
                    D,
                ],
                only: Some(&["animations", "wind_fields", "blades", "modes", "segments", "eval"]),
            },
        ],
        cases: BENCH_CASES,
        pictures: false,
        display: false,
    },
    Subcommand {
        name: "overhead",
        configs: &[
            Config {
                name: "two strategies",
                args: &[
                    "--blades",
                    "500",
                    "--segments",
                    "1",
                    "--strategies",
                    "instanced,per-cluster",
                    "--clusters",
                    "2",
                    "--size",
                    "64x36",
                    "--warmup",
                    "0",
                    "--frames",
                    "1",
                    "--out",
                    "out",
                    "--device",
                    D,
                ],
                only: None,
            },
            Config {
                name: "one draw",
                args: &[
                    "--blades",
                    "10000",
                    "--strategies",
                    "instanced",
                    "--size",
                    "64x36",
                    "--warmup",
                    "0",
                    "--frames",
                    "1",
                    "--out",
                    "out",
                    "--device",
                    D,
                ],
                only: Some(&["clusters"]),
            },
        ],
        cases: OVERHEAD_CASES,
        pictures: false,
        display: false,
    },
    Subcommand {
        name: "keyframes",
        configs: &[Config { name: "small table", args: &["--poses", "8"], only: None }],
        cases: KEYFRAMES_CASES,
        pictures: true,
        display: false,
    },
    Subcommand {
        name: "devices",
        configs: &[Config { name: "plain", args: &[], only: None }],
        cases: DEVICES_CASES,
        pictures: false,
        display: false,
    },
    Subcommand {
        name: "completions",
        configs: &[Config { name: "bash", args: &["bash"], only: None }],
        cases: COMPLETIONS_CASES,
        pictures: false,
        display: false,
    },
];

/// Flags of `view` and `timing` that are not `render`'s scene flags: their own cases.
const OWN: &[&str] = &["frames", "validation", "device"];

/// Every argument id of subcommand `name`, from clap.
fn flags_of(name: &str) -> Vec<String> {
    let root = meadow::cli::Cli::command();
    let command = root.find_subcommand(name).unwrap_or_else(|| panic!("no subcommand {name}"));
    command.get_arguments().map(|a| a.get_id().to_string()).filter(|id| id != "help" && id != "version").collect()
}

/// The scene flags `view` and `timing` share with `render` (proven through `render`).
fn scene_flags() -> BTreeSet<String> {
    let (render, view, timing) = (flags_of("render"), flags_of("view"), flags_of("timing"));
    render.into_iter().filter(|f| view.contains(f) && timing.contains(f) && !OWN.contains(&f.as_str())).collect()
}

#[test]
fn every_flag_of_every_subcommand_has_a_case() {
    let root = meadow::cli::Cli::command();
    let scene = scene_flags();
    for command in root.get_subcommands().filter(|c| c.get_name() != "help") {
        let name = command.get_name();
        let sub = SUBCOMMANDS.iter().find(|s| s.name == name).unwrap_or_else(|| {
            panic!("subcommand `{name}` has no cases in tests/flag_effects.rs: add its flags and configurations")
        });
        for flag in flags_of(name) {
            let shared = matches!(name, "view" | "timing") && scene.contains(&flag);
            assert!(
                shared || sub.cases.iter().any(|(id, _)| *id == flag),
                "{name} --{flag} has no case in tests/flag_effects.rs: give it a value that changes the output"
            );
        }
        for (id, _) in sub.cases {
            assert!(flags_of(name).iter().any(|f| f == id), "{name} has no flag {id} (a stale case)");
        }
    }
}

/// What a run showed: exit code, stdout and the files written, measured numbers masked.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Observation {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    files: BTreeMap<String, String>,
}

impl Observation {
    /// The first line where `self` and `other` differ, for a failure's message.
    fn difference(&self, other: &Observation) -> String {
        let show = |o: &Observation| {
            let mut text = format!("exit {:?}\n{}\n{}", o.code, o.stdout, o.stderr);
            for (name, content) in &o.files {
                text.push_str(&format!("\n== {name}\n{content}"));
            }
            text
        };
        let (a, b) = (show(self), show(other));
        let line = a.lines().zip(b.lines()).find(|(x, y)| x != y);
        match line {
            Some((x, y)) => format!("'{x}' against '{y}'"),
            None => format!("{} lines against {}", a.lines().count(), b.lines().count()),
        }
    }
}

/// `text` with what is measured masked: decimal numbers, numbers in scientific notation, and
/// whole numbers of milliseconds, microseconds, nanoseconds, percents and ± deviations.
fn mask(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        if chars[i].is_ascii_digit() {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent (`1.5e-3`, `2e6`): scientific notation is a measured number.
            let sign = usize::from(matches!(chars.get(i + 1), Some('+' | '-')));
            let exponent =
                matches!(chars.get(i), Some('e' | 'E')) && chars.get(i + 1 + sign).is_some_and(|c| c.is_ascii_digit());
            if exponent {
                i += 1 + sign;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            let number: String = chars[start..i].iter().collect();
            let rest: String = chars[i..chars.len().min(i + 3)].iter().collect();
            let rest = rest.trim_start();
            let deviation = start > 0 && chars[start - 1] == '±';
            let measured = exponent
                || number.contains('.')
                || deviation
                || ["ms", "µs", "ns", "%"].iter().any(|unit| rest.starts_with(unit));
            out.push_str(if measured { "#" } else { &number });
        } else {
            out.push(chars[i]);
            i += 1;
        }
    }
    // Column widths follow the masked numbers' widths.
    let mut collapsed = String::with_capacity(out.len());
    for c in out.chars() {
        if !(c == ' ' && collapsed.ends_with(' ')) {
            collapsed.push(c);
        }
    }
    collapsed
}

/// The lines of a `view` run that depend on the clock or on the X server: dropped (stats) or
/// masked (samples; the summary's swapchain counts, which follow the resize events Xvfb sends
/// under load: two identical runs were seen to re-create the swapchain twice and once).
fn unclocked(stdout: &str) -> String {
    stdout
        .lines()
        .filter(|l| !l.starts_with("stats: "))
        .map(|l| match l {
            _ if l.starts_with("sample: ") => l.replace(|c: char| c.is_ascii_digit(), ""),
            _ if l.starts_with("viewer: ") => unswapchained(l),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The viewer's summary line with the digits of its swapchain clause ("N swapchains created
/// (at most N alive at once), N re-creations") masked; the rest of the line kept, with the count
/// of injected out-of-date results (`--inject-out-of-date`), which a flag decides.
fn unswapchained(line: &str) -> String {
    let Some(start) = line.find("frames, ").map(|i| i + "frames, ".len()) else { return line.to_string() };
    let Some(end) = line[start..].find(" re-creations").map(|i| start + i) else { return line.to_string() };
    let masked = line[start..end].replace(|c: char| c.is_ascii_digit(), "#");
    format!("{}{masked}{}", &line[..start], &line[end..])
}

/// Files a run starts with (its inputs), kept out of the observation.
const FIXTURES: &[&str] = &["old.json", "new.json", "quit.txt", "capture.txt", "map.png"];

/// Write the inputs a run may name into `dir`: two bench documents whose static variant differs
/// by 20 % (a regression at the 10 % threshold, not at 50 %), and two viewer scripts.
fn fixtures(dir: &Path) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/bench-thesis/bench.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).expect("thesis")).expect("JSON");
    doc["rows"] = serde_json::Value::from(vec![doc["rows"][0].clone()]);
    let mut slower = doc.clone();
    let v = &mut slower["rows"][0]["variants"][0];
    for f in v["frames"].as_array_mut().expect("frames") {
        f["gpu_ms"] = serde_json::Value::from(f["gpu_ms"].as_f64().expect("ms") * 1.2);
    }
    v["gpu_ms"]["median"] = serde_json::Value::from(v["gpu_ms"]["median"].as_f64().expect("median") * 1.2);
    std::fs::write(dir.join("old.json"), doc.to_string()).expect("write");
    std::fs::write(dir.join("new.json"), slower.to_string()).expect("write");
    std::fs::write(dir.join("quit.txt"), "1 quit\n").expect("write");
    // A heightmap (`--heightmap`): a 16-bit ramp along x with a bump.
    let map: Vec<u16> = (0..32u32 * 32)
        .map(|i| {
            let (x, z) = ((i % 32) as f32, (i / 32) as f32);
            (x * 1500.0 + 20_000.0 * (-((x - 16.0).powi(2) + (z - 16.0).powi(2)) / 30.0).exp()) as u16
        })
        .collect();
    let bytes: Vec<u8> = map.iter().flat_map(|v| v.to_ne_bytes()).collect();
    image::save_buffer(dir.join("map.png"), &bytes, 32, 32, image::ColorType::L16).expect("map");
    // A covering map (`--cover`): bare on one diagonal, full on the other.
    image::save_buffer(dir.join("cover.png"), &[0, 255, 255, 0], 2, 2, image::ColorType::L8).expect("cover");
    // The overlay is laid out by frame 5 (at 640x480 its timing window, with the capture button,
    // fits); the capture takes 60 frames.
    std::fs::write(dir.join("capture.txt"), "5 ui-click capture\n70 quit\n").expect("write");
}

/// Every file under `dir` but the fixtures, by relative path: pictures by a hash of their pixels
/// (when `pictures`), other PNGs (charts of measured numbers) by name only, text masked.
fn files(dir: &Path, pictures: bool) -> BTreeMap<String, String> {
    let mut found = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("read dir").flatten() {
            let path = entry.path();
            let name = path.strip_prefix(dir).expect("inside").to_string_lossy().into_owned();
            if path.is_dir() {
                found.insert(format!("{name}/"), String::new());
                stack.push(path);
            } else if !FIXTURES.contains(&name.as_str()) {
                let bytes = std::fs::read(&path).expect("read");
                let content = match path.extension().and_then(|e| e.to_str()) {
                    Some("png") if pictures => {
                        let image = image::load_from_memory(&bytes).expect("png").to_rgba8();
                        // FNV-1a of the pixels.
                        let hash = image.as_raw().iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
                            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
                        });
                        format!("{}x{} pixels {hash:016x}", image.width(), image.height())
                    }
                    Some("png") => "a chart".to_string(),
                    _ => mask(&String::from_utf8_lossy(&bytes)),
                };
                found.insert(name, content);
            }
        }
    }
    found
}

/// `args` as groups of one flag and its values (`--a 1 --b` → [[--a, 1], [--b]]); positionals
/// before any flag are one group of their own.
fn groups(args: &[&str]) -> Vec<Vec<String>> {
    let mut out: Vec<Vec<String>> = Vec::new();
    for a in args {
        if a.starts_with("--") || out.is_empty() {
            out.push(vec![a.to_string()]);
        } else {
            out.last_mut().expect("a group").push(a.to_string());
        }
    }
    out
}

/// `base` with each group of `more` replacing the group of the same flag, or added.
fn merged(base: &[&str], more: &[&[&str]]) -> Vec<String> {
    let mut all = groups(base);
    for m in more {
        for g in groups(m) {
            // A flag replaces the same flag; positionals replace the positionals.
            let same = |a: &&mut Vec<String>| match g[0].starts_with("--") {
                true => a[0] == g[0],
                false => !a[0].starts_with("--"),
            };
            match all.iter_mut().find(same) {
                Some(a) => *a = g,
                None => all.push(g),
            }
        }
    }
    all.concat()
}

/// Run `meadow SUB ARGS` in a fresh directory and observe it.
fn observe(sub: &Subcommand, args: &[String], dir: &Path, display: Option<&str>) -> (Observation, Output) {
    let output = run_in(sub, args, dir, display);
    let mut stdout = mask(&String::from_utf8_lossy(&output.stdout));
    if sub.display {
        stdout = unclocked(&stdout);
    }
    let stderr = match output.status.code() {
        Some(0) => String::new(),
        _ => mask(&String::from_utf8_lossy(&output.stderr)),
    };
    let observation = Observation { code: output.status.code(), stdout, stderr, files: files(dir, sub.pictures) };
    (observation, output)
}

/// Times a `view` run is tried while the X server refuses the connection.
const DISPLAY_TRIES: usize = 4;

/// Run `meadow SUB ARGS` in `dir`, emptied and given the fixtures. A `view` run the X server
/// refused (our Xvfb, under load, can refuse a client: the viewer's "no display" line, which no
/// flag causes with a display set) is run again, a few times.
fn run_in(sub: &Subcommand, args: &[String], dir: &Path, display: Option<&str>) -> Output {
    let mut tries = 0;
    loop {
        let _ = std::fs::remove_dir_all(dir);
        std::fs::create_dir_all(dir).expect("dir");
        fixtures(dir);
        let mut cmd = meadow();
        cmd.arg(sub.name).args(args).current_dir(dir).env_remove("WAYLAND_DISPLAY");
        match display {
            // The overlay's layout at scale 1, whatever DPI the server reports.
            Some(d) => cmd.env("DISPLAY", d).env("WINIT_X11_SCALE_FACTOR", "1"),
            None => cmd.env_remove("DISPLAY"),
        };
        let output = cmd.output().expect("run meadow");
        tries += 1;
        let stderr = String::from_utf8_lossy(&output.stderr);
        let refused_by_x =
            sub.display && output.status.code() == Some(2) && stderr.contains(meadow::viewer::NO_DISPLAY);
        if !refused_by_x || tries == DISPLAY_TRIES {
            return output;
        }
        eprintln!("the X server refused {} {} (try {tries}); again", sub.name, args.join(" "));
        std::thread::sleep(std::time::Duration::from_millis(500 * tries as u64));
    }
}

/// Whether `output` is a refusal: exit 2, one `error:` line, nothing on stdout.
fn refused(output: &Output) -> bool {
    let stderr = String::from_utf8_lossy(&output.stderr);
    output.status.code() == Some(2)
        && stderr.starts_with("error: ")
        && stderr.lines().count() == 1
        && output.stdout.is_empty()
}

/// Whether `output` refuses a flag for the configuration it is in: the rule's line, or clap's
/// conflict between two flags. (Another error — a value out of range, no such device — shows
/// that the flag was read: a change.)
fn refused_here(output: &Output) -> bool {
    let stderr = String::from_utf8_lossy(&output.stderr);
    refused(output) && (stderr.contains(" has no effect with ") || stderr.contains("cannot be used with"))
}

/// Flags the rule refuses in every configuration of their subcommand, by design: `devices`
/// takes `GpuArgs` for `--validation`, and lists every device whatever `--device` says.
const REFUSED_EVERYWHERE: &[(&str, &str)] = &[("devices", "device")];

/// Run `jobs` on a few threads (the machine's cores; each run is a process).
fn parallel<T: Send, R: Send>(jobs: Vec<T>, run: impl Fn(T) -> R + Sync) -> Vec<R> {
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()).clamp(1, 4);
    let queue = Mutex::new(jobs.into_iter().enumerate().collect::<Vec<_>>());
    let results = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let Some((i, job)) = queue.lock().expect("queue").pop() else { break };
                let r = run(job);
                results.lock().expect("results").push((i, r));
            });
        }
    });
    let mut results = results.into_inner().expect("results");
    results.sort_by_key(|(i, _)| *i);
    results.into_iter().map(|(_, r)| r).collect()
}

/// What happened to one flag in one configuration.
#[derive(Debug)]
enum Verdict {
    Changed,
    Refused(String),
    /// The configuration sets the flag already, to every value tried.
    AlreadySet,
    Ignored(String),
}

/// Every (subcommand, configuration, flag) of the subcommands `names`: run the configuration twice
/// (it must repeat), then each of the flag's ways until one changes the output; refused or
/// changed, else ignored. Each #[test] below takes a few subcommands, so that cargo runs them side
/// by side.
fn every_flag_changes_the_output_or_is_refused(names: &[&str]) {
    let root = scratch(&format!("flag-effects-{}", names.join("-")));
    let xvfb = SUBCOMMANDS.iter().any(|s| s.display && names.contains(&s.name)).then(|| Xvfb::start("1280x1024x24"));
    let display = xvfb.as_ref().map(|x| x.display().to_string());
    let display = display.as_deref();
    // (subcommand, configuration, flag, alternatives)
    let mut jobs = Vec::new();
    let mut baselines = BTreeSet::new();
    for (s, sub) in SUBCOMMANDS.iter().enumerate().filter(|(_, sub)| names.contains(&sub.name)) {
        for (c, config) in sub.configs.iter().enumerate() {
            for (id, alts) in sub.cases {
                if config.only.is_some_and(|only| !only.contains(id)) {
                    continue;
                }
                for a in alts.iter() {
                    baselines.insert((s, c, a.context));
                }
                jobs.push((s, c, *id, *alts));
            }
        }
    }
    // The configurations' own outputs, twice each.
    let baseline_jobs: Vec<_> = baselines.iter().flat_map(|&b| [(b, 0), (b, 1)]).collect();
    let observed = parallel(baseline_jobs.clone(), |((s, c, context), run)| {
        let sub = &SUBCOMMANDS[s];
        let args = merged(sub.configs[c].args, &[context]);
        let dir = root.join(format!("base-{s}-{c}-{}-{run}", context.join("_").replace(['/', '.'], "")));
        observe(sub, &args, &dir, display)
    });
    let mut base = BTreeMap::new();
    let mut problems = Vec::new();
    for (((key, run), (observation, output)), _) in baseline_jobs.iter().zip(observed).zip(0..) {
        let (s, c, context) = *key;
        let what = format!("{} ({}) {}", SUBCOMMANDS[s].name, SUBCOMMANDS[s].configs[c].name, context.join(" "));
        // A context the configuration refuses (e.g. `--time` with the floor) is not a way there.
        if context.is_empty() && refused(&output) {
            problems.push(format!("{what}: the configuration itself is refused:\n{}", transcript(&output)));
        }
        match base.get(key) {
            None => {
                base.insert(*key, observation);
            }
            Some(first) if first != &observation => problems.push(format!(
                "{what}: two runs of the same configuration differ (run {run}), so a difference proves nothing: {}",
                first.difference(&observation)
            )),
            Some(_) => {}
        }
    }
    let verdicts = parallel(jobs, |(s, c, id, alts)| {
        let sub = &SUBCOMMANDS[s];
        let config = &sub.configs[c];
        // The verdict of the first way tried, unless a later one changes the output.
        let (mut first, mut already_set) = (None, false);
        let mut changed = false;
        for (i, a) in alts.iter().enumerate() {
            let baseline = &base[&(s, c, a.context)];
            let args = merged(config.args, &[a.context, a.args]);
            if args == merged(config.args, &[a.context]) {
                // The configuration already sets the flag so (`--brute-force` in "brute force").
                already_set = true;
                continue;
            }
            let dir = root.join(format!("{}-{c}-{id}-{i}", sub.name));
            let (observation, output) = observe(sub, &args, &dir, display);
            if observation != *baseline && !refused_here(&output) {
                changed = true;
                break;
            }
            first.get_or_insert(match refused_here(&output) {
                true => Verdict::Refused(String::from_utf8_lossy(&output.stderr).trim().to_string()),
                false => Verdict::Ignored(format!("{} {}", sub.name, args.join(" "))),
            });
        }
        let verdict = match (changed, first, already_set) {
            (true, _, _) => Some(Verdict::Changed),
            (false, Some(v), _) => Some(v),
            (false, None, true) => Some(Verdict::AlreadySet),
            (false, None, false) => None,
        };
        let verdict = verdict.unwrap_or_else(|| Verdict::Ignored(format!("no way of --{id} could be tried")));
        if let Verdict::Ignored(run) = &verdict {
            eprintln!("ignored: {run}");
        }
        (s, c, id, verdict)
    });
    let mut ignored = problems;
    let mut effective: BTreeSet<(usize, &str)> = BTreeSet::new();
    for (s, c, id, verdict) in &verdicts {
        match verdict {
            Verdict::Changed => {
                effective.insert((*s, id));
            }
            Verdict::Refused(_) | Verdict::AlreadySet => {}
            Verdict::Ignored(run) => {
                ignored.push(format!(
                    "{} ({}): --{id} neither changed the output nor was refused: {run}",
                    SUBCOMMANDS[*s].name, SUBCOMMANDS[*s].configs[*c].name
                ));
            }
        }
    }
    for (s, sub) in SUBCOMMANDS.iter().enumerate().filter(|(_, sub)| names.contains(&sub.name)) {
        for (id, _) in sub.cases {
            if !effective.contains(&(s, *id)) && !REFUSED_EVERYWHERE.contains(&(sub.name, *id)) {
                ignored.push(format!("{} --{id} changes the output in no configuration", sub.name));
            }
        }
    }
    assert!(ignored.is_empty(), "flags silently ignored:\n{}", ignored.join("\n"));
    if names.contains(&"render") {
        view_and_timing_refuse_what_render_refuses(&verdicts);
    }
    drop(xvfb);
    let _ = std::fs::remove_dir_all(&root);
}

/// `view` and `timing` refuse the scene flags `render` refuses (its `verdicts`), in the same
/// configurations, with the same line.
fn view_and_timing_refuse_what_render_refuses(verdicts: &[(usize, usize, &str, Verdict)]) {
    let scene = scene_flags();
    let shared: Vec<_> = verdicts
        .iter()
        .filter_map(|(s, c, id, v)| match v {
            Verdict::Refused(line)
                if SUBCOMMANDS[*s].name == "render" && scene.contains(*id) && line.contains("has no effect") =>
            {
                Some((*c, *id, line.clone()))
            }
            _ => None,
        })
        .flat_map(|(c, id, line)| ["view", "timing"].map(|other| (c, id, line.clone(), other)))
        .collect();
    let checked = shared.len();
    let mismatches: Vec<String> = parallel(shared, |(c, id, line, other)| {
        let config = &RENDER_CONFIGS[c];
        let (_, alts) = RENDER_CASES.iter().find(|(i, _)| *i == id).expect("a case");
        let scene_args: Vec<&str> = config.args.iter().copied().filter(|a| !["--out", "out.png"].contains(a)).collect();
        let args = merged(&scene_args, &[alts[0].context, alts[0].args]);
        let output = meadow().arg(other).args(&args).env_remove("DISPLAY").output().expect("run");
        let got = String::from_utf8_lossy(&output.stderr).trim().to_string();
        (!(refused(&output) && got == line)).then(|| format!("{other} {}: {got} (render: {line})", args.join(" ")))
    })
    .into_iter()
    .flatten()
    .collect();
    assert!(checked > 0, "no shared refusal was checked");
    assert!(mismatches.is_empty(), "view/timing do not refuse what render refuses:\n{}", mismatches.join("\n"));
}

#[test]
fn every_flag_of_render_changes_the_picture_or_is_refused() {
    every_flag_changes_the_output_or_is_refused(&["render"]);
}

#[test]
fn every_flag_of_view_changes_the_session_or_is_refused() {
    every_flag_changes_the_output_or_is_refused(&["view"]);
}

#[test]
fn every_flag_of_the_measuring_tools_changes_the_output_or_is_refused() {
    every_flag_changes_the_output_or_is_refused(&["timing", "bench", "overhead"]);
}

#[test]
fn every_flag_of_keyframes_devices_and_completions_changes_the_output_or_is_refused() {
    every_flag_changes_the_output_or_is_refused(&["keyframes", "devices", "completions"]);
}

/// Each subcommand is in one of the tests above.
#[test]
fn every_subcommand_is_run_by_a_flag_test() {
    let tested = ["render", "view", "timing", "bench", "overhead", "keyframes", "devices", "completions"];
    for sub in SUBCOMMANDS {
        assert!(tested.contains(&sub.name), "{} is in no every_flag test", sub.name);
    }
}

/// Each case issue 38 names, refused with its one line before any work (the parse alone: no
/// device, no window).
#[test]
fn the_cases_the_issue_names_are_refused() {
    let scene = ["render", "view", "timing"];
    let mut cases: Vec<(Vec<&str>, &str)> = Vec::new();
    for sub in scene {
        for flag in [
            &["--view-distance", "50"][..],
            &["--lod-segments", "2,1"],
            &["--lod-scale", "2"],
            &["--cull", "frustum"],
            &["--lod", "density"],
            &["--budget-ms", "10"],
        ] {
            cases.push(([&[sub, "--brute-force"][..], flag].concat(), "with --brute-force"));
        }
        for flag in [&["--view-distance", "50"][..], &["--budget-ms", "10"], &["--debug-view", "force"]] {
            cases.push(([&[sub, "--mode", "floor"][..], flag].concat(), "with --mode floor"));
        }
        for flag in [&["--budget-ms", "10"][..], &["--lod-scale", "2"]] {
            cases.push(([&[sub, "--lod", "none"][..], flag].concat(), "with a --lod without density or segments"));
        }
        cases.push((vec![sub, "--cull", "none,frustum"], "--cull none has no effect with other tests"));
        cases.push((vec![sub, "--lod", "none,density"], "--lod none has no effect with other levels"));
        cases.push((vec![sub, "--no-alpha-to-coverage"], "--no-alpha-to-coverage has no effect with --msaa 1"));
        cases.push((vec![sub, "--blades", "100", "--density", "5"], "--density has no effect with stored blades"));
        cases.push((vec![sub, "--blades", "100", "--relief", "hills"], "--relief has no effect with stored blades"));
        cases.push((
            vec![sub, "--brute-force", "--blade-distance", "50"],
            "--blade-distance has no effect with --brute-force",
        ));
        let both = vec![sub, "--blades", "100", "--view-distance", "300", "--blade-distance", "100"];
        cases.push((both, "--view-distance has no effect with --blade-distance on stored blades"));
    }
    for sub in ["render", "timing"] {
        cases.push((vec![sub, "--clusters", "8"], "--clusters has no effect with --submission instanced"));
    }
    for flag in [&["--preset", "lod"][..], &["--blades", "10"], &["--out", "x"], &["--validation"]] {
        cases.push(([&["bench", "--compare", "a.json", "b.json"][..], flag].concat(), "has no effect with --compare"));
    }
    cases.push((vec!["bench", "--threshold", "5"], "--threshold has no effect with no --compare"));
    let outputs = parallel(cases, |(args, expect)| {
        let output = meadow().args(&args).env_remove("DISPLAY").output().expect("run");
        (args, expect, output)
    });
    for (args, expect, output) in outputs {
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            refused(&output) && stderr.contains("has no effect") && stderr.contains(expect),
            "meadow {}: expected a refusal containing '{expect}':\n{}",
            args.join(" "),
            transcript(&output)
        );
    }
}

/// `MEADOW_INJECT_*` values are checked at start: a bad one is exit 2 and one `error:` line,
/// before any log line (the logger is at its most verbose here) and before any device.
#[test]
fn injection_switches_with_bad_values_are_refused_before_anything_logs() {
    let switches = [
        "MEADOW_INJECT_ALLOC_FAILURE",
        "MEADOW_INJECT_ACQUIRE_FAILURE",
        "MEADOW_INJECT_PRESENT_FAILURE",
        "MEADOW_INJECT_HOST_MEMORY_FAILURE",
        "MEADOW_INJECT_FREE_FAILURE",
        "MEADOW_INJECT_SUBMIT_FAILURE",
        "MEADOW_INJECT_WRITE_FAILURE",
    ];
    let mut jobs = Vec::new();
    for name in switches {
        for bad in ["abc", "0", "-1", "18446744073709551616", "1:SYNC"] {
            jobs.push((name, bad));
        }
    }
    jobs.push(("MEADOW_INJECT_ALOC_FAILURE", "1"));
    let dir = scratch("flag-effects-inject");
    let outputs = parallel(jobs, |(name, bad)| {
        let output = meadow()
            .args(["render", "--blades", "100", "--size", "16x16", "--device", D, "--out"])
            .arg(dir.join(format!("{name}.png")))
            .env(name, bad)
            // A good value of another switch beside it, and the free failure that logs.
            .env(
                if name == "MEADOW_INJECT_FREE_FAILURE" {
                    "MEADOW_INJECT_ALLOC_FAILURE"
                } else {
                    "MEADOW_INJECT_FREE_FAILURE"
                },
                "1",
            )
            .env("RUST_LOG", "trace")
            .output()
            .expect("run");
        (name, bad, output)
    });
    for (name, bad, output) in outputs {
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(refused(&output), "{name}={bad}: {}", transcript(&output));
        assert!(stderr.starts_with(&format!("error: {name}=")), "{name}={bad}: {stderr}");
        assert!(!dir.join(format!("{name}.png")).exists(), "{name}={bad}: rendered");
    }
    // A good value still injects: the first allocation fails, at run time (exit 1).
    let output = meadow()
        .args(["render", "--blades", "100", "--size", "16x16", "--device", D, "--out"])
        .arg(dir.join("good.png"))
        .env("MEADOW_INJECT_ALLOC_FAILURE", "1")
        .output()
        .expect("run");
    assert_eq!(output.status.code(), Some(1), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("out of device memory"), "{}", transcript(&output));
}

/// The swapchain counts of the viewer's summary are masked, and nothing else of it is: two runs
/// that differ only in re-creations compare equal; a different present mode, frame count or
/// injected count does not.
#[test]
fn the_viewer_summary_is_compared_without_its_swapchain_counts() {
    let line = |n: u32, present: &str| {
        format!("viewer: 4 frames, {n} swapchains created (at most {n} alive at once), {n} re-creations (0 injected); present {present}, 2 frames in flight, overlay on")
    };
    assert_eq!(unclocked(&line(2, "fifo")), unclocked(&line(1, "fifo")));
    assert_ne!(unclocked(&line(1, "fifo")), unclocked(&line(1, "mailbox")));
    assert_ne!(unclocked(&line(1, "fifo").replace("4 frames", "5 frames")), unclocked(&line(1, "fifo")));
    assert_ne!(unclocked(&line(1, "fifo").replace("0 injected", "1 injected")), unclocked(&line(1, "fifo")));
}
