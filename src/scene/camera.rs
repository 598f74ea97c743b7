//! The camera: position and yaw/pitch in degrees; perspective with reversed, infinite Z.
//!
//! Yaw 0 looks along -z; positive yaw turns left (counter-clockwise seen from above). Pitch is
//! positive upwards.

use glam::{Mat4, Vec3};

use crate::scene::terrain::Terrain;

/// Vertical field of view in degrees.
pub const FOV_Y_DEG: f32 = 60.0;
/// Near plane in metres (far is at infinity with reversed Z).
pub const NEAR: f32 = 0.05;
/// Eye height of the default camera above the ground (metres).
pub const EYE_HEIGHT: f32 = 1.7;

/// Where the camera is and where it looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position in world space.
    pub position: Vec3,
    /// Heading in degrees.
    pub yaw_deg: f32,
    /// Elevation in degrees.
    pub pitch_deg: f32,
}

impl Camera {
    /// Standing 1.7 m above the ground at the field's edge, looking across it and slightly down.
    pub fn default_for(terrain: &Terrain) -> Self {
        let z = 0.5 * terrain.size;
        Self { position: Vec3::new(0.0, terrain.height_at(0.0, z) + EYE_HEIGHT, z), yaw_deg: 0.0, pitch_deg: -12.0 }
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        let (yaw, pitch) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        Vec3::new(-yaw.sin() * pitch.cos(), pitch.sin(), -yaw.cos() * pitch.cos())
    }

    /// World → view.
    pub fn view(&self) -> Mat4 {
        Mat4::look_to_rh(self.position, self.forward(), Vec3::Y)
    }

    /// View → clip for Vulkan: reversed infinite Z (near → 1, infinity → 0) and y pointing down.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let mut proj = Mat4::perspective_infinite_reverse_rh(FOV_Y_DEG.to_radians(), aspect, NEAR);
        proj.y_axis.y = -proj.y_axis.y;
        proj
    }

    /// World → clip.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn yaw_and_pitch_conventions() {
        let mut c = Camera { position: Vec3::ZERO, yaw_deg: 0.0, pitch_deg: 0.0 };
        assert!((c.forward() - Vec3::NEG_Z).length() < 1e-6);
        c.yaw_deg = 90.0;
        assert!((c.forward() - Vec3::NEG_X).length() < 1e-6, "positive yaw turns left");
        c.pitch_deg = 90.0;
        assert!((c.forward() - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn reversed_z_and_vulkan_y() {
        let c = Camera { position: Vec3::ZERO, yaw_deg: 0.0, pitch_deg: 0.0 };
        let vp = c.view_projection(1.0);
        let near = vp.project_point3(Vec3::new(0.0, 0.0, -NEAR));
        let far = vp.project_point3(Vec3::new(0.0, 0.0, -1000.0));
        assert!((near.z - 1.0).abs() < 1e-5 && far.z > 0.0 && far.z < 1e-3);
        let up = vp.project_point3(Vec3::new(0.0, 1.0, -5.0));
        assert!(up.y < 0.0, "world up is towards the top of the image (negative y in Vulkan clip space)");
    }
}
