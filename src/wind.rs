//! External forces (thesis 3.2.2, 4.5, 5.1, 5.2): a global wind with gusts, point wind sources
//! (eq. 4.1) that may move, calm areas where the wind is blocked, and 3-D colliders that push
//! the part of a blade inside them. Forces are horizontal (x, z) in keyframe units: a blade of
//! stiffness 1 under a force of magnitude 1 takes the table's strongest pose. The wind field the
//! blades sample (`render::wind`) holds velocities in m/s: a force of `f` keyframe units is a wind of
//! `f · KEYFRAME_WIND_SCALE` m/s, and the `*_f64` functions are its f64 reference.

use std::f64::consts::TAU;

use glam::{DVec2, DVec3, Vec2, Vec3};

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
    /// Height above the ground in metres, where the fluid wind injects it
    /// (`DEFAULT_SOURCE_HEIGHT` unless given; the analytic and Perlin fields blow along the
    /// ground).
    pub height: f32,
}

/// A point source's height above the ground when none is given, in metres.
pub const DEFAULT_SOURCE_HEIGHT: f32 = 0.5;

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

/// A colliding object (thesis 5.2) in 3-D: an ellipsoid at a world position (its `center.y` is a
/// world height) that pushes the part of a blade inside it away from its vertical axis. Not part
/// of the wind field: each blade response takes the colliders' shapes and maps them to its own
/// input. Responses that take one force per blade (keyframes) get the reach-weighted equivalent
/// force (`blade_force`, `docs/animation.md`, "Colliders in 3-D", eq. C.1–C.4): the moment about
/// the root of the push over the blade's overlap with the ellipsoid, divided by the moment arm
/// of a uniform load over the blade. Blades that do not reach into it feel nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collider {
    /// Centre: ground position (x, z) and world height (y).
    pub center: Vec3,
    /// Radii (x, y, z); equal for a sphere.
    pub radii: Vec3,
    /// Velocity in m/s: a collider may move (its centre at time t is `center + velocity · t`).
    pub velocity: Vec3,
}

/// The keyframe force on a blade wholly inside a collider (its push per unit of blade, eq. C.2).
pub const COLLIDER_PUSH: f32 = 1.2;

/// The heights above a blade's root (0 to `height`) where its upright backbone is inside the
/// ellipsoid, and the unit push direction there (eq. C.1): `None` when the blade misses it. The
/// vertical line through the root meets the ellipsoid where (q · q) + ((y − c_y) / r_y)² ≤ 1,
/// q = (root − c)_xz / r_xz, so over c_y ± r_y √(1 − q · q).
fn overlap(center: Vec3, radii: Vec3, root: Vec3, height: f32) -> Option<(f32, f32, Vec2)> {
    let q = (Vec2::new(root.x, root.z) - Vec2::new(center.x, center.z)) / Vec2::new(radii.x, radii.z);
    let d2 = q.length_squared();
    if !(1e-12..1.0).contains(&d2) || height <= 0.0 {
        return None;
    }
    let half = radii.y * (1.0 - d2).sqrt();
    let s0 = (center.y - half - root.y).clamp(0.0, height);
    let s1 = (center.y + half - root.y).clamp(0.0, height);
    // The ellipse's outward normal in (x, z): the push direction (eq. C.1).
    let n = (q / Vec2::new(radii.x, radii.z)).normalize();
    (s1 > s0).then_some((s0, s1, n))
}

impl Collider {
    /// A collider at rest.
    pub fn at_rest(center: Vec3, radii: Vec3) -> Self {
        Self { center, radii, velocity: Vec3::ZERO }
    }

    /// Centre at time `t`.
    pub fn center_at(&self, t: f32) -> Vec3 {
        self.center + self.velocity * t
    }

    /// Centre at time `t`, in f64: what the GPU's emitters are differenced from (relative to O).
    pub fn center_f64(&self, t: f64) -> DVec3 {
        self.center.as_dvec3() + self.velocity.as_dvec3() * t
    }

    /// The reach-weighted keyframe force of a collider on a blade of backbone length `height`
    /// rooted at world `root` (eq. C.3): `COLLIDER_PUSH · n̂ · (s₁² − s₀²) / h²`, where [s₀, s₁]
    /// is the part of the upright backbone inside the ellipsoid. The CPU mirror of
    /// `collider_force` in `shaders/animation/forces.glsl`.
    pub fn blade_force(center: Vec3, radii: Vec3, root: Vec3, height: f32) -> Vec2 {
        match overlap(center, radii, root, height) {
            Some((s0, s1, n)) => n * (COLLIDER_PUSH * (s1 * s1 - s0 * s0) / (height * height)),
            None => Vec2::ZERO,
        }
    }

