//! The fluid wind's scheme on the CPU: the reference the GPU's steps (`shaders/wind/fluid.comp`,
//! `shaders/wind/fluid.glsl`) are tested against, line for line, in the window's local cells
//! (the GPU's toroidal slots are an addressing of the same cells). It reads the frame's
//! [`Params`], as the GPU does. One step (Zhang Xia §2, after Stam 1999): the sources, calm areas
//! and colliders (f of eq. 2), `DIFFUSE_ITERATIONS` Jacobi iterations of eq. 4, the
//! semi-Lagrangian self-advection (§2.3.3), the divergence and the pressure's
//! `pressure_iterations` weighted Jacobi iterations on (D G) p = D u, and the projection (§2.3.6).

use glam::{IVec3, Vec2, Vec3};

use super::{CALM_DAMPING, DIFFUSE_ITERATIONS, SOURCE_RADIUS, SOURCE_TIME};
use crate::render::wind::params::Params;

/// A grid's velocities (m/s) and pressures, local cells x fastest, then y, then z.
#[derive(Clone, Debug)]
pub struct FluidState {
    /// Cells per axis.
    pub dims: IVec3,
    /// Velocity per cell.
    pub velocity: Vec<Vec3>,
    /// Pressure per cell (the next step's first guess).
    pub pressure: Vec<f32>,
}

/// What one frame's parameters say about the grid: its shape, faces and cells.
struct Frame<'a> {
    p: &'a Params,
    dims: IVec3,
    h: Vec3,
}

