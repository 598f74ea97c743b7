//! How the blade pass submits its draws (`meadow overhead`): the same blades as one instanced
//! draw, or split into `clusters` contiguous ranges drawn one by one (push constants, Pelzer
//! §7.4.2), through indirect commands (a loop, one multi-draw, a GPU count), from secondary
//! command buffers recorded on worker threads, or from a command buffer recorded once.
//!
//! The blades of a range are contiguous in the blade buffer, which the scatter fills row by row
//! over the field, so a range is a strip of the field: a spatial cluster for culling to come.

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::error::{Result, VkContext};
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, Destroy, Device, Guard};

/// A way to submit the blade draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Strategy {
    /// One `vkCmdDraw` of every blade (one instance per blade).
    Instanced,
    /// One `vkCmdDraw` per cluster, its first blade in a push constant (Pelzer §7.4.2).
    PerCluster,
    /// One `vkCmdDrawIndirect` per cluster, reading a command each from a GPU buffer.
    Indirect,
    /// One `vkCmdDrawIndirect` of all clusters' commands (`multiDrawIndirect`).
    Mdi,
    /// One `vkCmdDrawIndirectCount`, the draw count read from a GPU buffer (`drawIndirectCount`).
    MdiCount,
    /// The per-cluster draws recorded into secondary command buffers on worker threads.
    Secondary,
    /// A command buffer recorded once and submitted every frame.
    Prerecorded,
}

impl Strategy {
    /// Every strategy, in report order.
    pub const ALL: [Strategy; 7] = [
        Strategy::Instanced,
        Strategy::PerCluster,
        Strategy::Indirect,
        Strategy::Mdi,
        Strategy::MdiCount,
        Strategy::Secondary,
        Strategy::Prerecorded,
    ];

    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Instanced => "instanced",
            Strategy::PerCluster => "per-cluster",
            Strategy::Indirect => "indirect",
            Strategy::Mdi => "mdi",
            Strategy::MdiCount => "mdi-count",
            Strategy::Secondary => "secondary",
            Strategy::Prerecorded => "prerecorded",
        }
    }

    /// Parse a command-line name.
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Draw calls the blade pass records for `clusters` clusters.
    pub fn blade_draws(self, clusters: u32) -> u32 {
        match self {
            Strategy::Instanced | Strategy::Prerecorded => 1,
            Strategy::Mdi | Strategy::MdiCount => 1,
            Strategy::PerCluster | Strategy::Indirect | Strategy::Secondary => clusters,
        }
    }

    /// Draws the GPU executes for `clusters` clusters (a multi-draw counts each of its draws).
    pub fn gpu_draws(self, clusters: u32) -> u32 {
        match self {
            Strategy::Instanced | Strategy::Prerecorded => 1,
            _ => clusters,
        }
    }

    /// Whether the blade shader takes its first blade from a push constant.
    pub fn pushes_first_blade(self) -> bool {
        matches!(self, Strategy::PerCluster | Strategy::Secondary)
    }

    /// Why `device` cannot run this strategy with `clusters` clusters, if it cannot.
    pub fn unsupported(self, device: &Device, clusters: u32) -> Option<String> {
        let capabilities = DrawCapabilities {
            first_instance: device.features.draw_indirect_first_instance == vk::TRUE,
            multi_draw_indirect: device.features.multi_draw_indirect == vk::TRUE,
            draw_indirect_count: device.draw_indirect_count,
            max_draw_indirect_count: device.limits().max_draw_indirect_count,
        };
        self.missing(&capabilities, clusters)
    }

    /// What the spec requires of the device for this strategy, and what `capabilities` lack:
    /// every indirect strategy reads `firstInstance`; `vkCmdDrawIndirect` with a `drawCount` over
    /// 1 needs `multiDrawIndirect` (VUID-vkCmdDrawIndirect-drawCount-02718); the count of
    /// `vkCmdDrawIndirectCount` needs `drawIndirectCount` and at most `maxDrawIndirectCount`
    /// draws (VUID-vkCmdDrawIndirectCount-countBuffer-02717), not `multiDrawIndirect`.
    fn missing(self, capabilities: &DrawCapabilities, clusters: u32) -> Option<String> {
        let max = capabilities.max_draw_indirect_count;
        match self {
            Strategy::Indirect | Strategy::Mdi | Strategy::MdiCount if !capabilities.first_instance => {
                Some("no drawIndirectFirstInstance".into())
            }
            Strategy::Mdi if !capabilities.multi_draw_indirect && clusters > 1 => Some("no multiDrawIndirect".into()),
            Strategy::Mdi | Strategy::MdiCount if clusters > max => {
                Some(format!("{clusters} draws exceed maxDrawIndirectCount {max}"))
            }
            Strategy::MdiCount if !capabilities.draw_indirect_count => Some("no drawIndirectCount".into()),
            _ => None,
        }
    }
}

