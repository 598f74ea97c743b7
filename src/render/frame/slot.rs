//! One frame in flight: what it owns (`Frame`), what it measured (`FrameTimings`), and what a
//! kept recording was made for (`Replay`).

use std::time::Instant;

use ash::vk;

use crate::error::Result;
use crate::render::culling::CullCounts;
use crate::render::frame::Deletion;
use crate::render::graph::{Outputs, RecordedPass, Scopes};
use crate::render::target::TargetView;
use crate::vk::commands::CommandRecorder;
use crate::vk::query::{PipelineStatistics, StatisticsQueries, Timeline, TimestampQueries};
use crate::vk::tracker::ResourceStates;
use crate::vk::{sync, Buffer, BufferDesc, Destroy, Device, Guard};

/// Passes a frame's queries measure before they grow: the frame's plan sizes them
/// (`Frame::reserve_queries`), so any number of passes is measured.
const FIRST_PASSES: u32 = 16;

/// GPU time of one pass.
#[derive(Clone, Copy, Debug)]
pub struct PassTime {
    /// Pass name.
    pub name: &'static str,
    /// Milliseconds.
    pub ms: f64,
    /// Start, in nanoseconds of the device's timestamp clock (masked, scaled).
    pub start_ns: f64,
    /// What the pass made the pipeline do, when statistics were asked for and supported.
    pub statistics: Option<PipelineStatistics>,
}

/// GPU time of one named step of a pass (`graph::Declaration::step`).
#[derive(Clone, Copy, Debug)]
pub struct StepTime {
    /// The pass's name.
    pub pass: &'static str,
    /// The step's name.
    pub name: &'static str,
    /// Milliseconds, its barriers included.
    pub ms: f64,
}

/// What one frame cost.
#[derive(Clone, Debug, Default)]
pub struct FrameTimings {
    /// CPU time to record the command buffer.
    pub cpu_record_ms: f64,
    /// CPU time of `vkQueueSubmit2`.
    pub cpu_submit_ms: f64,
    /// CPU time blocked on the frame fence.
    pub cpu_wait_ms: f64,
    /// GPU time of the frame's passes: from its first timestamp to the end of its last pass (0
    /// when `gpu_available` is false).
    pub gpu_ms: f64,
    /// Whether the GPU times were measured: false when the queue cannot write timestamps
    /// (`timestampValidBits` = 0); every GPU time then reads 0 and is reported "unavailable".
    pub gpu_available: bool,
    /// GPU time after the passes: the copy of the picture to the host (`render`, the harness),
    /// reported apart from `gpu_ms`.
    pub readback_ms: f64,
    /// GPU time inside `gpu_ms` outside every pass: from the frame's first timestamp to the first
    /// pass's start and from each pass's end to the next one's start (the device scheduling the
    /// next command; barriers are inside the pass they precede).
    pub between_passes_ms: f64,
    /// GPU time per pass.
    pub passes: Vec<PassTime>,
    /// GPU time of the passes' named steps, inside their pass's time.
    pub steps: Vec<StepTime>,
    /// Whether the frame was a kept recording submitted again (`Prerecorded`), not recorded.
    pub replayed: bool,
    /// First and last timestamp of the frame, in nanoseconds of the device's timestamp clock.
    pub gpu_span_ns: (f64, f64),
    /// When recording started, ended, and submission returned (`None` only in `Default`).
    pub cpu_spans: Option<[Instant; 3]>,
    /// When the fence wait before reading these timings started and ended.
    pub cpu_wait: Option<[Instant; 2]>,
    /// What the cull kept and drew (`None` with `--brute-force`; filled in by the cull's own part
    /// of the frame, `passes::cull::CullFrame`).
    pub cull: Option<CullCounts>,
}

/// Everything a recording names besides the renderer's own objects: its target and outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReplayKey {
    images: [vk::Image; 2],
    views: [vk::ImageView; 2],
    extent: vk::Extent2D,
    readback: Option<vk::Buffer>,
    present: bool,
}

impl ReplayKey {
    /// The key of a frame into `target` with `outputs`.
    pub fn new(target: &TargetView, outputs: Outputs) -> Self {
        Self {
            images: [target.color, target.depth],
            views: [target.color_view, target.depth_view],
            extent: target.extent,
            readback: outputs.readback,
            present: outputs.present,
        }
    }
}

/// A command buffer kept for replay (the `Prerecorded` submission): what it was recorded for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Replay {
    /// The target and outputs it was recorded for.
    pub target: ReplayKey,
    /// The resource states its barriers assumed at its start.
    pub entry: ResourceStates,
    /// The states it leaves.
    pub exit: ResourceStates,
    /// What its passes' commands were a function of (`graph::Plan::replay`).
    pub passes: Vec<u64>,
}

