//! The analytic wind field: the thesis' global wind with gusts, moving point sources (eq. 4.1),
//! calm areas (5.1) and colliders (5.2), at the cluster corners (3.2.2), in m/s. With the cull it
//! is evaluated on the GPU each step by `corners_pass::AnalyticCornersPass` from a small
//! parameter block (`Params`) the CPU fills per frame: the gusts' wave phases at the frame's O
//! taken in f64 (`wind::GlobalWind::phases`, as `scene::field::Relief::phases` does for the
//! relief), so the GPU adds only k · (p − O) in f32 and a field 100 km from the origin is as exact
//! as at it; the calm areas, sources and colliders relative to O, also differenced in f64. With
//! `--brute-force` the CPU writes the corners as the thesis did
//! (`render::animation::corner_forces_at`). Both attenuations (4.5) are options: with delayed
//! attenuation the corners carry the global wind and the exposure only.

use std::cell::RefCell;
use std::rc::Rc;

use bytemuck::Zeroable;
use glam::{DVec2, Vec4};

use super::corners_pass::{AnalyticCornersPass, CornerVariant};
pub use super::params::{Params, MAX_CALM_AREAS};
use super::{WindField, WindInput, WindSetup};
use crate::error::Result;
use crate::render::animation;
use crate::render::graph::Pass;
use crate::render::wind::FrameForces;
use crate::vk::Device;
use crate::wind::Wind;

/// The emitters of a frame relative to `origin`, differenced in f64: point sources at their
/// positions at `time` as (x, z, power, sigma), then each collider as two elements, its centre at
/// `time` (x, y, z, 0; y a world height) and its radii (x, y, z, 0); the first `MAX_SOURCES` sources and `MAX_COLLIDERS` colliders
/// (`animation::emitter_counts`); then from `collider_bins::COLLIDER_BINS` the colliders binned
/// over the ground (`animation::collider_bins`).
pub fn emitters_relative(wind: &Wind, origin: DVec2, time: f64) -> Vec<Vec4> {
    let relative = |p: DVec2| (p - origin).as_vec2();
    let (sources, colliders) = animation::emitter_counts(wind);
    let mut out: Vec<Vec4> = wind
        .sources
        .iter()
        .take(sources as usize)
        .map(|s| relative(s.position_f64(time)).extend(s.power).extend(s.sigma))
        .chain(wind.colliders.iter().take(colliders as usize).flat_map(|c| {
            let at = c.center_f64(time);
            let centre = relative(DVec2::new(at.x, at.z));
            [Vec4::new(centre.x, at.y as f32, centre.y, 0.0), c.radii.extend(0.0)]
        }))
        .collect();
    animation::collider_bins::append(&mut out, sources as usize);
    out
}

/// The analytic wind field. Its pass reads the parameters `update` leaves for the frame.
pub struct AnalyticWind {
    params: Rc<RefCell<Params>>,
}

impl Default for AnalyticWind {
    fn default() -> Self {
        Self { params: Rc::new(RefCell::new(Zeroable::zeroed())) }
    }
}

impl AnalyticWind {
    /// A field with no frame written yet.
    pub fn new() -> Self {
        Self::default()
    }
}

impl WindField for AnalyticWind {
    fn name(&self) -> &'static str {
        "analytic"
    }

    fn update(&self, forces: &mut FrameForces, input: &WindInput) {
        forces.emitters.write(0, &emitters_relative(input.wind, input.origin, input.time));
        if input.cpu_corners {
            // The thesis' path, in f32 as it computed it (3.2.2).
            let origin = input.origin.as_vec2();
            let time = input.time as f32;
            let corners = animation::corner_forces_at(input.grid, origin, input.wind, time, input.attenuation);
            forces.corners.write(0, &corners);
        } else {
            *self.params.borrow_mut() = Params::new(input);
        }
    }

    fn passes(&self, device: &Device, setup: &WindSetup) -> Result<Vec<Box<dyn Pass>>> {
        Ok(vec![Box::new(AnalyticCornersPass::new(device, setup, self.params.clone(), CornerVariant::Analytic)?)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::clusters::ClusterGrid;
    use crate::wind::{Attenuation, CalmArea, GlobalWind};
    use glam::Vec2;

    #[test]
    fn calm_areas_and_phases_are_relative_to_the_origin() {
        let wind = Wind {
            global: Some(GlobalWind { direction_deg: 30.0, strength: 0.5, gusts: true }),
            calm: vec![CalmArea { min: Vec2::new(100_000.0, 4.0), max: Vec2::new(100_002.0, 6.0) }],
            ..Default::default()
        };
        let grid = ClusterGrid::new(8.0, 1.0);
        let origin = DVec2::new(100_000.0, 0.0);
        let input = WindInput {
            grid: &grid,
            levels: 1,
            wind: &wind,
            attenuation: Attenuation::Cluster,
            time: 2.0,
            origin,
            cpu_corners: false,
            camera: glam::DVec3::ZERO,
            dt: 1.0 / 60.0,
            ground: None,
        };
        let params = Params::new(&input);
        assert_eq!(params.calm[0], [0.0, 4.0, 2.0, 6.0]);
        assert_eq!(params.counts, [0, 0, 1, 0]);
        let phases = wind.global.expect("global").phases(origin, 2.0);
        assert_eq!(params.phases, phases.map(|p| p as f32));
        assert!(params.phases.iter().all(|p| (0.0..std::f32::consts::TAU + 1e-6).contains(p)));
        assert_eq!(params.global[2], 4.0, "0.5 keyframe units are 4 m/s");
    }
}
