//! `meadow timing`: where a frame's time goes. The scene of `meadow render` is rendered with 1,
//! 2 and 3 frames in flight; for every frame the CPU spans (record, submit, fence wait) and the
//! GPU spans (each pass, from timestamps) are kept. Reported: per-pass GPU percentiles and
//! pipeline statistics, a frame-interval histogram, throughput and CPU–GPU overlap per number of
//! frames in flight, and a Chrome-trace / Perfetto JSON with CPU and GPU spans on one timeline.
//!
//! The timeline: with `VK_EXT_calibrated_timestamps` (device and CLOCK_MONOTONIC domains) the
//! GPU clock is mapped to the CPU's by a calibration taken before each run, and the mapping's
//! maximum deviation is reported. Without it, the offset is estimated from the first frame:
//! its last GPU timestamp cannot be later than the CPU's return from its fence wait, which
//! gives an upper bound, reported as such.

use crate::render::animation::clock::StepClock;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use crate::app::RenderOptions;
use crate::error::{Error, Result, VkContext};
use crate::harness::document::{statistics, CullSummary, Header, Summary};
pub(crate) use crate::harness::measure::Frame;
use crate::harness::measure::{measure, Schedule, Subject};
use crate::harness::Progress;
use crate::render::graph::Outputs;
use crate::render::renderer::FrameSync;
use crate::render::target::TargetView;
use crate::render::{OffscreenTarget, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::{Access, Device};

pub mod document;
pub mod flight;

pub use document::{ClockRecord, PassSummary, RunSummary, SubmissionSummary, TimingDocument};

/// What to measure.
#[derive(Clone, Debug)]
pub struct TimingOptions {
    /// The scene, as `meadow render` builds it (`frames` is the frames per run).
    pub render: RenderOptions,
    /// Frames discarded at the start of each run.
    pub warmup: u32,
    /// Chrome-trace JSON to write, if any.
    pub trace: Option<PathBuf>,
    /// Directory for timing.json and the histogram.
    pub out: PathBuf,
    /// `--fly`: the camera's speed along its heading (m/s), if it moves.
    pub fly: Option<f32>,
}

/// How GPU timestamps map to CPU time.
#[derive(Clone, Copy, Debug)]
pub struct ClockMapping {
    /// CPU instant of GPU time `gpu_ns`.
    pub cpu: Instant,
    /// GPU timestamp (ns, masked and scaled) at `cpu`.
    pub gpu_ns: f64,
    /// Uncertainty of the mapping (ns): the calibration's maximum deviation plus the time the
    /// CPU clock reads took; or, estimated, the length of the chosen frame's fence wait (when it
    /// blocked, the GPU finished within it; when it did not, the bound is looser than this says).
    pub deviation_ns: f64,
    /// `calibrated` (VK_EXT_calibrated_timestamps) or `estimated` (fence-return bound).
    pub method: &'static str,
}

impl ClockMapping {
    /// Seconds from `anchor` at which GPU time `gpu_ns` happened.
    pub fn seconds_since(&self, anchor: Instant, gpu_ns: f64) -> f64 {
        let base =
            if self.cpu >= anchor { (self.cpu - anchor).as_secs_f64() } else { -(anchor - self.cpu).as_secs_f64() };
        base + (gpu_ns - self.gpu_ns) * 1e-9
    }
}

/// Sample the device clock and CLOCK_MONOTONIC together (VK_EXT_calibrated_timestamps), and
/// `Instant` around the call; `None` without the extension.
pub fn calibrate(device: &Device) -> Result<Option<ClockMapping>> {
    let Some(ext) = &device.calibrated_timestamps else { return Ok(None) };
    let infos = [
        vk::CalibratedTimestampInfoEXT::default().time_domain(vk::TimeDomainEXT::DEVICE),
        vk::CalibratedTimestampInfoEXT::default().time_domain(vk::TimeDomainEXT::CLOCK_MONOTONIC),
    ];
    let before = Instant::now();
    // SAFETY: the extension is enabled and both domains are calibrateable (checked at creation).
    let (stamps, deviation) = unsafe { ext.get_calibrated_timestamps(&infos) }.vk("vkGetCalibratedTimestampsEXT")?;
    let after = Instant::now();
    let valid = device.timestamp_valid_bits;
    let mask = if valid >= 64 { u64::MAX } else { (1u64 << valid) - 1 };
    // Placed on the frames' timeline by `run_one` (the counter may wrap between here and them).
    let gpu_ns = (stamps[0] & mask) as f64;
    // `Instant` reads CLOCK_MONOTONIC on Linux but hides its value: the midpoint of the two reads
    // around the call stands for the calibrated sample, within half their distance.
    let half = (after - before) / 2;
    Ok(Some(ClockMapping {
        cpu: before + half,
        gpu_ns,
        deviation_ns: deviation as f64 + half.as_secs_f64() * 1e9,
        method: "calibrated",
    }))
}

/// A run with `frames_in_flight` frames in flight.
pub(crate) struct Run {
    pub(crate) frames_in_flight: usize,
    pub(crate) frames: Vec<Frame>,
    pub(crate) mapping: ClockMapping,
    pub(crate) started: Instant,
    pub(crate) ended: Instant,
}

/// The subject of a run: one renderer with frames in flight into one offscreen target. A frame
/// is submitted without waiting; the frame that comes back is the one its slot held before.
struct Pipelined<'a> {
    renderer: &'a mut Renderer,
    view: TargetView,
    camera: Camera,
    /// `--fly`: the camera of each frame, over the scene.
    flight: Option<(flight::Flight, &'a Scene)>,
    /// The step of frame 0, the last at or before `--time` (frame n draws the step n after it).
    first_step: u64,
    /// The fixed step (`--dt`).
    clock: StepClock,
    /// Per slot, the index of the frame in it.
    in_flight: Vec<Option<u32>>,
}

impl Pipelined<'_> {
    /// The next slot, and the frame it held (its timings now read back).
    fn next_slot(&mut self) -> Result<(usize, Option<Frame>)> {
        let (slot, done) = self.renderer.begin_frame()?;
        let index = self.in_flight[slot].take();
        Ok((slot, done.zip(index).map(|(timings, index)| Frame { index, timings })))
    }
}

