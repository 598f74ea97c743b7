//! Per-frame data: the uniform block every pass reads, the resources one frame in flight owns
//! (`Frame`), and the ring of frames in flight with their deletion queues (`FrameRing`).

use std::time::Instant;

use ash::vk;

use crate::error::{Error, Result, VkContext};
use crate::render::graph::{RecordedPass, Scopes};
use crate::vk::commands::{self, CommandRecorder};
use crate::vk::query::{span_ms, PipelineStatistics, StatisticsQueries, TimestampQueries};
use crate::vk::tracker::ResourceStates;
use crate::vk::{sync, Buffer, BufferDesc, Device};

pub use crate::render::uniforms::{look, FrameUniforms};

/// Passes a frame can measure.
pub const MAX_PASSES: u32 = 15;
/// Timestamps per frame: a pair per pass and one at each end of the frame.
const TIMESTAMPS: u32 = 2 * MAX_PASSES + 2;
/// Bytes of a frame's query results: 64-bit timestamps, then six 64-bit counters per query.
const QUERY_RESULT_BYTES: u64 = 8 * TIMESTAMPS as u64 + 48 * MAX_PASSES as u64;

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

/// What one frame cost.
#[derive(Clone, Debug, Default)]
pub struct FrameTimings {
    /// CPU time to record the command buffer.
    pub cpu_record_ms: f64,
    /// CPU time of `vkQueueSubmit2`.
    pub cpu_submit_ms: f64,
    /// CPU time blocked on the frame fence.
    pub cpu_wait_ms: f64,
    /// GPU time from the first to the last timestamp of the frame.
    pub gpu_ms: f64,
    /// GPU time per pass.
    pub passes: Vec<PassTime>,
    /// First and last timestamp of the frame, in nanoseconds of the device's timestamp clock.
    pub gpu_span_ns: (f64, f64),
    /// When recording started, ended, and submission returned (`None` only in `Default`).
    pub cpu_spans: Option<[Instant; 3]>,
    /// When the fence wait before reading these timings started and ended.
    pub cpu_wait: Option<[Instant; 2]>,
}

/// Something to destroy once the GPU is done with it.
pub type Deletion = Box<dyn FnOnce(&Device)>;

/// A command buffer kept for replay (the `Prerecorded` submission): what it was recorded for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Replay {
    /// The colour view and size it draws into.
    pub target: (vk::ImageView, vk::Extent2D),
    /// The resource states its barriers assumed at its start.
    pub entry: ResourceStates,
    /// The states it leaves.
    pub exit: ResourceStates,
}

/// Everything one frame in flight owns. The fence guards all of it: the CPU waits on it before
/// reusing the command buffer, rewriting the uniforms, reading the queries or running the
/// deletions queued behind this frame.
pub struct Frame {
    /// Command pool and buffer, reset each use.
    pub recorder: CommandRecorder,
    /// Signalled when this frame's submission completes (created signalled).
    pub fence: vk::Fence,
    /// Host-visible `FrameUniforms`.
    pub uniforms: Buffer,
    /// Host-visible forces at cluster corners, written before each submission (thesis 3.2.2).
    pub corners: Buffer,
    /// Host-visible point sources and colliders at this frame's time.
    pub emitters: Buffer,
    /// Set 0 of the scene passes, pointing at this frame's uniforms.
    pub descriptor_set: vk::DescriptorSet,
    /// Timestamps of this frame's passes.
    pub timestamps: TimestampQueries,
    /// Pipeline statistics of this frame's passes, when asked for and supported.
    pub statistics: Option<StatisticsQueries>,
    /// Host-visible copy of the timestamps (from 0) and statistics (from `STATISTICS_OFFSET`),
    /// written by the frame's last commands.
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
    /// Destroyed once this frame's fence has signalled.
    deletions: Vec<Deletion>,
}

/// Offset of the statistics in `Frame::query_results`.
const STATISTICS_OFFSET: u64 = 8 * TIMESTAMPS as u64;

/// The parts of a `Frame` created so far (freed if creation fails half-way).
#[derive(Default)]
struct Parts {
    recorder: Option<CommandRecorder>,
    fence: vk::Fence,
    buffers: Vec<Buffer>,
    timestamps: Option<TimestampQueries>,
    statistics: Option<StatisticsQueries>,
    acquire: vk::Semaphore,
}

