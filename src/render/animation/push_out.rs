//! Push-out (Zhang Xia §6.2, issue #34): blades whose roots lie inside a collider's ground circle
//! are pushed out of it. A pass of the renderer's, after whichever blade response wrote the pose
//! records (`shaders/animation/push_out.comp`, the walk in `shaders/animation/push_out.glsl`), over
//! the same blades as the response's pose passes; so it works for every response that writes pose
//! records, stateless (keyframes, sine) and stateful (Verlet, the chains; their state is not
//! moved: the drawn blade is). A per-vertex response (`--eval vertex`) writes no records: there
//! the colliders act through their force alone.
//!
//! The walk, per collider whose ground circle holds the root (step 2): from the root up, the first
//! backbone point inside the collider goes onto its surface (step 3) and the segments above follow
//! the direction from the point below to it (step 4). meadow keeps each segment's length and puts
//! a point that would enter again onto the surface at its segment's length from the point below
//! ([`push_out`], the CPU mirror). A blade no circle holds is left to the bit.
//!
//! The pass is in every graph whose response writes pose records (the viewer adds colliders to a
//! running renderer) and declares nothing on a frame with no collider, so it costs nothing there.

use std::cell::Cell;
use std::rc::Rc;

use ash::vk;
use glam::Vec3;

use crate::error::Result;
use crate::render::animation::patches::PatchClock;
use crate::render::animation::pose_pass::{PosePass, PoseShader, PoseUniforms};
use crate::render::animation::pressed::MapReader;
use crate::render::animation::response::ResponseSetup;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::shaders;
use crate::vk::{Access, Device, Resource};

/// The push-out pass: a pose pass of its own shader that reads and writes the records, with a
/// step before it that empties the patch list (and, on its first frame or after a dropped one,
/// clears the patches' store).
pub struct PushOutPass {
    inner: PosePass,
    map: MapReader,
    /// `--debug-view pressed` or `patches`: recorded every frame, to colour every blade.
    shows_map: bool,
    /// The interaction patches' steps, shared with the patch pass.
    patches: Rc<PatchClock>,
    /// Whether a submitted frame has cleared the patches' store.
    cleared: Cell<bool>,
}

impl PushOutPass {
    /// Build it over the blades `setup`'s pose passes cover, on its records, reading `map`, listing
    /// the blades to patch by `patches`.
    pub fn new(device: &Device, setup: &ResponseSetup, map: MapReader, patches: Rc<PatchClock>) -> Result<Self> {
        let (reader, clock) = (map.clone(), patches.clone());
        let frame = PoseUniforms {
            name: "PressedFrame",
            size: MapReader::FRAME_BYTES,
            control: None,
            fill: Box::new(move |ctx| {
                reader.frame_bytes(clock.frame(ctx.clock.index, ctx.clock.time, ctx.uniforms.wind_counts.y))
            }),
        };
        let mut resources = vec![map.resource()];
        resources.extend(map.patches_resources());
        let shader = PoseShader {
            name: "push-out",
            spirv: shaders::PUSH_OUT_COMP.code(device.profile),
            resources,
            uses: vec![
                (Resource::Buffer(setup.poses.1), Access::ComputeShaderRead),
                (Resource::Buffer(map.cells), Access::ComputeShaderRead),
                (Resource::Buffer(map.patches), Access::ComputeShaderRead),
                (Resource::Buffer(map.patch_list), Access::ComputeShaderRead),
                (Resource::Buffer(map.patch_list), Access::ComputeShaderWrite),
            ],
            uniforms: Some(frame),
            store: None,
        };
        let views = crate::render::gpu_constants::FLAG_DEBUG_PRESSED | crate::render::gpu_constants::FLAG_DEBUG_PATCHES;
        let shows_map = setup.constants.flags & views != 0;
        let inner = PosePass::new(device, setup, shader)?;
        Ok(Self { inner, map, shows_map, patches, cleared: Cell::new(false) })
    }
}

