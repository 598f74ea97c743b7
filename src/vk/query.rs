//! GPU queries read after a frame's fence. Timestamps: a pool per frame, written around passes,
//! masked to `timestampValidBits` and scaled by `timestampPeriod`. Pipeline statistics: one query
//! per pass (`pipelineStatisticsQuery`), counting what the pass made the pipeline do.

use ash::vk;

use crate::error::{Result, VkContext};
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
    /// Create a pool of `capacity` timestamps. A queue that cannot write timestamps gets no pool:
    /// `write` only counts, and every span reads 0 (`available` says so).
    pub fn new(device: &Device, name: &str, capacity: u32) -> Result<Self> {
        if !device.has_timestamps() {
            return Ok(Self { pool: vk::QueryPool::null(), capacity, written: 0, period_ns: 0.0, valid_mask: 0 });
        }
        let info = vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(capacity);
        // SAFETY: valid create info.
        let pool = super::live::created(unsafe { device.raw.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?);
        device.set_name(pool, name);
        let valid_mask =
            if device.timestamp_valid_bits >= 64 { u64::MAX } else { (1u64 << device.timestamp_valid_bits) - 1 };
        Ok(Self { pool, capacity, written: 0, period_ns: f64::from(device.limits().timestamp_period), valid_mask })
    }

    /// Make room for `capacity` timestamps: a smaller pool is replaced by one that holds them
    /// (its name kept). Record a frame's `reset` after this.
    ///
    /// # Safety
    /// No pending work may use the pool.
    pub unsafe fn reserve(&mut self, device: &Device, name: impl FnOnce() -> String, capacity: u32) -> Result<()> {
        if capacity <= self.capacity {
            return Ok(());
        }
        let grown = Self::new(device, &name(), capacity)?;
        // SAFETY: per the contract.
        unsafe { std::mem::replace(self, grown).destroy(device) };
        Ok(())
    }

    /// Timestamps the pool holds.
    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// The bits of a tick that count (`timestampValidBits`), as a mask.
    pub fn valid_mask(&self) -> u64 {
        self.valid_mask
    }

    /// Whether timestamps are written (the queue has `timestampValidBits`).
    pub fn available(&self) -> bool {
        self.pool != vk::QueryPool::null()
    }

    /// Reset every query; record before the first `write` of a frame.
    pub fn reset(&mut self, device: &Device, cmd: vk::CommandBuffer) {
        if self.available() {
            // SAFETY: cmd is recording, outside a render pass.
            unsafe { device.raw.cmd_reset_query_pool(cmd, self.pool, 0, self.capacity) };
        }
        self.written = 0;
    }

    /// Write the next timestamp once all previous commands have finished (`ALL_COMMANDS`), so a
    /// pair brackets the GPU work between them. Returns its index.
    pub fn write(&mut self, device: &Device, cmd: vk::CommandBuffer) -> u32 {
        assert!(self.written < self.capacity, "timestamp pool overflow: a programming error");
        let index = self.written;
        if self.available() {
            // SAFETY: cmd is recording; the query was reset in this command buffer.
            unsafe { device.raw.cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::ALL_COMMANDS, self.pool, index) };
        }
        self.written += 1;
        index
    }

    /// Bytes `record_copy` writes at most.
    pub fn copy_size(&self) -> u64 {
        8 * u64::from(self.capacity)
    }

    /// Copy the timestamps written so far into `buffer` at `offset` (64-bit each), once they are
    /// available. Record after the last `write`, outside a render pass; the copy is a transfer
    /// write to make visible to the host.
    pub fn record_copy(&self, device: &Device, cmd: vk::CommandBuffer, buffer: vk::Buffer, offset: u64) {
        if self.written == 0 || !self.available() {
            return;
        }
        let flags = vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT;
        // SAFETY: cmd is recording outside a render pass; the buffer holds `copy_size` bytes from
        // `offset`.
        unsafe { device.raw.cmd_copy_query_pool_results(cmd, self.pool, 0, self.written, buffer, offset, 8, flags) };
    }

    /// The timestamps of the last recording, in ticks masked to the valid bits, from the bytes
    /// `record_copy` wrote
    /// (read after the frame's fence). Queries are copied on the GPU rather than read with
    /// `vkGetQueryPoolResults`, which lavapipe (Mesa 22.3) implements by draining its whole
    /// queue: with frames in flight that would serialise the CPU with every frame.
    pub fn read_ticks(&self, copied: &[u8]) -> Vec<u64> {
        if !self.available() {
            return vec![0; self.written as usize];
        }
        copied[..8 * self.written as usize]
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")) & self.valid_mask)
            .collect()
    }

    /// Milliseconds from tick `start` to tick `end`: subtracted as integers modulo the valid bits
    /// (a counter that wrapped in between still gives the elapsed time), then scaled, so no
    /// precision is lost to large absolute tick counts.
    pub fn elapsed_ms(&self, start: u64, end: u64) -> f64 {
        elapsed_ticks(start, end, self.valid_mask) as f64 * self.period_ns / 1.0e6
    }

    /// Tick `tick` in nanoseconds of the device's timestamp clock (for placing frames on a
    /// timeline; spans use `elapsed_ms`).
    pub fn ns(&self, tick: u64) -> f64 {
        tick as f64 * self.period_ns
    }

    /// Destroy the pool.
    ///
    /// # Safety
    /// No pending work may use it.
    pub unsafe fn destroy(self, device: &Device) {
        if self.available() {
            // SAFETY: per the contract.
            unsafe {
                super::live::destroyed(self.pool);
                device.raw.destroy_query_pool(self.pool, None)
            };
        }
    }
}

