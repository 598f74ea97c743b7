//! The measuring subcommands `bench`, `overhead` and `timing`: their flags become the options of
//! [`crate::harness`], which runs on the chosen device behind a progress bar.

use std::path::PathBuf;

use super::args::{BenchArgs, GpuArgs, OverheadArgs, PresetArg, TimingArgs};
use super::commands::finish;
use crate::app;
use crate::harness::bench::Column;

/// Run a measuring command on the device of `gpu`: a progress bar with ETA on a terminal (none
/// otherwise) fed by `run`'s `progress(done, total)`, then `report` of its result and a `wrote`
/// line. What `run` writes is one set, the `files` in `out` (`app::output::write_set`): all of
/// it or, on a failure or a signal (Ctrl-C: exit 130; checked after every frame), none. Each file's path is
/// checked before any work (exit 2 when it exists and is not a regular file). Returns the exit
/// code and the validation count.
pub(crate) fn measure<T>(
    gpu: &GpuArgs,
    unit: &str,
    (out, files): (&std::path::Path, &[&str]),
    run: impl FnOnce(&std::sync::Arc<crate::vk::Device>, &mut dyn FnMut(u64, u64)) -> crate::Result<T>,
    report: impl FnOnce(T),
) -> (u8, Option<u64>) {
    if let Err(e) = app::output::check_set(out, files) {
        return (finish(Err(e)), None);
    }
    let bar = std::io::IsTerminal::is_terminal(&std::io::stderr()).then(|| {
        let bar = indicatif::ProgressBar::new(0);
        let template = format!("{{bar:40}} {{pos}}/{{len}} {unit}, {{elapsed}} elapsed, ETA {{eta}}");
        bar.set_style(indicatif::ProgressStyle::with_template(&template).expect("valid template"));
        bar
    });
    let (result, validation) = app::with_device(&gpu.options(), false, |device| {
        if !device.has_timestamps() {
            return Err(crate::Error::Environment(format!(
                "{} cannot write timestamps on its queue: GPU times cannot be measured",
                device.info.name
            )));
        }
        app::output::write_set(out, || {
            run(device, &mut |done, total| {
                if let Some(bar) = &bar {
                    bar.set_length(total);
                    bar.set_position(done);
                }
            })
        })
    });
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let wrote = |doc| {
        report(doc);
        let (last, first) = files.split_last().expect("a set has files");
        let first = if first.is_empty() { String::new() } else { format!("{} and ", first.join(", ")) };
        println!("wrote {}/{first}{last}", out.display());
    };
    (finish(result.map(wrote)), validation)
}

