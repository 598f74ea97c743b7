//! SPIR-V compiled by `build.rs` from `shaders/`, embedded in the binary.

macro_rules! spirv {
    ($name:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".spv"))
    };
}

/// Blade vertex shader (vertex pulling, Bézier strips).
pub const BLADE_VERT: &[u8] = spirv!("blade.vert");
/// Blade fragment shader (alpha test, lighting).
pub const BLADE_FRAG: &[u8] = spirv!("blade.frag");
/// Blade fragment shader with `--msaa` and alpha to coverage: the outline's coverage per sample.
pub const BLADE_COVERAGE_FRAG: &[u8] = spirv!("blade_coverage.frag");
/// Terrain vertex shader (height-field pulling).
pub const TERRAIN_VERT: &[u8] = spirv!("terrain.vert");
/// Terrain fragment shader.
pub const TERRAIN_FRAG: &[u8] = spirv!("terrain.frag");
/// Test: reads every `BladeInstance` field back.
pub const BLADE_READBACK_COMP: &[u8] = spirv!("blade_readback.comp");
/// Test: reads every `FrameUniforms` field and the specialization constants back.
pub const FRAME_READBACK_COMP: &[u8] = spirv!("frame_readback.comp");
/// Test and experiment: per-blade forces through `forces.glsl`.
pub const BLADE_FORCES_COMP: &[u8] = spirv!("blade_forces.comp");
/// `--eval blade`: per-blade pose records.
pub const BLADE_POSE_COMP: &[u8] = spirv!("blade_pose.comp");
/// With the cull and pose records: each drawn blade's levels placed and lit once.
pub const BLADE_LEVELS_COMP: &[u8] = spirv!("blade_levels.comp");
/// Test: decodes the keyframe texture / uniform array through the vertex shader's decoder.
pub const KEYFRAME_DECODE_COMP: &[u8] = spirv!("keyframe_decode.comp");
/// Test: the keyframe selection and smoothing (`kf_select`, `kf_level`) for a buffer of forces.
pub const KEYFRAME_POSE_COMP: &[u8] = spirv!("keyframe_pose.comp");
/// Floor reference: transform only.
pub const FLOOR_VERT: &[u8] = spirv!("floor.vert");
/// Floor reference: flat colour.
pub const FLOOR_FRAG: &[u8] = spirv!("floor.frag");
/// Debug view: the cluster grid as lines (`--debug-view bounds`).
pub const CLUSTER_BOUNDS_VERT: &[u8] = spirv!("cluster_bounds.vert");
/// Debug view: line colour.
pub const CLUSTER_BOUNDS_FRAG: &[u8] = spirv!("cluster_bounds.frag");
/// A block field's terrain grid: the relief's height and normal at each vertex, each frame.
pub const RELIEF_GRID_COMP: &[u8] = spirv!("relief_grid.comp");
/// The depth pyramid of the terrain (Hi-Z) the cull's occlusion test reads.
pub const HIZ_COMP: &[u8] = spirv!("hiz.comp");
/// Cull step 1: the tile tests of every ring slot, the list of slots with candidates.
pub const CULL_TILES_COMP: &[u8] = spirv!("cull_tiles.comp");
/// Cull step 2: per listed slot, the blade tests and the counts per LOD bucket.
pub const CULL_COUNT_COMP: &[u8] = spirv!("cull_count.comp");
/// Cull step 2: offsets by prefix sum, the indirect draws and the frame's counts.
pub const CULL_SCAN_COMP: &[u8] = spirv!("cull_scan.comp");
/// Cull step 3: the visible list.
pub const CULL_EMIT_COMP: &[u8] = spirv!("cull_emit.comp");
/// Test: Belyaev's Fresnel term at static blades' strip vertices, through the blade shader's functions.
pub const FRESNEL_PROBE_COMP: &[u8] = spirv!("fresnel_probe.comp");
/// Test: `height_six`, the l^6 coarse strip levels are lit with, at every level of every strip.
pub const HEIGHT_SIX_PROBE_COMP: &[u8] = spirv!("height_six_probe.comp");
/// Test: `encode_output`, the sRGB transfer of the UNORM targets, over [0, 1].
pub const SRGB_PROBE_COMP: &[u8] = spirv!("srgb_probe.comp");
/// `--msaa`: the depth pyramid over a multisampled depth image.
pub const HIZ_MS_COMP: &[u8] = spirv!("hiz_ms.comp");
/// `--msaa`: the resolve pass's full-target triangle.
pub const RESOLVE_VERT: &[u8] = spirv!("resolve.vert");
/// `--msaa`: the resolve in linear space, then the target's encoding.
pub const RESOLVE_FRAG: &[u8] = spirv!("resolve.frag");
/// The egui overlay: egui's vertices pulled from a storage buffer, points to clip space.
pub const OVERLAY_VERT: &[u8] = spirv!("overlay.vert");
/// The egui overlay: vertex colour times texel, gamma-space sRGB, premultiplied alpha.
pub const OVERLAY_FRAG: &[u8] = spirv!("overlay.frag");
