// Shading shared by the passes.
#ifndef MEADOW_LIGHTING_GLSL
#define MEADOW_LIGHTING_GLSL

// Belyaev et al. §2.3:  I = Ka Ia + Kd Id (max(N·L, 0) + C max(-N·L, 0)),
// with the height terms  Ia = Ia** + l (Ia* - Ia**)  and  Id = Id* l^6  (l = 0 root, 1 tip).
// C tints light that traverses the blade (translucency).
// `l6`: l^6, or its mean over the stretch of blade a coarse strip level stands for
// (`height_six`).
const vec3 BLADE_TRANSLUCENCY = vec3(0.55, 0.75, 0.25); // C

// The direction terms max(N·L, 0) + C max(-N·L, 0) of a surface of normal `n`.
vec3 blade_sun_terms(vec3 n, vec3 l_dir) {
    float ndl = dot(n, l_dir);
    return vec3(max(ndl, 0.0)) + BLADE_TRANSLUCENCY * max(-ndl, 0.0);
}

// I from the direction terms `sun` (`blade_sun_terms`): a surface lit per vertex in direction and
// per fragment in height (the far field, far.frag) takes them apart.
vec3 blade_radiance_terms(vec3 ka, vec3 kd, vec3 sun, float l, float l6) {
    const vec3 ambient_tip = vec3(0.55, 0.60, 0.70);   // Ia*
    const vec3 ambient_base = vec3(0.10, 0.12, 0.12);  // Ia**
    const vec3 sun_tip = vec3(1.55, 1.45, 1.25);       // Id*
    vec3 ia = ambient_base + l * (ambient_tip - ambient_base);
    vec3 id = sun_tip * l6;
    return ka * ia + kd * id * sun;
}

vec3 blade_radiance_l6(vec3 ka, vec3 kd, vec3 n, vec3 l_dir, float l, float l6) {
    return blade_radiance_terms(ka, kd, blade_sun_terms(n, l_dir), l, l6);
}

// The height factor l^6 of the terms above at strip level t of a blade drawn with `segments`
// segments, when its model has `model_segments`. Lit per vertex, a strip interpolates the colour
// linearly between levels, which the linear terms survive but l^6 does not: a one-segment blade
// interpolating 0 at the root to 1 at the tip is lit as if l^6 were l, several times too bright
// (the far field's LOD buckets showed it: +2.3 % at the 1M-blade field's horizon against brute
// force). A coarser strip than the model's therefore takes at each level the mean of l^6 over the
// stretch [t - 1/(2 segments), t + 1/(2 segments)] ∩ [0, 1] the level stands for,
// (b^7 - a^7) / (7 (b - a)); the model's own segment count keeps the point value, as brute force
// draws it.
float height_six(float t, uint segments, uint model_segments) {
    if (segments >= model_segments) {
        float t2 = t * t;
        return t2 * t2 * t2;
    }
    float half_step = 0.5 / float(segments);
    float a = max(t - half_step, 0.0);
    float b = min(t + half_step, 1.0);
    float a2 = a * a;
    float b2 = b * b;
    return (b2 * b2 * b2 * b - a2 * a2 * a2 * a) / (7.0 * (b - a));
}

// Belyaev et al. §2.3, the Fresnel term added to I on contour terrain areas:
//   Is = Ks · l^6 · (1 - N_L·V)^10,  N_L the terrain's normal under the blade, V the unit
// direction to the camera, l = 0 root, 1 tip.
// The paper prints (N_L·V)^10 and says the term brightens blades where N_L·V is near 0, seen
// edge-on (hill outlines, the far field). As printed it does the opposite: it peaks looking
// straight down (N_L·V = 1) and vanishes on contours. Fresnel reflectance grows as the angle of
// incidence θ approaches 90°, which Schlick writes F0 + (1 - F0)(1 - cos θ)^5 with
// cos θ = N·V; reading the paper's dot product as that complement, with its exponent 10, gives
// the effect the text describes, and the high power keeps it to grazing views (cos θ < ~0.3).
// A terrain facing away from the camera (N_L·V < 0) counts as fully grazing.
// Ks: a slightly sky-tinted reflectance (grazing light off the blades reflects the sky), so a
// fully grazing tip gains about a third of the tip's sunlit diffuse radiance.
const vec3 FRESNEL_KS = vec3(0.26, 0.30, 0.34);
vec3 blade_fresnel_l6(vec3 terrain_normal, vec3 to_camera, float l6) {
    float c = 1.0 - clamp(dot(terrain_normal, to_camera), 0.0, 1.0);
    float c2 = c * c;
    float c10 = c2 * c2 * c2 * c2 * c2;
    return FRESNEL_KS * l6 * c10;
}

vec3 blade_fresnel(vec3 terrain_normal, vec3 to_camera, float l) {
    float l2 = l * l;
    return blade_fresnel_l6(terrain_normal, to_camera, l2 * l2 * l2);
}

// Exponential distance fog: the fraction of a surface's colour that reaches the eye.
float fog_transmittance(vec3 world, vec4 camera_position, vec4 sky) {
    return exp(-sky.w * length(world - camera_position.xyz));
}

// Under a block field, the haze where the ground ends: the share of a surface `d` metres away
// left after the fog's, falling from 1 at 80 % of the view distance `view` (m; 0: stored blades,
// nothing changes) to 0 at it, so the ground, the blades, the flowers and the far field end in the
// sky's colour and not at a line (issue #37 item 5; the value: `render::renderer::uniforms`).
float horizon_haze(float d, float view) {
    return view > 0.0 ? clamp((view - d) / (0.2 * view), 0.0, 1.0) : 1.0;
}

// Exponential distance fog towards the sky colour.
vec3 apply_fog(vec3 color, vec3 world, vec4 camera_position, vec4 sky) {
    return mix(sky.rgb, color, fog_transmittance(world, camera_position, sky));
}

// Linear -> sRGB transfer for UNORM targets (a specialization constant: no cost on *_SRGB ones).
// The curve 1.055 c^(1/2.4) - 0.055 by Ian Taylor's fit in three square roots ("sRGB
// approximations for HLSL", 2012): within 0.41/255 of it over [0, 1] (tests/lighting.rs), where
// a pow per channel is a log2 and an exp2 that llvmpipe evaluates in software for every fragment
// (`render::uniforms::look::encode_srgb` mirrors it for the clear colour).
vec3 encode_output(vec3 linear) {
    if (ENCODE_SRGB == 0u) {
        return linear;
    }
    vec3 c = clamp(linear, 0.0, 1.0);
    vec3 s1 = sqrt(c);
    vec3 s2 = sqrt(s1);
    vec3 s3 = sqrt(s2);
    vec3 curve = 0.585122381 * s1 + 0.783140355 * s2 - 0.368262736 * s3;
    return mix(c * 12.92, curve, step(vec3(0.0031308), c));
}

#endif
