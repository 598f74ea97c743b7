//! Comparing pictures with a tolerance: golden-image tests, and viewer screenshots against
//! headless renders.

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_pixels_within_tolerance_and_the_largest_difference() {
        let a = [10, 10, 10, 100, 100, 100, 0, 0, 0];
        let b = [12, 10, 9, 100, 140, 100, 0, 0, 3];
        let (stats, diff) = compare_rgb(&a, &b, 3);
        assert_eq!(stats, DiffStats { pixels: 3, within: 2, max_diff: 40 });
        assert_eq!(&diff[3..6], &[255, 0, 160]);
        assert!((stats.within_fraction() - 2.0 / 3.0).abs() < 1e-12);
    }
}
