//! Access tracking: what each resource was last used for, so the next use's barrier can be
//! derived instead of written by hand. One [`ResourceState`] per buffer or image records the
//! accesses a later write must wait for; [`ResourceState::access`] turns the next use into the
//! `previous → next` pair `sync::transition` makes a barrier of, or into nothing when there is no
//! hazard (a read of data already made visible to that read).
//!
//! The rules, after vk-sync-rs and kajiya's render graph:
//! - a write (or any layout change) waits for every access since the last write, and for that
//!   write (WAR and WAW, the write made available);
//! - a read waits for the last write, once per kind of read (RAW); reads of data nobody wrote
//!   since it was imported need nothing;
//! - an image's layout is the one its last barrier left; reading it in another layout is a
//!   transition like a write.

use std::collections::HashMap;

use ash::vk;
use smallvec::SmallVec;

use crate::vk::image::{COLOR_RANGE, DEPTH_RANGE};
use crate::vk::sync::{self, Access};

/// A resource whose accesses are tracked: a whole buffer, or mips of one aspect of an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Resource {
    /// A whole buffer.
    Buffer(vk::Buffer),
    /// Mips `base_mip .. base_mip + mips` of one aspect of a single-layer image, 2-D or 3-D (a
    /// 3-D image has one layer: its depth slices are one subresource, tracked as a whole).
    Image {
        /// The image.
        raw: vk::Image,
        /// Colour or depth.
        aspect: vk::ImageAspectFlags,
        /// First mip.
        base_mip: u32,
        /// Number of mips.
        mips: u32,
    },
}

impl Resource {
    /// A whole colour image with one mip (2-D, or 3-D: a storage grid).
    pub fn color(raw: vk::Image) -> Self {
        Resource::Image { raw, aspect: vk::ImageAspectFlags::COLOR, base_mip: 0, mips: 1 }
    }

    /// A whole depth image with one mip.
    pub fn depth(raw: vk::Image) -> Self {
        Resource::Image { raw, aspect: vk::ImageAspectFlags::DEPTH, base_mip: 0, mips: 1 }
    }

    /// Whether this is an image (whose accesses carry layouts).
    pub fn is_image(self) -> bool {
        matches!(self, Resource::Image { .. })
    }

    /// The subresource range of an image resource.
    pub fn range(self) -> vk::ImageSubresourceRange {
        match self {
            Resource::Image { aspect, base_mip, mips, .. } => {
                let whole = if aspect == vk::ImageAspectFlags::DEPTH { DEPTH_RANGE } else { COLOR_RANGE };
                vk::ImageSubresourceRange { aspect_mask: aspect, base_mip_level: base_mip, level_count: mips, ..whole }
            }
            Resource::Buffer(_) => COLOR_RANGE,
        }
    }
}

/// What a resource was last used for.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ResourceState {
    /// What a new kind of read waits on: the last write, or the last layout transition, or the
    /// accesses the resource was imported with (their memory dependency made the data available);
    /// empty when nothing wrote the resource since it was created.
    source: Accesses,
    /// Reads since `source` whose memory is already visible (repeating one needs no barrier).
    reads: Accesses,
    /// Current image layout (UNDEFINED for buffers and unwritten images).
    layout: vk::ImageLayout,
    /// Whether the state came from an import (images must be imported before use).
    imported: bool,
}

/// The transition a use needs: previous accesses → next accesses.
pub type Hazard = (Accesses, Accesses);

/// A few accesses of one resource, kept inline: tracking a frame allocates nothing (the frame's
/// record is measured against 0.1 ms of CPU).
pub type Accesses = SmallVec<[Access; 4]>;

impl ResourceState {
    /// The state of a resource last accessed by `accesses` (e.g. `Nothing` to discard an image,
    /// `Acquired` for a swapchain image, the read accesses an upload made it visible to).
    pub fn imported(accesses: &[Access]) -> Self {
        let reads = accesses.iter().copied().filter(|a| a.writes() == vk::AccessFlags2::NONE).collect();
        let layout = accesses.first().map_or(vk::ImageLayout::UNDEFINED, |a| a.info().layout);
        Self { source: Accesses::from_slice(accesses), reads, layout, imported: true }
    }

