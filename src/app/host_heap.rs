//! The process's heap policy, set once before the first Vulkan instance.
//!
//! A software device (lavapipe) runs in this process and allocates its host memory from the C
//! heap: llvmpipe bins every draw's triangles into scene blocks it mallocs while it records and
//! frees when the scene has been rasterised, several times a frame. By default glibc gives the
//! free top of a heap back to the kernel once it exceeds 128 KiB (`M_TRIM_THRESHOLD`), so every
//! frame faults the same pages in again and the kernel zeroes them: at the unbounded field's
//! default view, 364 000 page faults in a `meadow timing` run (about 3 000 a frame) and the blade
//! pass 62 ms; with the freed memory kept for reuse, 77 000 and 53 ms. A hardware driver does not
//! bin triangles in host memory, so there is little for it to keep. The heap keeps at most what
//! the largest frame used; the soaks (`make test`) check that it does not grow.

/// Keep freed heap memory for reuse instead of returning it to the kernel (glibc's
/// `M_TRIM_THRESHOLD`, 1 GiB). Idempotent; a no-op where the C library is not glibc.
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        static ONCE: std::sync::Once = std::sync::Once::new();
        ONCE.call_once(|| {
            // SAFETY: mallopt takes no pointers, and glibc sets the parameter under the
            // allocator's own lock, so other threads' allocations are not disturbed.
            let set = unsafe { libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD) };
            if set != 1 {
                log::warn!("mallopt(M_TRIM_THRESHOLD) was refused: the heap returns freed memory to the kernel");
            }
        });
    }
}

/// Free memory at the top of a heap that glibc keeps before trimming it: 1 GiB.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const TRIM_THRESHOLD: libc::c_int = 1 << 30;

#[cfg(all(test, target_os = "linux", target_env = "gnu"))]
mod tests {
    use super::*;

    /// Minor page faults of the calling thread so far.
    fn thread_faults() -> i64 {
        // SAFETY: getrusage writes the zeroed struct it is given.
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        assert_eq!(unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut usage) }, 0);
        usage.ru_minflt
    }

    /// 16 MiB in 64 KiB blocks (llvmpipe's scene block size), every page written.
    fn touch_blocks() -> Vec<Vec<u8>> {
        (0..256).map(|i| vec![i as u8 | 1; 64 << 10]).collect()
    }

    #[test]
    fn freed_blocks_are_reused_without_faulting_them_in_again() {
        keep_freed_memory();
        // On a thread of its own: glibc gives a new thread an arena no other live thread uses, so
        // the other tests' allocations cannot take the freed blocks in between.
        let faults = std::thread::spawn(|| {
            drop(touch_blocks());
            let before = thread_faults();
            let again = touch_blocks();
            let faults = thread_faults() - before;
            assert!(again.iter().all(|b| b[0] != 0));
            faults
        })
        .join()
        .expect("the measuring thread");
        // 4 096 pages: glibc's default trims the freed top of the heap and faults every one of
        // them in again (measured: 4 067).
        assert!(faults < 400, "{faults} page faults for 4 096 pages allocated a second time");
    }
}
