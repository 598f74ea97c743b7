//! Fault injection for the tests: environment variables that make the N-th call of a kind fail
//! as the driver would report it, so that every failure path runs on lavapipe, which never
//! fails these calls on its own. `MEADOW_INJECT_ALLOC_FAILURE=N`: the N-th memory allocation of
//! the process runs out of device memory; `MEADOW_INJECT_ACQUIRE_FAILURE=N` and
//! `MEADOW_INJECT_PRESENT_FAILURE=N`: the N-th `vkAcquireNextImageKHR` / `vkQueuePresentKHR` loses
//! the surface; `MEADOW_INJECT_HOST_MEMORY_FAILURE=N`: the N-th `vkCreateShaderModule` (every
//! pipeline makes one) runs out of host memory; `MEADOW_INJECT_FREE_FAILURE=N`: the allocator
//! reports an error for the N-th free (the memory is freed). (Submissions:
//! `MEADOW_INJECT_SUBMIT_FAILURE`, `render::frame::FrameRing`.)
//!
//! Every call of a kind is counted, asked for or not: [`calls`] tells a test where a run is (the
//! viewer's `sample:` lines print the allocations made), so it can aim a failure at one moment.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};

/// A kind of call that can be made to fail.
#[derive(Clone, Copy)]
pub enum Fault {
    /// Memory allocation (`Device::allocate`).
    Allocation,
    /// `vkAcquireNextImageKHR`.
    Acquire,
    /// `vkQueuePresentKHR`.
    Present,
    /// `vkCreateShaderModule`, failing with `VK_ERROR_OUT_OF_HOST_MEMORY`.
    HostMemory,
    /// `Allocator::free`.
    Free,
}

const KINDS: usize = 5;

impl Fault {
    fn variable(self) -> &'static str {
        match self {
            Fault::Allocation => "MEADOW_INJECT_ALLOC_FAILURE",
            Fault::Acquire => "MEADOW_INJECT_ACQUIRE_FAILURE",
            Fault::Present => "MEADOW_INJECT_PRESENT_FAILURE",
            Fault::HostMemory => "MEADOW_INJECT_HOST_MEMORY_FAILURE",
            Fault::Free => "MEADOW_INJECT_FREE_FAILURE",
        }
    }

    fn counter(self) -> &'static AtomicU64 {
        static CALLS: [AtomicU64; KINDS] = [const { AtomicU64::new(0) }; KINDS];
        &CALLS[self as usize]
    }
}

/// Calls of kind `fault` made so far in this process.
pub fn calls(fault: Fault) -> u64 {
    fault.counter().load(Ordering::Relaxed)
}

/// Count one call of kind `fault`; true when it is the one to fail. The variables are read once
/// per process (acquire and present ask every frame).
pub fn fails(fault: Fault) -> bool {
    static NTH: OnceLock<[Option<u64>; KINDS]> = OnceLock::new();
    let nth = NTH.get_or_init(|| {
        [Fault::Allocation, Fault::Acquire, Fault::Present, Fault::HostMemory, Fault::Free]
            .map(|f| std::env::var(f.variable()).ok().and_then(|v| v.trim().parse::<u64>().ok()))
    });
    let call = fault.counter().fetch_add(1, Ordering::Relaxed) + 1;
    record_site(fault);
    nth[fault as usize] == Some(call) || armed(fault).load(Ordering::Relaxed) == call
}

/// The call of each kind [`fail_in`] aimed at (0: none).
fn armed(fault: Fault) -> &'static AtomicU64 {
    static ARMED: [AtomicU64; KINDS] = [const { AtomicU64::new(0) }; KINDS];
    &ARMED[fault as usize]
}

/// Make the `nth` next call of kind `fault` in this process fail (`None`: none), as its
/// variable would: a test that builds many renderers in one process aims at each call in turn.
pub fn fail_in(fault: Fault, nth: Option<u64>) {
    armed(fault).store(nth.map_or(0, |n| calls(fault) + n), Ordering::Relaxed);
}

/// Where the calls of each kind were made while recording (`record_sites`), in call order.
fn sites_of(fault: Fault) -> &'static Mutex<Option<Vec<String>>> {
    static SITES: [Mutex<Option<Vec<String>>>; KINDS] = [const { Mutex::new(None) }; KINDS];
    &SITES[fault as usize]
}

/// Record the call site of every call of kind `fault` from now on, until [`sites`] takes them:
/// a test runs a construction once, then aims one failure at each distinct site.
pub fn record_sites(fault: Fault) {
    *sites_of(fault).lock().unwrap_or_else(|p| p.into_inner()) = Some(Vec::new());
}

/// The call sites recorded since [`record_sites`], one per call in call order, and stop
/// recording. A site is the call's stack through meadow's own source files (`src/…:line`).
pub fn sites(fault: Fault) -> Vec<String> {
    sites_of(fault).lock().unwrap_or_else(|p| p.into_inner()).take().unwrap_or_default()
}

fn record_site(fault: Fault) {
    let mut sites = sites_of(fault).lock().unwrap_or_else(|p| p.into_inner());
    if let Some(sites) = sites.as_mut() {
        let trace = std::backtrace::Backtrace::force_capture().to_string();
        let frames: Vec<&str> = trace
            .lines()
            .filter_map(|line| line.trim().strip_prefix("at "))
            .filter(|at| at.contains("src/") && !at.contains("/rustc/") && !at.contains("/.cargo/"))
            .collect();
        sites.push(frames.join(" < "));
    }
}