impl Frame<'_> {
    fn index(&self, c: IVec3) -> usize {
        ((c.z * self.dims.y + c.y) * self.dims.x + c.x) as usize
    }

    fn centre(&self, c: IVec3) -> Vec3 {
        let q = (c.as_vec3() + 0.5) * self.h;
        Vec3::new(self.p.fluid_corner[0] + q.x, q.y, self.p.fluid_corner[1] + q.z)
    }

    /// `fluid_analytic`: the global wind at the cell's centre.
    fn analytic(&self, c: IVec3) -> Vec3 {
        let g = self.p.global;
        if g[3] < 0.5 {
            return Vec3::ZERO;
        }
        let v = global_wind(
            self.p,
            {
                let q = self.centre(c);
                Vec2::new(q.x, q.z)
            },
            g[3] > 1.5,
        );
        Vec3::new(v.x, 0.0, v.y)
    }

    fn upwind(&self, c: IVec3) -> bool {
        let (d, faces) = (self.dims, self.p.fluid_dims[3]);
        (c.x < 0 && faces & 1 != 0)
            || (c.x >= d.x && faces & 2 != 0)
            || (c.z < 0 && faces & 4 != 0)
            || (c.z >= d.z && faces & 8 != 0)
    }

    fn inside(&self, c: IVec3) -> (IVec3, bool) {
        let d = self.dims;
        let mirrored = c.y < 0 || c.y >= d.y;
        let y = if c.y < 0 {
            -1 - c.y
        } else if c.y >= d.y {
            2 * d.y - 1 - c.y
        } else {
            c.y
        };
        (IVec3::new(c.x, y, c.z).clamp(IVec3::ZERO, d - 1), mirrored)
    }

    fn velocity(&self, src: &[Vec3], c: IVec3) -> Vec3 {
        if self.upwind(c) {
            return self.analytic(c);
        }
        let (r, mirrored) = self.inside(c);
        let v = src[self.index(r)];
        if mirrored {
            Vec3::new(v.x, -v.y, v.z)
        } else {
            v
        }
    }

    fn sample(&self, src: &[Vec3], g: Vec3) -> Vec3 {
        let i = g.floor();
        let f = g - i;
        let c = i.as_ivec3();
        let v = |dx, dy, dz| self.velocity(src, c + IVec3::new(dx, dy, dz));
        let x00 = v(0, 0, 0).lerp(v(1, 0, 0), f.x);
        let x10 = v(0, 1, 0).lerp(v(1, 1, 0), f.x);
        let x01 = v(0, 0, 1).lerp(v(1, 0, 1), f.x);
        let x11 = v(0, 1, 1).lerp(v(1, 1, 1), f.x);
        x00.lerp(x10, f.y).lerp(x01.lerp(x11, f.y), f.z)
    }

    fn pressure_at(&self, p: &[f32], c: IVec3, centre: Option<IVec3>) -> f32 {
        let d = self.dims;
        let outside = c.x < 0 || c.z < 0 || c.x >= d.x || c.z >= d.z;
        if outside && !self.upwind(c) {
            return 0.0;
        }
        let r = c.clamp(IVec3::ZERO, d - 1);
        match centre {
            Some(centre) => f32::from(u8::from(r == centre)),
            None => p[self.index(r)],
        }
    }

    fn gradient_inside(&self, p: &[f32], c: IVec3, centre: Option<IVec3>) -> Vec3 {
        let at = |e: IVec3| self.pressure_at(p, c + e, centre) - self.pressure_at(p, c - e, centre);
        Vec3::new(at(IVec3::X), at(IVec3::Y), at(IVec3::Z)) / (2.0 * self.h)
    }

    fn gradient_at(&self, p: &[f32], c: IVec3, centre: Option<IVec3>) -> Vec3 {
        if self.upwind(c) {
            return Vec3::ZERO;
        }
        let (r, mirrored) = self.inside(c);
        let g = self.gradient_inside(p, r, centre);
        if mirrored {
            Vec3::new(g.x, -g.y, g.z)
        } else {
            g
        }
    }

    fn laplacian(&self, p: &[f32], c: IVec3, delta: bool) -> f32 {
        let centre = delta.then_some(c);
        let h = self.h;
        let g = |e: IVec3| self.gradient_at(p, c + e, centre) - self.gradient_at(p, c - e, centre);
        g(IVec3::X).x / (2.0 * h.x) + g(IVec3::Y).y / (2.0 * h.y) + g(IVec3::Z).z / (2.0 * h.z)
    }

    /// D u at `c`, the solver's divergence.
    fn divergence(&self, src: &[Vec3], c: IVec3) -> f32 {
        let h = self.h;
        let v = |e: IVec3| self.velocity(src, c + e) - self.velocity(src, c - e);
        v(IVec3::X).x / (2.0 * h.x) + v(IVec3::Y).y / (2.0 * h.y) + v(IVec3::Z).z / (2.0 * h.z)
    }

    fn solid(&self, c: IVec3) -> bool {
        let p = self.centre(c);
        (0..self.p.fluid_counts[1] as usize).any(|i| {
            let (centre, radii) = (self.p.fluid_colliders[2 * i], self.p.fluid_colliders[2 * i + 1]);
            let q = (p - Vec3::from_slice(&centre[..3])) / Vec3::from_slice(&radii[..3]);
            q.dot(q) <= 1.0
        })
    }

    fn forced(&self, c: IVec3, mut u: Vec3) -> Vec3 {
        let p = self.centre(c);
        let dt = self.p.fluid_cell[3];
        for s in &self.p.fluid_sources[..self.p.fluid_counts[0] as usize] {
            let r = p - Vec3::new(s[0], s[2], s[1]);
            let g = (-r.dot(r) / (2.0 * SOURCE_RADIUS * SOURCE_RADIUS)).exp();
            u += (dt / SOURCE_TIME).min(1.0) * g * (Vec3::new(0.0, -s[3], 0.0) - u);
        }
        for a in &self.p.calm[..self.p.counts[2] as usize] {
            if p.x >= a[0] && p.z >= a[1] && p.x <= a[2] && p.z <= a[3] {
                u *= (-dt * CALM_DAMPING).exp();
            }
        }
        if self.solid(c) {
            Vec3::ZERO
        } else {
            u
        }
    }

    fn cells(&self) -> impl Iterator<Item = IVec3> + '_ {
        let d = self.dims;
        (0..d.z).flat_map(move |z| (0..d.y).flat_map(move |y| (0..d.x).map(move |x| IVec3::new(x, y, z))))
    }

    fn map(&self, f: impl Fn(IVec3) -> Vec3) -> Vec<Vec3> {
        self.cells().map(f).collect()
    }
}

/// `global_wind` of `shaders/wind/analytic.glsl` at `q` (relative to O) from the frame's
/// parameters: the gusts' waves at their phases.
pub fn global_wind(p: &Params, q: Vec2, gusts: bool) -> Vec2 {
    let direction = Vec2::new(p.global[0], p.global[1]);
    let speed = p.global[2];
    if !gusts {
        return direction * speed;
    }
    let w = [Vec2::new(p.waves[0][0], p.waves[0][1]), Vec2::new(p.waves[0][2], p.waves[0][3])];
    let w2 = [Vec2::new(p.waves[1][0], p.waves[1][1]), Vec2::new(p.waves[1][2], p.waves[1][3])];
    let theta = [w[0].dot(q), w[1].dot(q), w2[0].dot(q), w2[1].dot(q)];
    let s: Vec<f32> = theta.iter().zip(p.phases).map(|(t, ph)| (ph + t).sin()).collect();
    let gust = 0.55 * s[0] + 0.30 * s[1] + 0.15 * s[2];
    let swirl = 0.12 * s[3];
    let d = Vec2::new(direction.x - swirl * direction.y, direction.y + swirl * direction.x).normalize();
    d * speed * (1.0 + 0.45 * gust)
}