impl Subject for Pipelined<'_> {
    fn variants(&self) -> usize {
        1
    }

    fn frame(&mut self, _: usize, round: u32) -> Result<Option<Frame>> {
        let (slot, done) = self.next_slot()?;
        let time = self.clock.time_of(self.first_step + u64::from(round)) as f32;
        let camera = self.flight.map_or(self.camera, |(flight, scene)| flight.camera(scene, round));
        self.renderer.submit_frame(slot, &self.view, &camera, time, FrameSync::default(), Outputs::default())?;
        self.in_flight[slot] = Some(round);
        // Each frame's first barrier waits for the previous frame's attachment writes (same queue).
        self.view.color_previous = Access::ColorAttachmentWrite;
        if self.renderer.uses_target_depth() {
            self.view.depth_previous = Access::DepthAttachmentReadWrite;
        }
        Ok(done)
    }

    /// Each slot's last frame.
    fn drain(&mut self, _: usize) -> Result<Vec<Frame>> {
        let mut frames = Vec::new();
        for _ in 0..self.in_flight.len() {
            frames.extend(self.next_slot()?.1);
        }
        Ok(frames)
    }
}

/// Render `frames` frames with `frames_in_flight` in flight into one offscreen target, through
/// the measuring loop.
fn run_one(
    device: &Arc<Device>,
    scene: &Scene,
    options: &TimingOptions,
    frames_in_flight: usize,
    progress: &mut Progress,
) -> Result<Run> {
    let render = &options.render;
    let settings = render.offscreen_settings(frames_in_flight);
    let mut renderer = Renderer::new(device.clone(), scene, settings, render.animation.clone())?;
    let extent = vk::Extent2D { width: render.size.0, height: render.size.1 };
    let target = OffscreenTarget::new(device, extent)?;
    let camera = scene.camera(render.camera);
    let result = (|| {
        let calibrated = super::trace::calibrated(device, &mut renderer)?;
        let started = Instant::now();
        let mut subject = Pipelined {
            renderer: &mut renderer,
            view: target.view(),
            camera,
            flight: options
                .fly
                .map(|speed| (flight::Flight::new(scene, camera, speed, render.animation.clock.dt), scene)),
            first_step: render.animation.clock.steps_to(render.time.into()),
            clock: render.animation.clock,
            in_flight: vec![None; frames_in_flight],
        };
        // Ctrl-C stops at a frame (the renderer waits for what is in flight on drop).
        let schedule = Schedule { warmup: options.warmup, frames: render.frames };
        let measured = measure(&mut subject, schedule, progress)?;
        let ended = Instant::now();
        let mut frames = measured.into_frames().pop().expect("one variant");
        let mapping = match calibrated {
            Some(mapping) => mapping,
            None => estimated_mapping(&frames, started, ended)?,
        };
        frames.retain(|f| f.index >= options.warmup);
        Ok(Run { frames_in_flight, frames, mapping, started, ended })
    })();
    drop(renderer);
    // SAFETY: the renderer waited for its frames when dropped.
    unsafe { target.destroy(device) };
    result
}