    /// The same force in f64 by quadrature of its definition (eq. C.2), the reference the
    /// closed form is checked against: the push density `COLLIDER_PUSH / h` at every point of the
    /// upright backbone inside the ellipsoid, its moment about the root summed over `steps`
    /// midpoints, divided by the moment arm h / 2 of a uniform load.
    pub fn blade_force_f64(&self, root: DVec3, height: f64, steps: u32) -> DVec2 {
        let (c, r) = (self.center.as_dvec3(), self.radii.as_dvec3());
        let q = DVec2::new((root.x - c.x) / r.x, (root.z - c.z) / r.z);
        if q.length_squared() < 1e-12 {
            return DVec2::ZERO;
        }
        let n = DVec2::new(q.x / r.x, q.y / r.z).normalize();
        let ds = height / f64::from(steps);
        let moment: f64 = (0..steps)
            .map(|i| (f64::from(i) + 0.5) * ds)
            .filter(|s| {
                let e = (root - c + DVec3::Y * s) / r;
                e.length_squared() < 1.0
            })
            .map(|s| f64::from(COLLIDER_PUSH) / height * s * ds)
            .sum();
        n * moment / (height / 2.0)
    }
}

/// The library's wind fields (`--wind-field`, `render::wind`): what carries these forces to the
/// blades.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FieldKind {
    /// The thesis' global wind with gusts, sources and calm areas (`analytic`).
    #[default]
    Analytic,
    /// Belyaev's three scrolling noise layers in place of the global wind (`perlin`).
    Perlin,
    /// Zhang Xia's stable-fluid grid around the camera, the analytic field past it (`fluid`).
    Fluid,
}

/// The fluid wind's grid (`--fluid-grid`, `--fluid-cell`; `render::wind::fluid`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FluidGrid {
    /// Cells per axis (x, y up, z).
    pub dims: [u32; 3],
    /// A cell's width (x and z) and height, in metres.
    pub cell: [f32; 2],
}

/// Cells per axis a fluid grid takes at least: its central differences reach two cells.
pub const MIN_FLUID_CELLS: u32 = 4;

impl Default for FluidGrid {
    fn default() -> Self {
        Self { dims: [32, 16, 32], cell: [1.0, 0.5] }
    }
}

impl FluidGrid {
    /// Refuse a grid of fewer than `MIN_FLUID_CELLS` cells on an axis, or a cell that is not a
    /// finite length above 0 (`max_dim`: the device's largest 3-D image side).
    pub fn check(&self, max_dim: u32) -> Result<(), String> {
        if let Some(n) = self.dims.iter().find(|&&n| n < MIN_FLUID_CELLS) {
            return Err(format!("a fluid grid needs at least {MIN_FLUID_CELLS} cells per axis, not {n}"));
        }
        if let Some(n) = self.dims.iter().find(|&&n| n > max_dim) {
            return Err(format!(
                "a fluid grid of {n} cells on an axis is over the device's 3-D image limit of {max_dim}"
            ));
        }
        if !self.cell.iter().all(|c| c.is_finite() && *c > 0.0) {
            return Err(format!("a fluid cell of {:?} m: each edge must be a length above 0", self.cell));
        }
        Ok(())
    }
}

impl FieldKind {
    /// Its name (`render::wind::WindField::name`, the CLI's value).
    pub fn name(self) -> &'static str {
        match self {
            FieldKind::Analytic => "analytic",
            FieldKind::Perlin => "perlin",
            FieldKind::Fluid => "fluid",
        }
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
    /// Cutters (`--cut`): colliders that push nothing but cut the blades they sweep to a stub,
    /// which regrow (`render::animation::pressed`).
    pub cuts: Vec<Collider>,
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
    /// cluster attenuation the sources too, blocked in calm areas. Colliders are not in it: the
    /// blades take them from their shapes (`Collider::blade_force`).
    pub fn corner_force(&self, p: Vec2, t: f32, attenuation: Attenuation) -> Vec2 {
        let mut wind = self.global.map_or(Vec2::ZERO, |g| g.force(p, t));
        if attenuation == Attenuation::Cluster {
            wind += self.sources_force(p, t);
        }
        wind * self.exposure(p)
    }

    /// Sum of the point sources at `p` (eq. 4.1).
    pub fn sources_force(&self, p: Vec2, t: f32) -> Vec2 {
        self.sources.iter().map(|s| PointSource::force_from(s.position_at(t), s.power, s.sigma, p)).sum()
    }