impl FluidState {
    /// A grid filled as cells that enter it are: the analytic wind, no pressure.
    pub fn entered(p: &Params) -> Self {
        let dims = IVec3::new(p.fluid_dims[0] as i32, p.fluid_dims[1] as i32, p.fluid_dims[2] as i32);
        let frame = Frame { p, dims, h: Vec3::from_slice(&p.fluid_cell[..3]) };
        let velocity = frame.map(|c| frame.analytic(c));
        Self { dims, pressure: vec![0.0; velocity.len()], velocity }
    }

    /// One step under the frame's parameters `p`.
    pub fn step(&mut self, p: &Params) {
        let frame = Frame { p, dims: self.dims, h: Vec3::from_slice(&p.fluid_cell[..3]) };
        let forced = frame.map(|c| frame.forced(c, self.velocity[frame.index(c)]));
        let a = Vec3::from_slice(&p.fluid_coef[..3]);
        let mut x = forced.clone();
        for _ in 0..DIFFUSE_ITERATIONS {
            x = frame.map(|c| {
                let v = |e: IVec3| frame.velocity(&x, c + e) + frame.velocity(&x, c - e);
                let sum = a.x * v(IVec3::X) + a.y * v(IVec3::Y) + a.z * v(IVec3::Z);
                (forced[frame.index(c)] + sum) / (1.0 + 2.0 * (a.x + a.y + a.z))
            });
        }
        let dt = p.fluid_cell[3];
        let advected = frame.map(|c| {
            let back = c.as_vec3() - dt * x[frame.index(c)] / frame.h;
            frame.sample(&x, back.clamp(Vec3::splat(-1.0), self.dims.as_vec3()))
        });
        self.project(&frame, advected, p.fluid_base[3]);
    }

    fn project(&mut self, frame: &Frame, u: Vec<Vec3>, iterations: u32) {
        let div: Vec<f32> = frame.cells().map(|c| frame.divergence(&u, c)).collect();
        let diag: Vec<f32> = frame.cells().map(|c| frame.laplacian(&[], c, true)).collect();
        for k in 0..iterations {
            let weight = super::pressure_weight(k);
            let p = &self.pressure;
            let next: Vec<f32> = frame
                .cells()
                .map(|c| {
                    let i = frame.index(c);
                    p[i] + weight * (div[i] - frame.laplacian(p, c, false)) / diag[i]
                })
                .collect();
            self.pressure = next;
        }
        let p = &self.pressure;
        self.velocity = frame.map(|c| {
            let v = u[frame.index(c)] - frame.gradient_inside(p, c, None);
            if frame.solid(c) {
                Vec3::ZERO
            } else {
                v
            }
        });
    }

    /// The RMS of the solver's divergence D u over the grid's cells under `p`'s boundaries.
    pub fn rms_divergence(&self, p: &Params) -> f32 {
        let frame = Frame { p, dims: self.dims, h: Vec3::from_slice(&p.fluid_cell[..3]) };
        let sum: f32 = frame.cells().map(|c| frame.divergence(&self.velocity, c).powi(2)).sum();
        (sum / self.velocity.len() as f32).sqrt()
    }

    /// The velocity of local cell `c`.
    pub fn at(&self, c: IVec3) -> Vec3 {
        self.velocity[((c.z * self.dims.y + c.y) * self.dims.x + c.x) as usize]
    }
}

/// The projection alone, for the tests of the solver: `state`'s velocities made divergence-free
/// by `iterations` Jacobi iterations from zero pressure; the RMS divergence before and after.
pub fn project_only(state: &mut FluidState, p: &Params, iterations: u32) -> (f32, f32) {
    let before = state.rms_divergence(p);
    let frame = Frame { p, dims: state.dims, h: Vec3::from_slice(&p.fluid_cell[..3]) };
    state.pressure.fill(0.0);
    let u = state.velocity.clone();
    state.project(&frame, u, iterations);
    (before, state.rms_divergence(p))
}
