//! Keyframe memory, thesis 3.3: raw poses, then only moving vertices, one displacement per rigid
//! segment vertex pair, 16-bit components, and the four-fold mirror symmetry.

use std::fmt;

/// The vertex structure of a blade geometry, as far as compression is concerned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BladeGeometry {
    /// What it is.
    pub name: &'static str,
    /// Segments.
    pub segments: u32,
    /// Vertices of one pose.
    pub vertices: u32,
    /// Vertices that never move (the root pair).
    pub static_vertices: u32,
    /// Components stored per displacement after compression.
    pub components: u32,
}

impl BladeGeometry {
    /// The thesis' blade (fig. 3.4 and 3.7): every segment is its own quad, 4 vertices per
    /// segment (8 segments: 32 vertices), the root pair static, three components per vector.
    pub fn thesis(segments: u32) -> Self {
        Self { name: "thesis blade", segments, vertices: 4 * segments, static_vertices: 2, components: 3 }
    }

    /// meadow's blade: one strip, 2(S+1) vertices shared between segments, the root pair static,
    /// and a fourth component per pair, the twist of the width (the blade turns to face a side
    /// wind), so a pair's two vertices can move differently while one record describes both.
    pub fn meadow(segments: u32) -> Self {
        Self { name: "meadow blade", segments, vertices: 2 * (segments + 1), static_vertices: 2, components: 4 }
    }

    /// Displacement records per pose: one per rigid pair of moving vertices.
    pub fn records(&self) -> u32 {
        (self.vertices - self.static_vertices) / 2
    }
}

/// Sizes in bits of `poses` keyframes of a geometry at each compression step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CompressionReport {
    /// The geometry.
    pub geometry: BladeGeometry,
    /// Poses over the full circle.
    pub poses: u32,
    /// Every vertex of every pose, 3 × 32-bit floats.
    pub raw_bits: u64,
    /// Only moving vertices, 3 × 32 bits.
    pub moving_bits: u64,
    /// One record per rigid pair, 32-bit components.
    pub pairs_bits: u64,
    /// One record per pair, 16-bit components: compressed without symmetry.
    pub compressed_bits: u64,
    /// The same for a quarter of the poses (mirror symmetry).
    pub symmetric_bits: u64,
}

impl CompressionReport {
    /// Figures for `poses` poses of `geometry`.
    pub fn new(geometry: BladeGeometry, poses: u32) -> Self {
        let p = u64::from(poses);
        let c = u64::from(geometry.components);
        let records = u64::from(geometry.records());
        Self {
            geometry,
            poses,
            raw_bits: p * u64::from(geometry.vertices) * 3 * 32,
            moving_bits: p * u64::from(geometry.vertices - geometry.static_vertices) * 3 * 32,
            pairs_bits: p * records * c * 32,
            compressed_bits: p * records * c * 16,
            symmetric_bits: p.div_ceil(4) * records * c * 16,
        }
    }
}

fn kib(bits: u64) -> f64 {
    bits as f64 / 8.0 / 1024.0
}

impl fmt::Display for CompressionReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let g = &self.geometry;
        writeln!(
            f,
            "{}: {} segments, {} vertices ({} static), {} records of {} components per pose, {} poses",
            g.name,
            g.segments,
            g.vertices,
            g.static_vertices,
            g.records(),
            g.components,
            self.poses
        )?;
        let pct = |bits: u64| 100.0 * (1.0 - bits as f64 / self.raw_bits as f64);
        let rows = [
            ("raw (all vertices, 3 x 32 bit)", self.raw_bits),
            ("moving vertices only", self.moving_bits),
            ("one record per rigid vertex pair", self.pairs_bits),
            ("16-bit components (compressed)", self.compressed_bits),
            ("+ mirror symmetry (a quarter stored)", self.symmetric_bits),
        ];
        for (name, bits) in rows {
            writeln!(f, "  {name:<38} {bits:>12} bits {:>10.2} KiB  -{:.2} %", kib(bits), pct(bits))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_the_thesis_example_exactly() {
        // Thesis 3.3: 1000 poses, 8 segments, 32 vertices.
        let r = CompressionReport::new(BladeGeometry::thesis(8), 1000);
        assert_eq!(r.geometry.vertices, 32);
        assert_eq!(r.geometry.records(), 15);
        assert_eq!(r.raw_bits, 3_072_000);
        assert_eq!(r.compressed_bits, 720_000);
        assert_eq!(r.symmetric_bits, 180_000);
    }

    #[test]
    fn meadow_geometry_figures() {
        let r = CompressionReport::new(BladeGeometry::meadow(4), 1000);
        assert_eq!(r.geometry.vertices, 10);
        assert_eq!(r.geometry.records(), 4);
        assert_eq!(r.raw_bits, 1000 * 10 * 96);
        assert_eq!(r.compressed_bits, 1000 * 4 * 4 * 16);
        assert_eq!(r.symmetric_bits, 250 * 4 * 4 * 16);
    }
}