/// The mapping of GPU to CPU time without calibrated timestamps, from `frames` (in order) rendered
/// between `started` and `ended`.
pub(crate) fn estimated_mapping(frames: &[Frame], started: Instant, ended: Instant) -> Result<ClockMapping> {
    // Each frame's GPU end happened before its fence wait returned: an upper bound of
    // the offset per frame. The tightest is the frame whose wait returned soonest after
    // its GPU end (with frames in flight, a wait may start long after that frame ended).
    let first = frames.first().ok_or_else(|| Error::bad_input("no frame rendered"))?;
    let reference = first.timings.gpu_span_ns.1;
    let best = frames.iter().filter_map(|f| Some((f, f.timings.cpu_wait?[1]))).min_by(|(a, ra), (b, rb)| {
        let bound =
            |f: &Frame, r: &Instant| (*r - started).as_secs_f64() - (f.timings.gpu_span_ns.1 - reference) * 1e-9;
        bound(a, ra).total_cmp(&bound(b, rb))
    });
    let (frame, returned) = best.map_or((first, ended), |(f, r)| (f, r));
    let wait = frame.timings.cpu_wait.map_or(0.0, |w| (w[1] - w[0]).as_secs_f64() * 1e9);
    Ok(ClockMapping { cpu: returned, gpu_ns: frame.timings.gpu_span_ns.1, deviation_ns: wait, method: "estimated" })
}

/// Intersection length of two sorted lists of disjoint intervals.
fn overlap(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let (mut i, mut j, mut total) = (0, 0, 0.0);
    while i < a.len() && j < b.len() {
        let start = a[i].0.max(b[j].0);
        let end = a[i].1.min(b[j].1);
        if end > start {
            total += end - start;
        }
        if a[i].1 < b[j].1 {
            i += 1;
        } else {
            j += 1;
        }
    }
    total
}

/// What a run did, on the CPU timeline (seconds since `anchor`): per frame the CPU's record +
/// submit span, its recording alone (which cannot overlap its own frame's GPU work, unlike the
/// submission, during which the queue may already start), and the GPU span.
struct Spans {
    cpu: Vec<(f64, f64)>,
    recording: Vec<(f64, f64)>,
    gpu: Vec<(f64, f64)>,
}

fn spans(run: &Run, anchor: Instant) -> Spans {
    let since = |t: Instant| (t - anchor).as_secs_f64();
    let mut cpu = Vec::new();
    let mut recording = Vec::new();
    let mut gpu = Vec::new();
    for f in &run.frames {
        if let Some([started, recorded, submitted]) = f.timings.cpu_spans {
            cpu.push((since(started), since(submitted)));
            recording.push((since(started), since(recorded)));
        }
        let (a, b) = f.timings.gpu_span_ns;
        gpu.push((run.mapping.seconds_since(anchor, a), run.mapping.seconds_since(anchor, b)));
    }
    Spans { cpu, recording, gpu }
}

