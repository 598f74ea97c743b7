//! The frames in flight (`FrameRing`): round-robin use, fence waits, submission (a failed one
//! never hangs), and the deletion queues that destroy what a frame may still use once its fence
//! has signalled. What the ring owns of one frame is in `slot`; what a subsystem owns of each
//! frame is its own `PerFrame`.

mod per_frame;
mod slot;

pub use per_frame::PerFrame;
pub use slot::{Frame, FrameTimings, PassTime, Replay, ReplayKey, StepTime};

use std::time::Instant;

use ash::vk;

use crate::error::{Error, Result, VkContext};
use crate::vk::commands;
use crate::vk::query::Timeline;
use crate::vk::{sync, Device};

pub use crate::render::uniforms::{look, FrameUniforms};

/// Something to destroy once the GPU is done with it.
pub type Deletion = Box<dyn FnOnce(&Device)>;

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
    /// Acquire semaphores a failed submission left signalled (or about to be): nothing waits on
    /// them, so they are only destroyed with the ring, after the device is idle.
    parked: Vec<vk::Semaphore>,
    /// The queue's timestamps, unwrapped: frames complete in submission order, so their ticks are
    /// placed in the order the queue wrote them.
    timeline: Timeline,
}

impl FrameRing {
    /// A ring of `frames`. `MEADOW_INJECT_SUBMIT_FAILURE=N` makes the N-th submission fail.
    pub fn new(frames: Vec<Frame>) -> Self {
        let inject_failure = crate::vk::fault::submit_failure();
        let timeline = Timeline::new(frames.first().map_or(0, |f| f.timestamps.valid_mask()));
        Self {
            timeline,
            frames,
            next: 0,
            last_submitted: None,
            completed: 0,
            submitted: 0,
            after_frames: Vec::new(),
            inject_failure,
            parked: Vec::new(),
        }
    }

    /// Place a raw timestamp of the queue read before the frames (a calibration's) on the frames'
    /// timeline (`FrameTimings` nanoseconds); returns it in nanoseconds.
    pub fn place_timestamp(&mut self, raw: u64, period_ns: f64) -> f64 {
        self.timeline.place(raw) as f64 * period_ns
    }

    /// Make the `nth` submission from now on (1 = the next) fail, for tests.
    pub fn inject_submit_failure(&mut self, nth: u64) {
        self.inject_failure = Some(self.submitted + nth);
    }

    /// Number of frame slots (frames in flight).
    pub fn slots(&self) -> usize {
        self.frames.len()
    }

    /// Frame `slot`.
    pub fn frame(&self, slot: usize) -> &Frame {
        &self.frames[slot]
    }

    /// Frame `slot`, mutably.
    pub fn frame_mut(&mut self, slot: usize) -> &mut Frame {
        &mut self.frames[slot]
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
        let timings = frame.timings([started, ended], &mut self.timeline);
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
        // Oldest first (`next` is the slot submitted longest ago): the timeline places the queue's
        // timestamps in the order they were written.
        let (slots, oldest) = (self.frames.len(), self.next);
        for slot in (0..slots).map(|i| (oldest + i) % slots) {
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

    /// Wait for every frame and for the queue (presentations included), then run every queued
    /// deletion: the way out when objects are retired faster than frames complete (a resize storm
    /// retiring a second swapchain while the first is still queued). Not used inside a frame.
    pub fn drain(&mut self, device: &Device) -> Result<()> {
        self.wait_all(device)?;
        // SAFETY: the queue is externally synchronised by `&mut self` (one renderer per queue).
        unsafe { device.raw.queue_wait_idle(device.queue) }.vk("vkQueueWaitIdle")?;
        for (_, deletion) in self.after_frames.drain(..) {
            deletion(device);
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
        // The acquire semaphore is waited before any of the frame's work (ALL_COMMANDS), its
        // first timestamp included: the viewer's GPU times then measure the frame's work from
        // when the GPU starts it, not the wait for a presentable image (with FIFO, vsync). The
        // image's first write (colour output) comes after, so its layout transition still
        // chains with the wait (`Access::Acquired`).
        let wait: Vec<_> = info(sync.wait, vk::PipelineStageFlags2::ALL_COMMANDS).into_iter().collect();
        let signal: Vec<_> = info(sync.signal, vk::PipelineStageFlags2::ALL_COMMANDS).into_iter().collect();
        self.submitted += 1;
        let inject = self.inject_failure == Some(self.submitted);
        let frame = &mut self.frames[slot];
        // SAFETY: `begin` waited for this fence; nothing pending uses the frame.
        unsafe { device.raw.reset_fences(&[frame.fence]) }.vk("vkResetFences")?;
        let submitted = if inject {
            Err(Error::vulkan("vkQueueSubmit2 (injected failure)", vk::Result::ERROR_DEVICE_LOST))
        } else {
            commands::submit(device, frame.recorder.cmd, &wait, &signal, frame.fence)
        };
        if let Err(e) = submitted {
            frame.replay = None;
            // SAFETY: the failed submission did not take the fence: nothing will signal it.
            unsafe {
                crate::vk::live::destroyed(frame.fence);
                device.raw.destroy_fence(frame.fence, None)
            };
            frame.fence = vk::Fence::null();
            frame.fence = sync::fence(device, true, &format!("frame {slot} fence"))?;
            if sync.wait.is_some() {
                // The image acquired with it signals it with no wait to unsignal it: a later
                // acquire must not use it again.
                self.parked.push(frame.acquire);
                frame.acquire = vk::Semaphore::null();
                frame.acquire = sync::semaphore(device, &format!("frame {slot} acquire"))?;
            }
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
        for semaphore in self.parked.drain(..) {
            // SAFETY: the device is idle.
            unsafe {
                crate::vk::live::destroyed(semaphore);
                device.raw.destroy_semaphore(semaphore, None)
            };
        }
        for frame in self.frames {
            // SAFETY: per the contract.
            unsafe { frame.destroy(device) };
        }
    }
}
