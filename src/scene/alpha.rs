//! The blade outline (thesis 4.1): an alpha channel laid over each blade's quads. The interior is
//! opaque, the edge falls off smoothly so that multiplying the diffuse colour by alpha darkens the
//! rim (the "cell-shaded" look), and the outline tapers to a point at the tip. Generated at start
//! and uploaded as an R8 image; u runs across the blade, v from root (0) to tip (1).

/// Texture width (across the blade).
pub const WIDTH: u32 = 64;
/// Texture height (root to tip).
pub const HEIGHT: u32 = 256;
/// Alpha below which a fragment is discarded (must match `shaders/blades/blade.frag`).
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

/// The solid outline's inset from `half_width`: where `alpha` reaches the cutoff.
const SOLID_INSET: f32 = ALPHA_CUTOFF * 0.22 - 0.06;

/// The solid outline's width at height `t`, as a fraction of the quad width: where the
/// alpha-tested outline passes the cutoff (`outline_width` in `shaders/blades/blade_place.glsl`).
pub fn solid_width(t: f32) -> f32 {
    (2.0 * (half_width(t) - SOLID_INSET)).max(0.0)
}

/// Samples of the integrals below (midpoint rule over t in [0, 1]).
const SAMPLES: usize = 4096;

/// `values` at the `values.len() - 1` equal segments' levels, interpolated linearly at `t`: how a
/// strip carries a per-level quantity along its length.
fn at_levels(values: &[f64], t: f64) -> f64 {
    let segments = values.len() - 1;
    let x = t * segments as f64;
    let k = (x as usize).min(segments - 1);
    values[k] + (x - k as f64) * (values[k + 1] - values[k])
}

/// ∫ f(t) w(t) dt and ∫ w(t) dt over the blade.
fn weighted(f: impl Fn(f64) -> f64, w: impl Fn(f64) -> f64) -> (f64, f64) {
    (0..SAMPLES).map(|i| (i as f64 + 0.5) / SAMPLES as f64).fold((0.0, 0.0), |(fw, ww), t| {
        let weight = w(t);
        (fw + f(t) * weight, ww + weight)
    })
}

/// The width of a solid strip of `segments`: the outline's width at its levels, joined by
/// straight edges.
fn strip_width(segments: u32) -> impl Fn(f64) -> f64 {
    let levels: Vec<f64> = (0..=segments).map(|k| f64::from(solid_width(k as f32 / segments as f32))).collect();
    move |t| at_levels(&levels, t)
}

/// How much wider a solid strip of `segments` is drawn so that it covers the alpha-tested
/// outline's area (`STRIP_AREA`): the outline's width is concave in t (`half_width`), so the
/// strip that joins its levels' widths by straight edges is thinner, by 4, 12 and 41 % for 4, 2
/// and 1 segments. A far blade is a pixel or less across: its coverage of the pixels it crosses
/// is what shows, and too little of it let the ground through at the 1M field's horizon.
pub fn strip_area_scale(segments: u32) -> f32 {
    let outline = weighted(|_| 1.0, |t| f64::from(solid_width(t as f32))).0;
    let strip = weighted(|_| 1.0, strip_width(segments.max(1))).0;
    (outline / strip) as f32
}

/// The factor on l^6 (`STRIP_L6`; Belyaev §2.3's height term of the sun and Fresnel terms)
/// that gives a solid strip of `segments` the area-weighted mean of l^6 brute force draws: brute
/// force interpolates the point values t^6 of its `model_segments` levels over the alpha-tested
/// outline, a coarser strip the means of l^6 over its levels' stretches (`height_six` in
/// lighting.glsl) over its own straight-edged width. Uniform in t, those means weigh the tip's
/// stretch as much as the root's, where the outline is widest: the 2-segment bucket's mean was 26 %
/// over brute force's, and its blades showed it (the 1M field's horizon up to 0.7 % brighter).
pub fn strip_l6_scale(segments: u32, model_segments: u32) -> f32 {
    let (segments, model) = (segments.max(1), model_segments.max(1));
    let height_six = |t: f64| -> f64 {
        if segments >= model {
            return t.powi(6);
        }
        let half = 0.5 / f64::from(segments);
        let (a, b) = ((t - half).max(0.0), (t + half).min(1.0));
        (b.powi(7) - a.powi(7)) / (7.0 * (b - a))
    };
    let brute: Vec<f64> = (0..=model).map(|k| (f64::from(k) / f64::from(model)).powi(6)).collect();
    let strip: Vec<f64> = (0..=segments).map(|k| height_six(f64::from(k) / f64::from(segments))).collect();
    let (bf, bw) = weighted(|t| at_levels(&brute, t), |t| f64::from(solid_width(t as f32)));
    let (sf, sw) = weighted(|t| at_levels(&strip, t), strip_width(segments));
    ((bf / bw) / (sf / sw)) as f32
}

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
    fn coarse_strips_cover_the_outlines_area_with_its_mean_height_term() {
        // One segment is one triangle: its area is half its root's width.
        let outline: f64 = (0..100_000).map(|i| f64::from(solid_width((i as f32 + 0.5) / 1e5))).sum::<f64>() / 1e5;
        let triangle = 0.5 * f64::from(solid_width(0.0));
        assert!((f64::from(strip_area_scale(1)) - outline / triangle).abs() < 1e-3, "{}", strip_area_scale(1));
        // Thinner the coarser: 4, 12 and 41 % for 4, 2 and 1 segments; about exact from 8 on.
        let scales: Vec<f32> = [1, 2, 4, 8, 16].map(strip_area_scale).to_vec();
        assert!(
            (scales[0] - 1.686).abs() < 2e-3 && (scales[1] - 1.142).abs() < 2e-3 && (scales[2] - 1.040).abs() < 2e-3
        );
        assert!(scales[3..].iter().all(|&s| (s - 1.0).abs() < 0.01), "{scales:?}");
        // The height term: brute force's area-weighted mean of l^6 over each strip's (the values
        // of a separate integration of the same formulas), below 1 since a straight-edged strip
        // weighs its upper levels more than the outline; a strip of the model's own segments is
        // brute force's levels on a thinner width.
        let l6 = [1, 2, 4].map(|s| strip_l6_scale(s, 4));
        assert!((l6[0] - 0.628).abs() < 2e-3 && (l6[1] - 0.796).abs() < 2e-3 && (l6[2] - 0.949).abs() < 2e-3, "{l6:?}");
        assert!(strip_l6_scale(8, 8) < 1.0 && strip_l6_scale(8, 8) > 0.95);
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
