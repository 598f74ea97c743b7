//! A subsystem's own part of each frame in flight (`PerFrame`): one value per frame slot, made
//! with the ring and indexed by the slot `FrameRing::begin` hands out. The ring's fence for a
//! slot guards that slot's part of every subsystem, so a subsystem rewrites its part after
//! `begin` returned the slot and reads what the GPU wrote there when the slot's timings come
//! back. A new subsystem (a wind grid, a blade state store) adds its per-frame buffers by owning
//! a `PerFrame` of them; the ring (`Frame`) holds only the fence, the commands and the queries.

use std::ops::{Index, IndexMut};

use crate::error::Result;
use crate::vk::{Destroy, Device, Guard};

/// One `T` per frame in flight, by slot.
pub struct PerFrame<T> {
    slots: Vec<T>,
}

impl<T> Default for PerFrame<T> {
    fn default() -> Self {
        Self { slots: Vec::new() }
    }
}

impl<T: Destroy> PerFrame<T> {
    /// `slots` values, `make(slot)` each; on failure the ones made are destroyed.
    pub fn new(device: &Device, slots: usize, mut make: impl FnMut(usize) -> Result<T>) -> Result<Self> {
        let mut made = Guard::new(device, Vec::with_capacity(slots));
        for slot in 0..slots {
            let value = make(slot)?;
            made.push(value);
        }
        Ok(Self { slots: made.take() })
    }
}

impl<T> PerFrame<T> {
    /// Number of slots.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Whether there is none (not built yet).
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// Every slot's value, by slot.
    pub fn iter(&self) -> std::slice::Iter<'_, T> {
        self.slots.iter()
    }
}

impl<T> Index<usize> for PerFrame<T> {
    type Output = T;
    fn index(&self, slot: usize) -> &T {
        &self.slots[slot]
    }
}

impl<T> IndexMut<usize> for PerFrame<T> {
    fn index_mut(&mut self, slot: usize) -> &mut T {
        &mut self.slots[slot]
    }
}

impl<T: Destroy> Destroy for PerFrame<T> {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.slots.destroy(device) };
    }
}

impl<T> From<PerFrame<T>> for Vec<T> {
    fn from(ring: PerFrame<T>) -> Self {
        ring.slots
    }
}
