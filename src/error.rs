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
    /// A Vulkan call returned an error code.
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
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        source: std::io::Error,
    },
}

impl Error {
    /// Process exit code for this error: 2 for bad input, 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::BadInput(_) => 2,
            _ => 1,
        }
    }

    /// Shorthand for [`Error::BadInput`].
    pub fn bad_input(message: impl Into<String>) -> Self {
        Error::BadInput(message.into())
    }
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
        self.map_err(|result| Error::Vulkan { call, result })
    }
}