/// What the indirect strategies depend on, as a device reports it.
struct DrawCapabilities {
    /// `drawIndirectFirstInstance`.
    first_instance: bool,
    /// `multiDrawIndirect`.
    multi_draw_indirect: bool,
    /// `drawIndirectCount` (Vulkan 1.2), enabled.
    draw_indirect_count: bool,
    /// `maxDrawIndirectCount`.
    max_draw_indirect_count: u32,
}

/// How the blade pass submits: the strategy and the number of clusters (draws) it splits the
/// blades into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Submission {
    /// The strategy.
    pub strategy: Strategy,
    /// Clusters (contiguous blade ranges); ignored by `Instanced` and `Prerecorded`.
    pub clusters: u32,
}

impl Default for Submission {
    fn default() -> Self {
        Self { strategy: Strategy::Instanced, clusters: 1 }
    }
}

/// The blade ranges of `clusters` clusters over `blades` blades: `(first, count)`, as even as
/// possible, none empty (fewer clusters when there are fewer blades).
pub fn ranges(blades: u32, clusters: u32) -> Vec<(u32, u32)> {
    let clusters = clusters.clamp(1, blades.max(1));
    (0..clusters)
        .map(|i| {
            let first = (u64::from(blades) * u64::from(i) / u64::from(clusters)) as u32;
            let end = (u64::from(blades) * u64::from(i + 1) / u64::from(clusters)) as u32;
            (first, end - first)
        })
        .filter(|r| r.1 > 0)
        .collect()
}

/// Push constant of the per-cluster draws (`blade.vert`, `FLAG_CLUSTER_PUSH`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ClusterPush {
    /// Index of the cluster's first blade.
    pub first_blade: u32,
}

/// The push constant range of the scene pipeline layout.
pub fn push_constant_range() -> vk::PushConstantRange {
    vk::PushConstantRange {
        stage_flags: vk::ShaderStageFlags::VERTEX,
        offset: 0,
        size: std::mem::size_of::<ClusterPush>() as u32,
    }
}

