//! External forces (thesis 3.2.2, 4.5, 5.1, 5.2): a global wind with gusts, point wind sources
//! (eq. 4.1) that may move, calm areas where the wind is blocked, and colliders acting as
//! concentrated local wind. Forces are horizontal (x, z) in keyframe units: a blade of stiffness
//! 1 under a force of magnitude 1 takes the table's strongest pose. The wind field the blades
//! sample (`render::wind`) holds velocities in m/s: a force of `f` keyframe units is a wind of
//! `f · KEYFRAME_WIND_SCALE` m/s, and the `*_f64` functions are its f64 reference.

use std::f64::consts::TAU;

use glam::{DVec2, Vec2, Vec3};

/// Metres per second of wind per keyframe force unit: the fixed scale between the wind field's
/// velocities and the keyframes' input (|f| = 1, the table's strongest pose, is 8 m/s, a fresh
/// breeze). A power of two, so the mapping both ways is exact in floating point.
pub const KEYFRAME_WIND_SCALE: f32 = 8.0;

/// The gusts' four travelling waves (`GlobalWind::force`), each (a, b, ω, c): phase
/// θ = a (p · dir) + b (p · dir⊥) − ω t + c. Waves 0–2 are the gust fronts, wave 3 the swirl.
const GUST_WAVES: [[f64; 4]; 4] =
    [[0.35, 0.0, 1.7, 0.0], [0.9, 0.5, 3.1, 1.3], [2.1, -0.8, 5.3, 4.0], [0.0, 0.4, 0.9, 0.0]];

/// Closest distance (metres) at which eq. 4.1 is evaluated, so a blade at a source is finite.
pub const MIN_SOURCE_DISTANCE: f32 = 0.05;

/// Wind blowing over the whole field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlobalWind {
    /// Direction the wind blows towards, degrees from +x towards +z.
    pub direction_deg: f32,
    /// Mean force magnitude.
    pub strength: f32,
    /// Gust fronts travelling with the wind (varying in time and space).
    pub gusts: bool,
}

impl GlobalWind {
    /// Unit direction.
    pub fn direction(&self) -> Vec2 {
        let a = self.direction_deg.to_radians();
        Vec2::new(a.cos(), a.sin())
    }

    /// Force at `p` at time `t`: the mean wind scaled by gust fronts, three travelling waves
    /// along and slightly across the wind.
    pub fn force(&self, p: Vec2, t: f32) -> Vec2 {
        let dir = self.direction();
        if !self.gusts {
            return dir * self.strength;
        }
        let along = p.dot(dir);
        let across = p.dot(dir.perp());
        let gust = 0.55 * (0.35 * along - 1.7 * t).sin()
            + 0.30 * (0.9 * along + 0.5 * across - 3.1 * t + 1.3).sin()
            + 0.15 * (2.1 * along - 0.8 * across - 5.3 * t + 4.0).sin();
        let swirl = 0.12 * (0.4 * across - 0.9 * t).sin();
        let d = Vec2::new(dir.x - swirl * dir.y, dir.y + swirl * dir.x).normalize();
        d * self.strength * (1.0 + 0.45 * gust)
    }

    /// Unit direction in f64.
    pub fn direction_f64(&self) -> DVec2 {
        let a = f64::from(self.direction_deg).to_radians();
        DVec2::new(a.cos(), a.sin())
    }

    /// The four waves' vectors (rad/m, x and z): θ_k = k_k · p − ω_k t + c_k.
    pub fn wave_vectors(&self) -> [DVec2; 4] {
        let dir = self.direction_f64();
        GUST_WAVES.map(|[a, b, _, _]| dir * a + dir.perp() * b)
    }

    /// The four waves' phases at world point `origin` and time `t`, in [0, 2π), in f64: the GPU
    /// adds k_k · (p − O) in f32, so a field far from the world's origin is as exact as at it
    /// (as `scene::field::Relief::phases` does for the relief).
    pub fn phases(&self, origin: DVec2, t: f64) -> [f64; 4] {
        let k = self.wave_vectors();
        std::array::from_fn(|i| (k[i].dot(origin) - GUST_WAVES[i][2] * t + GUST_WAVES[i][3]).rem_euclid(TAU))
    }

    /// The wind at world `p` and time `t` in m/s, in f64: the reference of the GPU's field.
    pub fn velocity_f64(&self, p: DVec2, t: f64) -> DVec2 {
        let dir = self.direction_f64();
        let speed = f64::from(self.strength) * f64::from(KEYFRAME_WIND_SCALE);
        if !self.gusts {
            return dir * speed;
        }
        let theta = self.phases(p, t);
        let gust = 0.55 * theta[0].sin() + 0.30 * theta[1].sin() + 0.15 * theta[2].sin();
        let swirl = 0.12 * theta[3].sin();
        (dir + dir.perp() * swirl).normalize() * speed * (1.0 + 0.45 * gust)
    }
}

