//! Blade geometry (thesis 4.1): two parallel cubic Bézier splines; S segments give S quads.
//! The vertex shader (`shaders/blades/blade.vert`) evaluates exactly these functions; the CPU copy is
//! used by tests and, with keyframes, by the pose generator.

use glam::Vec3;

use crate::scene::blades::BladeInstance;

/// Cubic Bézier point `B(t) = (1-t)³P0 + 3(1-t)²tP1 + 3(1-t)t²P2 + t³P3`.
pub fn point(p: &[Vec3; 4], t: f32) -> Vec3 {
    let s = 1.0 - t;
    p[0] * (s * s * s) + p[1] * (3.0 * s * s * t) + p[2] * (3.0 * s * t * t) + p[3] * (t * t * t)
}

/// Derivative `B'(t) = 3(1-t)²(P1-P0) + 6(1-t)t(P2-P1) + 3t²(P3-P2)`.
pub fn tangent(p: &[Vec3; 4], t: f32) -> Vec3 {
    let s = 1.0 - t;
    (p[1] - p[0]) * (3.0 * s * s) + (p[2] - p[1]) * (6.0 * s * t) + (p[3] - p[2]) * (3.0 * t * t)
}

/// Neutral-pose control points of a blade in its local frame (x across the blade, y up,
/// z along its normal). The natural lean bends the tip forward by up to 45 % of the height; the
/// tip height keeps the chord `h` so leaning blades do not grow.
pub fn neutral_control_points(blade: &BladeInstance) -> [Vec3; 4] {
    let h = blade.height;
    let lean = 0.45 * blade.variation(2) * h;
    let tip_y = (h * h - lean * lean).sqrt();
    [
        Vec3::ZERO,
        Vec3::new(0.0, 0.4 * tip_y, 0.0),
        Vec3::new(0.0, 0.8 * tip_y, 0.35 * lean),
        Vec3::new(0.0, tip_y, lean),
    ]
}

/// The blade's side (across the width) and normal directions in world space.
pub fn frame(blade: &BladeInstance) -> (Vec3, Vec3) {
    let (s, c) = blade.facing.sin_cos();
    (Vec3::new(c, 0.0, -s), Vec3::new(s, 0.0, c))
}

/// World-space position of strip vertex `vertex` of a blade drawn with `segments` segments:
/// vertex `2k + side` lies on spline `side` (0 left, 1 right) at `t = k / segments`.
pub fn strip_vertex(blade: &BladeInstance, segments: u32, vertex: u32) -> Vec3 {
    let t = (vertex / 2) as f32 / segments as f32;
    let side_sign = if vertex & 1 == 0 { -0.5 } else { 0.5 };
    let (side, normal) = frame(blade);
    let local = point(&neutral_control_points(blade), t);
    Vec3::from(blade.position) + side * (local.x + side_sign * blade.width) + Vec3::Y * local.y + normal * local.z
}

/// Vertices per blade for a triangle strip of `segments` quads.
pub fn strip_vertices(segments: u32) -> u32 {
    2 * (segments + 1)
}

/// How blades are laid out in the vertices of one instance.
///
/// One blade per instance: its strip alone. Several: each blade's strip with its first and last
/// vertex repeated, which joins neighbours with degenerate (zero-area) triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Batching {
    /// Blades per instance.
    pub blades_per_instance: u32,
    /// Vertices per blade.
    pub stride: u32,
    /// Repeats of the first vertex before the strip (0 or 1).
    pub lead: u32,
}

impl Batching {
    /// Layout for `blades_per_instance` blades of `segments` segments.
    pub fn new(segments: u32, blades_per_instance: u32) -> Self {
        let lead = u32::from(blades_per_instance > 1);
        Self { blades_per_instance, stride: strip_vertices(segments) + 2 * lead, lead }
    }

    /// Vertices of one instance.
    pub fn vertices_per_instance(&self) -> u32 {
        self.stride * self.blades_per_instance
    }

    /// Which blade of the instance, and which of its strip vertices, vertex `vertex` is.
    pub fn vertex(&self, segments: u32, vertex: u32) -> (u32, u32) {
        let j = vertex % self.stride;
        (vertex / self.stride, j.saturating_sub(self.lead).min(strip_vertices(segments) - 1))
    }
}

/// A LOD bucket's blade as an indexed triangle list (the cull's draws, blade.vert): the strip's
/// triangles in the strip's order and winding, without the degenerate ones. No joins between the
/// blades of an instance, and with `collapsed_tip` (the outline drawn as geometry, zero wide at
/// the tip) one tip vertex: the top segment is one triangle. Against the joined strips, a
/// 1-segment blade shades 3 vertices instead of 6 and sets up 1 triangle instead of 6.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BladeMesh {
    /// Segments.
    pub segments: u32,
    /// One tip vertex instead of two.
    pub collapsed_tip: bool,
}

impl BladeMesh {
    /// Vertices of one blade: strip vertex `j` is vertex `j`.
    pub fn vertices(&self) -> u32 {
        strip_vertices(self.segments) - u32::from(self.collapsed_tip)
    }

    /// Triangles of one blade.
    pub fn triangles(&self) -> u32 {
        2 * self.segments - u32::from(self.collapsed_tip)
    }

    /// Indices of `blades` blades (blade k's vertices from `k * vertices()`): strip triangle `i`
    /// is `(i, i+1, i+2)` for even `i` and `(i+1, i, i+2)` for odd `i`, as Vulkan assembles a
    /// strip, so each triangle is the strip's own.
    pub fn indices(&self, blades: u32) -> Vec<u32> {
        let stride = self.vertices();
        (0..blades)
            .flat_map(|k| {
                (0..self.triangles()).flat_map(move |i| {
                    let t = if i % 2 == 0 { [i, i + 1, i + 2] } else { [i + 1, i, i + 2] };
                    t.map(|v| k * stride + v)
                })
            })
            .collect()
    }
}