/// Ticks from `start` to `end` of a counter of `mask`'s valid bits, which may have wrapped once
/// in between.
fn elapsed_ticks(start: u64, end: u64, mask: u64) -> u64 {
    end.wrapping_sub(start) & mask
}

/// One queue's raw timestamps placed on a line of ticks that keeps counting up when the counter
/// wraps (`timestampValidBits` < 64): each tick is the previous one plus their difference modulo
/// the valid bits, read as signed (a difference past half the range is a step back: a clock
/// sample taken while earlier frames were still in flight). Place ticks about in the order the
/// queue wrote them, each less than 2^(bits-1) ticks from the one before.
#[derive(Clone, Copy, Debug)]
pub struct Timeline {
    mask: u64,
    /// The last tick placed: (raw, placed).
    last: Option<(u64, u64)>,
}

impl Timeline {
    /// A line for a counter of `mask`'s bits (`TimestampQueries::valid_mask`).
    pub fn new(mask: u64) -> Self {
        Self { mask, last: None }
    }

    /// Where raw tick `raw` falls on the line.
    pub fn place(&mut self, raw: u64) -> u64 {
        let raw = raw & self.mask;
        let placed = match self.last {
            None => raw,
            Some((last_raw, last_placed)) => {
                let ahead = elapsed_ticks(last_raw, raw, self.mask);
                let half = self.mask / 2 + 1;
                match ahead >= half {
                    true => last_placed.wrapping_sub(elapsed_ticks(raw, last_raw, self.mask)),
                    false => last_placed.wrapping_add(ahead),
                }
            }
        };
        self.last = Some((raw, placed));
        placed
    }
}

#[cfg(test)]
mod tests {
    use super::{elapsed_ticks, Timeline};

    #[test]
    fn a_wrapping_counter_keeps_counting_up_on_the_timeline() {
        let mut line = Timeline::new((1 << 8) - 1);
        let placed: Vec<u64> = [250u64, 253, 3, 100, 200, 1].iter().map(|&t| line.place(t)).collect();
        assert_eq!(placed, [250, 253, 259, 356, 456, 513]);
        // A step back (a clock sample taken before frames in flight finished), across the wrap.
        assert_eq!(line.place(250), 506);
        assert_eq!(line.place(4), 516);
        // 64 valid bits: a step back stays a step back.
        let mut line = Timeline::new(u64::MAX);
        assert_eq!(line.place(1_000_000), 1_000_000);
        assert_eq!(line.place(999_990), 999_990);
        assert_eq!(line.place(1_000_020), 1_000_020);
    }

    #[test]
    fn spans_are_integer_differences_modulo_the_valid_bits() {
        let mask36 = (1u64 << 36) - 1;
        assert_eq!(elapsed_ticks(100, 250, mask36), 150);
        // A 36-bit counter wrapping between the two stamps.
        assert_eq!(elapsed_ticks(mask36 - 9, 20, mask36), 30);
        // 64 valid bits near the top: exact, where f64 nanoseconds would round.
        assert_eq!(elapsed_ticks(u64::MAX - 1000, u64::MAX - 1, u64::MAX), 999);
        assert_ne!((u64::MAX - 1) as f64 - (u64::MAX - 1000) as f64, 999.0);
    }
}

/// What one pipeline-statistics query counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PipelineStatistics {
    /// Vertices the input assembler fetched.
    pub input_vertices: u64,
    /// Primitives the input assembler formed.
    pub input_primitives: u64,
    /// Vertex shader invocations.
    pub vertex_invocations: u64,
    /// Primitives that reached the clipping stage.
    pub clipping_invocations: u64,
    /// Primitives that left it (what was rasterised).
    pub clipping_primitives: u64,
    /// Fragment shader invocations.
    pub fragment_invocations: u64,
}

impl PipelineStatistics {
    /// The counters, in the order Vulkan writes them (increasing flag bits). Graphics only:
    /// with `COMPUTE_SHADER_INVOCATIONS` in the pool, lavapipe (Mesa 22.3) binds the compute
    /// state at `vkCmdBeginQuery` and crashes when no compute pipeline is bound.
    const FLAGS: [vk::QueryPipelineStatisticFlags; 6] = [
        vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_VERTICES,
        vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES,
        vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS,
        vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS,
        vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES,
        vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
    ];

