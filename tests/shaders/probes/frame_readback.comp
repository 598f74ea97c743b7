#version 460
#extension GL_GOOGLE_include_directive : require
// Test shader: reads every field of `FrameUniforms` through the std140 declaration in common.glsl
// and writes them as 244 words, then the specialization constants as the shaders see them (by
// `SPEC(NAME)` id, build.rs's) and a few shared.glsl constants, so the test can compare them with what Rust wrote
// and with the constants build.rs generated (`render::gpu_constants`).
#include "common/common.glsl"

layout(local_size_x = 1) in;

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1, std430) writeonly buffer Fields { uint fields[]; };
layout(constant_id = SPEC(KEYFRAME_UVEC4S)) const uint KEYFRAME_UVEC4S = 4096u;

const uint FRAME_WORDS = 248u;     // 992 bytes
const uint SPEC_WORDS = 22u;       // SPEC_* ids 0..=21

void put_vec4(inout uint o, vec4 v) {
    for (uint i = 0u; i < 4u; i++) {
        fields[o + i] = floatBitsToUint(v[i]);
    }
    o += 4u;
}

void put_uvec4(inout uint o, uvec4 v) {
    for (uint i = 0u; i < 4u; i++) {
        fields[o + i] = v[i];
    }
    o += 4u;
}

void main() {
    uint o = 0u;
    for (int c = 0; c < 4; c++) {
        put_vec4(o, frame.view_proj[c]);
    }
    put_vec4(o, frame.camera_position);
    put_vec4(o, frame.sun_direction);
    put_vec4(o, frame.sky_color);
    put_vec4(o, frame.terrain);
    put_uvec4(o, frame.params);
    put_uvec4(o, frame.wind_counts);
    for (int c = 0; c < 4; c++) {
        put_vec4(o, frame.cull_view_proj[c]);
    }
    put_vec4(o, frame.cull_eye);
    put_vec4(o, frame.lod);
    put_vec4(o, frame.tile_grid);
    put_uvec4(o, frame.cull_tiles);
    put_uvec4(o, frame.cull_lod);
    for (uint i = 0u; i < RELIEF_WAVES; i++) {
        put_vec4(o, frame.relief_waves[i]);
    }
    for (uint i = 0u; i < RELIEF_WAVES / 2u; i++) {
        put_vec4(o, frame.relief_phases[i]);
    }
    put_uvec4(o, uvec4(frame.field_cells));
    put_vec4(o, frame.field);
    put_uvec4(o, frame.ground);
    for (uint i = 0u; i < RELIEF_WAVES / 2u; i++) {
        put_uvec4(o, uvec4(frame.relief_cycles[i]));
    }
    for (uint i = 0u; i < CAMERA_GRID_MAX_LEVELS; i++) {
        put_vec4(o, frame.ground_levels[i]);
    }
    for (uint i = 0u; i < CAMERA_GRID_MAX_LEVELS; i++) {
        put_uvec4(o, uvec4(frame.ground_windows[i]));
    }
    put_uvec4(o, frame.cull_classes);
    put_uvec4(o, frame.cull_class_first);
    for (uint i = 0u; i < MAX_LOD_BUCKETS / 2u; i++) {
        put_uvec4(o, frame.cull_bucket_draws[i]);
    }
    put_vec4(o, frame.band_eye);
    put_uvec4(o, frame.cull_room);

    fields[FRAME_WORDS + SPEC(KEYFRAME_UVEC4S)] = KEYFRAME_UVEC4S;
    fields[FRAME_WORDS + SPEC(ANIMATION_MODE)] = ANIMATION_MODE;
    fields[FRAME_WORDS + SPEC(SMOOTHING)] = SMOOTHING;
    fields[FRAME_WORDS + SPEC(KEYFRAME_ENCODING)] = KEYFRAME_ENCODING;
    fields[FRAME_WORDS + SPEC(ATTENUATION)] = ATTENUATION;
    fields[FRAME_WORDS + SPEC(REPRESENTATION)] = REPRESENTATION;
    fields[FRAME_WORDS + SPEC(RENDER_FLAGS)] = RENDER_FLAGS;
    fields[FRAME_WORDS + SPEC(SEGMENTS)] = SEGMENTS;
    fields[FRAME_WORDS + SPEC(BLADES_PER_INSTANCE)] = BLADES_PER_INSTANCE;
    fields[FRAME_WORDS + SPEC(ENCODE_SRGB)] = ENCODE_SRGB;
    fields[FRAME_WORDS + SPEC(MODEL_SEGMENTS)] = MODEL_SEGMENTS;
    fields[FRAME_WORDS + SPEC(CULL_GROUP)] = CULL_GROUP;
    fields[FRAME_WORDS + SPEC(MSAA_SAMPLES)] = MSAA_SAMPLES;
    fields[FRAME_WORDS + SPEC(STRIP_AREA)] = floatBitsToUint(STRIP_AREA);
    fields[FRAME_WORDS + SPEC(STRIP_L6)] = floatBitsToUint(STRIP_L6);
    fields[FRAME_WORDS + SPEC(TILE_ROWS_CAPACITY)] = TILE_ROWS_CAPACITY;
    fields[FRAME_WORDS + SPEC(LOD_BUCKET)] = LOD_BUCKET;
    fields[FRAME_WORDS + SPEC(GROUND_CELLS)] = GROUND_CELLS;
    fields[FRAME_WORDS + SPEC(GROUND_LEVELS)] = GROUND_LEVELS;
    fields[FRAME_WORDS + SPEC(GROUND_COVER)] = GROUND_COVER;
    fields[FRAME_WORDS + SPEC(CLUMP_SIZE_MM)] = CLUMP_SIZE_MM;
    fields[FRAME_WORDS + SPEC(FLOWER_SHARE)] = FLOWER_SHARE;

    uint s = FRAME_WORDS + SPEC_WORDS;
    fields[s + 0u] = MAX_SEGMENTS;
    fields[s + 1u] = MAX_COLLIDERS;
    fields[s + 2u] = POSE_WORDS;
    fields[s + 3u] = FLAG_DEBUG_FORCE | FLAG_EVAL_BLADE | FLAG_CLUSTER_PUSH;
    fields[s + 4u] = BINDING_POSES;
    fields[s + 5u] = SET_POSES;
}
