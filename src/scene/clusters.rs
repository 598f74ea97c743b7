//! Clusters (thesis 3.2.2): the field is split into square clusters; forces are computed at their
//! corners on the CPU every frame and interpolated per blade on the GPU with weights computed once
//! (eq. 3.6–3.8).

use bytemuck::{Pod, Zeroable};
use glam::Vec2;

use crate::scene::BladeInstance;

/// Per-blade interpolation record (`shaders/common/common.glsl`, `BladeCluster`): 8 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct BladeCluster {
    /// Index of the cluster's corner with the smallest x and z.
    pub corner: u32,
    /// The four weights δ of eq. 3.7 as unorm8, in order (x0,z0) (x1,z0) (x0,z1) (x1,z1).
    pub weights: u32,
}

const _: () = assert!(std::mem::size_of::<BladeCluster>() == 8);

impl BladeCluster {
    /// The four weights as floats (what the GPU's `unpackUnorm4x8` returns).
    pub fn unpacked_weights(&self) -> [f32; 4] {
        std::array::from_fn(|i| ((self.weights >> (8 * i)) & 0xff) as f32 / 255.0)
    }
}

/// A square grid of clusters over the field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterGrid {
    /// World x (= z) of the first corner.
    pub origin: f32,
    /// Cluster edge in metres (the field is covered exactly, so it may be slightly smaller than
    /// asked).
    pub cluster_size: f32,
    /// Clusters per side.
    pub clusters: u32,
}

impl ClusterGrid {
    /// Clusters of about `cluster_size` metres over a square field of side `field`.
    pub fn new(field: f32, cluster_size: f32) -> Self {
        let clusters = (field / cluster_size).ceil().max(1.0) as u32;
        Self { origin: -0.5 * field, cluster_size: field / clusters as f32, clusters }
    }

    /// Corners per side.
    pub fn corners_per_side(&self) -> u32 {
        self.clusters + 1
    }

    /// Number of corners.
    pub fn corner_count(&self) -> u32 {
        self.corners_per_side() * self.corners_per_side()
    }

    /// World (x, z) of corner `index`.
    pub fn corner_position(&self, index: u32) -> Vec2 {
        let n = self.corners_per_side();
        Vec2::new(
            self.origin + (index % n) as f32 * self.cluster_size,
            self.origin + (index / n) as f32 * self.cluster_size,
        )
    }

    /// The cluster record of a blade at (x, z): its corner and the bilinear weights of eq. 3.7.
    ///
    /// Eq. 3.7 reads δ_i = |P_ix − P_cx| · |P_iz − P_cz| in the cluster's unit coordinates: the
    /// area of the sub-rectangle between P_c and corner P_i. That area weighs the *opposite*
    /// corner's force (a blade at a corner takes that corner's force), which is how it is paired
    /// here.
    pub fn locate(&self, x: f32, z: f32) -> BladeCluster {
        let gx = ((x - self.origin) / self.cluster_size).clamp(0.0, self.clusters as f32);
        let gz = ((z - self.origin) / self.cluster_size).clamp(0.0, self.clusters as f32);
        let cx = (gx.floor() as u32).min(self.clusters - 1);
        let cz = (gz.floor() as u32).min(self.clusters - 1);
        let (u, v) = (gx - cx as f32, gz - cz as f32);
        let areas = [(1.0 - u) * (1.0 - v), u * (1.0 - v), (1.0 - u) * v, u * v];
        let mut bytes = areas.map(|w| (w * 255.0).round() as u8);
        // Keep the quantised weights summing to exactly 255, so a uniform wind stays uniform.
        let sum: i32 = bytes.iter().map(|b| i32::from(*b)).sum();
        let largest = (0..4).max_by(|a, b| areas[*a].total_cmp(&areas[*b])).expect("four weights");
        bytes[largest] = (i32::from(bytes[largest]) + 255 - sum).clamp(0, 255) as u8;
        BladeCluster { corner: cz * self.corners_per_side() + cx, weights: u32::from_le_bytes(bytes) }
    }

    /// Cluster records of every blade.
    pub fn assign(&self, blades: &[BladeInstance]) -> Vec<BladeCluster> {
        blades.iter().map(|b| self.locate(b.position[0], b.position[2])).collect()
    }

    /// Eq. 3.6: the force of a blade from its cluster record and the corner forces.
    pub fn interpolate(&self, cluster: &BladeCluster, corners: &[Vec2]) -> Vec2 {
        let n = self.corners_per_side();
        let w = cluster.unpacked_weights();
        let c = cluster.corner;
        corners[c as usize] * w[0]
            + corners[(c + 1) as usize] * w[1]
            + corners[(c + n) as usize] * w[2]
            + corners[(c + n + 1) as usize] * w[3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_are_bilinear_and_sum_to_one() {
        let grid = ClusterGrid::new(10.0, 2.0);
        assert_eq!(grid.clusters, 5);
        let c = grid.locate(-5.0 + 0.5, -5.0 + 1.5); // u = 0.25, v = 0.75 in cluster (0, 0)
        assert_eq!(c.corner, 0);
        let w = c.unpacked_weights();
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert!((w[2] - 0.75 * 0.75).abs() < 3e-3, "{w:?}");
        // A blade on a corner takes that corner's force.
        let corner = grid.locate(-5.0 + 4.0, -5.0 + 2.0);
        let corners: Vec<Vec2> = (0..grid.corner_count()).map(|i| Vec2::splat(i as f32)).collect();
        let expected = grid.corner_position(grid.corners_per_side() + 2);
        assert_eq!(
            grid.corner_position(corner.corner + if corner.unpacked_weights()[0] > 0.5 { 0 } else { 1 }),
            expected
        );
        assert!((grid.interpolate(&corner, &corners).x - (grid.corners_per_side() + 2) as f32).abs() < 1e-4);
    }
}
