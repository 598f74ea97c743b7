//! Comparing pictures with a tolerance: golden-image tests, viewer screenshots against headless
//! renders, and (box-filtered) the GPU-driven LOD against brute force.

/// Per-channel differences between two RGB8 pictures of the same size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffStats {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels whose largest channel difference is within the tolerance.
    pub within: usize,
    /// Largest channel difference anywhere (0..=255).
    pub max_diff: u8,
}

impl DiffStats {
    /// Fraction of pixels within the tolerance.
    pub fn within_fraction(&self) -> f64 {
        if self.pixels == 0 {
            1.0
        } else {
            self.within as f64 / self.pixels as f64
        }
    }
}

/// Compare two RGB8 buffers; `tolerance` is the largest channel difference a pixel may have to
/// count as matching. Returns the statistics and a diff picture (difference ×4, red where a pixel
/// is outside the tolerance).
///
/// # Panics
/// If the buffers differ in length or are not RGB8: the caller checks sizes first.
pub fn compare_rgb(a: &[u8], b: &[u8], tolerance: u8) -> (DiffStats, Vec<u8>) {
    assert_eq!(a.len(), b.len(), "pictures of different sizes");
    assert_eq!(a.len() % 3, 0, "RGB8 expected");
    let mut stats = DiffStats { pixels: a.len() / 3, within: 0, max_diff: 0 };
    let mut diff = Vec::with_capacity(a.len());
    for (pa, pb) in a.chunks_exact(3).zip(b.chunks_exact(3)) {
        let d = pa.iter().zip(pb).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0);
        stats.max_diff = stats.max_diff.max(d);
        if d <= tolerance {
            stats.within += 1;
            let g = d.saturating_mul(4);
            diff.extend_from_slice(&[g, g, g]);
        } else {
            diff.extend_from_slice(&[255, 0, d.saturating_mul(4)]);
        }
    }
    (stats, diff)
}

/// How far apart two pictures are once detail below a block is averaged away: what a level of
/// detail may change (which blade covers which pixel) cancels inside a block, what it must not
/// change (the field's colour and coverage at that scale) does not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxDifference {
    /// Mean over the blocks of the block's difference, in % of full scale (255).
    pub mean_percent: f64,
    /// The 99th-percentile block (nearest rank), in % of full scale.
    pub p99_percent: f64,
    /// The most different block, in % of full scale.
    pub max_percent: f64,
}

/// Compare two RGB8 pictures of `width`×`height` after a `block`×`block` box filter: each whole
/// block (a partial block at the right or bottom edge is left out) is averaged per channel in
/// both pictures, and the block's difference is the absolute difference of those averages,
/// averaged over the 3 channels, in % of 255. A picture smaller than one block has no block:
/// every figure is 0.
///
/// # Panics
/// If a buffer is not `width * height` RGB8 pixels or `block` is 0: the caller checks sizes first.
pub fn box_filtered_difference(a_rgb: &[u8], b_rgb: &[u8], width: u32, height: u32, block: u32) -> BoxDifference {
    let (w, h, n) = (width as usize, height as usize, block as usize);
    assert!(n > 0, "a block is at least one pixel");
    assert_eq!(a_rgb.len(), w * h * 3, "first picture is not {width}x{height} RGB8");
    assert_eq!(b_rgb.len(), w * h * 3, "second picture is not {width}x{height} RGB8");
    let (columns, rows) = (w / n, h / n);
    // Per block and channel, the sum of a's values minus the sum of b's.
    let mut sums = vec![[0i64; 3]; columns * rows];
    for y in 0..rows * n {
        let line = y * w * 3;
        for x in 0..columns * n {
            let (pa, pb) = (&a_rgb[line + x * 3..][..3], &b_rgb[line + x * 3..][..3]);
            for ((sum, &va), &vb) in sums[(y / n) * columns + x / n].iter_mut().zip(pa).zip(pb) {
                *sum += i64::from(va) - i64::from(vb);
            }
        }
    }
    let pixels = (n * n) as f64;
    let mut blocks: Vec<f64> = sums
        .iter()
        .map(|s| s.iter().map(|d| d.unsigned_abs() as f64 / pixels).sum::<f64>() / 3.0 * 100.0 / 255.0)
        .collect();
    if blocks.is_empty() {
        return BoxDifference { mean_percent: 0.0, p99_percent: 0.0, max_percent: 0.0 };
    }
    blocks.sort_by(f64::total_cmp);
    // Nearest rank, as the measuring commands' percentiles.
    let rank = (0.99 * blocks.len() as f64).ceil().max(1.0) as usize;
    BoxDifference {
        mean_percent: blocks.iter().sum::<f64>() / blocks.len() as f64,
        p99_percent: blocks[rank.min(blocks.len()) - 1],
        max_percent: blocks[blocks.len() - 1],
    }
}

