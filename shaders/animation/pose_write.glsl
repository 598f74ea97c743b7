// What every pose pass of a blade response shares (`render::animation::pose_pass`): which blade
// an invocation poses, and how a level's pose record is written (the format bindings.glsl gives).
// The includer defines POSE_WRITER (or POSE_EDITOR, to read them too) before including
// common/bindings.glsl.
#ifndef MEADOW_POSE_WRITE_GLSL
#define MEADOW_POSE_WRITE_GLSL
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "blades/visible_buckets.glsl"

// The blade invocation gl_GlobalInvocationID.x poses: with the cull (FLAG_CULLED) entry `entry`
// of the visible list in its LOD bucket's range, `record` being the entry's index (records are by
// entry); without it stored blade `record` (entry (record, 0)). `blade_index` is what the wind
// and the clusters are looked up by. False past the range, on the list's padding or past the
// stored blades: nothing to write.
bool posed_blade(out uint record, out uvec2 entry, out BladeInstance blade, out uint blade_index) {
    record = gl_GlobalInvocationID.x;
    entry = uvec2(record, 0u);
    blade_index = record;
    if ((RENDER_FLAGS & FLAG_CULLED) != 0u) {
        if (!bucket_entry(record)) {
            return false;
        }
        entry = visible_entry(record);
        if (entry.x == VISIBLE_PADDING) {
            return false;
        }
        blade = visible_instance(entry, blade_index);
        return true;
    }
    if (record >= frame.params.y) {
        return false;
    }
    blade = blade_record(record);
    return true;
}

// The first word of record `record`'s levels.
uint pose_base(uint record) {
    return record * (MODEL_SEGMENTS + 1u) * POSE_WORDS;
}

// Level `level` of the records at `base`: its point in the blade's frame (x across, y up, z
// along the normal) over the blade's height and POSE_SCALE, its unit tangent, its twist's cos and
// sin, and the force magnitude the debug view shows (0 to 1).
void write_pose_level(uint base, uint level, vec3 unit, vec3 tangent, vec2 twist_cs, float force) {
    uint at = base + level * POSE_WORDS;
    poses[at] = packSnorm2x16(unit.xy);
    // z as snorm16 in the low half, cos and sin of the twist as snorm8 in the high half.
    poses[at + 1u] = (packSnorm2x16(vec2(unit.z, 0.0)) & 0xffffu)
        | (packSnorm4x8(vec4(0.0, 0.0, twist_cs)) & 0xffff0000u);
    poses[at + 2u] = packSnorm4x8(vec4(tangent, clamp(force, 0.0, 1.0)));
}

#ifdef POSE_EDITOR
// Level `level` of the records at `base` as `write_pose_level` wrote it: its point over the blade's
// height and POSE_SCALE, its twist's cos and sin, and its tangent with the force in w.
void read_pose_level(uint base, uint level, out vec3 unit, out vec2 twist_cs, out vec4 tangent_force) {
    uint at = base + level * POSE_WORDS;
    uint w1 = poses[at + 1u];
    unit = vec3(unpackSnorm2x16(poses[at]), unpackSnorm2x16(w1 & 0xffffu).x);
    twist_cs = unpackSnorm4x8(w1).zw;
    tangent_force = unpackSnorm4x8(poses[at + 2u]);
}
#endif

// Whether a strip of `segments` segments reads model level `level` (`level_read`, for a bucket
// known only at run time: the interaction patches' list, animation/patch.comp).
bool level_read_in(uint segments, uint level) {
    return (MODEL_SEGMENTS % segments) != 0u || (level * segments) % MODEL_SEGMENTS == 0u;
}

// Whether a `segments`-segment strip reads model level `level` (`model_level`): every
// MODEL_SEGMENTS / segments-th, or all of them when `segments` does not divide MODEL_SEGMENTS.
// `segments` is a specialization constant (its bucket's with the cull; MODEL_SEGMENTS without),
// so in an unrolled loop over the levels each test folds away and the pipeline stores only what
// its bucket reads.
bool level_read(uint level) {
    return level_read_in((RENDER_FLAGS & FLAG_CULLED) != 0u ? SEGMENTS : MODEL_SEGMENTS, level);
}

#endif
