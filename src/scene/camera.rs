//! The camera: position and yaw/pitch in degrees; perspective with reversed, infinite Z. And the
//! orthographic view of a bake (an atlas rendered from the side): reversed Z over a finite depth.
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
/// Eye height of the landscape camera (`--camera landscape`) above the ground under it (metres).
pub const LANDSCAPE_HEIGHT: f32 = 20.0;
/// Pitch of the landscape camera in degrees. With the 60° field of view at 1280×720 (623.5 px
/// per unit of tan), flat ground 1 km ahead lies atan(20 / 1000) = 1.15° below the horizon:
/// 623.5 (tan 8° − tan 6.85°) = 12.7 px below it (`rows_below_horizon`), 5 km ahead
/// 2.5 px; the horizon itself is 88 px above the picture's centre.
pub const LANDSCAPE_PITCH_DEG: f32 = -8.0;

/// `--camera`: a position and orientation, or a named preset placed on the scene's ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraChoice {
    /// Exactly this camera.
    At(Camera),
    /// `landscape`: `LANDSCAPE_HEIGHT` above the ground where the default camera stands, looking
    /// the same way at `LANDSCAPE_PITCH_DEG`, so what lies kilometres away spans rows of pixels.
    Landscape,
}

/// The camera presets `--camera` names.
pub const CAMERA_PRESETS: &[&str] = &["landscape"];

/// How many pixel rows below the horizon flat ground `distance` metres ahead lies, seen from
/// `height` metres up at `pitch_deg` into a picture `rows` high (the vertical field of view
/// `FOV_Y_DEG`).
pub fn rows_below_horizon(height: f32, pitch_deg: f32, distance: f32, rows: u32) -> f32 {
    let focal = 0.5 * rows as f32 / (0.5 * FOV_Y_DEG.to_radians()).tan();
    let pitch = -pitch_deg.to_radians();
    let below = (height / distance).atan();
    focal * (pitch.tan() - (pitch - below).tan())
}

/// Depth steps a fixed-point depth format resolves at the view distance, at least
/// (`near_plane`).
pub const FAR_DEPTH_STEPS: f32 = 4.0;

/// The near plane for a view out to `view_distance` metres into a depth format of `steps` steps
/// (2^bits − 1 for a UNORM format; `None` for a float one). With reversed infinite Z a point at
/// distance z stores near / z, so a UNORM format rounds everything past `steps` × near to the
/// cleared 0: with D16 and the 0.05 m `NEAR`, ground past 3.3 km vanished. The near plane moves
/// out until the view distance keeps `FAR_DEPTH_STEPS` steps: D16 0.061 m at 1 km, 0.31 m at
/// 5 km, 0.61 m at 10 km; D24 stays at `NEAR`. A float format's exponent keeps its precision.
pub fn near_plane(steps: Option<u32>, view_distance: f32) -> f32 {
    match steps {
        Some(steps) => NEAR.max(FAR_DEPTH_STEPS * view_distance / steps as f32),
        None => NEAR,
    }
}

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

    /// View → clip for Vulkan: reversed infinite Z (near → 1, infinity → 0) and y pointing down,
    /// the near plane at `NEAR`.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        self.projection_near(aspect, NEAR)
    }

    /// `projection` with its near plane at `near` metres (`near_plane`).
    pub fn projection_near(&self, aspect: f32, near: f32) -> Mat4 {
        let mut proj = Mat4::perspective_infinite_reverse_rh(FOV_Y_DEG.to_radians(), aspect, near);
        proj.y_axis.y = -proj.y_axis.y;
        proj
    }

    /// World → clip.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// World → clip with the near plane at `near` metres.
    pub fn view_projection_near(&self, aspect: f32, near: f32) -> Mat4 {
        self.projection_near(aspect, near) * self.view()
    }
}

/// An orthographic view: a box `2 half_extent.x` wide, `2 half_extent.y` high and from `near` to
/// `far` deep in front of `position`, looking along `forward` with `up` upwards in the picture.
/// Reversed Z like the perspective camera (near → 1, far → 0), over a finite range: depth keeps
/// its precision for the box it bakes (an atlas of blades seen from the side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrthographicCamera {
    /// Eye position in world space (the centre of the box's near face).
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// World direction that is up in the picture (not parallel to `forward`).
    pub up: Vec3,
    /// Half the box's width and height in metres.
    pub half_extent: glam::Vec2,
    /// Near plane in metres (may be 0 or negative: the box may start behind the eye).
    pub near: f32,
    /// Far plane in metres (finite).
    pub far: f32,
}