impl Parts {
    fn create(&mut self, device: &Device, index: usize, corners: u32, emitters: u32, statistics: bool) -> Result<()> {
        self.recorder = Some(CommandRecorder::new(device, &format!("frame {index} commands"))?);
        self.fence = sync::fence(device, true, &format!("frame {index} fence"))?;
        let vec4 = 16u64;
        for (name, size, usage) in [
            ("uniforms", std::mem::size_of::<FrameUniforms>() as u64, vk::BufferUsageFlags::UNIFORM_BUFFER),
            ("corner forces", vec4 * u64::from(corners), vk::BufferUsageFlags::STORAGE_BUFFER),
            ("emitters", vec4 * u64::from(emitters.max(1)), vk::BufferUsageFlags::STORAGE_BUFFER),
        ] {
            self.buffers.push(Buffer::new(device, &BufferDesc::upload(&format!("frame {index} {name}"), size, usage))?);
        }
        let name = format!("frame {index} query results");
        let results = BufferDesc::readback(&name, QUERY_RESULT_BYTES, vk::BufferUsageFlags::TRANSFER_DST);
        self.buffers.push(Buffer::new(device, &results)?);
        self.timestamps = Some(TimestampQueries::new(device, &format!("frame {index} timestamps"), TIMESTAMPS)?);
        if statistics {
            self.statistics = StatisticsQueries::new(device, &format!("frame {index} statistics"), MAX_PASSES)?;
        }
        self.acquire = sync::semaphore(device, &format!("frame {index} acquire"))?;
        Ok(())
    }

    /// # Safety
    /// Nothing was submitted with these parts.
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract; destroying null handles is a no-op.
        unsafe {
            for buffer in self.buffers {
                buffer.destroy(device);
            }
            if let Some(timestamps) = self.timestamps {
                timestamps.destroy(device);
            }
            if let Some(statistics) = self.statistics {
                statistics.destroy(device);
            }
            device.raw.destroy_semaphore(self.acquire, None);
            device.raw.destroy_fence(self.fence, None);
            if let Some(recorder) = self.recorder {
                recorder.destroy(device);
            }
        }
    }
}

impl Frame {
    /// Create the resources of frame `index`, with room for `corners` corner forces and
    /// `emitters` emitters.
    pub fn new(
        device: &Device,
        index: usize,
        descriptor_set: vk::DescriptorSet,
        corners: u32,
        emitters: u32,
        statistics: bool,
    ) -> Result<Self> {
        let mut parts = Parts::default();
        if let Err(e) = parts.create(device, index, corners, emitters, statistics) {
            // SAFETY: nothing was submitted.
            unsafe { parts.destroy(device) };
            return Err(e);
        }
        let mut buffers = parts.buffers.into_iter();
        let mut next = || buffers.next().expect("four buffers");
        Ok(Self {
            recorder: parts.recorder.expect("created"),
            fence: parts.fence,
            uniforms: next(),
            corners: next(),
            emitters: next(),
            query_results: next(),
            descriptor_set,
            timestamps: parts.timestamps.expect("created"),
            statistics: parts.statistics,
            passes: Vec::new(),
            acquire: parts.acquire,
            pending: None,
            replay: None,
            deletions: Vec::new(),
        })
    }

    /// The queries the graph measures this frame's passes with.
    pub fn scopes(&mut self) -> Scopes<'_> {
        Scopes { timestamps: &mut self.timestamps, statistics: self.statistics.as_mut() }
    }

    /// Record the copy of the frame's query results into `query_results` (after the last
    /// query); returns the buffer, whose host read the caller orders after the copies.
    pub fn record_query_copies(&self, device: &Device, cmd: vk::CommandBuffer) -> vk::Buffer {
        let results = self.query_results.raw;
        self.timestamps.record_copy(device, cmd, results, 0);
        if let Some(statistics) = &self.statistics {
            statistics.record_copy(device, cmd, results, STATISTICS_OFFSET);
        }
        results
    }

    /// The timings of the submission just waited for (`pending`), from the copied queries.
    fn timings(&mut self, wait: [Instant; 2]) -> Option<FrameTimings> {
        let [started, recorded, submitted] = self.pending.take()?;
        let copied = self.query_results.mapped();
        let stamps = self.timestamps.read_ns(copied);
        let statistics = match &self.statistics {
            Some(queries) => queries.read(&copied[STATISTICS_OFFSET as usize..]),
            None => Vec::new(),
        };
        let passes = self
            .passes
            .iter()
            .map(|p| PassTime {
                name: p.name,
                ms: span_ms(stamps[p.begin as usize], stamps[p.end as usize]),
                start_ns: stamps[p.begin as usize],
                statistics: p.statistics.and_then(|q| statistics.get(q as usize).copied()),
            })
            .collect();
        let (first, last) = (stamps[0], stamps[stamps.len() - 1]);
        Some(FrameTimings {
            cpu_record_ms: (recorded - started).as_secs_f64() * 1e3,
            cpu_submit_ms: (submitted - recorded).as_secs_f64() * 1e3,
            cpu_wait_ms: (wait[1] - wait[0]).as_secs_f64() * 1e3,
            gpu_ms: span_ms(first, last),
            passes,
            gpu_span_ns: (first, last),
            cpu_spans: Some([started, recorded, submitted]),
            cpu_wait: Some(wait),
        })
    }

    /// Run the deletions queued behind this frame (its fence has signalled).
    fn run_deletions(&mut self, device: &Device) {
        for deletion in self.deletions.drain(..) {
            deletion(device);
        }
    }

    /// Destroy everything (the descriptor set goes with its pool), the queued deletions first.
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
            self.uniforms.destroy(device);
            self.corners.destroy(device);
            self.emitters.destroy(device);
            self.query_results.destroy(device);
            device.raw.destroy_fence(self.fence, None);
            device.raw.destroy_semaphore(self.acquire, None);
            self.recorder.destroy(device);
        }
    }
}