/// What the ring owns of one frame in flight: its commands, fence, queries and kept recording.
/// The fence guards it and every subsystem's part of the same slot (`PerFrame`: the uniforms and
/// set 0, the forces, the cull's counts): the CPU waits on it before reusing the command buffer,
/// rewriting any of those parts, reading the queries or running the deletions queued behind
/// this frame.
pub struct Frame {
    /// Command pool and buffer, reset each use.
    pub recorder: CommandRecorder,
    /// Signalled when this frame's submission completes (created signalled).
    pub fence: vk::Fence,
    /// Timestamps of this frame's passes.
    pub timestamps: TimestampQueries,
    /// Pipeline statistics of this frame's passes, when asked for and supported.
    pub statistics: Option<StatisticsQueries>,
    /// Host-visible copy of the timestamps (from 0) and statistics (after the timestamps'
    /// `copy_size`), written by the frame's last commands.
    pub query_results: Buffer,
    /// The passes recorded, in order, with the queries that measured them.
    pub passes: Vec<RecordedPass>,
    /// Signalled when this frame's swapchain image is acquired (unused headless).
    pub acquire: vk::Semaphore,
    /// When recording of the submission in flight started, ended, and when its submission
    /// returned, until its fence is read.
    pub pending: Option<[Instant; 3]>,
    /// `Prerecorded` submission: what the command buffer was recorded for; while it holds, it is
    /// submitted again as is.
    pub replay: Option<Replay>,
    /// Whether the submission in flight is a replay of `replay`.
    pub replayed: bool,
    /// The frame's index in the ring (names its objects).
    index: usize,
    /// Destroyed once this frame's fence has signalled.
    pub(super) deletions: Vec<Deletion>,
}

/// The readback buffer of frame `index`'s query results.
fn query_results(device: &Device, index: usize, bytes: u64) -> Result<Buffer> {
    let name = format!("frame {index} query results");
    Buffer::new(device, &BufferDesc::readback(&name, bytes, vk::BufferUsageFlags::TRANSFER_DST))
}

impl Frame {
    /// Create the commands, fence, queries and acquire semaphore of frame `index` (pipeline
    /// statistics too when `statistics`). On failure nothing is left.
    pub fn new(device: &Device, index: usize, statistics: bool) -> Result<Self> {
        let recorder = Guard::new(device, CommandRecorder::new(device, &format!("frame {index} commands"))?);
        let fence = Guard::new(device, sync::fence(device, true, &format!("frame {index} fence"))?);
        let name = format!("frame {index} timestamps");
        let timestamps = Guard::new(device, TimestampQueries::new(device, &name, 2 * FIRST_PASSES + 2)?);
        let statistics = match statistics {
            true => StatisticsQueries::new(device, &format!("frame {index} statistics"), FIRST_PASSES)?,
            false => None,
        };
        let statistics = Guard::new(device, statistics);
        let bytes = timestamps.copy_size() + statistics.as_ref().map_or(0, |s| s.copy_size());
        let query_results = Guard::new(device, query_results(device, index, bytes)?);
        let acquire = Guard::new(device, sync::semaphore(device, &format!("frame {index} acquire"))?);
        Ok(Self {
            recorder: recorder.take(),
            fence: fence.take(),
            timestamps: timestamps.take(),
            statistics: statistics.take(),
            query_results: query_results.take(),
            passes: Vec::new(),
            acquire: acquire.take(),
            pending: None,
            replay: None,
            replayed: false,
            index,
            deletions: Vec::new(),
        })
    }