impl OrthographicCamera {
    /// World → view.
    pub fn view(&self) -> Mat4 {
        Mat4::look_to_rh(self.position, self.forward, self.up)
    }

    /// View → clip for Vulkan: reversed Z (glam maps near → 0 and far → 1; the planes swapped
    /// map near → 1 and far → 0) and y pointing down.
    pub fn projection(&self) -> Mat4 {
        let h = self.half_extent;
        let mut proj = Mat4::orthographic_rh(-h.x, h.x, -h.y, h.y, self.far, self.near);
        proj.y_axis.y = -proj.y_axis.y;
        proj
    }

    /// World → clip.
    pub fn view_projection(&self) -> Mat4 {
        self.projection() * self.view()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_landscape_camera_sees_a_kilometre_rows_below_the_horizon() {
        let rows = |d| rows_below_horizon(LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG, d, 720);
        assert!((rows(1000.0) - 12.7).abs() < 0.05, "{}", rows(1000.0));
        assert!((rows(5000.0) - 2.5).abs() < 0.05, "{}", rows(5000.0));
        // The default camera's eye, 1.7 m up at -12°: 1.1 px at 1 km.
        assert!((rows_below_horizon(EYE_HEIGHT, -12.0, 1000.0, 720) - 1.11).abs() < 0.05);
    }

    #[test]
    fn a_unorm_near_plane_keeps_the_view_distance_off_the_cleared_depth() {
        assert_eq!(near_plane(None, 10_000.0), NEAR);
        assert_eq!(near_plane(Some(65_535), 150.0), NEAR);
        assert_eq!(near_plane(Some(16_777_215), 10_000.0), NEAR);
        for view in [1000.0, 5000.0, 10_000.0] {
            let near = near_plane(Some(65_535), view);
            let c = Camera { position: Vec3::ZERO, yaw_deg: 0.0, pitch_deg: 0.0 };
            let z = c.view_projection_near(1.0, near).project_point3(Vec3::new(0.0, 0.0, -view)).z;
            let stored = (z * 65_535.0).round();
            assert!(stored >= FAR_DEPTH_STEPS, "{view} m stores {stored} steps");
            // The old near plane stored less than one step past 3.3 km.
            let old = c.view_projection(1.0).project_point3(Vec3::new(0.0, 0.0, -view)).z;
            assert_eq!(old * 65_535.0 < 1.0, view > 3300.0, "{view}");
        }
    }

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

    #[test]
    fn orthographic_reversed_z_over_a_finite_box() {
        let c = OrthographicCamera {
            position: Vec3::new(10.0, 0.5, 0.0),
            forward: Vec3::NEG_X,
            up: Vec3::Y,
            half_extent: glam::Vec2::new(2.0, 0.5),
            near: 0.0,
            far: 20.0,
        };
        let vp = c.view_projection();
        let near = vp.project_point3(Vec3::new(10.0, 0.5, 0.0));
        let far = vp.project_point3(Vec3::new(-10.0, 0.5, 0.0));
        let middle = vp.project_point3(Vec3::new(0.0, 0.5, 0.0));
        assert!((near.z - 1.0).abs() < 1e-6 && far.z.abs() < 1e-6, "{near} {far}");
        assert!((middle.z - 0.5).abs() < 1e-6, "depth is linear in an orthographic box: {middle}");
        // The box's top edge is at the top of the picture, its side edge at the side; no
        // perspective: the same at every depth.
        let top = vp.project_point3(Vec3::new(5.0, 1.0, 0.0));
        assert!((top.y + 1.0).abs() < 1e-6, "{top}");
        let side = [vp.project_point3(Vec3::new(9.0, 0.5, 2.0)), vp.project_point3(Vec3::new(-9.0, 0.5, 2.0))];
        assert!(side.iter().all(|p| (p.x.abs() - 1.0).abs() < 1e-6), "{side:?}");
    }
}