/// Run the measurement; `progress(done, total)` after every frame. Returns the document and the
/// frame intervals (ms) of the 2-in-flight run, for the histogram.
pub fn run(
    device: &Arc<Device>,
    options: &TimingOptions,
    mut progress: impl FnMut(u64, u64),
) -> Result<(TimingDocument, Vec<f64>)> {
    let render = &options.render;
    if let Some(trace) = &options.trace {
        crate::app::output::check_output(trace, "--trace")?;
    }
    render.check_field()?;
    render.check_clusters()?;
    let blades = render.stored_blades();
    crate::app::check_scene(
        device,
        blades,
        render.segments,
        render.size,
        &render.animation,
        render.floor,
        (render.culling.enabled, render.msaa, render.offscreen_settings(1).linear_scene()),
    )?;
    let scene = render.scene()?;
    const IN_FLIGHT: [usize; 3] = [1, 2, 3];
    let total = IN_FLIGHT.len() as u64 * u64::from(options.warmup + render.frames);
    let mut frames = Progress::new(total, &mut progress);
    let mut runs = Vec::new();
    for fif in IN_FLIGHT {
        runs.push(run_one(device, &scene, options, fif, &mut frames)?);
    }
    let anchor = runs[0].started;
    let mut comparison = Vec::new();
    let mut intervals_2 = Vec::new();
    for run in &runs {
        let (entry, intervals) = compare_run(run, anchor);
        if run.frames_in_flight == 2 {
            intervals_2 = intervals;
        }
        comparison.push(entry);
    }
    // Per-pass percentiles and statistics: the 1-in-flight run, where frames do not queue.
    let base = &runs[0];
    let passes = pass_percentiles(base);
    let of = |f: fn(&Frame) -> f64| Summary::of(&base.frames.iter().map(f).collect::<Vec<f64>>());
    let last = base.frames.last();
    let doc = TimingDocument {
        header: Header::new(device, "timing", render.size),
        blades: render.blades,
        segments: render.segments,
        mode: if render.floor { "floor".into() } else { format!("{:?}", render.animation.mode).to_lowercase() },
        warmup: options.warmup,
        frames_per_run: render.frames,
        dt_s: Some(render.animation.clock.dt),
        fly_m_per_s: options.fly,
        submission: Some(SubmissionSummary {
            strategy: render.submission.strategy.name().to_string(),
            clusters: render.submission.clusters,
        }),
        blades_per_instance: Some(render.blades_per_instance),
        timestamp_period_ns: f64::from(device.limits().timestamp_period),
        timestamp_valid_bits: device.timestamp_valid_bits,
        calibrated_timestamps: device.calibrated_timestamps.is_some(),
        gpu_frame_ms: of(|f| f.timings.gpu_ms),
        cpu_record_ms: of(|f| f.timings.cpu_record_ms),
        cpu_submit_ms: of(|f| f.timings.cpu_submit_ms),
        passes,
        pipeline_statistics: last.map(|f| statistics(&f.timings.passes)),
        cull: last.and_then(|f| f.timings.cull.as_ref()).map(CullSummary::of),
        frames_in_flight: comparison,
    };
    if let Some(path) = &options.trace {
        crate::app::write_text(path, &serde_json::to_string(&super::trace::trace(&runs, anchor)).expect("serialises"))?;
    }
    Ok((doc, intervals_2))
}

/// A run's entry of the frames-in-flight comparison, and its frame intervals (ms between
/// consecutive GPU frame ends).
fn compare_run(run: &Run, anchor: Instant) -> (RunSummary, Vec<f64>) {
    let s = spans(run, anchor);
    let wall = (run.ended - run.started).as_secs_f64();
    let measured = s.gpu.last().map_or(0.0, |g| g.1) - s.cpu.first().map_or(0.0, |c| c.0);
    let gpu_busy: f64 = s.gpu.iter().map(|g| g.1 - g.0).sum();
    let cpu_busy: f64 = s.cpu.iter().map(|c| c.1 - c.0).sum();
    let recording: f64 = s.recording.iter().map(|c| c.1 - c.0).sum();
    let both = overlap(&s.recording, &s.gpu);
    let waits: Vec<f64> = run.frames.iter().map(|f| f.timings.cpu_wait_ms).collect();
    // Frame interval: between consecutive GPU frame ends, what a viewer would see.
    let intervals: Vec<f64> = s.gpu.windows(2).map(|w| (w[1].1 - w[0].1) * 1e3).collect();
    let entry = RunSummary {
        frames_in_flight: run.frames_in_flight,
        frames: run.frames.len(),
        fps: if measured > 0.0 { run.frames.len() as f64 / measured } else { 0.0 },
        wall_s: wall,
        gpu_busy_fraction: if measured > 0.0 { gpu_busy / measured } else { 0.0 },
        cpu_work_ms_per_frame: cpu_busy * 1e3 / run.frames.len().max(1) as f64,
        cpu_gpu_overlap_fraction: if recording > 0.0 { both / recording } else { 0.0 },
        cpu_wait_ms: Summary::of(&waits),
        frame_interval_ms: Summary::of(&intervals),
        clock: ClockRecord { method: run.mapping.method.into(), deviation_ns: run.mapping.deviation_ns },
    };
    (entry, intervals)
}