    /// The queries the graph measures this frame's passes with.
    pub fn scopes(&mut self) -> Scopes<'_> {
        Scopes { timestamps: &mut self.timestamps, statistics: self.statistics.as_mut() }
    }

    /// Make room in the queries and their results for a frame that writes `timestamps`
    /// timestamps and uses `statistics` statistics queries. Returns the results buffer it
    /// replaced, destroyed (forget it in the graph).
    ///
    /// # Safety
    /// No pending work may use the frame's queries (its fence has signalled). Its kept recording
    /// names them: drop it first.
    pub unsafe fn reserve_queries(
        &mut self,
        device: &Device,
        timestamps: u32,
        statistics: u32,
    ) -> Result<Option<vk::Buffer>> {
        let index = self.index;
        // SAFETY: per the contract.
        unsafe {
            self.timestamps.reserve(device, || format!("frame {index} timestamps"), timestamps)?;
            if let Some(queries) = &mut self.statistics {
                queries.reserve(device, || format!("frame {index} statistics"), statistics)?;
            }
        }
        let bytes = self.timestamps.copy_size() + self.statistics.as_ref().map_or(0, |s| s.copy_size());
        if bytes <= self.query_results.size {
            return Ok(None);
        }
        let grown = query_results(device, index, bytes)?;
        let old = std::mem::replace(&mut self.query_results, grown);
        let raw = old.raw;
        // SAFETY: per the contract.
        unsafe { old.destroy(device) };
        Ok(Some(raw))
    }

    /// Record the copy of the frame's query results into `query_results` (after the last
    /// query); returns the buffer, whose host read the caller orders after the copies.
    pub fn record_query_copies(&self, device: &Device, cmd: vk::CommandBuffer) -> vk::Buffer {
        let results = self.query_results.raw;
        self.timestamps.record_copy(device, cmd, results, 0);
        if let Some(statistics) = &self.statistics {
            statistics.record_copy(device, cmd, results, self.timestamps.copy_size());
        }
        results
    }

    /// The timings of the submission just waited for (`pending`), from the copied queries.
    pub(super) fn timings(&mut self, wait: [Instant; 2], timeline: &mut Timeline) -> Option<FrameTimings> {
        let [started, recorded, submitted] = self.pending.take()?;
        let copied = self.query_results.mapped();
        let ticks = self.timestamps.read_ticks(copied);
        // Positions on the queue's unwrapped line (spans subtract the raw ticks modulo the bits).
        let placed: Vec<u64> = ticks.iter().map(|&tick| timeline.place(tick)).collect();
        let clock = &self.timestamps;
        let statistics = match &self.statistics {
            Some(queries) => queries.read(&copied[self.timestamps.copy_size() as usize..]),
            None => Vec::new(),
        };
        let passes = self
            .passes
            .iter()
            .map(|p| PassTime {
                name: p.name,
                ms: clock.elapsed_ms(ticks[p.begin as usize], ticks[p.end as usize]),
                start_ns: clock.ns(placed[p.begin as usize]),
                statistics: p.statistics.and_then(|q| statistics.get(q as usize).copied()),
            })
            .collect();
        let steps = self
            .passes
            .iter()
            .flat_map(|p| p.steps.iter().map(move |s| (p.name, s)))
            .map(|(pass, s)| StepTime {
                pass,
                name: s.name,
                ms: clock.elapsed_ms(ticks[s.begin as usize], ticks[s.end as usize]),
            })
            .collect();
        // The frame's first timestamp, the last pass's end, and the last one (after the outputs'
        // copy to the host).
        let (first, last) = (ticks[0], ticks[ticks.len() - 1]);
        let passes_end = self.passes.last().map_or(last, |p| ticks[p.end as usize]);
        let ends = std::iter::once(first).chain(self.passes.iter().map(|p| ticks[p.end as usize]));
        let between_passes_ms =
            self.passes.iter().zip(ends).map(|(p, end)| clock.elapsed_ms(end, ticks[p.begin as usize])).sum();
        Some(FrameTimings {
            cpu_record_ms: (recorded - started).as_secs_f64() * 1e3,
            cpu_submit_ms: (submitted - recorded).as_secs_f64() * 1e3,
            cpu_wait_ms: (wait[1] - wait[0]).as_secs_f64() * 1e3,
            gpu_ms: clock.elapsed_ms(first, passes_end),
            gpu_available: clock.available(),
            readback_ms: clock.elapsed_ms(passes_end, last),
            between_passes_ms,
            passes,
            steps,
            replayed: self.replayed,
            gpu_span_ns: (clock.ns(placed[0]), clock.ns(placed[placed.len() - 1])),
            cpu_spans: Some([started, recorded, submitted]),
            cpu_wait: Some(wait),
            cull: None,
        })
    }

    /// Run the deletions queued behind this frame (its fence has signalled).
    pub(super) fn run_deletions(&mut self, device: &Device) {
        for deletion in self.deletions.drain(..) {
            deletion(device);
        }
    }

    /// Destroy everything, the queued deletions first.
    ///
    /// # Safety
    /// The frame's fence must have signalled (or the device be idle).
    pub unsafe fn destroy(mut self, device: &Device) {
        self.run_deletions(device);
        // SAFETY: per the contract.
        unsafe {
            self.timestamps.destroy(device);
            if let Some(statistics) = self.statistics {
                statistics.destroy(device);
            }
            self.query_results.destroy(device);
            crate::vk::live::destroyed(self.fence);
            device.raw.destroy_fence(self.fence, None);
            crate::vk::live::destroyed(self.acquire);
            device.raw.destroy_semaphore(self.acquire, None);
            self.recorder.destroy(device);
        }
    }
}

impl Destroy for Frame {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { Frame::destroy(self, device) };
    }
}
