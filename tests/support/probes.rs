//! The tests' own shaders (`tests/shaders/`), compiled by `build.rs` like the library's and not
//! part of it: `meadow::spirv_shader!("tests/<path under tests/shaders>")`.
#![allow(dead_code)] // each test crate uses a different subset of these probes

use meadow::spirv_shader;
use meadow::vk::profile::Shader;

/// Reads every `BladeInstance` field back.
pub const BLADE_READBACK_COMP: Shader = spirv_shader!("tests/probes/blade_readback.comp");
/// Reads every `FrameUniforms` field and the specialization constants back.
pub const FRAME_READBACK_COMP: Shader = spirv_shader!("tests/probes/frame_readback.comp");
/// Per-blade forces through `forces.glsl`.
pub const BLADE_FORCES_COMP: Shader = spirv_shader!("tests/probes/blade_forces.comp");
/// Decodes the keyframe texture / uniform array through the vertex shader's decoder.
pub const KEYFRAME_DECODE_COMP: Shader = spirv_shader!("tests/probes/keyframe_decode.comp");
/// The keyframe selection and smoothing (`kf_select`, `kf_level`) for a buffer of forces.
pub const KEYFRAME_POSE_COMP: Shader = spirv_shader!("tests/probes/keyframe_pose.comp");
/// Belyaev's Fresnel term at static blades' strip vertices, through the blade shader's functions.
pub const FRESNEL_PROBE_COMP: Shader = spirv_shader!("tests/probes/fresnel_probe.comp");
/// `height_six`, the l^6 coarse strip levels are lit with, at every level of every strip.
pub const HEIGHT_SIX_PROBE_COMP: Shader = spirv_shader!("tests/probes/height_six_probe.comp");
/// `encode_output`, the sRGB transfer of the UNORM targets, over [0, 1].
pub const SRGB_PROBE_COMP: Shader = spirv_shader!("tests/probes/srgb_probe.comp");