    fn from_words(w: &[u64]) -> Self {
        Self {
            input_vertices: w[0],
            input_primitives: w[1],
            vertex_invocations: w[2],
            clipping_invocations: w[3],
            clipping_primitives: w[4],
            fragment_invocations: w[5],
        }
    }

    /// `(name, value)` pairs, for reports.
    pub fn fields(&self) -> [(&'static str, u64); 6] {
        [
            ("input_vertices", self.input_vertices),
            ("input_primitives", self.input_primitives),
            ("vertex_invocations", self.vertex_invocations),
            ("clipping_invocations", self.clipping_invocations),
            ("clipping_primitives", self.clipping_primitives),
            ("fragment_invocations", self.fragment_invocations),
        ]
    }
}

/// A pool of `capacity` pipeline-statistics queries, begun and ended around passes.
pub struct StatisticsQueries {
    /// The pool.
    pub pool: vk::QueryPool,
    capacity: u32,
    used: u32,
}

impl StatisticsQueries {
    /// Create a pool, or `None` when the device lacks `pipelineStatisticsQuery`.
    pub fn new(device: &Device, name: &str, capacity: u32) -> Result<Option<Self>> {
        if device.features.pipeline_statistics_query == vk::FALSE {
            return Ok(None);
        }
        let flags = PipelineStatistics::FLAGS.iter().fold(vk::QueryPipelineStatisticFlags::empty(), |a, b| a | *b);
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(capacity)
            .pipeline_statistics(flags);
        // SAFETY: valid create info; the feature is enabled.
        let pool = super::live::created(unsafe { device.raw.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?);
        device.set_name(pool, name);
        Ok(Some(Self { pool, capacity, used: 0 }))
    }

    /// Make room for `capacity` queries, as `TimestampQueries::reserve`.
    ///
    /// # Safety
    /// No pending work may use the pool.
    pub unsafe fn reserve(&mut self, device: &Device, name: impl FnOnce() -> String, capacity: u32) -> Result<()> {
        if capacity <= self.capacity {
            return Ok(());
        }
        let Some(grown) = Self::new(device, &name(), capacity)? else { return Ok(()) };
        // SAFETY: per the contract.
        unsafe { std::mem::replace(self, grown).destroy(device) };
        Ok(())
    }

    /// Reset every query; record before the first `begin` of a frame, outside a render pass.
    pub fn reset(&mut self, device: &Device, cmd: vk::CommandBuffer) {
        // SAFETY: cmd is recording, outside a render pass.
        unsafe { device.raw.cmd_reset_query_pool(cmd, self.pool, 0, self.capacity) };
        self.used = 0;
    }

    /// Begin the next query (outside a rendering instance; end it outside too). Returns its index.
    pub fn begin(&mut self, device: &Device, cmd: vk::CommandBuffer) -> u32 {
        assert!(self.used < self.capacity, "statistics pool overflow: a programming error");
        let index = self.used;
        // SAFETY: cmd is recording; the query was reset in this command buffer.
        unsafe { device.raw.cmd_begin_query(cmd, self.pool, index, vk::QueryControlFlags::empty()) };
        self.used += 1;
        index
    }

    /// End the query `begin` returned.
    pub fn end(&self, device: &Device, cmd: vk::CommandBuffer, index: u32) {
        // SAFETY: the query is active in cmd.
        unsafe { device.raw.cmd_end_query(cmd, self.pool, index) };
    }

    /// Bytes `record_copy` writes at most.
    pub fn copy_size(&self) -> u64 {
        (8 * PipelineStatistics::FLAGS.len() as u64) * u64::from(self.capacity)
    }

    /// Copy the results of the queries used so far into `buffer` at `offset`, once available
    /// (record after the last `end`, outside a render pass).
    pub fn record_copy(&self, device: &Device, cmd: vk::CommandBuffer, buffer: vk::Buffer, offset: u64) {
        if self.used == 0 {
            return;
        }
        let stride = 8 * PipelineStatistics::FLAGS.len() as u64;
        let flags = vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT;
        // SAFETY: as TimestampQueries::record_copy.
        unsafe { device.raw.cmd_copy_query_pool_results(cmd, self.pool, 0, self.used, buffer, offset, stride, flags) };
    }

    /// The statistics of the last recording from the bytes `record_copy` wrote.
    pub fn read(&self, copied: &[u8]) -> Vec<PipelineStatistics> {
        let per = PipelineStatistics::FLAGS.len();
        let words: Vec<u64> = copied[..8 * per * self.used as usize]
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
            .collect();
        words.chunks_exact(per).map(PipelineStatistics::from_words).collect()
    }

    /// Destroy the pool.
    ///
    /// # Safety
    /// No pending work may use it.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            super::live::destroyed(self.pool);
            device.raw.destroy_query_pool(self.pool, None)
        };
    }
}