    /// The contents discarded (the next transition starts from UNDEFINED), ordered after every
    /// access since the source.
    fn discarded(&self) -> Self {
        let mut source = self.reads.clone();
        source.extend(self.source.iter().copied().filter(|a| !self.reads.contains(a) && *a != Access::Nothing));
        source.push(Access::Nothing);
        Self { source, reads: Accesses::new(), layout: vk::ImageLayout::UNDEFINED, imported: true }
    }

    /// Whether the state came from an import rather than from a default.
    pub fn is_imported(&self) -> bool {
        self.imported
    }

    /// Record that the resource is used by `next` (one use: all of them happen together, and on an
    /// image they share one layout), returning the transition it needs, if any.
    pub fn access(&mut self, next: &[Access], image: bool) -> Option<Hazard> {
        let layout = next.first().map_or(vk::ImageLayout::UNDEFINED, |a| a.info().layout);
        let writes = next.iter().any(|a| a.writes() != vk::AccessFlags2::NONE);
        // Accesses without stages (presentation) are layout changes only.
        let relayout = image && (layout != self.layout || next.iter().any(|a| a.info().stages.is_empty()));
        if writes || relayout {
            // WAR on every read since the source, WAW (or the chain) on the source itself.
            let mut previous = self.reads.clone();
            previous.extend(self.source.iter().copied().filter(|a| !self.reads.contains(a)));
            if image && previous.is_empty() {
                previous.push(Access::Nothing);
            }
            // A write leaves nothing visible; a read in a new layout is visible to itself, and a
            // later read of another kind chains through it (the transition made the data
            // available, the next barrier makes it visible to that read).
            let reads = if writes { Accesses::new() } else { Accesses::from_slice(next) };
            *self = Self { source: Accesses::from_slice(next), reads, layout, imported: self.imported };
            // A buffer nobody used yet needs no barrier before its first write.
            return (!previous.is_empty()).then(|| (previous, Accesses::from_slice(next)));
        }
        if next.iter().all(|a| self.reads.contains(a)) {
            return None;
        }
        for a in next {
            if !self.reads.contains(a) {
                self.reads.push(*a);
            }
        }
        (!self.source.is_empty()).then(|| (self.source.clone(), Accesses::from_slice(next)))
    }
}

/// The states of every tracked resource, carried from frame to frame (one queue: the order of
/// recording is the order of execution).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ResourceStates {
    states: HashMap<Resource, ResourceState>,
}

impl ResourceStates {
    /// Set `resource`'s state to "last accessed by `accesses`". Importing a tracked resource as
    /// `[Access::Nothing]` discards its contents but still waits for what the tracked state says
    /// used it last (earlier frames may be using it still).
    pub fn import(&mut self, resource: Resource, accesses: &[Access]) {
        let state = match (accesses, self.states.get(&resource)) {
            ([Access::Nothing], Some(tracked)) => tracked.discarded(),
            _ => ResourceState::imported(accesses),
        };
        self.states.insert(resource, state);
    }

    /// Forget `resource` (destroyed, or its handle may be reused).
    pub fn forget(&mut self, resource: Resource) {
        self.states.remove(&resource);
    }

    /// The state of `resource` (default for one never seen).
    pub fn get(&self, resource: Resource) -> Option<&ResourceState> {
        self.states.get(&resource)
    }

    /// Record the use of `resource` by `next`; returns its transition, if it needs one.
    pub fn access(&mut self, resource: Resource, next: &[Access]) -> Option<Hazard> {
        self.states.entry(resource).or_default().access(next, resource.is_image())
    }
}