/// Semaphores a frame's submission waits on (at colour output) and signals.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameSync {
    /// E.g. the swapchain image's acquire semaphore.
    pub wait: Option<vk::Semaphore>,
    /// E.g. the swapchain image's present semaphore.
    pub signal: Option<vk::Semaphore>,
}

/// The frames in flight, used round-robin, and what waits for them to finish.
///
/// Deletion: an object a submitted frame may still use goes on the queue of the last frame
/// submitted (`defer`) and is destroyed when that frame's fence has signalled, which on one queue
/// means every earlier frame has finished too. Objects the presentation engine may still use (an
/// old swapchain's images, views and present semaphores) have no fence without
/// `VK_EXT_swapchain_maintenance1`: `defer_frames` destroys them after a number of further frames
/// has completed (the caller chooses it; see the viewer's swapchain).
pub struct FrameRing {
    frames: Vec<Frame>,
    next: usize,
    last_submitted: Option<usize>,
    /// Frames whose fence was waited after their submission.
    completed: u64,
    /// Frames submitted.
    submitted: u64,
    /// Deletions run once `completed` reaches their count.
    after_frames: Vec<(u64, Deletion)>,
    /// Fault injection for tests: this submission (1-based) fails as if the driver had returned
    /// `VK_ERROR_DEVICE_LOST` (`MEADOW_INJECT_SUBMIT_FAILURE`).
    inject_failure: Option<u64>,
}

impl FrameRing {
    /// A ring of `frames`. `MEADOW_INJECT_SUBMIT_FAILURE=N` makes the N-th submission fail.
    pub fn new(frames: Vec<Frame>) -> Self {
        let inject_failure = std::env::var("MEADOW_INJECT_SUBMIT_FAILURE").ok().and_then(|v| v.parse().ok());
        Self {
            frames,
            next: 0,
            last_submitted: None,
            completed: 0,
            submitted: 0,
            after_frames: Vec::new(),
            inject_failure,
        }
    }

    /// Make the `nth` submission from now on (1 = the next) fail, for tests.
    pub fn inject_submit_failure(&mut self, nth: u64) {
        self.inject_failure = Some(self.submitted + nth);
    }

    /// Number of frames in flight.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether the ring has no frames (never, once built).
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Frame `slot`.
    pub fn frame(&self, slot: usize) -> &Frame {
        &self.frames[slot]
    }

    /// Frame `slot`, mutably.
    pub fn frame_mut(&mut self, slot: usize) -> &mut Frame {
        &mut self.frames[slot]
    }

    /// Every frame.
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Take the next slot: wait for its fence, run the deletions queued behind it, and return it
    /// with the timings of the frame it rendered last, if any. Only that slot's fence is waited.
    pub fn begin(&mut self, device: &Device) -> Result<(usize, Option<FrameTimings>)> {
        let slot = self.next;
        self.next = (self.next + 1) % self.frames.len();
        Ok((slot, self.wait(device, slot)?))
    }

    /// Wait for `slot`'s fence and read the timings of its last submission, if any.
    pub fn wait(&mut self, device: &Device, slot: usize) -> Result<Option<FrameTimings>> {
        let frame = &mut self.frames[slot];
        if frame.fence == vk::Fence::null() {
            return Err(Error::Environment("a failed submission left this frame without a fence".into()));
        }
        let started = Instant::now();
        sync::wait_fence(device, frame.fence)?;
        let ended = Instant::now();
        let had_pending = frame.pending.is_some();
        frame.run_deletions(device);
        let timings = frame.timings([started, ended]);
        if had_pending {
            self.completed += 1;
            self.run_after_frames(device);
        }
        Ok(timings)
    }

