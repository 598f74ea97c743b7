//! Free camera driven by keys and mouse: WASD + Q/E, look with the right button held, Shift
//! faster, the wheel changes speed, G walks on the ground.

use std::collections::HashSet;

use glam::Vec3;

use crate::scene::{camera::EYE_HEIGHT, Camera};

/// Keys the camera reads, by the names the help and scripts use.
pub const MOVE_KEYS: [&str; 7] = ["w", "a", "s", "d", "q", "e", "shift"];

/// Camera state and what is held down.
#[derive(Clone, Debug)]
pub struct CameraControl {
    /// The camera.
    pub camera: Camera,
    /// Metres per second.
    pub speed: f32,
    /// Keep the eye 1.7 m above the ground.
    pub walk: bool,
    held: HashSet<String>,
    looking: bool,
    last_cursor: Option<(f64, f64)>,
}

impl CameraControl {
    /// Start at `camera`.
    pub fn new(camera: Camera) -> Self {
        Self { camera, speed: 3.0, walk: false, held: HashSet::new(), looking: false, last_cursor: None }
    }

    /// A movement key went down or up; returns whether the camera uses it.
    pub fn key(&mut self, name: &str, pressed: bool) -> bool {
        if !MOVE_KEYS.contains(&name) {
            return false;
        }
        if pressed {
            self.held.insert(name.to_string());
        } else {
            self.held.remove(name);
        }
        true
    }

    /// Whether key `name` is held down.
    pub fn is_held(&self, name: &str) -> bool {
        self.held.contains(name)
    }

    /// The right button went down or up.
    pub fn look_button(&mut self, pressed: bool) {
        self.looking = pressed;
    }

    /// The cursor moved to (x, y) pixels: turns the camera while looking.
    pub fn cursor(&mut self, x: f64, y: f64) {
        if let (true, Some((lx, ly))) = (self.looking, self.last_cursor) {
            self.camera.yaw_deg -= ((x - lx) * 0.2) as f32;
            self.camera.pitch_deg = (self.camera.pitch_deg - ((y - ly) * 0.2) as f32).clamp(-89.0, 89.0);
        }
        self.last_cursor = Some((x, y));
    }

    /// Wheel: scale the speed.
    pub fn wheel(&mut self, steps: f32) {
        self.speed = (self.speed * 1.25f32.powf(steps)).clamp(0.1, 200.0);
    }

    /// Advance by `dt` seconds.
    pub fn update(&mut self, dt: f32, ground: impl Fn(f32, f32) -> f32) {
        let forward = self.camera.forward();
        let flat = Vec3::new(forward.x, 0.0, forward.z).normalize_or_zero();
        let right = flat.cross(Vec3::Y);
        let mut step = Vec3::ZERO;
        let held = |k: &str| self.held.contains(k);
        if held("w") {
            step += if self.walk { flat } else { forward };
        }
        if held("s") {
            step -= if self.walk { flat } else { forward };
        }
        if held("d") {
            step += right;
        }
        if held("a") {
            step -= right;
        }
        if held("e") {
            step += Vec3::Y;
        }
        if held("q") {
            step -= Vec3::Y;
        }
        let speed = if held("shift") { 4.0 * self.speed } else { self.speed };
        self.camera.position += step.normalize_or_zero() * speed * dt;
        if self.walk {
            let p = self.camera.position;
            self.camera.position.y = ground(p.x, p.z) + EYE_HEIGHT;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Terrain;

    #[test]
    fn keys_move_and_walk_follows_the_ground() {
        let terrain = Terrain::generate(20.0, 1);
        let mut c = CameraControl::new(Camera { position: Vec3::new(0.0, 5.0, 5.0), yaw_deg: 0.0, pitch_deg: 0.0 });
        assert!(c.key("w", true));
        assert!(!c.key("m", true));
        c.update(1.0, |x, z| terrain.height_at(x, z));
        assert!((c.camera.position.z - 2.0).abs() < 1e-4, "moved 3 m along -z");
        c.walk = true;
        c.update(0.1, |x, z| terrain.height_at(x, z));
        let p = c.camera.position;
        assert!((p.y - terrain.height_at(p.x, p.z) - EYE_HEIGHT).abs() < 1e-4);
        c.look_button(true);
        c.cursor(100.0, 100.0);
        c.cursor(110.0, 100.0);
        assert!((c.camera.yaw_deg + 2.0).abs() < 1e-4);
    }
}
