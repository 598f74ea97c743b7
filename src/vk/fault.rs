//! Fault injection for the tests: environment variables that make the N-th call of a kind fail
//! as the driver would report it, so that every failure path runs on lavapipe, which never
//! fails these calls on its own. `MEADOW_INJECT_ALLOC_FAILURE=N`: the N-th memory allocation of
//! the process runs out of device memory; `MEADOW_INJECT_ACQUIRE_FAILURE=N` and
//! `MEADOW_INJECT_PRESENT_FAILURE=N`: the N-th `vkAcquireNextImageKHR` / `vkQueuePresentKHR` loses
//! the surface. (Submissions: `MEADOW_INJECT_SUBMIT_FAILURE`, `render::frame::FrameRing`.)

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

/// A kind of call that can be made to fail.
#[derive(Clone, Copy)]
pub enum Fault {
    /// Memory allocation (`Device::allocate`).
    Allocation,
    /// `vkAcquireNextImageKHR`.
    Acquire,
    /// `vkQueuePresentKHR`.
    Present,
}

impl Fault {
    fn variable(self) -> &'static str {
        match self {
            Fault::Allocation => "MEADOW_INJECT_ALLOC_FAILURE",
            Fault::Acquire => "MEADOW_INJECT_ACQUIRE_FAILURE",
            Fault::Present => "MEADOW_INJECT_PRESENT_FAILURE",
        }
    }

    fn calls(self) -> &'static AtomicU64 {
        static CALLS: [AtomicU64; 3] = [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)];
        &CALLS[self as usize]
    }
}

/// Count one call of kind `fault`; true when it is the one to fail. The variables are read once
/// per process (acquire and present ask every frame).
pub fn fails(fault: Fault) -> bool {
    static NTH: OnceLock<[Option<u64>; 3]> = OnceLock::new();
    let nth = NTH.get_or_init(|| {
        [Fault::Allocation, Fault::Acquire, Fault::Present]
            .map(|f| std::env::var(f.variable()).ok().and_then(|v| v.trim().parse::<u64>().ok()))
    });
    let Some(nth) = nth[fault as usize] else {
        return false;
    };
    fault.calls().fetch_add(1, Ordering::Relaxed) + 1 == nth
}
