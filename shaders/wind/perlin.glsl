// Belyaev's Perlin wind (§3.2, `render::wind::perlin`): W[u] = Σ_{i=1..3} k_i T[w_i t + c_i R_i u],
// three layers of one tileable noise texture T (two channels n_a, n_b in [-1, 1], its mips after
// it: `render::wind::perlin::Noise`), each turned to its direction d_i, scaled by c_i and
// scrolled downwind. A layer's wind in its own frame is (1 + STRENGTH·n_a, SWIRL·n_b): along d_i
// on average, its strength and direction varied by the noise. Layer i's texture coordinate at q
// (relative to O) is its offset at O (folded into the period in f64 on the CPU) plus
// c_i (d_i · q, d_i⊥ · q); a wind level samples each layer at the mip the CPU chose for its
// spacing (`render::wind::perlin::mip_for`: band-limited far away). The includer declares
// `noise_texels` and the parameters `wind` (`render::wind::params::Params`).
#ifndef MEADOW_WIND_PERLIN_GLSL
#define MEADOW_WIND_PERLIN_GLSL

const float PERLIN_STRENGTH = 0.6; // render::wind::perlin::STRENGTH
const float PERLIN_SWIRL = 0.35; // render::wind::perlin::SWIRL

// Bilinear at `x` (texels of the finest level) in mip level `level`, wrapped
// (`render::wind::perlin::Noise::sample`). Level m starts at Σ_{l<m} (N >> l)² =
// 4 (N² − (N >> m)²) / 3 texels, and its side is a power of two, so wrapping is a mask (two's
// complement: negatives too).
vec2 perlin_texel(vec2 x, uint level) {
    int side = int(PERLIN_TEXELS >> level);
    int base = 4 * (int(PERLIN_TEXELS * PERLIN_TEXELS) - side * side) / 3;
    vec2 g = x / float(1u << level) - vec2(0.5);
    vec2 i = floor(g);
    vec2 f = g - i;
    ivec2 c0 = ivec2(i) & ivec2(side - 1);
    ivec2 c1 = (c0 + 1) & ivec2(side - 1);
    vec2 t00 = texelFetch(noise_texels, base + c0.y * side + c0.x).xy;
    vec2 t10 = texelFetch(noise_texels, base + c0.y * side + c1.x).xy;
    vec2 t01 = texelFetch(noise_texels, base + c1.y * side + c0.x).xy;
    vec2 t11 = texelFetch(noise_texels, base + c1.y * side + c1.x).xy;
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

// W at `q` (relative to O) on wind level `level`, m/s (x, z).
vec2 perlin_wind(vec2 q, uint level) {
    vec2 w = vec2(0.0);
    for (uint i = 0u; i < 3u; i++) {
        vec4 layer = wind.perlin[i]; // offset x, y (texels), c_i, k_i · speed
        vec2 d = wind.perlin_dirs[i].xy;
        vec2 across = vec2(-d.y, d.x);
        vec2 x = layer.xy + layer.z * vec2(dot(d, q), dot(across, q));
        vec2 n = perlin_texel(x, wind.perlin_mips[level][i]);
        w += layer.w * ((1.0 + PERLIN_STRENGTH * n.x) * d + PERLIN_SWIRL * n.y * across);
    }
    return w;
}

#endif
