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