/// A point wind source (eq. 4.1): `wind = normalise(WP) · ω / |WP|^σ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSource {
    /// Position at time 0 (x, z).
    pub position: Vec2,
    /// Emissive power ω.
    pub power: f32,
    /// Concentration σ (higher: more local).
    pub sigma: f32,
    /// Velocity in m/s: sources may move over time.
    pub velocity: Vec2,
}

impl PointSource {
    /// Position at time `t`.
    pub fn position_at(&self, t: f32) -> Vec2 {
        self.position + self.velocity * t
    }

    /// Eq. 4.1 at `p` for a source at `w`.
    pub fn force_from(w: Vec2, power: f32, sigma: f32, p: Vec2) -> Vec2 {
        let wp = p - w;
        let d = wp.length();
        if d < 1e-6 {
            return Vec2::ZERO;
        }
        wp / d * power / d.max(MIN_SOURCE_DISTANCE).powf(sigma)
    }

    /// Position at time `t`, in f64.
    pub fn position_f64(&self, t: f64) -> DVec2 {
        self.position.as_dvec2() + self.velocity.as_dvec2() * t
    }

    /// Eq. 4.1 in m/s and f64: the reference of the GPU's field.
    pub fn velocity_f64(&self, p: DVec2, t: f64) -> DVec2 {
        let wp = p - self.position_f64(t);
        let d = wp.length();
        if d < 1e-6 {
            return DVec2::ZERO;
        }
        let scale = f64::from(self.power) * f64::from(KEYFRAME_WIND_SCALE);
        wp / d * scale / d.max(f64::from(MIN_SOURCE_DISTANCE)).powf(f64::from(self.sigma))
    }
}

/// A rectangle where the wind is blocked (thesis 5.1): cluster corners inside get no wind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CalmArea {
    /// Corner with the smaller coordinates.
    pub min: Vec2,
    /// Corner with the larger coordinates.
    pub max: Vec2,
}

impl CalmArea {
    /// Whether `p` lies inside (edges included).
    pub fn contains(&self, p: Vec2) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Whether `p` lies inside, in f64.
    pub fn contains_f64(&self, p: DVec2) -> bool {
        p.cmpge(self.min.as_dvec2()).all() && p.cmple(self.max.as_dvec2()).all()
    }
}

/// A colliding object as concentrated local wind (thesis 5.2): blades are pushed away from its
/// centre, most strongly near its surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collider {
    /// Centre.
    pub center: Vec3,
    /// Radii (x, y, z); equal for a sphere.
    pub radii: Vec3,
}

/// Force at the surface of a collider, and the falloff exponent beyond it.
pub const COLLIDER_PUSH: f32 = 1.2;
/// Concentration of the collision force (σ of eq. 4.1 in ellipsoid units).
pub const COLLIDER_SIGMA: f32 = 3.0;

impl Collider {
    /// Push at ground point `p`: eq. 4.1 in the collider's scaled space, with the power set so
    /// the push is `COLLIDER_PUSH` at the surface and flat inside it.
    pub fn force(center: Vec2, radii: Vec2, p: Vec2) -> Vec2 {
        let q = (p - center) / radii;
        let d = q.length();
        if d < 1e-6 {
            return Vec2::ZERO;
        }
        let direction = (q / radii).normalize();
        direction * COLLIDER_PUSH / d.max(1.0).powf(COLLIDER_SIGMA)
    }

    /// The push at ground point `p` in m/s and f64: the reference of the GPU's field.
    pub fn velocity_f64(&self, p: DVec2) -> DVec2 {
        let (center, radii) = (
            DVec2::new(self.center.x.into(), self.center.z.into()),
            DVec2::new(self.radii.x.into(), self.radii.z.into()),
        );
        let q = (p - center) / radii;
        let d = q.length();
        if d < 1e-6 {
            return DVec2::ZERO;
        }
        let push = f64::from(COLLIDER_PUSH) * f64::from(KEYFRAME_WIND_SCALE);
        (q / radii).normalize() * push / d.max(1.0).powf(f64::from(COLLIDER_SIGMA))
    }
}

/// Where source magnitudes are attenuated (thesis 4.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Attenuation {
    /// Sources evaluated at cluster corners and interpolated like the global wind.
    #[default]
    Cluster,
    /// Delayed attenuation: sources and colliders evaluated per blade in the shader from their
    /// positions; corners carry the global wind and the calm mask only.
    Blade,
}

/// Every external force of the scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Wind {
    /// Global wind, if any.
    pub global: Option<GlobalWind>,
    /// Point sources.
    pub sources: Vec<PointSource>,
    /// Calm areas.
    pub calm: Vec<CalmArea>,
    /// Colliders.
    pub colliders: Vec<Collider>,
}