/// Halve an RGB8 picture of `width`×`height` (sRGB-encoded, both even) by averaging each 2×2
/// block in linear light and encoding the mean again: the downsampling a supersampled reference
/// needs (averaging encoded values would darken every edge).
///
/// # Panics
/// If the buffer is not `width * height` RGB8 pixels or a side is odd.
pub fn downsample_2x_srgb(rgb: &[u8], width: u32, height: u32) -> Vec<u8> {
    let (w, h) = (width as usize, height as usize);
    assert!(w % 2 == 0 && h % 2 == 0, "{width}x{height} has an odd side");
    assert_eq!(rgb.len(), w * h * 3, "picture is not {width}x{height} RGB8");
    let decode = |v: u8| {
        let c = f64::from(v) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let encode = |l: f64| {
        let c = if l <= 0.0031308 { l * 12.92 } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 };
        (c.clamp(0.0, 1.0) * 255.0).round() as u8
    };
    let mut out = Vec::with_capacity(w * h * 3 / 4);
    for y in (0..h).step_by(2) {
        for x in (0..w).step_by(2) {
            for c in 0..3 {
                let at = |dx: usize, dy: usize| decode(rgb[((y + dy) * w + x + dx) * 3 + c]);
                out.push(encode((at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)) / 4.0));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_in_linear_light() {
        // Black and white pixels average to linear 0.5, which encodes as 188, not 128.
        let rgb = [0, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0];
        assert_eq!(downsample_2x_srgb(&rgb, 2, 2), vec![188, 188, 188]);
        let grey = [77u8; 12];
        assert_eq!(downsample_2x_srgb(&grey, 2, 2), vec![77, 77, 77]);
    }

    #[test]
    fn counts_pixels_within_tolerance_and_the_largest_difference() {
        let a = [10, 10, 10, 100, 100, 100, 0, 0, 0];
        let b = [12, 10, 9, 100, 140, 100, 0, 0, 3];
        let (stats, diff) = compare_rgb(&a, &b, 3);
        assert_eq!(stats, DiffStats { pixels: 3, within: 2, max_diff: 40 });
        assert_eq!(&diff[3..6], &[255, 0, 160]);
        assert!((stats.within_fraction() - 2.0 / 3.0).abs() < 1e-12);
    }

    /// A `w`×`h` grey picture.
    fn grey(w: usize, h: usize, v: u8) -> Vec<u8> {
        vec![v; w * h * 3]
    }

    /// Set channel `c` of every pixel of the 8×8 block (`bx`, `by`) of a `w`-wide picture.
    fn paint_block(rgb: &mut [u8], w: usize, (bx, by): (usize, usize), c: usize, v: u8) {
        for y in by * 8..by * 8 + 8 {
            for x in bx * 8..bx * 8 + 8 {
                rgb[(y * w + x) * 3 + c] = v;
            }
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn identical_pictures_do_not_differ() {
        let a: Vec<u8> = (0..32 * 24 * 3).map(|i| (i * 7 % 256) as u8).collect();
        let d = box_filtered_difference(&a, &a, 32, 24, 8);
        assert_eq!(d, BoxDifference { mean_percent: 0.0, p99_percent: 0.0, max_percent: 0.0 });
    }

    #[test]
    fn one_block_off_by_a_known_amount() {
        // 16×16: four blocks; one is 51 brighter in every channel: 51 / 255 = 20 %.
        let a = grey(16, 16, 100);
        let mut b = a.clone();
        for c in 0..3 {
            paint_block(&mut b, 16, (1, 0), c, 151);
        }
        let d = box_filtered_difference(&a, &b, 16, 16, 8);
        assert!(close(d.mean_percent, 5.0), "{d:?}");
        // Nearest rank: ceil(0.99 × 4) = the 4th of 4 blocks.
        assert!(close(d.p99_percent, 20.0) && close(d.max_percent, 20.0), "{d:?}");
        // In one channel only, 30 darker: 30 / 3 / 255 = 3.92 % (the order does not matter).
        let mut c = a.clone();
        paint_block(&mut c, 16, (0, 1), 0, 70);
        let d = box_filtered_difference(&c, &a, 16, 16, 8);
        let block = 10.0 / 255.0 * 100.0;
        assert!(close(d.max_percent, block) && close(d.mean_percent, block / 4.0), "{d:?}");
    }

    #[test]
    fn the_99th_percentile_leaves_out_the_worst_percent_of_blocks() {
        // 80×80: 100 blocks. One block 51 off: mean 0.2 %, p99 (the 99th of 100) 0, max 20 %.
        let a = grey(80, 80, 100);
        let mut b = a.clone();
        for c in 0..3 {
            paint_block(&mut b, 80, (3, 7), c, 151);
        }
        let d = box_filtered_difference(&a, &b, 80, 80, 8);
        assert!(close(d.mean_percent, 0.2) && d.p99_percent == 0.0 && close(d.max_percent, 20.0), "{d:?}");
        // A second block 102 off (40 %): the 99th block is now the first one's 20 %.
        for c in 0..3 {
            paint_block(&mut b, 80, (9, 0), c, 202);
        }
        let d = box_filtered_difference(&a, &b, 80, 80, 8);
        assert!(close(d.mean_percent, 0.6) && close(d.p99_percent, 20.0) && close(d.max_percent, 40.0), "{d:?}");
    }

    #[test]
    fn detail_inside_a_block_cancels_and_partial_blocks_are_left_out() {
        // A checkerboard against its inverse: every pixel 255 off, every block's mean equal.
        let (w, h) = (20, 12); // one row of two whole blocks; 4 columns and 4 rows left over
        let checker = |invert: bool| -> Vec<u8> {
            (0..w * h).flat_map(|i| [if ((i % w + i / w) % 2 == 0) != invert { 255 } else { 0 }; 3]).collect()
        };
        let (a, b) = (checker(false), checker(true));
        assert_eq!(compare_rgb(&a, &b, 0).0.max_diff, 255);
        assert_eq!(box_filtered_difference(&a, &b, w as u32, h as u32, 8).max_percent, 0.0);
        // A difference only in the partial column (x 16..20) and row (y 8..12) is not counted.
        let mut c = a.clone();
        for y in 0..h {
            for x in 0..w {
                if x >= 16 || y >= 8 {
                    c[(y * w + x) * 3..][..3].copy_from_slice(&[7, 7, 7]);
                }
            }
        }
        assert_eq!(box_filtered_difference(&a, &c, w as u32, h as u32, 8).max_percent, 0.0);
        // Smaller than a block: no block, nothing to differ.
        assert_eq!(box_filtered_difference(&a[..7 * 3], &b[..7 * 3], 7, 1, 8).mean_percent, 0.0);
    }
}
