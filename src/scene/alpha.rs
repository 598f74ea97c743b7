//! The blade outline (thesis 4.1): an alpha channel laid over each blade's quads. The interior is
//! opaque, the edge falls off smoothly so that multiplying the diffuse colour by alpha darkens the
//! rim (the "cell-shaded" look), and the outline tapers to a point at the tip. Generated at start
//! and uploaded as an R8 image; u runs across the blade, v from root (0) to tip (1).

/// Texture width (across the blade).
pub const WIDTH: u32 = 64;
/// Texture height (root to tip).
pub const HEIGHT: u32 = 256;
/// Alpha below which a fragment is discarded (must match `shaders/blade.frag`).
pub const ALPHA_CUTOFF: f32 = 0.35;

/// Half-width of the outline at height `v`, as a fraction of the quad width.
pub fn half_width(v: f32) -> f32 {
    let taper = 1.0 - v.powf(2.2);
    let root = 0.8 + 0.2 * (v / 0.08).min(1.0);
    0.5 * taper * root
}

/// Alpha at texel centre (u, v).
pub fn alpha(u: f32, v: f32) -> f32 {
    let distance = half_width(v) - (u - 0.5).abs(); // inside > 0, in units of the quad width
    let edge = 0.22;
    ((distance + 0.06) / edge).clamp(0.0, 1.0)
}

/// With the outline drawn as geometry (`--lod outline`, blade.vert), the factor the
/// fragment shader darkens the blade's colour by at (u, v) of the narrowed quad: 0.45 at the rim
/// to 1 inside, as `alpha` darkens the alpha-tested blade (blade_shading.glsl).
pub fn solid_shade(u: f32, v: f32) -> f32 {
    let inset = ALPHA_CUTOFF * 0.22 - 0.06;
    let half = half_width(v);
    let inside = half - (u - 0.5).abs() * 2.0 * (half - inset).max(0.0);
    let rim = ((inside + 0.06) / 0.22).clamp(0.0, 1.0);
    0.45 + 0.55 * rim
}

/// `solid_shade` over a one-segment blade, as an affine function of v: its value at the root.
/// The blade's one triangle (collapsed tip) carries (u, v) = (0, 0), (1, 0) and (0, 1) at its
/// corners, so its rim darkens towards the tip. A one-segment blade is a few pixels at most, so
/// the LOD's one-segment bucket lights it with this fit (blade.vert) and its fragment shader
/// neither interpolates (u, v) nor computes the rim (`meadow timing` at the unbounded field's
/// default view: 65 165 of 88 897 drawn blades). The least-squares fit over the triangle's area
/// (a constant mean, 0.928, lost the darker tips: the 1M field's 8x8 difference from brute force
/// rose from 0.48 to 0.49 %).
pub const ONE_SEGMENT_SHADE_ROOT: f32 = 1.0027;
/// See `ONE_SEGMENT_SHADE_ROOT`: the fit's value at the tip.
pub const ONE_SEGMENT_SHADE_TIP: f32 = 0.7780;

/// The R8 texels, row 0 at the root.
pub fn texels() -> Vec<u8> {
    let mut out = Vec::with_capacity((WIDTH * HEIGHT) as usize);
    for y in 0..HEIGHT {
        let v = (y as f32 + 0.5) / HEIGHT as f32;
        for x in 0..WIDTH {
            let u = (x as f32 + 0.5) / WIDTH as f32;
            out.push((alpha(u, v) * 255.0).round() as u8);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_one_segment_shade_is_the_least_squares_fit_over_its_triangle() {
        // Normal equations of a (1 - v) + b v against solid_shade over the triangle u + v <= 1.
        let n = 1000;
        let (mut aa, mut ab, mut bb, mut ya, mut yb) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            for j in 0..n - i {
                let (u, v) = ((i as f32 + 0.25) / n as f32, (j as f32 + 0.25) / n as f32);
                let (p, q, y) = (1.0 - f64::from(v), f64::from(v), f64::from(solid_shade(u, v)));
                (aa, ab, bb, ya, yb) = (aa + p * p, ab + p * q, bb + q * q, ya + p * y, yb + q * y);
            }
        }
        let det = aa * bb - ab * ab;
        let fit = [(ya * bb - yb * ab) / det, (aa * yb - ab * ya) / det];
        for (k, (want, have)) in fit.iter().zip([ONE_SEGMENT_SHADE_ROOT, ONE_SEGMENT_SHADE_TIP]).enumerate() {
            assert!((want - f64::from(have)).abs() < 2e-3, "{k}: fit {fit:?}");
        }
        // The inside is not darkened, the edge of the narrowed quad is (the cutoff's rim).
        assert!(solid_shade(0.5, 0.3) == 1.0 && solid_shade(0.0, 0.5) < 0.7);
    }

    #[test]
    fn outline_is_opaque_in_the_middle_transparent_outside_and_tapers() {
        assert_eq!(alpha(0.5, 0.3), 1.0);
        assert_eq!(alpha(0.01, 0.5), 0.0);
        assert!(alpha(0.5, 0.999) < ALPHA_CUTOFF, "tip is a point");
        assert!(half_width(0.2) > half_width(0.8));
        let t = texels();
        assert_eq!(t.len(), (WIDTH * HEIGHT) as usize);
        // The rim is darker than the centre but still passes the alpha test somewhere.
        let row = &t[(HEIGHT / 3 * WIDTH) as usize..][..WIDTH as usize];
        assert!(row.iter().any(|&a| a > (ALPHA_CUTOFF * 255.0) as u8 && a < 250));
    }
}