impl Wind {
    /// 0 inside a calm area, 1 elsewhere.
    pub fn exposure(&self, p: Vec2) -> f32 {
        if self.calm.iter().any(|c| c.contains(p)) {
            0.0
        } else {
            1.0
        }
    }

    /// The part of the force interpolated from cluster corners: the global wind, and with
    /// cluster attenuation the sources and colliders too. Calm areas block wind, not colliders.
    pub fn corner_force(&self, p: Vec2, t: f32, attenuation: Attenuation) -> Vec2 {
        let exposure = self.exposure(p);
        let mut wind = self.global.map_or(Vec2::ZERO, |g| g.force(p, t));
        let mut push = Vec2::ZERO;
        if attenuation == Attenuation::Cluster {
            wind += self.sources_force(p, t);
            push = self.colliders_force(p);
        }
        wind * exposure + push
    }

    /// Sum of the point sources at `p` (eq. 4.1).
    pub fn sources_force(&self, p: Vec2, t: f32) -> Vec2 {
        self.sources.iter().map(|s| PointSource::force_from(s.position_at(t), s.power, s.sigma, p)).sum()
    }

    /// Sum of the collider pushes at `p`.
    pub fn colliders_force(&self, p: Vec2) -> Vec2 {
        self.colliders
            .iter()
            .map(|c| Collider::force(Vec2::new(c.center.x, c.center.z), Vec2::new(c.radii.x, c.radii.z), p))
            .sum()
    }

    /// The wind field at a cluster corner at world `p` and time `t` in f64, as the analytic field
    /// writes it (`render::wind::analytic`): velocity (x, z) in m/s and the exposure. With
    /// cluster attenuation the sources and colliders are in it; with delayed attenuation only
    /// the global wind (the blades add the rest).
    pub fn corner_velocity_f64(&self, p: DVec2, t: f64, attenuation: Attenuation) -> (DVec2, f64) {
        let exposure = if self.calm.iter().any(|c| c.contains_f64(p)) { 0.0 } else { 1.0 };
        let mut wind = self.global.map_or(DVec2::ZERO, |g| g.velocity_f64(p, t));
        let mut push = DVec2::ZERO;
        if attenuation == Attenuation::Cluster {
            wind += self.sources.iter().map(|s| s.velocity_f64(p, t)).sum::<DVec2>();
            push = self.colliders.iter().map(|c| c.velocity_f64(p)).sum();
        }
        (wind * exposure + push, exposure)
    }

    /// The true force at `p`: what the interpolated forces approximate.
    pub fn force_at(&self, p: Vec2, t: f32) -> Vec2 {
        (self.global.map_or(Vec2::ZERO, |g| g.force(p, t)) + self.sources_force(p, t)) * self.exposure(p)
            + self.colliders_force(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq_4_1_points_away_and_falls_with_distance() {
        let w = Vec2::ZERO;
        let near = PointSource::force_from(w, 1.0, 2.0, Vec2::new(1.0, 0.0));
        let far = PointSource::force_from(w, 1.0, 2.0, Vec2::new(2.0, 0.0));
        assert!((near - Vec2::new(1.0, 0.0)).length() < 1e-6);
        assert!((far - Vec2::new(0.25, 0.0)).length() < 1e-6);
    }

    #[test]
    fn calm_areas_block_wind_but_not_colliders() {
        let wind = Wind {
            global: Some(GlobalWind { direction_deg: 0.0, strength: 0.5, gusts: false }),
            calm: vec![CalmArea { min: Vec2::new(-1.0, -1.0), max: Vec2::new(1.0, 1.0) }],
            colliders: vec![Collider { center: Vec3::new(0.5, 0.0, 0.0), radii: Vec3::splat(0.2) }],
            ..Default::default()
        };
        let inside = Vec2::new(-0.5, 0.0);
        assert_eq!(wind.corner_force(inside, 0.0, Attenuation::Cluster), wind.colliders_force(inside));
        assert!(wind.corner_force(Vec2::new(0.75, 0.0), 0.0, Attenuation::Cluster).x > 0.3);
        assert!((wind.corner_force(Vec2::new(3.0, 0.0), 0.0, Attenuation::Cluster).x - 0.5).abs() < 0.01);
    }

    #[test]
    fn gusts_vary_in_time_and_space_around_the_mean() {
        let g = GlobalWind { direction_deg: 90.0, strength: 1.0, gusts: true };
        let a = g.force(Vec2::ZERO, 0.0);
        let b = g.force(Vec2::ZERO, 1.0);
        let c = g.force(Vec2::new(0.0, 5.0), 0.0);
        assert!(a != b && a != c);
        for f in [a, b, c] {
            assert!(f.y > 0.3 && f.length() < 1.6, "{f:?}");
        }
    }
}
