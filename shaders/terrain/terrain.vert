#version 460
#extension GL_GOOGLE_include_directive : require
// Terrain by vertex pulling, indexed: vertex v is grid vertex (v % (cells + 1), v / (cells + 1))
// of a level of the ground's clipmap (common/ground.glsl); the index buffer splits each cell
// (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1), as `scene::terrain::Terrain::height_at`
// (`render::terrain_chunks::chunked_indices`).
#include "common/bindings.glsl"
#include "common/ground.glsl"

#include "common/lighting.glsl"

// Lit, fogged and encoded per vertex (Gouraud): the ground's normal and its distance vary slowly
// over a cell, and most of the ground ends up under grass, so the fragment shader only writes the
// interpolated colour. Per pixel, lighting and fog cost the terrain pass about a third of its
// time on llvmpipe, and the sRGB encoding (`encode_output`'s three square roots a channel) 0.9 of
// its 3.3 ms from 41 m above (`meadow timing --camera 0,41,0,0,-89`, 2026-12-07). Interpolating
// the encoded colour instead of encoding the interpolated one moved 1.4 % of the landscape's
// pixels by one step of 255 and none by more: across a cell the colour changes by a few steps.
layout(location = 0) out vec3 out_color;

// The far grass's tint on the ground: the blades' diffuse colour (blades/blade_place.glsl's
// blade_diffuse) at mean hue and brightness two thirds up the blade, darkened by the shade the
// blades cast on each other.
const vec3 GROUND_GRASS_TINT = vec3(0.14, 0.2, 0.04);

// Ground under the grass: earthy green, Lambert plus sky ambient, fogged like the blades; with
// cover rules (GROUND_COVER), bare earth where the cover is 0, the green where it is 1.
vec3 ground_color(vec3 normal, vec3 world, float cover) {
    vec3 n = normalize(normal);
    vec3 albedo = vec3(0.07, 0.085, 0.03);
    if (GROUND_COVER != 0u) {
        albedo = mix(vec3(0.11, 0.085, 0.06), albedo, cover);
    }
    // With a far field (`render::far_field`, the frame's `params.z`): where its plants fade out
    // at the view distance (the last tenth, far.frag's `far_end`), the ground takes on what they
    // leave, the grass's tint over about half of it where the cover grows grass, so the field
    // ends in haze and not at a line (item 5 of issue #37). Nearer, the ground is the blades':
    // the far field's band matches the blades alone (`meadow bench --preset far`).
    if (uintBitsToFloat(frame.params.z) > 0.0) {
        float d = length(world - frame.camera_position.xyz);
        float view = uintBitsToFloat(frame.params.w);
        float beyond = clamp((d - 0.9 * view) / (0.1 * view), 0.0, 1.0);
        albedo = mix(albedo, GROUND_GRASS_TINT, 0.5 * beyond * cover);
    }
    float lambert = max(dot(n, frame.sun_direction.xyz), 0.0);
    vec3 color = albedo * (vec3(0.35, 0.38, 0.45) + vec3(1.2, 1.1, 0.95) * lambert);
    float haze = horizon_haze(length(world - frame.camera_position.xyz), uintBitsToFloat(frame.params.w));
    return mix(frame.sky_color.rgb, apply_fog(color, world, frame.camera_position, frame.sky_color), haze);
}


void main() {
    // Level gl_InstanceIndex of the ground's clipmap (`render::ground`): a stored terrain's one
    // grid, or a level of a block field's relief, ground_cells()² cells at the level's step, of
    // which the terrain pass draws the chunks in view but the finer level's. Its texel was
    // uploaded or filled (ground_fill's pass) when it entered the window; `ground_vertex` applies
    // the morph onto the next level's mesh.
    uvec2 shape = ground_shape();
    uvec2 grid = uvec2(uint(gl_VertexIndex) % (shape.x + 1u), uint(gl_VertexIndex) / (shape.x + 1u));
    uint level = uint(gl_InstanceIndex);
    GroundLevel at = ground_level(level, shape);
    vec4 ground = ground_vertex(at, ivec2(grid));
    vec2 p = vec2(grid) * ground_level_step(level) + ground_level_offset(level);
    vec3 world = vec3(p.x, ground.x, p.y);
    float cover = ground_vertex_cover(at, ivec2(grid));
    vec3 color = (RENDER_FLAGS & FLAG_DEBUG_COVER) != 0u ? 0.5 * cover_debug_color(cover) // unlit, unfogged
                                                       : ground_color(ground.yzw, world, cover);
    out_color = encode_output(color);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
