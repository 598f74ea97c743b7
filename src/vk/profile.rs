//! Backend profiles: which driver's workarounds the shaders and the scene's bindings are built
//! for. `build.rs` compiles every shader once per profile (`MEADOW_PROFILE_LAVAPIPE`,
//! `MEADOW_PROFILE_GENERIC`); the device picks one, and a pipeline takes its shader's code for it
//! (`Shader::code`).
//!
//! `MEADOW_PROFILE=lavapipe|generic` chooses; without it a llvmpipe device takes `lavapipe` and
//! any other `generic`.

use crate::error::{Error, Result};
use crate::vk::Access;

/// A backend profile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// Lavapipe's (Mesa 22.3 llvmpipe): the storage and texel-buffer twins of
    /// `shaders/common/profile.glsl`.
    Lavapipe,
    /// Any other driver: each resource bound once, as the shader reads it.
    Generic,
}

/// The environment variable that chooses the profile.
pub const PROFILE_VARIABLE: &str = "MEADOW_PROFILE";

impl Profile {
    /// The profile's name, as `MEADOW_PROFILE` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Profile::Lavapipe => "lavapipe",
            Profile::Generic => "generic",
        }
    }

    /// How a vertex shader reads a buffer of the scene that the lavapipe profile fetches through
    /// a texel view (its twin, `shaders/common/profile.glsl`) and the generic one as storage: the
    /// access the graph's barriers are derived for.
    pub fn vertex_fetch(self) -> Access {
        match self {
            Profile::Lavapipe => Access::VertexShaderSampledRead,
            Profile::Generic => Access::VertexShaderStorageRead,
        }
    }

    /// `vertex_fetch` for a compute shader.
    pub fn compute_fetch(self) -> Access {
        match self {
            Profile::Lavapipe => Access::ComputeShaderSampledRead,
            Profile::Generic => Access::ComputeShaderRead,
        }
    }

    /// `vertex_fetch` and `compute_fetch` together: how a buffer the scene's shaders fetch in
    /// both stages is left by its upload and imported into each graph.
    pub fn fetches(self) -> &'static [Access] {
        match self {
            Profile::Lavapipe => &[Access::VertexShaderSampledRead, Access::ComputeShaderSampledRead],
            Profile::Generic => &[Access::VertexShaderStorageRead, Access::ComputeShaderRead],
        }
    }

    /// The profile for a device whose `driverName` is `driver`: `MEADOW_PROFILE` (if set), else
    /// `lavapipe` on llvmpipe and `generic` elsewhere.
    pub fn choose(driver: &str) -> Result<Self> {
        Self::parse(std::env::var(PROFILE_VARIABLE).ok().as_deref(), driver)
    }

    /// `choose` with the variable's value given.
    pub fn parse(value: Option<&str>, driver: &str) -> Result<Self> {
        match value {
            None | Some("") => {
                Ok(if driver.eq_ignore_ascii_case("llvmpipe") { Profile::Lavapipe } else { Profile::Generic })
            }
            Some("lavapipe") => Ok(Profile::Lavapipe),
            Some("generic") => Ok(Profile::Generic),
            Some(other) => {
                Err(Error::bad_input(format!("{PROFILE_VARIABLE}={other:?}: expected `lavapipe` or `generic`")))
            }
        }
    }
}

/// One shader compiled by `build.rs`, in each profile.
#[derive(Clone, Copy, Debug)]
pub struct Shader {
    /// Its path under its tree, with the variant (`blades/blade.frag.coverage`).
    pub path: &'static str,
    /// SPIR-V built with `MEADOW_PROFILE_LAVAPIPE`.
    pub lavapipe: &'static [u8],
    /// SPIR-V built with `MEADOW_PROFILE_GENERIC`.
    pub generic: &'static [u8],
}

impl Shader {
    /// The SPIR-V for `profile`.
    pub fn code(&self, profile: Profile) -> &'static [u8] {
        match profile {
            Profile::Lavapipe => self.lavapipe,
            Profile::Generic => self.generic,
        }
    }
}

/// A `Shader` from `OUT_DIR/spirv/<profile>/<path>.spv`, as `build.rs` writes them: the
/// library's by their path under `shaders/`, a test's as `"tests/<path under tests/shaders>"`.
#[macro_export]
macro_rules! spirv_shader {
    ($path:literal) => {
        $crate::vk::profile::Shader {
            path: $path,
            lavapipe: include_bytes!(concat!(env!("OUT_DIR"), "/spirv/lavapipe/", $path, ".spv")),
            generic: include_bytes!(concat!(env!("OUT_DIR"), "/spirv/generic/", $path, ".spv")),
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_variable_overrides_the_driver_and_bad_values_are_refused() {
        assert_eq!(Profile::parse(None, "llvmpipe").unwrap(), Profile::Lavapipe);
        assert_eq!(Profile::parse(None, "NVIDIA").unwrap(), Profile::Generic);
        assert_eq!(Profile::parse(Some("generic"), "llvmpipe").unwrap(), Profile::Generic);
        assert_eq!(Profile::parse(Some("lavapipe"), "radv").unwrap(), Profile::Lavapipe);
        let error = Profile::parse(Some("fast"), "llvmpipe").unwrap_err();
        assert_eq!(error.exit_code(), 2);
        assert!(error.to_string().contains("MEADOW_PROFILE"), "{error}");
    }
}