/// The index lists of the cull's LOD buckets, one after the other (`segments` per bucket,
/// `blades` per instance), as `cull_scan.comp` addresses them (`firstIndex` of bucket b is the
/// length of the lists before it).
pub fn bucket_indices(segments: &[u32], collapsed_tip: bool, blades: u32) -> Vec<u32> {
    segments.iter().flat_map(|&segments| BladeMesh { segments, collapsed_tip }.indices(blades)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blade(lean_byte: u32) -> BladeInstance {
        BladeInstance {
            position: [1.0, 2.0, 3.0],
            facing: 0.0,
            height: 0.5,
            width: 0.01,
            stiffness: 1.0,
            variation: lean_byte << 16,
        }
    }

    #[test]
    fn bezier_hits_end_points_and_matches_the_bernstein_form() {
        let p = [Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(2.0, 2.0, 1.0)];
        assert_eq!(point(&p, 0.0), p[0]);
        assert_eq!(point(&p, 1.0), p[3]);
        // t = 1/2: (P0 + 3P1 + 3P2 + P3) / 8
        let mid = (p[0] + 3.0 * p[1] + 3.0 * p[2] + p[3]) / 8.0;
        assert!((point(&p, 0.5) - mid).length() < 1e-6);
        // Derivative against a central difference.
        for t in [0.1f32, 0.5, 0.9] {
            let numeric = (point(&p, t + 1e-3) - point(&p, t - 1e-3)) / 2e-3;
            assert!((tangent(&p, t) - numeric).length() < 1e-2);
        }
    }

    #[test]
    fn straight_blade_is_vertical_and_leaning_blade_keeps_its_chord() {
        let straight = neutral_control_points(&blade(0));
        assert!((straight[3] - Vec3::new(0.0, 0.5, 0.0)).length() < 1e-6);
        let leaning = neutral_control_points(&blade(255));
        assert!((leaning[3].length() - 0.5).abs() < 1e-5);
        assert!(leaning[3].z > 0.2, "the lean bends the tip forward");
    }

    #[test]
    fn batched_strips_join_blades_with_degenerate_triangles() {
        let s = 2;
        let single = Batching::new(s, 1);
        assert_eq!(single.vertices_per_instance(), 6);
        assert_eq!((0..6).map(|v| single.vertex(s, v).1).collect::<Vec<_>>(), vec![0, 1, 2, 3, 4, 5]);
        let batch = Batching::new(s, 2);
        assert_eq!(batch.vertices_per_instance(), 16);
        let order: Vec<_> = (0..16).map(|v| batch.vertex(s, v)).collect();
        assert_eq!(&order[..8], &[(0, 0), (0, 0), (0, 1), (0, 2), (0, 3), (0, 4), (0, 5), (0, 5)]);
        assert_eq!(order[8], (1, 0));
        // Every triangle either lies in one blade's strip or repeats a vertex (zero area).
        for w in order.windows(3) {
            let same_blade = w[0].0 == w[1].0 && w[1].0 == w[2].0;
            let repeats = w[0] == w[1] || w[1] == w[2] || w[0] == w[2];
            assert!(repeats || (same_blade && w[1].1 == w[0].1 + 1 && w[2].1 == w[1].1 + 1), "{w:?}");
        }
    }

    #[test]
    fn a_blade_mesh_is_its_strip_without_the_degenerate_triangles() {
        for segments in [1, 2, 3, 4, 8, 16] {
            let strip = strip_vertices(segments);
            // Vulkan's strip triangles, as vertex pairs (level, side); the tip's two vertices
            // are one when it collapses.
            for collapsed_tip in [false, true] {
                let mesh = BladeMesh { segments, collapsed_tip };
                let at = |v: u32| if collapsed_tip && v == strip - 1 { strip - 2 } else { v };
                let expected: Vec<[u32; 3]> = (0..strip - 2)
                    .map(|i| if i % 2 == 0 { [i, i + 1, i + 2] } else { [i + 1, i, i + 2] }.map(at))
                    .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                    .collect();
                let indices = mesh.indices(3);
                assert_eq!(indices.len() as u32, 3 * 3 * mesh.triangles());
                let first: Vec<[u32; 3]> =
                    indices[..3 * mesh.triangles() as usize].chunks(3).map(|t| [t[0], t[1], t[2]]).collect();
                assert_eq!(first, expected, "{mesh:?}");
                assert!(indices.iter().all(|&v| v < 3 * mesh.vertices()));
                // Blade k's triangles are blade 0's, moved by k blades.
                let third = &indices[6 * mesh.triangles() as usize..];
                assert!(third.iter().zip(&indices).all(|(&b, &a)| b == a + 2 * mesh.vertices()));
            }
        }
        assert_eq!(BladeMesh { segments: 1, collapsed_tip: true }.indices(1), vec![0, 1, 2]);
        let lists = bucket_indices(&[4, 1], true, 2);
        assert_eq!(lists.len(), 3 * 2 * (7 + 1));
    }

    #[test]
    fn strip_vertices_are_parallel_splines() {
        let b = blade(128);
        let segments = 4;
        assert_eq!(strip_vertices(segments), 10);
        for k in 0..=segments {
            let left = strip_vertex(&b, segments, 2 * k);
            let right = strip_vertex(&b, segments, 2 * k + 1);
            assert!(((right - left).length() - b.width).abs() < 1e-6);
        }
        assert!((strip_vertex(&b, segments, 0) - Vec3::new(1.0 - 0.005, 2.0, 3.0)).length() < 1e-6);
    }
}
