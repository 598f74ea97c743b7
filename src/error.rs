//! Typed errors of the library. The binary prints them as one `error: …` line and exits with
//! [`Error::exit_code`]: 2 for bad input (the user can fix the command line), 1 for runtime
//! failures (driver, I/O, a missing layer).

use ash::vk;

/// Everything meadow can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value given by the user is out of range, malformed, or exceeds a device limit or budget.
    #[error("{0}")]
    BadInput(String),
    /// The device was lost (`VK_ERROR_DEVICE_LOST`): a GPU reset or a driver failure. Nothing
    /// on it can be used again; every object is still destroyed on the way out.
    #[error("{call}: the GPU device was lost (VK_ERROR_DEVICE_LOST); its work is gone, nothing was written")]
    DeviceLost {
        /// The entry point that reported it.
        call: &'static str,
    },
    /// Out of device or host memory: a Vulkan call's `VK_ERROR_OUT_OF_{DEVICE,HOST}_MEMORY`, or
    /// the allocator finding no memory for a resource.
    #[error("{during}: out of {memory} memory (try fewer blades, segments or pixels)")]
    OutOfMemory {
        /// The call, or the resource being allocated.
        during: String,
        /// `device` or `host`.
        memory: &'static str,
    },
    /// The window's surface was lost (`VK_ERROR_SURFACE_LOST_KHR`): the window went away under
    /// the swapchain.
    #[error("{call}: the window's surface was lost (VK_ERROR_SURFACE_LOST_KHR)")]
    SurfaceLost {
        /// The entry point that reported it.
        call: &'static str,
    },
    /// A Vulkan call returned another error code.
    #[error("{call} failed: {result:?}")]
    Vulkan {
        /// The failing entry point, e.g. `vkCreateDevice`.
        call: &'static str,
        /// The code it returned.
        result: vk::Result,
    },
    /// gpu-allocator could not allocate or free.
    #[error("allocation of `{name}` failed: {source}")]
    Allocation {
        /// Debug name of the allocation.
        name: String,
        /// The allocator's error.
        source: gpu_allocator::AllocationError,
    },
    /// The environment lacks something meadow needs (loader, layer, device, feature).
    #[error("{0}")]
    Environment(String),
    /// A broken invariant of the renderer itself (e.g. a pass declaring an image it never
    /// imported): a bug, reported rather than panicking.
    #[error("internal error: {0}")]
    Internal(String),
    /// Drawing a chart failed (the measuring harness draws PNG charts).
    #[error("plot: {0}")]
    Plot(String),
    /// SIGINT (Ctrl-C), SIGTERM or SIGHUP stopped a command before it wrote anything (exit 128
    /// + the signal's number, as a shell reports it: 130, 143, 129; `app::interrupt`).
    #[error("interrupted by {}: nothing written", signal_name(.signal))]
    Interrupted {
        /// The signal's number.
        signal: i32,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", quoted(.path))]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        source: std::io::Error,
    },
}

impl Error {
    /// Process exit code for this error: 2 for bad input, 128 + the signal for a signal (130
    /// for Ctrl-C), 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::BadInput(_) => 2,
            Error::Interrupted { signal } => 128 + signal,
            _ => 1,
        }
    }

    /// The error of Vulkan call `call` returning `result`: device lost, out of memory and surface
    /// lost are their own variants, with their own messages; the rest is [`Error::Vulkan`].
    pub fn vulkan(call: &'static str, result: vk::Result) -> Self {
        match result {
            vk::Result::ERROR_DEVICE_LOST => Error::DeviceLost { call },
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => Error::OutOfMemory { during: call.into(), memory: "device" },
            vk::Result::ERROR_OUT_OF_HOST_MEMORY => Error::OutOfMemory { during: call.into(), memory: "host" },
            vk::Result::ERROR_SURFACE_LOST_KHR => Error::SurfaceLost { call },
            result => Error::Vulkan { call, result },
        }
    }

    /// The error of allocating `name` from gpu-allocator: out of memory is
    /// [`Error::OutOfMemory`], the rest [`Error::Allocation`].
    pub fn allocation(name: &str, source: gpu_allocator::AllocationError) -> Self {
        match source {
            gpu_allocator::AllocationError::OutOfMemory => {
                Error::OutOfMemory { during: format!("allocating `{name}`"), memory: "device" }
            }
            source => Error::Allocation { name: name.into(), source },
        }
    }

    /// Shorthand for [`Error::BadInput`].
    pub fn bad_input(message: impl Into<String>) -> Self {
        Error::BadInput(message.into())
    }
}

/// The name of a signal that stops a command.
fn signal_name(signal: &i32) -> String {
    match *signal {
        libc::SIGINT => "SIGINT".into(),
        libc::SIGTERM => "SIGTERM".into(),
        libc::SIGHUP => "SIGHUP".into(),
        other => format!("signal {other}"),
    }
}

/// Most characters of user text an error message quotes ([`quoted`]).
pub const QUOTE_CHARS: usize = 80;

/// User text (a value, a label, a name, a path) as every error message quotes it: whole up to
/// [`QUOTE_CHARS`] characters, else its first and last characters around `…` and how long it
/// was, so a 10 MB device name or label cannot make a 10 MB error line (the end of a long path,
/// its file name, stays readable).
pub fn quoted(text: &str) -> std::borrow::Cow<'_, str> {
    let chars = text.chars().count();
    if chars <= QUOTE_CHARS {
        return text.into();
    }
    let keep = QUOTE_CHARS / 2 - 1;
    let head: String = text.chars().take(keep).collect();
    let tail: String = text.chars().skip(chars - keep).collect();
    format!("{head}…{tail} ({} bytes)", text.len()).into()
}

/// Result alias of the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Attach the entry-point name to a raw `VkResult` error.
pub trait VkContext<T> {
    /// Turn `Err(vk::Result)` into [`Error::Vulkan`] naming `call`.
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::vulkan(call, result))
    }
}