/// The barriers of a batch of uses, built through `sync`.
#[derive(Default)]
pub struct Barriers {
    /// Buffer barriers.
    pub buffers: SmallVec<[vk::BufferMemoryBarrier2<'static>; 4]>,
    /// Image barriers.
    pub images: SmallVec<[vk::ImageMemoryBarrier2<'static>; 2]>,
}

impl Barriers {
    /// Add the barrier of `hazard` on `resource`.
    pub fn push(&mut self, resource: Resource, (previous, next): &Hazard) {
        match resource {
            Resource::Buffer(raw) => self.buffers.push(sync::buffer_barrier(raw, previous, next)),
            Resource::Image { raw, .. } => {
                self.images.push(sync::image_barrier(raw, resource.range(), previous, next));
            }
        }
    }

    /// Whether there is nothing to record.
    pub fn is_empty(&self) -> bool {
        self.buffers.is_empty() && self.images.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use smallvec::smallvec;

    use super::*;

    const IMAGE: bool = true;
    const BUFFER: bool = false;

    #[test]
    fn compute_then_vertex_read_then_next_frame_write() {
        // The blade-pose records: written in compute, read by the vertex shader, written again
        // by the next frame (WAR on the reads, WAW on the write).
        let mut s = ResourceState::default();
        assert_eq!(s.access(&[Access::ComputeShaderWrite], BUFFER), None, "first write: nothing to wait for");
        let raw = s.access(&[Access::VertexShaderStorageRead], BUFFER);
        assert_eq!(raw, Some((smallvec![Access::ComputeShaderWrite], smallvec![Access::VertexShaderStorageRead])));
        assert_eq!(s.access(&[Access::VertexShaderStorageRead], BUFFER), None, "already visible");
        let war = s.access(&[Access::ComputeShaderWrite], BUFFER).expect("a hazard");
        assert_eq!(war.0.to_vec(), vec![Access::VertexShaderStorageRead, Access::ComputeShaderWrite]);
    }

    #[test]
    fn a_new_kind_of_read_waits_for_the_write_again() {
        let mut s = ResourceState::default();
        s.access(&[Access::ComputeShaderWrite], BUFFER);
        s.access(&[Access::VertexShaderStorageRead], BUFFER);
        let indirect = s.access(&[Access::IndirectCommandRead], BUFFER);
        assert_eq!(indirect, Some((smallvec![Access::ComputeShaderWrite], smallvec![Access::IndirectCommandRead])));
    }

    #[test]
    fn a_new_kind_of_read_after_a_transition_or_an_import_waits_for_it() {
        let mut s = ResourceState::imported(&[Access::ColorAttachmentWrite]);
        s.access(&[Access::FragmentShaderSampledRead], IMAGE).expect("layout change");
        let vertex = s.access(&[Access::VertexShaderSampledRead], IMAGE);
        assert_eq!(
            vertex,
            Some((smallvec![Access::FragmentShaderSampledRead], smallvec![Access::VertexShaderSampledRead]))
        );
        assert_eq!(s.access(&[Access::VertexShaderSampledRead], IMAGE), None, "now visible");
        let mut uploaded = ResourceState::imported(&[Access::VertexShaderSampledRead]);
        let fragment = uploaded.access(&[Access::FragmentShaderSampledRead], IMAGE);
        assert_eq!(
            fragment,
            Some((smallvec![Access::VertexShaderSampledRead], smallvec![Access::FragmentShaderSampledRead]))
        );
        // A later write waits for both reads, once each.
        let war = s.access(&[Access::ColorAttachmentWrite], IMAGE).expect("WAR");
        assert_eq!(war.0.to_vec(), vec![Access::FragmentShaderSampledRead, Access::VertexShaderSampledRead]);
    }

    #[test]
    fn uploaded_data_read_as_imported_needs_no_barrier() {
        let mut s = ResourceState::imported(&[Access::VertexShaderSampledRead, Access::ComputeShaderSampledRead]);
        assert_eq!(s.access(&[Access::VertexShaderSampledRead], IMAGE), None);
        assert_eq!(s.access(&[Access::ComputeShaderSampledRead], IMAGE), None);
    }

    #[test]
    fn acquired_image_is_transitioned_then_presented() {
        let mut s = ResourceState::imported(&[Access::Acquired]);
        let first = s.access(&[Access::ColorAttachmentWrite], IMAGE).expect("layout change");
        assert_eq!(first.0.to_vec(), vec![Access::Acquired]);
        let t = sync::transition(&first.0, &first.1);
        assert_eq!(
            (t.old_layout, t.new_layout),
            (vk::ImageLayout::UNDEFINED, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        );
        // A second pass loading the same attachment: write after write, same layout.
        let second = s.access(&[Access::ColorAttachmentWrite], IMAGE).expect("WAW");
        assert_eq!(second.0.to_vec(), vec![Access::ColorAttachmentWrite]);
        let present = s.access(&[Access::Present], IMAGE).expect("layout change");
        assert_eq!(sync::transition(&present.0, &present.1).new_layout, vk::ImageLayout::PRESENT_SRC_KHR);
    }

    #[test]
    fn unimported_image_discards_and_reading_in_a_new_layout_transitions() {
        let mut s = ResourceState::default();
        let first = s.access(&[Access::ColorAttachmentWrite], IMAGE).expect("layout change");
        assert_eq!(first.0.to_vec(), vec![Access::Nothing]);
        let copy = s.access(&[Access::TransferRead], IMAGE).expect("layout change");
        assert_eq!(copy.0.to_vec(), vec![Access::ColorAttachmentWrite]);
        assert_eq!(s.access(&[Access::TransferRead], IMAGE), None);
        // The next frame writes it again: waits for the copy.
        let again = s.access(&[Access::ColorAttachmentWrite], IMAGE).expect("WAR + layout");
        assert_eq!(again.0.to_vec(), vec![Access::TransferRead]);
    }

    #[test]
    fn discarding_a_tracked_image_still_waits_for_its_last_use() {
        let mut states = ResourceStates::default();
        let image = Resource::color(vk::Image::null());
        states.import(image, &[Access::Nothing]);
        assert_eq!(
            states.access(image, &[Access::ColorAttachmentWrite]).expect("layout").0.to_vec(),
            vec![Access::Nothing]
        );
        states.import(image, &[Access::Nothing]);
        let (previous, next) = states.access(image, &[Access::ColorAttachmentWrite]).expect("WAW");
        assert_eq!(previous.to_vec(), vec![Access::ColorAttachmentWrite, Access::Nothing]);
        let t = sync::transition(&previous, &next);
        assert_eq!(t.old_layout, vk::ImageLayout::UNDEFINED, "contents discarded");
        assert!(
            t.src_stages.contains(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT),
            "after the last frame's writes"
        );
        assert_eq!(t.src_access, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE);
    }

    #[test]
    fn storage_grid_written_read_sampled_and_written_again() {
        // A 3-D grid of a solver: written by one dispatch, read by the next (RAW in GENERAL),
        // sampled by a third (a layout change), written by the next frame (WAR, back to GENERAL).
        let mut states = ResourceStates::default();
        let grid = Resource::color(vk::Image::null());
        states.import(grid, &[Access::Nothing]);
        let (previous, next) = states.access(grid, &[Access::ComputeShaderWrite]).expect("layout");
        let first = sync::transition(&previous, &next);
        assert_eq!((first.old_layout, first.new_layout), (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL));
        let (previous, next) = states.access(grid, &[Access::ComputeShaderRead]).expect("RAW");
        let raw = sync::transition(&previous, &next);
        assert_eq!(
            (raw.src_access, raw.dst_access),
            (vk::AccessFlags2::SHADER_STORAGE_WRITE, vk::AccessFlags2::SHADER_STORAGE_READ)
        );
        assert_eq!((raw.old_layout, raw.new_layout), (vk::ImageLayout::GENERAL, vk::ImageLayout::GENERAL));
        assert_eq!(states.access(grid, &[Access::ComputeShaderRead]), None, "already visible");
        let (previous, next) = states.access(grid, &[Access::ComputeShaderSampledRead]).expect("layout");
        let sampled = sync::transition(&previous, &next);
        assert_eq!(sampled.new_layout, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
        assert_eq!(sampled.src_access, vk::AccessFlags2::SHADER_STORAGE_WRITE, "the write made available");
        let (previous, next) = states.access(grid, &[Access::ComputeShaderWrite]).expect("WAR + layout");
        assert_eq!(previous.to_vec(), vec![Access::ComputeShaderSampledRead]);
        let again = sync::transition(&previous, &next);
        assert_eq!(
            (again.old_layout, again.new_layout),
            (vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL, vk::ImageLayout::GENERAL)
        );
    }

    #[test]
    fn states_persist_per_resource() {
        let mut states = ResourceStates::default();
        let a = Resource::Buffer(vk::Buffer::null());
        states.access(a, &[Access::TransferWrite]);
        assert!(states.access(a, &[Access::HostRead]).is_some());
        assert!(states.access(Resource::color(vk::Image::null()), &[Access::ColorAttachmentWrite]).is_some());
    }
}
