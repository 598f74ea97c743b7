// Keyframe selection and smoothing in the vertex shader (thesis 3.2.5–3.2.6, 4.4.1). Mirrors
// `keyframes::table::KeyframeTable::{select, blend}`.
#ifndef MEADOW_KEYFRAMES_GLSL
#define MEADOW_KEYFRAMES_GLSL

// The keyframe response's own resources (`render::animation::keyframed::KeyframeResponse`, given
// by these names): in the own set of the pass that includes this header (`SET_PASS`, from
// binding KEYFRAME_BINDING of its numbering), unless the includer puts them elsewhere first.
#ifndef KEYFRAME_SET
#define KEYFRAME_SET SET_PASS
#endif
#ifndef KEYFRAME_BINDING
#define KEYFRAME_BINDING 4
#endif
layout(set = KEYFRAME_SET, binding = KEYFRAME_BINDING) uniform sampler2D keyframe_texture;
// Keyframes as a uniform array (thesis 4.4.2): two keyframe words per uvec4 half; the array fills
// min(maxUniformBufferRange, 64 KiB), set by the pipeline (`render::animation::keyframe_gpu::KeyframeUniforms::capacity`).
// A buffer block, so sizing it by a specialization constant is fine; arrays in shader code are
// sized by the fixed limits of shared.glsl.
layout(constant_id = SPEC(KEYFRAME_UVEC4S)) const uint KEYFRAME_UVEC4S = 4096u;
layout(set = KEYFRAME_SET, binding = KEYFRAME_BINDING + 1, std140) uniform KeyframeWords { uvec4 keyframe_words[KEYFRAME_UVEC4S]; };
// The response's uniform block: the table's shape, x magnitudes, y angles, z records per pose (the
// model's segments, or 3 Bézier control points), w unused.
layout(set = KEYFRAME_SET, binding = KEYFRAME_BINDING + 2, std140) uniform KeyframeShape { uvec4 keyframe_shape; };

const float HALF_PI = 1.57079637; // the f32 nearest π/2, as Rust's FRAC_PI_2
const float MAX_FORCE = 1.0; // keyframes::pose::MAX_FORCE

struct KfSelection {
    uvec4 rows;
    vec4 weights;
    float t_magnitude;
    float t_angle;
    float sign_x;
    float sign_z;
};

// Force (fx, fz) in the blade frame, divided by the blade's stiffness. Front/back by the sign of
// F'·N' (eq. 3.10–3.11), the angle ω of eq. 3.12 folded into the stored quarter (fig. 3.9).
KfSelection kf_select(vec2 f) {
    uint magnitudes = keyframe_shape.x;
    uint angles = keyframe_shape.y;
    // A non-finite force would give an undefined row: treat it as none.
    float magnitude = isnan(length(f)) || isinf(length(f)) ? 0.0 : min(length(f), MAX_FORCE);
    float phi = magnitude > 0.0 ? atan(abs(f.x), abs(f.y)) : 0.0;
    KfSelection s;
    s.sign_x = f.x < 0.0 ? -1.0 : 1.0;
    s.sign_z = f.y < 0.0 ? -1.0 : 1.0;
    float mf = magnitude / MAX_FORCE * float(magnitudes - 1u);
    float af = angles > 1u ? phi / HALF_PI * float(angles - 1u) : 0.0;
    if (SMOOTHING == 0u) {
        // floor(x + 0.5): the same tie rule as the CPU (GLSL round() leaves .5 to the driver).
        uint row = min(uint(floor(mf + 0.5)), magnitudes - 1u) * angles + min(uint(floor(af + 0.5)), angles - 1u);
        s.rows = uvec4(row);
        s.weights = vec4(1.0, 0.0, 0.0, 0.0);
        s.t_magnitude = 0.0;
        s.t_angle = 0.0;
    } else {
        uint m0 = min(uint(floor(mf)), magnitudes - 2u);
        uint a0 = min(uint(floor(af)), angles > 1u ? angles - 2u : 0u);
        uint a1 = min(a0 + 1u, angles - 1u);
        float tm = clamp(mf - float(m0), 0.0, 1.0);
        float ta = a1 > a0 ? clamp(af - float(a0), 0.0, 1.0) : 0.0;
        s.rows = uvec4(m0 * angles + a0, (m0 + 1u) * angles + a0, m0 * angles + a1, (m0 + 1u) * angles + a1);
        s.weights = vec4((1.0 - tm) * (1.0 - ta), tm * (1.0 - ta), (1.0 - tm) * ta, tm * ta);
        s.t_magnitude = tm;
        s.t_angle = ta;
    }
    return s;
}

