#version 460
#extension GL_GOOGLE_include_directive : require
// Belyaev's virtually-inertial blades (§3.3), the drawn blades' pass of the virtually-inertial
// response (`render::animation::virtual_inertial`): each drawn blade takes the virtual wind of its
// wind corners (animation/virtual_blades.comp wrote it this frame: the virtual blades' moments as
// forces), weighted as the wind itself is (wind/wind_field.glsl: the cluster's bilinear weights,
// or a block field's levels and their blend), and draws its static equilibrium under it
// (`chain_equilibrium_framed`, §3.3's solve, 3 iterations), with its own chain at t = k / 4 of its
// neutral curve and its own facing. No state per drawn blade. The colliders' push and, with
// delayed attenuation, the point sources at the blade are what the corners do not carry: they
// add their still drag (a local wind, no inertia). Mirrored on the CPU by
// `render::animation::chain::Chain::equilibrium_under`.
#define POSE_WRITER
#include "common/bindings.glsl"
#include "animation/forces.glsl"
#include "animation/pose_write.glsl"
#include "animation/chain.glsl"
#include "animation/chain_pose.glsl"

layout(local_size_x = POSE_GROUP) in;

// The response's constants (`render::animation::chain::ChainParams`), in its pass's own set.
layout(set = SET_PASS, binding = 1, std140) uniform VirtualShape {
    vec4 virtual_shape; // x k/J, the joints' stiffness (1/s²); yzw unused
};
// Per wind corner, per joint: the virtual moment as a force per unit mass (world axes), 0. Under
// the lavapipe profile gathered through a texel view of the same buffer (common/profile.glsl).
#ifdef TEXEL_TWINS
layout(set = SET_PASS, binding = 2) uniform samplerBuffer virtual_texels;
vec3 virtual_force(uint i) {
    return texelFetch(virtual_texels, int(i)).xyz;
}
#else
layout(set = SET_PASS, binding = 2, std430) readonly buffer VirtualWind { vec4 virtual_wind[]; };
vec3 virtual_force(uint i) {
    return virtual_wind[i].xyz;
}
#endif

// Add the weighted virtual wind and wind of the four corners of cluster `c` (weights w, times
// `scale`) to f and wind.
void gather(BladeCluster c, vec4 w, float scale, inout vec3 f[CHAIN_SEGMENTS], inout vec4 wind) {
    uint n = frame.wind_counts.z;
    uint corner[4] = uint[4](c.corner, c.corner + 1u, c.corner + n, c.corner + n + 1u);
    for (uint j = 0u; j < 4u; j++) {
        float weight = w[j] * scale;
        wind += wind_corner(corner[j]) * weight;
        for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
            f[k] += virtual_force(corner[j] * CHAIN_SEGMENTS + k) * weight;
        }
    }
}

// The virtual wind per joint at a blade (world axes), and the corners' wind there, weighted as
// `wind_at_blade` weights it.
void virtual_wind_at(uint blade_index, vec2 root, out vec3 f[CHAIN_SEGMENTS], out vec4 wind) {
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        f[k] = vec3(0.0);
    }
    wind = vec4(0.0);
    vec4 w;
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        float blend;
        uint level = wind_level_at(root, blend);
        gather(level_cluster(level, root, w), w, 1.0 - blend, f, wind);
        if (blend > 0.0) {
            gather(level_cluster(level + 1u, root, w), w, blend, f, wind);
        }
    } else {
        BladeCluster c;
        c.corner = clusters[blade_index].corner;
        gather(c, unpackUnorm4x8(clusters[blade_index].weights), 1.0, f, wind);
    }
}

void main() {
    uint i;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    if (!posed_blade(i, entry, blade, blade_index)) {
        return;
    }
    vec2 across = vec2(cos(blade.facing), -sin(blade.facing));
    vec2 normal_dir = vec2(sin(blade.facing), cos(blade.facing));
    vec3 virtual_f[CHAIN_SEGMENTS];
    vec4 corner_wind;
    virtual_wind_at(blade_index, blade.position.xz, virtual_f, corner_wind);
    // What the corners do not carry: the colliders' push, and with delayed attenuation the
    // sources at the blade (the blade's wind less the corners' part). Without colliders the push
    // adds nothing. The sources' part is compiled in only under ATTENUATION_BLADE (a
    // specialization constant): an `if` on the frame's collider count, as this was, cost llvmpipe
    // the blade's whole wind in every lane whether a lane took it or not (it runs an `if`'s body
    // under a lane mask), 9.1 of the pass's ms against 6.1 without it at the unbounded field.
    vec2 extra = add_collider_push(vec2(0.0), blade) * KEYFRAME_WIND_SCALE;
    if (ATTENUATION == ATTENUATION_BLADE) {
        extra += wind_at_blade(blade_index, blade.position.xz).xz - corner_wind.xz;
    }
    vec3 still = extra == vec2(0.0) ? vec3(0.0) : chain_drag(vec3(dot(extra, across), 0.0, dot(extra, normal_dir)));
    vec3 force[CHAIN_SEGMENTS];
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        vec3 v = virtual_f[k];
        force[k] = vec3(dot(v.xz, across), v.y, dot(v.xz, normal_dir)) + still;
    }
    vec3 n[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), n);
    Chain chain = chain_of(n);
    vec4 frames[CHAIN_SEGMENTS];
    chain_equilibrium_framed(chain, force, virtual_shape.x, frames);
    vec3 p[3];
    chain_controls(chain, frames, p);
    write_chain_pose(pose_base(i), blade.height, n[3], p, frames);
}