impl Pass for PushOutPass {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let colliders = ctx.uniforms.wind_counts.y;
        let patches = self.patches.frame(ctx.clock.index, ctx.clock.time, colliders).steps[3] != 0;
        // No collider this frame, no patch alive and a map that reads as empty: not recorded.
        if !(colliders > 0 || patches || self.map.read() || self.shows_map) {
            return None;
        }
        // The list emptied (the store cleared first), then the walk that fills it.
        let reset = Declaration::compute().step("patch list").buffer(self.map.patch_list, Access::TransferWrite);
        let reset = match self.cleared.get() {
            true => reset,
            false => reset.buffer(self.map.patches, Access::TransferWrite),
        };
        Some(self.inner.declare_from(ctx, reset.step("push-out")))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        if ctx.step > 0 {
            self.inner.record_dispatch(ctx, cmd);
            return Ok(());
        }
        let device = ctx.device;
        // SAFETY: cmd is recording outside a rendering instance; both buffers allow transfers. An
        // empty list: no workgroups (x 0, y 1, z 1), no blade.
        unsafe {
            if !self.cleared.get() {
                device.raw.cmd_fill_buffer(cmd, self.map.patches, 0, vk::WHOLE_SIZE, 0);
                self.cleared.set(true);
            }
            device.raw.cmd_update_buffer(cmd, self.map.patch_list, 0, bytemuck::cast_slice(&[0u32, 1, 1, 0]));
        }
        Ok(())
    }

    fn uniforms(&self, ctx: &PassContext) -> Option<(&crate::render::graph::PassUniforms, Vec<u8>)> {
        self.inner.uniforms(ctx)
    }

    fn frame_dropped(&self) {
        // The clear may not have run: do it again.
        self.cleared.set(false);
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { Box::new(self.inner).destroy(device) }
    }
}

/// Whether the ground circle of the ellipsoid at `center` with `radii` holds `root` (step 2).
pub fn circle_holds(center: Vec3, radii: Vec3, root: Vec3) -> bool {
    let q = (glam::Vec2::new(root.x, root.z) - glam::Vec2::new(center.x, center.z)) / glam::Vec2::new(radii.x, radii.z);
    q.length_squared() < 1.0
}

/// The point at distance `len` from `a` on the unit sphere nearest its point straight out through
/// `q` (the collider's unit space); a segment's length straight out from the centre through `q`
/// when `a` is inside. `unit_surface_from` of
/// `push_out.glsl`.
fn unit_surface_from(a: Vec3, q: Vec3, len: f32) -> Vec3 {
    let radial = if q.length() > 1e-6 { q.normalize() } else { Vec3::Y };
    let d = a.length();
    if d < 1.0 - 1e-4 {
        return a + len * radial;
    }
    let u = -a / d;
    let h = (d * d + len * len - 1.0) / (2.0 * d);
    let rho = (len * len - h * h).max(0.0).sqrt();
    let towards = radial - a;
    let mut v = towards - towards.dot(u) * u;
    if v.length_squared() < 1e-12 {
        v = if u.x.abs() < 0.9 { u.cross(Vec3::X) } else { u.cross(Vec3::Z) };
    }
    a + h * u + rho * v.normalize()
}