/// The blade draws of one command buffer, with the pipeline already bound.
pub enum BladeDraws<'a> {
    /// `instances` instances of `vertices` vertices.
    Instanced {
        /// Vertices per instance.
        vertices: u32,
        /// Instances.
        instances: u32,
    },
    /// One draw per range, its first blade pushed (`ClusterPush`).
    PerCluster {
        /// Vertices per blade.
        vertices: u32,
        /// `(first blade, blades)` per draw.
        ranges: &'a [(u32, u32)],
        /// The layout the push constant range belongs to.
        layout: vk::PipelineLayout,
    },
    /// One `vkCmdDrawIndirect` per command.
    IndirectLoop(&'a IndirectDraws),
    /// One `vkCmdDrawIndirect` of every command.
    MultiDraw(&'a IndirectDraws),
    /// One `vkCmdDrawIndirectCount`, the count read by the GPU.
    MultiDrawCount(&'a IndirectDraws),
}

/// Record `draws` into `cmd` (recording, inside the blade pass, its pipeline and set bound).
pub fn record_draws(device: &Device, cmd: vk::CommandBuffer, draws: &BladeDraws) {
    const STRIDE: u32 = std::mem::size_of::<vk::DrawIndirectCommand>() as u32;
    // SAFETY: per the contract above; indirect buffers hold `draws` commands of STRIDE bytes and
    // were made visible to indirect reads by their upload.
    unsafe {
        match *draws {
            BladeDraws::Instanced { vertices, instances } => device.raw.cmd_draw(cmd, vertices, instances, 0, 0),
            BladeDraws::PerCluster { vertices, ranges, layout } => {
                for &(first_blade, count) in ranges {
                    let push = ClusterPush { first_blade };
                    device.raw.cmd_push_constants(
                        cmd,
                        layout,
                        vk::ShaderStageFlags::VERTEX,
                        0,
                        bytemuck::bytes_of(&push),
                    );
                    device.raw.cmd_draw(cmd, vertices, count, 0, 0);
                }
            }
            BladeDraws::IndirectLoop(indirect) => {
                for i in 0..indirect.draws {
                    let offset = u64::from(i * STRIDE);
                    device.raw.cmd_draw_indirect(cmd, indirect.commands.raw, offset, 1, STRIDE);
                }
            }
            BladeDraws::MultiDraw(indirect) => {
                device.raw.cmd_draw_indirect(cmd, indirect.commands.raw, 0, indirect.draws, STRIDE)
            }
            BladeDraws::MultiDrawCount(indirect) => device.raw.cmd_draw_indirect_count(
                cmd,
                indirect.commands.raw,
                0,
                indirect.count.raw,
                0,
                indirect.draws,
                STRIDE,
            ),
        }
    }
}

/// The GPU side of the indirect strategies: one `VkDrawIndirectCommand` per cluster, and the draw
/// count in its own buffer for `vkCmdDrawIndirectCount`.
pub struct IndirectDraws {
    /// The commands.
    pub commands: Buffer,
    /// One `u32`: the number of commands.
    pub count: Buffer,
    /// Commands in the buffer.
    pub draws: u32,
}

impl IndirectDraws {
    /// Upload the commands drawing `ranges` as strips of `vertices` vertices (one instance per
    /// blade; `firstInstance` is the first blade).
    pub fn upload(batch: &mut UploadBatch, ranges: &[(u32, u32)], vertices: u32) -> Result<Self> {
        let commands: Vec<vk::DrawIndirectCommand> = ranges
            .iter()
            .map(|&(first, count)| vk::DrawIndirectCommand {
                vertex_count: vertices,
                instance_count: count,
                first_vertex: 0,
                first_instance: first,
            })
            .collect();
        let words: Vec<u32> = commands
            .iter()
            .flat_map(|c| [c.vertex_count, c.instance_count, c.first_vertex, c.first_instance])
            .collect();
        let (usage, next) = (vk::BufferUsageFlags::INDIRECT_BUFFER, &[Access::IndirectCommandRead][..]);
        // The batch has not been submitted.
        let commands_buffer = Guard::new(batch.device(), batch.buffer("indirect draws", &words, usage, next)?);
        let count = batch.buffer("indirect draw count", &[commands.len() as u32], usage, next)?;
        Ok(Self { commands: commands_buffer.take(), count, draws: commands.len() as u32 })
    }

    /// Destroy both buffers.
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.commands.destroy(device);
            self.count.destroy(device);
        }
    }
}

/// Secondary command buffers of one frame, one pool each, for worker threads.
pub struct SecondaryRecorders {
    /// `(pool, secondary command buffer)` per worker.
    pub workers: Vec<(vk::CommandPool, vk::CommandBuffer)>,
}

