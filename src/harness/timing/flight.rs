//! `meadow timing --fly`: the camera moving along its heading at a fixed speed, one `--dt` a
//! frame, at its height above the ground, so the passes that follow the camera (the ground's
//! fill, the wind's levels, the blade-state store) are measured as they cross their cells.

use crate::scene::{Camera, Scene};

/// A straight flight from a camera.
#[derive(Clone, Copy, Debug)]
pub struct Flight {
    /// Where it starts, and its heading.
    pub start: Camera,
    /// Metres a frame.
    pub step: f32,
    /// Metres above the ground at the start, kept all along.
    pub height: f32,
}

impl Flight {
    /// A flight from `start` over `scene` at `speed` m/s with frames `dt` seconds apart.
    pub fn new(scene: &Scene, start: Camera, speed: f32, dt: f64) -> Self {
        let height = start.position.y - scene.ground(start.position.x, start.position.z);
        Self { start, step: speed * dt as f32, height }
    }

    /// The camera of frame `frame`: `frame` steps along the heading, `height` above the ground.
    pub fn camera(&self, scene: &Scene, frame: u32) -> Camera {
        let yaw = self.start.yaw_deg.to_radians();
        // The camera looks along -z at yaw 0, turning towards -x (`Camera::forward`).
        let heading = glam::Vec3::new(-yaw.sin(), 0.0, -yaw.cos());
        let mut position = self.start.position + heading * (self.step * frame as f32);
        position.y = scene.ground(position.x, position.z) + self.height;
        Camera { position, ..self.start }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flight_keeps_its_height_over_the_ground_and_moves_along_the_heading() {
        let scene = Scene::blocks(crate::scene::field::FieldSpec { size: None, density: 10.0 }, 1);
        let start = Camera { yaw_deg: 0.0, ..scene.default_camera() };
        let flight = Flight::new(&scene, start, 30.0, 1.0 / 60.0);
        let later = flight.camera(&scene, 120);
        let moved = later.position - start.position;
        assert!((moved.z + 60.0).abs() < 1e-3 && moved.x.abs() < 1e-3, "{moved}");
        let above = later.position.y - scene.ground(later.position.x, later.position.z);
        assert!((above - flight.height).abs() < 1e-4, "{above} against {}", flight.height);
        assert!((flight.camera(&scene, 0).position - start.position).length() < 1e-5);
    }
}