/// `meadow timing`. Returns the exit code and validation count.
pub(crate) fn timing(args: TimingArgs) -> (u8, Option<u64>) {
    use crate::harness::timing::{self, TimingOptions};
    let mut render = args.scene.options(PathBuf::new(), args.frames);
    render.submission = args.submission.submission();
    if args.frames < 2 {
        let e = format!("--frames {}: timing measures the intervals between frames (2 at least)", args.frames);
        return (finish(Err(crate::Error::bad_input(e))), None);
    }
    let options = TimingOptions { render, warmup: args.warmup, trace: args.trace, out: args.out, fly: args.fly };
    let trace = options.trace.iter().map(|t| ("--trace", t.clone()));
    if let Err(e) = app::output::check_distinct(app::output::set_members(&options.out, &timing::FILES).chain(trace)) {
        return (finish(Err(e)), None);
    }
    measure(
        &args.gpu,
        "frames",
        (&options.out, &timing::FILES),
        |device, progress| {
            let (doc, intervals) = timing::run(device, &options, progress)?;
            timing::write(&doc, &intervals, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", timing::report(&doc));
            if let Some(trace) = &options.trace {
                println!("wrote {}", trace.display());
            }
        },
    )
}

/// `meadow overhead`. Returns the exit code and validation count.
pub(crate) fn overhead(args: OverheadArgs) -> (u8, Option<u64>) {
    use crate::harness::overhead::{self, OverheadOptions};
    let options = OverheadOptions {
        blades: args.blades,
        segments: args.segments,
        clusters: args.clusters,
        strategies: args.strategies,
        size: args.size,
        warmup: args.warmup,
        frames: args.frames,
        out: args.out,
    };
    measure(
        &args.gpu,
        "frames",
        (&options.out, &overhead::FILES),
        |device, progress| {
            let doc = overhead::run(device, &options, progress)?;
            overhead::write(&doc, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", overhead::table(&doc));
        },
    )
}

/// `meadow bench`: measure, or compare two runs. Returns the exit code and validation count.
pub(crate) fn bench(args: BenchArgs) -> crate::Result<(u8, Option<u64>)> {
    use crate::harness::bench;
    if let [old, new] = args.compare.as_slice() {
        let (report, regressed) = bench::compare(&bench::load(old)?, &bench::load(new)?, f64::from(args.threshold))?;
        print!("{report}");
        return Ok((u8::from(regressed), None));
    }
    let mut options = match args.preset {
        PresetArg::Thesis => bench::BenchOptions::thesis(args.out.clone()),
        PresetArg::Quick => bench::BenchOptions::quick(args.out.clone()),
        PresetArg::Lod => return lod(args),
        PresetArg::Msaa => return msaa(args),
        PresetArg::Animations => return animations(args),
        PresetArg::Response => return response(args),
        PresetArg::Landscape => return pair_preset(args, Pairs::Landscape),
        PresetArg::Plants => return pair_preset(args, Pairs::Plants),
        PresetArg::Interaction => return pair_preset(args, Pairs::Interaction),
        PresetArg::Far => return pair_preset(args, Pairs::Far),
    };
    let preset_blades: Vec<u32> = options.rows.iter().map(|r| r.0).collect();
    let preset_segments: Vec<u32> = options.rows.iter().map(|r| r.1).collect();
    if !args.blades.is_empty() || !args.segments.is_empty() {
        let blades = if args.blades.is_empty() { dedup(preset_blades) } else { args.blades.clone() };
        let segments = if args.segments.is_empty() { dedup(preset_segments) } else { args.segments.clone() };
        options.rows = segments.iter().flat_map(|s| blades.iter().map(move |b| (*b, *s))).collect();
    }
    if !args.modes.is_empty() {
        options.modes = args.modes.iter().map(|&m| Column::from(m)).collect();
    }
    if !args.eval.is_empty() {
        // The thesis benchmark draws every blade (brute force): `auto` is per vertex there.
        options.evals = args.eval.iter().map(|&e| e.resolve(false)).collect();
    }
    options.size = args.size.unwrap_or(options.size);
    options.warmup = args.warmup.unwrap_or(options.warmup);
    options.frames = args.frames.unwrap_or(options.frames);
    Ok(measure(
        &args.gpu,
        "frames",
        (&options.out, &bench::FILES),
        |device, progress| {
            let doc = bench::run(device, &options, progress)?;
            bench::write(&doc, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", bench::table(&doc));
            print!("\n{}", bench::statistics_table(&doc));
        },
    ))
}

/// `meadow bench --preset lod`. `--modes` and `--eval` do not apply (it renders the default
/// animation both ways; `cli::effect` refuses them); `--blades` and `--segments` take one value
/// each.
fn lod(args: BenchArgs) -> crate::Result<(u8, Option<u64>)> {
    use crate::harness::bench::lod::{self, LodBenchOptions};
    let mut options = LodBenchOptions::preset(args.out.clone());
    if let Some(blades) = at_most_one(&args.blades, "--preset lod takes one --blades count (the stored field's)")? {
        options.set_stored_blades(blades);
    }
    if let Some(segments) = at_most_one(&args.segments, "--preset lod takes one --segments count")? {
        options.segments = segments;
    }
    options.size = args.size.unwrap_or(options.size);
    options.warmup = args.warmup.unwrap_or(options.warmup);
    options.frames = args.frames.unwrap_or(options.frames);
    Ok(measure(
        &args.gpu,
        "frames",
        (&options.out, &lod::FILES),
        |device, progress| {
            let doc = lod::run(device, &options, progress)?;
            lod::write(&doc, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", lod::table(&doc));
        },
    ))
}

/// `meadow bench --preset msaa`: the default scene's blade count (one), size, warm-up and
/// frames can be changed; modes, evaluation placements and segment counts cannot (`cli::effect`
/// refuses them).
fn msaa(args: BenchArgs) -> crate::Result<(u8, Option<u64>)> {
    use crate::harness::bench::msaa::{self, MsaaBenchOptions};
    let mut options = MsaaBenchOptions::preset(args.out.clone());
    if let Some(blades) = at_most_one(&args.blades, "--preset msaa takes one --blades count")? {
        options.blades = blades;
    }
    options.size = args.size.unwrap_or(options.size);
    options.warmup = args.warmup.unwrap_or(options.warmup);
    options.frames = args.frames.unwrap_or(options.frames);
    Ok(measure(
        &args.gpu,
        "frames",
        (&options.out, &msaa::FILES),
        |device, progress| {
            let run = msaa::run(device, &options, progress)?;
            msaa::write(&run, &options.out)?;
            Ok(run.doc)
        },
        |doc| {
            print!("{}", msaa::table(&doc));
        },
    ))
}

/// `meadow bench --preset animations`: `--animations` picks the responses, `--blades` (one value)
/// every stored field's count; size, warm-up and frames can be changed; modes, evaluation
/// placements and segment counts cannot (`cli::effect` refuses them).
fn animations(args: BenchArgs) -> crate::Result<(u8, Option<u64>)> {
    use crate::harness::bench::animations::{self, AnimationsBenchOptions};
    let mut options = AnimationsBenchOptions::preset(args.out.clone());
    if let Some(blades) = at_most_one(&args.blades, "--preset animations takes one --blades count")? {
        options.set_blades(blades);
    }
    if !args.animations.is_empty() {
        let keyframes = super::animation::ModeArg::Texture;
        options.animations = args.animations.iter().map(|a| a.mode(keyframes)).collect();
    }
    options.wind_fields.extend(args.wind_fields.iter().map(|f| f.kind()).filter(|f| *f != Default::default()));
    options.size = args.size.unwrap_or(options.size);
    options.warmup = args.warmup.unwrap_or(options.warmup);
    options.frames = args.frames.unwrap_or(options.frames);
    Ok(measure(
        &args.gpu,
        "frames",
        (&options.out, &animations::FILES),
        |device, progress| {
            let doc = animations::run(device, &options, progress)?;
            animations::write(&doc, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", animations::table(&doc));
        },
    ))
}

/// `meadow bench --preset response`: `--animations` picks the responses; the field, the gust and
/// the frames are fixed (`cli::effect` refuses the flags that would change them).
fn response(args: BenchArgs) -> crate::Result<(u8, Option<u64>)> {
    use crate::harness::bench::response::{self, ResponseBenchOptions};
    let mut options = ResponseBenchOptions::preset(args.out.clone());
    if !args.animations.is_empty() {
        let keyframes = super::animation::ModeArg::Texture;
        options.animations = args.animations.iter().map(|a| a.mode(keyframes)).collect();
    }
    response::check(&options)?;
    Ok(measure(
        &args.gpu,
        "frames",
        (&options.out, &response::FILES),
        |device, progress| {
            let doc = response::run(device, &options, progress)?;
            response::write(&doc, &options.out)?;
            Ok(doc)
        },
        |doc| print!("{}", response::table(&doc)),
    ))
}

/// A benchmark of pairs side by side (`harness::bench::pairs`).
#[derive(Clone, Copy)]
enum Pairs {
    /// `--preset landscape` (issue #35).
    Landscape,
    /// `--preset plants` (issue #36).
    Plants,
    /// `--preset interaction` (issue #34).
    Interaction,
    /// `--preset far` (issue #37).
    Far,
}

/// `meadow bench --preset landscape`, `plants`, `interaction` or `far`: size, warm-up and frames can be changed; blade
/// counts, segments, modes and evaluation placements cannot (`cli::effect` refuses them).
fn pair_preset(args: BenchArgs, preset: Pairs) -> crate::Result<(u8, Option<u64>)> {
    use crate::harness::bench::{far, interaction, landscape, pairs::PairBenchOptions, plants};
    let mut options = PairBenchOptions::preset(args.out.clone());
    options.size = args.size.unwrap_or(options.size);
    options.warmup = args.warmup.unwrap_or(options.warmup);
    options.frames = args.frames.unwrap_or(options.frames);
    let files: &[&str] = match preset {
        Pairs::Landscape => &landscape::FILES,
        Pairs::Plants => &plants::FILES,
        Pairs::Interaction => &interaction::FILES,
        Pairs::Far => &far::FILES,
    };
    Ok(measure(
        &args.gpu,
        "frames",
        (&options.out, files),
        |device, progress| {
            Ok(match preset {
                Pairs::Landscape => {
                    let doc = landscape::run(device, &options, progress)?;
                    landscape::write(&doc, &options.out)?;
                    landscape::table(&doc)
                }
                Pairs::Plants => {
                    let doc = plants::run(device, &options, progress)?;
                    plants::write(&doc, &options.out)?;
                    plants::table(&doc)
                }
                Pairs::Interaction => {
                    let doc = interaction::run(device, &options, progress)?;
                    interaction::write(&doc, &options.out)?;
                    interaction::table(&doc)
                }
                Pairs::Far => {
                    let doc = far::run(device, &options, progress)?;
                    far::write(&doc, &options.out)?;
                    far::table(&doc)
                }
            })
        },
        |table| print!("{table}"),
    ))
}

/// The one value of a list flag a preset takes at most once, or `message` as bad input.
fn at_most_one(values: &[u32], message: &str) -> crate::Result<Option<u32>> {
    match values {
        [] => Ok(None),
        &[value] => Ok(Some(value)),
        _ => Err(crate::Error::bad_input(message)),
    }
}

/// `values` sorted, each once.
fn dedup(mut values: Vec<u32>) -> Vec<u32> {
    values.sort_unstable();
    values.dedup();
    values
}