    fn run_after_frames(&mut self, device: &Device) {
        let completed = self.completed;
        let (due, kept): (Vec<_>, Vec<_>) = self.after_frames.drain(..).partition(|(n, _)| *n <= completed);
        self.after_frames = kept;
        for (_, deletion) in due {
            deletion(device);
        }
    }

    /// Wait for every frame in flight (before reading a screenshot, or at teardown; never inside
    /// a frame).
    pub fn wait_all(&mut self, device: &Device) -> Result<Vec<(usize, FrameTimings)>> {
        let mut done = Vec::new();
        for slot in 0..self.frames.len() {
            if let Some(t) = self.wait(device, slot)? {
                done.push((slot, t));
            }
        }
        Ok(done)
    }

    /// Destroy `deletion` once every frame submitted so far has finished: now, when none is
    /// pending.
    pub fn defer(&mut self, device: &Device, deletion: Deletion) {
        match self.last_submitted {
            Some(slot) if self.frames[slot].pending.is_some() => self.frames[slot].deletions.push(deletion),
            _ => deletion(device),
        }
    }

    /// Deletions still queued: behind frames in flight, or waiting for later frames.
    pub fn pending_deletions(&self) -> usize {
        self.frames.iter().map(|f| f.deletions.len()).sum::<usize>() + self.after_frames.len()
    }

    /// Drop every kept recording (`Prerecorded`): they name pipelines that are being replaced.
    pub fn forget_replays(&mut self) {
        for frame in &mut self.frames {
            frame.replay = None;
        }
    }

    /// Wait for the frames that have deletions queued behind them, and run those deletions (e.g.
    /// before retiring a second swapchain while the first is still queued). Other frames keep
    /// running.
    pub fn flush_deletions(&mut self, device: &Device) -> Result<()> {
        for slot in 0..self.frames.len() {
            if !self.frames[slot].deletions.is_empty() {
                self.wait(device, slot)?;
            }
        }
        Ok(())
    }

    /// Destroy `deletion` once `frames` more frames have completed (for what the presentation
    /// engine may hold, which no fence covers).
    pub fn defer_frames(&mut self, frames: u64, deletion: Deletion) {
        self.after_frames.push((self.submitted.max(self.completed) + frames, deletion));
    }

    /// Submit `cmd` for `slot` (after `begin`), waiting and signalling `sync`'s semaphores and
    /// the slot's fence; `spans` are when recording started and ended.
    ///
    /// A failed `vkQueueSubmit2` leaves the fence unsignalled with nothing to signal it: the
    /// fence is replaced by a signalled one, so no later wait hangs, and the error is returned.
    pub fn submit(&mut self, device: &Device, slot: usize, sync: FrameSync, started: Instant) -> Result<()> {
        let recorded = Instant::now();
        let info = |semaphore: Option<vk::Semaphore>, stage| {
            semaphore.map(|s| vk::SemaphoreSubmitInfo::default().semaphore(s).stage_mask(stage))
        };
        // The acquire semaphore is waited where the image is first written.
        let wait: Vec<_> = info(sync.wait, vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT).into_iter().collect();
        let signal: Vec<_> = info(sync.signal, vk::PipelineStageFlags2::ALL_COMMANDS).into_iter().collect();
        self.submitted += 1;
        let inject = self.inject_failure == Some(self.submitted);
        let frame = &mut self.frames[slot];
        // SAFETY: `begin` waited for this fence; nothing pending uses the frame.
        unsafe { device.raw.reset_fences(&[frame.fence]) }.vk("vkResetFences")?;
        let submitted = if inject {
            Err(Error::Vulkan { call: "vkQueueSubmit2 (injected failure)", result: vk::Result::ERROR_DEVICE_LOST })
        } else {
            commands::submit(device, frame.recorder.cmd, &wait, &signal, frame.fence)
        };
        if let Err(e) = submitted {
            frame.replay = None;
            // SAFETY: the failed submission did not take the fence: nothing will signal it.
            unsafe { device.raw.destroy_fence(frame.fence, None) };
            frame.fence = vk::Fence::null();
            frame.fence = sync::fence(device, true, &format!("frame {slot} fence"))?;
            return Err(e);
        }
        frame.pending = Some([started, recorded, Instant::now()]);
        self.last_submitted = Some(slot);
        Ok(())
    }

    /// Destroy every frame and every queued deletion.
    ///
    /// # Safety
    /// The device must be idle.
    pub unsafe fn destroy(mut self, device: &Device) {
        for (_, deletion) in self.after_frames.drain(..) {
            deletion(device);
        }
        for frame in self.frames {
            // SAFETY: per the contract.
            unsafe { frame.destroy(device) };
        }
    }
}
