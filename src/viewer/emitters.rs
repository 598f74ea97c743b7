//! What the mouse and keys place in the wind: a click drops a wind source (Shift + click a
//! collider sphere) where the view ray meets the ground, the arrow keys drive a collider, and F7's
//! sphere rests on the ground under the eye, trampling the grass as the camera walks (issue #34;
//! the blades are pushed out of it, `render::animation::push_out`).

use glam::{Vec2, Vec3, Vec4};

use super::Viewer;
use crate::wind::{Collider, PointSource};

/// The radius of the spheres the arrow keys, Shift + click and F7 place, in metres.
const SPHERE_RADIUS: f32 = 0.3;

impl Viewer {
    /// An arrow key: drive the last collider a quarter metre along the view (made in front of the
    /// eye if there is none), resting on the ground.
    pub(super) fn drive_collider(&mut self, name: &str) {
        let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
        if wind.colliders.is_empty() && emitters_full(wind) {
            return;
        }
        if wind.colliders.is_empty() {
            let p = self.control.camera.position + self.control.camera.forward() * 3.0;
            let ground = self.scene.ground(p.x, p.z);
            let centre = Vec3::new(p.x, ground + SPHERE_RADIUS, p.z);
            wind.colliders.push(Collider::at_rest(centre, Vec3::splat(SPHERE_RADIUS)));
        }
        let forward = self.control.camera.forward();
        let flat = Vec3::new(forward.x, 0.0, forward.z).normalize_or_zero();
        let step = match name {
            "up" => flat,
            "down" => -flat,
            "right" => flat.cross(Vec3::Y),
            _ => -flat.cross(Vec3::Y),
        } * 0.25;
        let c = wind.colliders.last_mut().expect("one collider");
        c.center += step;
        c.center.y = self.scene.ground(c.center.x, c.center.z) + c.radii.y;
    }

    /// F7's sphere: resting on the ground under the eye, `None` when off or when the emitter
    /// buffers are full (the wind's own sources and colliders first).
    pub(super) fn trampler(&self) -> Option<Collider> {
        let wind = &self.renderer.as_ref()?.animation().wind;
        if !self.trample || full(wind) {
            return None;
        }
        let eye = self.control.camera.position;
        let ground = self.scene.ground(eye.x, eye.z);
        Some(Collider::at_rest(Vec3::new(eye.x, ground + SPHERE_RADIUS, eye.z), Vec3::splat(SPHERE_RADIUS)))
    }

    /// A script's collider: added, unless the emitter buffers are full (bad input).
    pub(super) fn add_collider(&mut self, collider: Collider) -> crate::error::Result<()> {
        let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
        if emitters_full(wind) {
            return Err(crate::error::Error::bad_input("--script: collider: the emitter buffers are full"));
        }
        wind.colliders.push(collider);
        Ok(())
    }

    /// A script's move: collider `index`'s centre at `at`, at rest (bad input if there is none).
    pub(super) fn move_collider(&mut self, index: usize, at: Vec3) -> crate::error::Result<()> {
        let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
        let count = wind.colliders.len();
        let collider = wind.colliders.get_mut(index).ok_or_else(|| {
            crate::error::Error::bad_input(format!("--script: move-collider {index}: there are {count} colliders"))
        })?;
        (collider.center, collider.velocity) = (at, Vec3::ZERO);
        Ok(())
    }

    /// Left click at a pixel: drop a wind source where the ray hits the terrain; with Shift held, a
    /// collider sphere resting on the ground there.
    pub(super) fn click(&mut self, x: f64, y: f64) {
        if let Some(hit) = self.pick(x, y) {
            let shift = self.control.is_held("shift");
            let ground = self.scene.ground(hit.x, hit.y);
            let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
            if emitters_full(wind) {
                return;
            }
            if shift {
                let centre = Vec3::new(hit.x, ground + SPHERE_RADIUS, hit.y);
                wind.colliders.push(Collider::at_rest(centre, Vec3::splat(SPHERE_RADIUS)));
                println!("collider at {:.1}, {:.1}", hit.x, hit.y);
                return;
            }
            wind.sources.push(PointSource {
                position: hit,
                power: 0.12,
                sigma: 2.0,
                velocity: Vec2::ZERO,
                height: 0.5,
            });
            self.dragging = true;
            println!("wind source at {:.1}, {:.1}", hit.x, hit.y);
        }
    }

    /// The terrain point under a pixel, marching the view ray.
    pub(super) fn pick(&self, x: f64, y: f64) -> Option<Vec2> {
        let extent = self.surface.as_ref()?.swapchain.extent;
        let ndc = Vec2::new(
            (2.0 * x / f64::from(extent.width) - 1.0) as f32,
            (2.0 * y / f64::from(extent.height) - 1.0) as f32,
        );
        let inverse = self.control.camera.view_projection(extent.width as f32 / extent.height as f32).inverse();
        let unproject = |z: f32| {
            let p = inverse * Vec4::new(ndc.x, ndc.y, z, 1.0);
            p.truncate() / p.w
        };
        // Any two depths give the ray: the picking does not depend on the drawn near plane.
        let (near, mid) = (unproject(1.0), unproject(0.5));
        let direction = (mid - near).normalize();
        // Out to the ground's extent, in steps of 5 cm near the eye that grow with the distance
        // (0.25 % of it: 2.5 m at 1 km, a pixel's footprint at the landscape camera's angle).
        let (reach, mut travelled) = (self.settings.culling.view_distance, 0.0);
        let mut p = near;
        while travelled < reach {
            let step = (0.0025 * travelled).max(0.05);
            p += direction * step;
            travelled += step;
            if p.y <= self.scene.ground(p.x, p.z) {
                return Some(Vec2::new(p.x, p.z));
            }
        }
        None
    }
}

/// Whether the emitter buffers hold no more sources or colliders, or the pressed map's sweeps no
/// more colliders and cuts.
fn full(wind: &crate::wind::Wind) -> bool {
    use crate::render::animation::{pressed::MAX_SWEEPS, MAX_COLLIDERS, MAX_SOURCES};
    wind.sources.len() >= MAX_SOURCES
        || wind.colliders.len() >= MAX_COLLIDERS
        || wind.colliders.len() + wind.cuts.len() >= MAX_SWEEPS
}

/// `full`, saying so when it is.
pub(super) fn emitters_full(wind: &crate::wind::Wind) -> bool {
    let full = full(wind);
    if full {
        use crate::render::animation::{pressed::MAX_SWEEPS, MAX_COLLIDERS, MAX_SOURCES};
        println!("at most {MAX_SOURCES} sources, {MAX_COLLIDERS} colliders and {MAX_SWEEPS} colliders and cuts");
    }
    full
}
