//! Timestamp queries: a pool per frame, written around passes, read after the frame's fence,
//! masked to `timestampValidBits` and scaled by `timestampPeriod`.

use ash::vk;

use crate::error::{Error, Result, VkContext};
use crate::vk::device::Device;

/// A pool of `capacity` timestamps.
pub struct TimestampQueries {
    /// The pool.
    pub pool: vk::QueryPool,
    capacity: u32,
    written: u32,
    period_ns: f64,
    valid_mask: u64,
}

impl TimestampQueries {
    /// Create a pool of `capacity` timestamps; fails when the queue cannot write timestamps.
    pub fn new(device: &Device, name: &str, capacity: u32) -> Result<Self> {
        if device.timestamp_valid_bits == 0 {
            return Err(Error::Environment(format!("{} cannot write timestamps on its queue", device.info.name)));
        }
        let info = vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(capacity);
        // SAFETY: valid create info.
        let pool = unsafe { device.raw.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        device.set_name(pool, name);
        let valid_mask =
            if device.timestamp_valid_bits >= 64 { u64::MAX } else { (1u64 << device.timestamp_valid_bits) - 1 };
        Ok(Self { pool, capacity, written: 0, period_ns: f64::from(device.limits().timestamp_period), valid_mask })
    }

    /// Reset every query; record before the first `write` of a frame.
    pub fn reset(&mut self, device: &Device, cmd: vk::CommandBuffer) {
        // SAFETY: cmd is recording, outside a render pass.
        unsafe { device.raw.cmd_reset_query_pool(cmd, self.pool, 0, self.capacity) };
        self.written = 0;
    }

    /// Write the next timestamp once all previous commands have finished (`ALL_COMMANDS`), so a
    /// pair brackets the GPU work between them. Returns its index.
    pub fn write(&mut self, device: &Device, cmd: vk::CommandBuffer) -> u32 {
        assert!(self.written < self.capacity, "timestamp pool overflow: a programming error");
        let index = self.written;
        // SAFETY: cmd is recording; the query was reset in this command buffer.
        unsafe { device.raw.cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::ALL_COMMANDS, self.pool, index) };
        self.written += 1;
        index
    }

    /// Read the timestamps written in the last recording, in nanoseconds. Call after the
    /// frame's fence signalled.
    pub fn read_ns(&self, device: &Device) -> Result<Vec<f64>> {
        let mut ticks = vec![0u64; self.written as usize];
        if ticks.is_empty() {
            return Ok(Vec::new());
        }
        // SAFETY: the queries were written by a completed submission.
        unsafe {
            device.raw.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        Ok(ticks.iter().map(|t| (t & self.valid_mask) as f64 * self.period_ns).collect())
    }

    /// Destroy the pool.
    ///
    /// # Safety
    /// No pending work may use it.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { device.raw.destroy_query_pool(self.pool, None) };
    }
}

/// Elapsed milliseconds between two timestamps in nanoseconds, robust to wrap-around within the
/// valid bits being already masked (a negative span reads as zero).
pub fn span_ms(start_ns: f64, end_ns: f64) -> f64 {
    ((end_ns - start_ns) / 1.0e6).max(0.0)
}
