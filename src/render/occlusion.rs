//! When the terrain cannot hide anything: the frame's occlusion test (`CULL_OCCLUSION`, the depth
//! pyramid of the terrain) is then skipped, pyramid and all.
//!
//! A point on or above a ground whose slope is at most `s` cannot be hidden from an eye by that
//! ground when the line of sight to it descends more steeply than `s`: walking from the point
//! back towards the eye, the line rises by more than `s` a metre and the ground by at most `s`, so
//! the line stays above the ground all the way. The lines of sight into the view are the convex
//! cone of its four corner rays, and the lines that descend by at least `t` a metre form a convex
//! cone round the downward vertical, so every line of the view descends that steeply when its four
//! corners do. Looking down from above (the landscape bench's camera 40 m up, a viewer's overview)
//! the test holds; at the horizon it never does.
//!
//! The ground drawn is triangles between exact samples of the ground: a block field's clipmap
//! (`render::ground`) or a stored terrain's grid. Each has one edge along x and one along z, whose
//! rises per metre are each at most the ground's slope bound (`scene::FieldGround::slope_bound`,
//! which bounds the gradient's length; `scene::terrain::Terrain::slope_bound`, the steepest rise
//! along an axis), so a triangle's slope is at most √2 times it. Blades and far plants stand on
//! that drawn surface.

use glam::{Mat4, Vec3, Vec3Swizzles, Vec4Swizzles};

/// The margin on the drawn ground's slope bound: f32 heights and the clipmap's morph between levels.
const MARGIN: f32 = 1.05;

/// Whether no line of sight into the view of `view_proj` (reversed Z) can meet a ground whose
/// slope is at most `slope` before the point it looks at, for any point on or above that ground.
pub fn terrain_cannot_occlude(view_proj: Mat4, slope: f32) -> bool {
    let drawn = std::f32::consts::SQRT_2 * slope * MARGIN;
    let inverse = view_proj.inverse();
    let at = |x: f32, y: f32, z: f32| {
        let p = inverse * glam::Vec4::new(x, y, z, 1.0);
        p.xyz() / p.w
    };
    [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)].iter().all(|&(x, y)| {
        // Reversed Z: the near plane at 1, farther points towards 0.
        let ray: Vec3 = at(x, y, 0.5) - at(x, y, 1.0);
        let across = ray.xz().length();
        ray.is_finite() && -ray.y > drawn * across
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;

    fn view(pitch_deg: f32) -> Mat4 {
        let camera = Camera { position: Vec3::new(3.0, 41.0, -2.0), yaw_deg: 30.0, pitch_deg };
        camera.view_projection_near(16.0 / 9.0, 0.05)
    }

    #[test]
    fn looking_down_steeply_over_a_gentle_ground_nothing_can_be_hidden() {
        // Straight down, a 60° view 16:9: its corner rays descend by about 0.8 a metre.
        assert!(terrain_cannot_occlude(view(-89.0), 0.5));
        assert!(terrain_cannot_occlude(view(-89.0), 0.0));
        // The same view over a steeper ground, and views that reach the horizon: not provable.
        assert!(!terrain_cannot_occlude(view(-89.0), 0.6));
        assert!(!terrain_cannot_occlude(view(-8.0), 0.0));
        assert!(!terrain_cannot_occlude(view(-30.0), 0.01));
    }

    #[test]
    fn the_corner_rays_bound_every_line_of_the_view() {
        // A brute-force check of the claim the test rests on: sample the view's lines on a grid
        // and compare the shallowest descent with the corners'.
        for pitch in [-89.0, -75.0, -60.0] {
            let inverse = view(pitch).inverse();
            let descent = |x: f32, y: f32| {
                let at = |z: f32| {
                    let p = inverse * glam::Vec4::new(x, y, z, 1.0);
                    p.xyz() / p.w
                };
                let ray = at(0.5) - at(1.0);
                -ray.y / ray.xz().length()
            };
            let corners = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)].map(|(x, y)| descent(x, y));
            let least = corners.iter().copied().fold(f32::INFINITY, f32::min);
            for i in 0..=20 {
                for j in 0..=20 {
                    let d = descent(-1.0 + 0.1 * i as f32, -1.0 + 0.1 * j as f32);
                    assert!(d >= least - 1e-4, "pitch {pitch}: {d} under the corners' {least}");
                }
            }
            let threshold = least / (std::f32::consts::SQRT_2 * MARGIN);
            assert!(terrain_cannot_occlude(view(pitch), 0.99 * threshold), "pitch {pitch}");
            assert!(!terrain_cannot_occlude(view(pitch), 1.01 * threshold), "pitch {pitch}");
        }
    }
}