impl SecondaryRecorders {
    /// `count` pools with a secondary command buffer each.
    pub fn new(device: &Device, name: &str, count: usize) -> Result<Self> {
        // Nothing is recorded in them yet.
        let mut out = Guard::new(device, Self { workers: Vec::with_capacity(count) });
        for i in 0..count {
            let info = vk::CommandPoolCreateInfo::default()
                .queue_family_index(device.queue_family)
                .flags(vk::CommandPoolCreateFlags::TRANSIENT);
            // SAFETY: valid create info.
            let pool = unsafe { device.raw.create_command_pool(&info, None) }
                .vk("vkCreateCommandPool")
                .map(crate::vk::live::created)?;
            let pool = Guard::new(device, pool);
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(*pool)
                .level(vk::CommandBufferLevel::SECONDARY)
                .command_buffer_count(1);
            // SAFETY: pool is valid.
            let buffers = unsafe { device.raw.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?;
            device.set_name(*pool, &format!("{name} {i} pool"));
            device.set_name(buffers[0], &format!("{name} {i}"));
            out.workers.push((pool.take(), buffers[0]));
        }
        Ok(out.take())
    }

    /// Destroy the pools (and their command buffers).
    ///
    /// # Safety
    /// None of the command buffers may be pending.
    pub unsafe fn destroy(&mut self, device: &Device) {
        for (pool, _) in self.workers.drain(..) {
            // SAFETY: per the contract.
            unsafe {
                crate::vk::live::destroyed(pool);
                device.raw.destroy_command_pool(pool, None)
            };
        }
    }
}

impl Destroy for SecondaryRecorders {
    unsafe fn destroy(mut self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { SecondaryRecorders::destroy(&mut self, device) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_cover_every_blade_once() {
        for (blades, clusters) in [(10, 3), (1000, 1000), (7, 10), (100_000, 4096), (1, 1)] {
            let r = ranges(blades, clusters);
            assert_eq!(r.len() as u32, clusters.min(blades));
            let mut next = 0;
            for (first, count) in r {
                assert_eq!(first, next);
                assert!(count > 0);
                next = first + count;
            }
            assert_eq!(next, blades);
        }
    }

    #[test]
    fn each_strategy_needs_what_the_spec_requires_and_no_more() {
        let all = DrawCapabilities {
            first_instance: true,
            multi_draw_indirect: true,
            draw_indirect_count: true,
            max_draw_indirect_count: 1 << 20,
        };
        for s in Strategy::ALL {
            assert_eq!(s.missing(&all, 1000), None, "{}", s.name());
        }
        // Without multiDrawIndirect: one MDI draw of many is invalid, the count draw is not.
        let no_mdi = DrawCapabilities { multi_draw_indirect: false, ..all };
        assert_eq!(Strategy::Mdi.missing(&no_mdi, 1000).as_deref(), Some("no multiDrawIndirect"));
        assert_eq!(Strategy::Mdi.missing(&no_mdi, 1), None);
        assert_eq!(Strategy::MdiCount.missing(&no_mdi, 1000), None);
        let no_count = DrawCapabilities { draw_indirect_count: false, ..all };
        assert_eq!(Strategy::MdiCount.missing(&no_count, 1000).as_deref(), Some("no drawIndirectCount"));
        let small = DrawCapabilities { max_draw_indirect_count: 1, ..all };
        assert!(Strategy::MdiCount.missing(&small, 2).is_some_and(|w| w.contains("maxDrawIndirectCount")));
        let no_first = DrawCapabilities { first_instance: false, ..all };
        assert_eq!(Strategy::Indirect.missing(&no_first, 10).as_deref(), Some("no drawIndirectFirstInstance"));
        assert_eq!(Strategy::PerCluster.missing(&no_first, 10), None);
    }

    #[test]
    fn names_round_trip() {
        for s in Strategy::ALL {
            assert_eq!(Strategy::parse(s.name()), Some(s));
        }
        assert_eq!(Strategy::parse("mesh"), None);
    }
}