    /// The wind field at a cluster corner at world `p` and time `t` in f64, as the analytic field
    /// writes it (`render::wind::analytic`): velocity (x, z) in m/s and the exposure. With
    /// cluster attenuation the sources are in it; with delayed attenuation only the global wind
    /// (the blades add the sources). Colliders never are (`Collider::blade_force`).
    pub fn corner_velocity_f64(&self, p: DVec2, t: f64, attenuation: Attenuation) -> (DVec2, f64) {
        let exposure = if self.calm.iter().any(|c| c.contains_f64(p)) { 0.0 } else { 1.0 };
        let mut wind = self.global.map_or(DVec2::ZERO, |g| g.velocity_f64(p, t));
        if attenuation == Attenuation::Cluster {
            wind += self.sources.iter().map(|s| s.velocity_f64(p, t)).sum::<DVec2>();
        }
        (wind * exposure, exposure)
    }

    /// The true wind force at `p`: what the interpolated forces approximate (colliders apart).
    pub fn force_at(&self, p: Vec2, t: f32) -> Vec2 {
        (self.global.map_or(Vec2::ZERO, |g| g.force(p, t)) + self.sources_force(p, t)) * self.exposure(p)
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
    fn calm_areas_block_the_wind() {
        let wind = Wind {
            global: Some(GlobalWind { direction_deg: 0.0, strength: 0.5, gusts: false }),
            calm: vec![CalmArea { min: Vec2::new(-1.0, -1.0), max: Vec2::new(1.0, 1.0) }],
            ..Default::default()
        };
        assert_eq!(wind.corner_force(Vec2::new(-0.5, 0.0), 0.0, Attenuation::Cluster), Vec2::ZERO);
        assert_eq!(wind.corner_force(Vec2::new(3.0, 0.0), 0.0, Attenuation::Cluster), Vec2::new(0.5, 0.0));
    }

    #[test]
    fn a_collider_pushes_only_the_part_of_a_blade_inside_it() {
        // A sphere whose lowest point is 0.3 m above the ground at x = 0.1 m from its axis.
        let (center, radii) = (Vec3::new(0.0, 0.6, 0.0), Vec3::splat(0.3));
        let root = Vec3::new(0.1, 0.0, 0.0);
        let tall = Collider::blade_force(center, radii, root, 0.55);
        assert!(tall.x > 0.1 && tall.y.abs() < 1e-6, "{tall:?}");
        // A blade under the sphere's lowest point does not reach it; a sphere 50 m up touches nothing.
        assert_eq!(Collider::blade_force(center, radii, root, 0.29), Vec2::ZERO);
        assert_eq!(Collider::blade_force(center + Vec3::Y * 50.0, radii, root, 0.55), Vec2::ZERO);
        // Wholly inside: the push of a uniform load, COLLIDER_PUSH.
        let inside = Collider::blade_force(Vec3::new(0.0, 0.3, 0.0), Vec3::splat(2.0), root, 0.5);
        assert!((inside - Vec2::new(COLLIDER_PUSH, 0.0)).length() < 1e-6, "{inside:?}");
        // The top half of a blade carries three quarters of the moment (eq. C.3).
        let top = Collider::blade_force(Vec3::new(0.0, 1.25, 0.0), Vec3::new(20.0, 1.0, 20.0), root, 0.5);
        assert!((top.x - 0.75 * COLLIDER_PUSH).abs() < 1e-3, "{top:?}");
    }

    #[test]
    fn the_closed_form_push_matches_its_quadrature() {
        let colliders = [
            Collider::at_rest(Vec3::new(0.0, 0.6, 0.0), Vec3::splat(0.3)),
            Collider::at_rest(Vec3::new(0.3, 0.2, -0.1), Vec3::new(0.4, 0.25, 0.6)),
            Collider::at_rest(Vec3::new(100_000.2, 10.3, 5.0), Vec3::new(0.5, 0.2, 0.3)),
        ];
        let mut pushed = 0;
        for c in colliders {
            for i in 0..200 {
                let t = i as f32 / 200.0;
                let offset = Vec2::from_angle(t * 37.0) * Vec2::new(c.radii.x, c.radii.z) * t.sqrt();
                let root =
                    Vec3::new(c.center.x + offset.x, c.center.y - c.radii.y * 1.1 + t * 0.4, c.center.z + offset.y);
                let height = 0.1 + 0.5 * ((i * 7) % 11) as f32 / 11.0;
                let closed = Collider::blade_force(c.center, c.radii, root, height).as_dvec2();
                let reference = c.blade_force_f64(root.as_dvec3(), height.into(), 200_000);
                assert!((closed - reference).length() < 1e-3, "{c:?} root {root} h {height}: {closed} vs {reference}");
                pushed += usize::from(reference.length() > 0.05);
            }
        }
        assert!(pushed > 100, "{pushed} of 600 blades pushed");
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