// Thesis 4.4.2: extract1(x) = round(x 2^16) / 2^15 - 1, extract2(x) = x 2^16 - round(x 2^16),
// the latter mapped back to [-1, 1] (see keyframes::encoding::thesis_extract2).
vec2 thesis_extract(float x) {
    float scaled = x * 65536.0;
    float whole = round(scaled);
    float fraction = scaled - whole;
    fraction = fraction < 0.0 ? fraction + 1.0 : fraction;
    return vec2(whole / 32768.0 - 1.0, 2.0 * fraction - 1.0);
}

// Stored keyframe of `row` at `level` (1..S): displacement xyz, twist w (radians), decoded.
vec4 kf_fetch(uint row, uint level) {
    uint encoding = KEYFRAME_ENCODING;
    vec4 v;
    if (encoding >= 3u) {
        // Uniform array: keyframe k is words 2k, 2k + 1; two keyframes per uvec4.
        uint k = row * keyframe_shape.z + level - 1u;
        uvec4 pair = keyframe_words[k >> 1];
        uvec2 words = (k & 1u) == 0u ? pair.xy : pair.zw;
        if (encoding == 3u) {
            v = vec4(thesis_extract(uintBitsToFloat(words.x)), thesis_extract(uintBitsToFloat(words.y)));
        } else {
            v = vec4(unpackSnorm2x16(words.x), unpackSnorm2x16(words.y));
        }
    } else if (encoding == 0u) {
        // rgba8x2: each component in two bytes, d1 + d2 (thesis 4.4.1, channels normalised).
        vec4 a = texelFetch(keyframe_texture, ivec2(2u * (level - 1u), row), 0);
        vec4 b = texelFetch(keyframe_texture, ivec2(2u * (level - 1u) + 1u, row), 0);
        v = vec4(a.x, a.z, b.x, b.z) * 2.0 - 1.0 + (vec4(a.y, a.w, b.y, b.w) * 2.0 - 1.0) / 255.0;
    } else if (encoding == 1u) {
        v = texelFetch(keyframe_texture, ivec2(level - 1u, row), 0) * 2.0 - 1.0;
    } else {
        v = texelFetch(keyframe_texture, ivec2(level - 1u, row), 0);
    }
    v.w *= HALF_PI;
    return v;
}

vec3 kf_slerp(vec3 a, vec3 b, float t) {
    float la = length(a);
    float lb = length(b);
    if (la == 0.0 || lb == 0.0) {
        return mix(a, b, t);
    }
    vec3 ua = a / la;
    vec3 ub = b / lb;
    float omega = acos(clamp(dot(ua, ub), -1.0, 1.0));
    vec3 d = omega < 1e-4 ? normalize(mix(ua, ub, t))
                          : (ua * sin((1.0 - t) * omega) + ub * sin(t * omega)) / sin(omega);
    return d * mix(la, lb, t);
}

// Root-relative position (xyz, unit blade) and w of record `level` (1-based), mirrored; `straight`
// is where the record sits on the straight blade (a level of the chain, or a control point).
vec4 kf_record(KfSelection s, uint level, vec3 straight) {
    vec4 k0 = kf_fetch(s.rows.x, level);
    vec4 r;
    if (SMOOTHING == 0u) {
        r = vec4(straight + k0.xyz, k0.w);
    } else {
        vec4 k1 = kf_fetch(s.rows.y, level);
        vec4 k2 = kf_fetch(s.rows.z, level);
        vec4 k3 = kf_fetch(s.rows.w, level);
        if (SMOOTHING == 1u) {
            // Eq. 3.13.
            vec4 k = k0 * s.weights.x + k1 * s.weights.y + k2 * s.weights.z + k3 * s.weights.w;
            r = vec4(straight + k.xyz, k.w);
        } else {
            // Eq. 3.14 on root-relative vectors, along magnitude then angle.
            vec3 lo = kf_slerp(straight + k0.xyz, straight + k1.xyz, s.t_magnitude);
            vec3 hi = kf_slerp(straight + k2.xyz, straight + k3.xyz, s.t_magnitude);
            float tw = mix(mix(k0.w, k1.w, s.t_magnitude), mix(k2.w, k3.w, s.t_magnitude), s.t_angle);
            r = vec4(kf_slerp(lo, hi, s.t_angle), tw);
        }
    }
    return vec4(r.x * s.sign_x, r.y, r.z * s.sign_z, r.w * s.sign_x * s.sign_z);
}

// Root-relative position and twist of chain level `level` (0..S), vertex representation.
vec4 kf_level(KfSelection s, uint level, uint segments) {
    if (level == 0u) {
        return vec4(0.0);
    }
    return kf_record(s, level, vec3(0.0, float(level) / float(segments), 0.0));
}

#endif