/// The CPU mirror of `push_out_points` (`shaders/animation/push_out.glsl`) over every level of
/// `points` (world positions, the root first): the points moved out of the ellipsoid, and the
/// first level moved (`None`: none was).
pub fn push_out(points: &mut [Vec3], center: Vec3, radii: Vec3) -> Option<usize> {
    let unit = |p: Vec3| (p - center) / radii;
    let mut moved = None;
    let (mut below, mut below_was) = (unit(points[0]), unit(points[0]));
    let mut along = Vec3::ZERO;
    for (level, point) in points.iter_mut().enumerate().skip(1) {
        let was = unit(*point);
        let len = (was - below_was).length();
        let mut q = if moved.is_none() { was } else { below + along * len };
        if q.length_squared() < 1.0 {
            q = unit_surface_from(below, q, len);
            along = (q - below).normalize();
            moved.get_or_insert(level);
        }
        below_was = was;
        below = q;
        if moved.is_some() {
            *point = center + q * radii;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An upright backbone of `n` segments over `height` at `root`, leaning by `lean` at the tip.
    fn backbone(root: Vec3, height: f32, n: usize, lean: Vec3) -> Vec<Vec3> {
        (0..=n).map(|i| i as f32 / n as f32).map(|t| root + Vec3::Y * height * t + lean * t * t).collect()
    }

    #[test]
    fn pushed_points_lie_outside_and_keep_their_segments() {
        let (center, radius) = (Vec3::new(0.0, 0.35, 0.0), 0.3);
        let mut pushed = 0;
        for i in 0..400 {
            let a = i as f32 * 0.37;
            let r = radius * (i % 20) as f32 / 20.0;
            let root = Vec3::new(r * a.cos(), 0.0, r * a.sin());
            let lean = Vec3::new((a * 1.7).cos(), 0.0, (a * 1.7).sin()) * 0.2 * ((i % 7) as f32 / 6.0);
            let before = backbone(root, 0.6, 8, lean);
            let mut after = before.clone();
            let moved = push_out(&mut after, center, Vec3::splat(radius));
            for p in &after[1..] {
                assert!((*p - center).length() >= radius - 1e-4, "root {root}: {p} inside");
            }
            for (w, pair) in before.windows(2).zip(after.windows(2)) {
                let (was, now) = ((w[1] - w[0]).length(), (pair[1] - pair[0]).length());
                assert!((was - now).abs() < 1e-4, "segment {was} became {now}");
            }
            match moved {
                Some(level) => {
                    pushed += 1;
                    assert_eq!(&after[..level], &before[..level], "the levels below the first moved stay");
                }
                None => assert_eq!(after, before),
            }
        }
        assert!(pushed > 300, "{pushed} of 400 blades pushed");
    }

    #[test]
    fn a_blade_rooted_inside_a_sunk_sphere_keeps_its_segments() {
        // The sphere reaches 0.1 m below the ground: roots near its centre are inside it.
        let (center, radii) = (Vec3::new(0.05, 0.2, 0.0), Vec3::splat(0.3));
        let before = backbone(Vec3::ZERO, 0.5, 8, Vec3::ZERO);
        let mut after = before.clone();
        assert_eq!(push_out(&mut after, center, radii), Some(1));
        for (w, pair) in before.windows(2).zip(after.windows(2)) {
            assert!(((w[1] - w[0]).length() - (pair[1] - pair[0]).length()).abs() < 1e-4);
        }
        // Out of the sphere where it can be, with the blade's length.
        assert!((after[8] - center).length() >= 0.3 - 1e-4, "{:?}", after[8]);
    }

    #[test]
    fn a_blade_under_or_beside_the_collider_is_left_alone() {
        let radii = Vec3::new(0.4, 0.2, 0.3);
        let low = backbone(Vec3::ZERO, 0.3, 4, Vec3::ZERO);
        let mut points = low.clone();
        assert_eq!(push_out(&mut points, Vec3::new(0.0, 0.55, 0.0), radii), None);
        assert_eq!(points, low);
        assert!(!circle_holds(Vec3::new(0.5, 0.0, 0.0), radii, Vec3::ZERO));
        assert!(circle_holds(Vec3::new(0.35, 5.0, 0.0), radii, Vec3::ZERO));
    }

    #[test]
    fn an_ellipsoid_pushes_its_points_out() {
        let (center, radii) = (Vec3::new(0.1, 0.25, -0.05), Vec3::new(0.5, 0.2, 0.3));
        let mut points = backbone(Vec3::ZERO, 0.5, 8, Vec3::ZERO);
        assert_eq!(push_out(&mut points, center, radii), Some(1));
        for p in &points[1..] {
            assert!(((*p - center) / radii).length() >= 1.0 - 1e-4, "{p} inside");
        }
        // Away from the centre, on the side the root lies.
        assert!(points[8].x < -0.1, "{:?}", points[8]);
    }
}
