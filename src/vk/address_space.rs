//! The process's address-space limit (`RLIMIT_AS`, what `ulimit -v` sets) against what is about
//! to be mapped. lavapipe maps its rasteriser threads' stacks and LLVM's code and data while the
//! device is created, and under a limit too tight for them it crashes inside `vkCreateDevice`
//! (a segfault, not an error code): the device's need is checked first, and a limit that
//! cannot hold it is one `error:` line (exit 1). The same check bounds what reading an input
//! may allocate (`app::input`), so a tight limit ends with a message, not an allocation abort.

use ash::vk;

use crate::error::{Error, Result};

/// Address space a software (CPU) device maps beyond what the process already has when
/// `vkCreateDevice` is called, through its first frames (pipelines compiled, rasteriser threads
/// started), in bytes. Measured on lavapipe (Mesa 22.3, LLVM 15, 2 cores): `VmSize` is 233 MiB
/// when the device is created (instance, loader, driver libraries; about 190 MiB more with the
/// validation layer, which the check sees as already mapped), and `VmPeak` of a whole
/// `meadow render` is 792 MiB at 2 000 blades and 802 MiB at 200 000 blades and 1280×720: about
/// 570 MiB for the device and its frames, and this leaves 70 MiB of margin. Under a limit that
/// leaves less, lavapipe segfaults in `vkCreateDevice` (250–500 MB) or fails later.
pub const SOFTWARE_DEVICE_BYTES: u64 = 640 << 20;

/// The soft `RLIMIT_AS` in bytes; `None` when unlimited (or unreadable).
pub fn limit() -> Option<u64> {
    let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: getrlimit writes the struct it is given.
    let read = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) };
    (read == 0 && limit.rlim_cur != libc::RLIM_INFINITY).then_some(limit.rlim_cur)
}

/// Address space the process maps now (`VmSize` of `/proc/self/status`); 0 when unreadable.
pub fn mapped() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kib = status.lines().find_map(|l| l.strip_prefix("VmSize:")).and_then(|v| v.trim().strip_suffix("kB"));
    kib.and_then(|v| v.trim().parse::<u64>().ok()).map_or(0, |kib| kib * 1024)
}

/// Refuse `bytes` more of address space for `what` when the limit leaves less than that
/// (exit 1: the environment, not the command, is short). A software device's memory is the
/// process's own: `Device::check_budget` checks its allocations here too.
pub fn check_headroom(bytes: u64, what: &str) -> Result<()> {
    let Some(limit) = limit() else { return Ok(()) };
    let used = mapped();
    let left = limit.saturating_sub(used);
    if bytes <= left {
        return Ok(());
    }
    Err(Error::Environment(format!(
        "{what} needs about {} of address space, but the limit (ulimit -v {} KiB) leaves {} of it: raise the limit",
        super::device::format_bytes(bytes),
        limit / 1024,
        super::device::format_bytes(left)
    )))
}

/// Refuse to create a device of `kind` named `name` when the address-space limit cannot hold
/// what its driver maps ([`SOFTWARE_DEVICE_BYTES`] for a software device; a hardware driver's
/// needs are its own, and not checked).
pub fn check_device(kind: vk::PhysicalDeviceType, name: &str) -> Result<()> {
    if kind != vk::PhysicalDeviceType::CPU {
        return Ok(());
    }
    check_headroom(SOFTWARE_DEVICE_BYTES, &format!("the software device {name} (measured on lavapipe)"))
}
