// The blade's alpha-tested outline (`scene::alpha`, thesis 4.1) as the shaders compute it: the
// half width at height v and the cutoff's inset from it, where the solid outline's geometry
// (blade_place.glsl, `outline_width`) and rim (blade_shading.glsl) end.
#ifndef MEADOW_OUTLINE_GLSL
#define MEADOW_OUTLINE_GLSL

// `scene::alpha`: the outline's inset from its half width where alpha reaches the cutoff
// (cutoff * edge - 0.06).
const float SOLID_INSET = 0.35 * 0.22 - 0.06;

// v^2.2 on [0, 1] within 2.6e-4 (a least-squares fit through 0 with the largest error minimised):
// four multiply-adds where pow is a log2 and an exp2 polynomial per vertex and fragment on
// llvmpipe.
float pow_2_2(float v) {
    return v * (-0.015108043 + v * (0.73099284 + v * (0.39241732 - 0.10855797 * v)));
}

// `scene::alpha::half_width`, with `pow_2_2`.
float outline_half_width(float v) {
    return 0.5 * (1.0 - pow_2_2(v)) * (0.8 + 0.2 * min(v / 0.08, 1.0));
}

#endif
