//! How the blade class's draws are issued from the cull's output (issue #30 item 1, its rows):
//! once per LOD bucket (`DrawRows::PerBucket`, the default: one indexed indirect draw each), or
//! once per visible tile and bucket inside one multi-draw-indirect (`DrawRows::PerTile`, Pelzer
//! §7.4.2's one draw per cluster), with the tile's record reaching the vertex shader by
//! `gl_DrawID`. The scan writes the per-tile rows (`shaders/cull/cull_scan.comp`) into the buffer
//! laid out by [`TileRows`] (`shaders/cull/tile_rows.glsl` mirrors it), and the blade pass draws
//! each bucket's rows with one `vkCmdDrawIndexedIndirectCount` (`passes::blades`).

use ash::vk;

use crate::error::{Error, Result};
use crate::render::gpu_constants as gpu;
use crate::vk::Device;

/// How the blade class issues its draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DrawRows {
    /// One indirect draw per LOD bucket.
    #[default]
    PerBucket,
    /// One draw per visible tile and LOD bucket, inside one multi-draw-indirect per bucket.
    PerTile,
}

impl DrawRows {
    /// Refuse per-tile rows on a device that cannot draw them: they need `multiDrawIndirect`,
    /// `drawIndirectCount` and `shaderDrawParameters` (`gl_DrawID`).
    pub fn check(self, device: &Device) -> Result<()> {
        if self == DrawRows::PerBucket {
            return Ok(());
        }
        let missing: Vec<&str> = [
            (device.features.multi_draw_indirect == vk::TRUE, "multiDrawIndirect"),
            (device.draw_indirect_count, "drawIndirectCount"),
            (device.draw_parameters, "shaderDrawParameters"),
        ]
        .iter()
        .filter(|(has, _)| !has)
        .map(|(_, name)| *name)
        .collect();
        if missing.is_empty() {
            return Ok(());
        }
        Err(Error::Environment(format!(
            "{} cannot draw one row per tile (no {}): use another --animation than sine-cluster",
            device.info.name,
            missing.join(", ")
        )))
    }
}

/// Refuse rows of `capacity` draws a bucket past the device's `maxDrawIndirectCount`.
pub fn check_capacity(device: &Device, capacity: u32) -> Result<()> {
    let limit = device.properties.limits.max_draw_indirect_count;
    match capacity <= limit {
        true => Ok(()),
        false => Err(Error::Environment(format!(
            "{} draws at most {limit} rows in one multi-draw-indirect, the field needs {capacity}: use another --animation than sine-cluster",
            device.info.name
        ))),
    }
}

/// Where the per-tile rows lie in their buffer, in 32-bit words: `MAX_LOD_BUCKETS` draw counts,
/// then per bucket `capacity` `VkDrawIndexedIndirectCommand`s, then per bucket `capacity` records
/// of `TILE_RECORD_WORDS` (the tile's first and end entries in the visible list, its ring slot).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileRows {
    /// Rows per bucket: the ring slots the cull holds (a tile draws at most once per bucket).
    pub capacity: u32,
}

impl TileRows {
    /// The word of bucket `bucket`'s draw count.
    pub fn count_word(bucket: u32) -> u32 {
        bucket
    }

    /// The word of bucket `bucket`'s first command.
    pub fn commands_word(&self, bucket: u32) -> u32 {
        gpu::MAX_LOD_BUCKETS + bucket * self.capacity * gpu::DRAW_WORDS
    }

    /// The word of row `row`'s record in bucket `bucket`.
    pub fn record_word(&self, bucket: u32, row: u32) -> u32 {
        self.commands_word(gpu::MAX_LOD_BUCKETS) + (bucket * self.capacity + row) * gpu::TILE_RECORD_WORDS
    }

    /// Words of the whole buffer.
    pub fn words(&self) -> u32 {
        self.record_word(gpu::MAX_LOD_BUCKETS, 0)
    }
}

// A row, like a bucket's draw in the cull's `draws`, is a `VkDrawIndexedIndirectCommand`.
const _: () = assert!(gpu::DRAW_WORDS as usize * 4 == std::mem::size_of::<vk::DrawIndexedIndirectCommand>());

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rows_follow_each_other_without_overlap() {
        let rows = TileRows { capacity: 10 };
        assert_eq!(rows.commands_word(0), gpu::MAX_LOD_BUCKETS);
        assert_eq!(rows.commands_word(1) - rows.commands_word(0), 10 * gpu::DRAW_WORDS);
        assert_eq!(rows.record_word(0, 0), rows.commands_word(gpu::MAX_LOD_BUCKETS));
        assert_eq!(rows.record_word(1, 0) - rows.record_word(0, 9), gpu::TILE_RECORD_WORDS);
        assert_eq!(rows.words(), gpu::MAX_LOD_BUCKETS * (1 + 10 * (gpu::DRAW_WORDS + gpu::TILE_RECORD_WORDS)));
    }
}