/// Per pass (in order of first appearance), the summary of its GPU times over the frames of `base`.
fn pass_percentiles(base: &Run) -> Vec<PassSummary> {
    let mut names: Vec<&str> = Vec::new();
    for f in &base.frames {
        for p in &f.timings.passes {
            if !names.contains(&p.name) {
                names.push(p.name);
            }
        }
    }
    names
        .iter()
        .map(|name| {
            let ms: Vec<f64> = base
                .frames
                .iter()
                .flat_map(|f| f.timings.passes.iter().filter(|p| p.name == *name).map(|p| p.ms))
                .collect();
            PassSummary { pass: name.to_string(), gpu_ms: Summary::of(&ms) }
        })
        .collect()
}

/// The report printed by `meadow timing`.
pub fn report(doc: &TimingDocument) -> String {
    let mut out = String::new();
    if let Some(speed) = doc.fly_m_per_s {
        out.push_str(&format!("the camera flies along its heading at {speed} m/s\n"));
    }
    out.push_str(&format!(
        "{:<14} {:>9} {:>9} {:>9} {:>9} {:>9}   (1 frame in flight, {} frames)\n",
        "GPU ms", "median", "p5", "p95", "p99", "max", doc.frames_per_run
    ));
    let line = |name: &str, s: &Summary| {
        let max = s.max.unwrap_or(s.p99);
        format!("{name:<14} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {max:>9.3}\n", s.median, s.p5, s.p95, s.p99)
    };
    out.push_str(&line("frame", &doc.gpu_frame_ms));
    for p in &doc.passes {
        out.push_str(&line(&p.pass, &p.gpu_ms));
    }
    if let Some(c) = &doc.cull {
        out.push_str(&format!(
            "cull: {} considered, {} after the tiles, {} density, {} frustum, {} orientation, {} occlusion: {} drawn, {} triangles (last frame)\n",
            c.considered,
            c.after_tiles,
            c.after_density,
            c.after_frustum,
            c.after_orientation,
            c.after_occlusion,
            c.drawn,
            c.triangles
        ));
    }
    out.push_str(&line("cpu record", &doc.cpu_record_ms));
    out.push_str(&line("cpu submit", &doc.cpu_submit_ms));
    out.push_str(&format!(
        "\n{:<14} {:>12} {:>12} {:>12} {:>12}\n",
        "statistics", "vertices", "VS invoc.", "clip prims", "FS invoc."
    ));
    for (pass, s) in doc.pipeline_statistics.iter().flatten() {
        out.push_str(&format!(
            "{:<14} {:>12} {:>12} {:>12} {:>12}\n",
            pass, s.input_vertices, s.vertex_invocations, s.clipping_primitives, s.fragment_invocations
        ));
    }
    out.push_str(&format!(
        "\n{:>9} {:>8} {:>9} {:>11} {:>12} {:>11} {:>14}  clock\n",
        "in flight", "fps", "GPU busy", "CPU ms/fr", "CPU∩GPU", "wait ms", "interval p95"
    ));
    for r in &doc.frames_in_flight {
        out.push_str(&format!(
            "{:>9} {:>8.2} {:>8.1}% {:>11.3} {:>11.1}% {:>11.2} {:>14.2}  {} ±{:.1} µs\n",
            r.frames_in_flight,
            r.fps,
            100.0 * r.gpu_busy_fraction,
            r.cpu_work_ms_per_frame,
            100.0 * r.cpu_gpu_overlap_fraction,
            r.cpu_wait_ms.median,
            r.frame_interval_ms.p95,
            r.clock.method,
            r.clock.deviation_ns * 1e-3,
        ));
    }
    out.push_str(
        "GPU busy: GPU frame spans over the run; CPU∩GPU: share of the CPU's recording time during \
         which the GPU was rendering an earlier frame (~0 % with one frame in flight: it waits for each)\n",
    );
    out
}

/// Write timing.json and timing.png (histogram of the frame intervals with 2 frames in flight)
/// into `dir`.
/// The files of a run, one set (the trace, when asked for, is written apart): the report and the
/// histogram of frame intervals.
pub const FILES: [&str; 2] = ["timing.json", "timing.png"];

pub fn write(doc: &TimingDocument, intervals: &[f64], dir: &std::path::Path) -> Result<()> {
    let [json, chart] = FILES;
    crate::app::write_text(&dir.join(json), &crate::harness::document::to_json(doc))?;
    let title = format!("Frame intervals, 2 in flight: {} blades x {} seg, {}", doc.blades, doc.segments, doc.mode);
    let bins = (intervals.len() / 3).clamp(5, 40);
    crate::harness::plot::histogram(&dir.join(chart), (1000, 560), &title, "ms between GPU frame ends", intervals, bins)
}
