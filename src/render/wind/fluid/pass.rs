//! The fluid wind's pass: one step of the grid (`shaders/wind/fluid.comp`, a variant per stage)
//! as the steps of one compute pass, then the corners (`shaders/wind/analytic_corners.comp`,
//! variant `fluid`), each step declaring the images it reads and writes so the graph puts a
//! barrier between each dependent dispatch. The images are GENERAL storage images, read with
//! `imageLoad` and written with `imageStore` only: U (the state, kept from frame to frame), A and
//! B (the stages' scratch), P0 and P1 (the pressure's Jacobi pair; an even count of iterations
//! leaves it in P0, the next step's first guess) and the divergence with its row's diagonal. The
//! stages read and write them through five assignments of one set layout:
//!
//! ```text
//!  stage          set  Src  Rhs  Dst   PIn  POut
//!  inflow         0    -    -    -     -    -      writes Inflow, the upwind ghosts' wind
//!  enter          0    -    -    U     -    P0     the cells that entered (push constants)
//!  forces         1    U    -    A
//!  diffuse 1, 2   2,3  A,B  A    B,U
//!  advect         1    U    -    A
//!  divergence     2    A    -    -     P0   -      writes DivDiag (its diagonal reads no P)
//!  pressure k     1/0  -    -    -     Pk%2 P1-k%2 reads DivDiag
//!  project        4    A    -    U     P0
//!  corners             U (its own set)             writes the frame's corners
//! ```
//!
//! Every stage that reads velocities through `fluid_velocity` (diffuse, advect, divergence,
//! corners) reads Inflow too: the analytic wind of the ghost columns round the window, one
//! texel each (`shaders/wind/fluid.glsl`'s `fluid_ring_texel`), written once a step where each
//! ghost read used to evaluate it.
//! Only the corners step is measured apart (`corners`); the pass's time less it is the step's.

use std::cell::RefCell;
use std::rc::Rc;

use ash::vk;
use glam::UVec3;

use super::{FluidWindow, DIFFUSE_ITERATIONS, PRESSURE_ITERATIONS};
use crate::error::Result;
use crate::render::camera_grid;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::{PassSet, PassSetDesc};
use crate::render::shaders;
use crate::render::wind::corners_pass::{storage_image, AnalyticCornersPass, CornerVariant};
use crate::render::wind::params::Params;
use crate::render::wind::WindSetup;
use crate::vk::{pipeline, Access, Device, Guard, Image, ImageDesc, Resource};
use crate::wind::FluidGrid;

const _: () = assert!(PRESSURE_ITERATIONS.is_multiple_of(2) && DIFFUSE_ITERATIONS == 2);

/// What the field's update and its pass share.
pub struct Shared {
    /// The frame's parameters.
    pub params: Rc<RefCell<Params>>,
    /// The window and what entered it.
    pub window: Rc<RefCell<FluidWindow>>,
    /// The images, for a test's readback.
    pub images: Rc<RefCell<Option<FluidImages>>>,
}

/// The fluid's images' handles (owned by the pass).
#[derive(Clone, Copy, Debug)]
pub struct FluidImages {
    /// U, A, B: RGBA32F velocities; U holds the state between frames.
    pub velocity: [vk::Image; 3],
    /// P0, P1: R32F pressures.
    pub pressure: [vk::Image; 2],
    /// RG32F divergence and diagonal.
    pub divergence: vk::Image,
    /// RGBA32F: the ghost columns' analytic wind.
    pub inflow: vk::Image,
    /// Cells per axis (the images' extent).
    pub extent: vk::Extent3D,
}

/// The pass's stages, in order.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Stage {
    Inflow,
    Enter,
    Forces,
    Diffuse(u32),
    Advect,
    Divergence,
    Pressure(u32),
    Project,
    Corners,
}

/// The fluid's images, pipelines and sets, and the corners' pass it ends with.
pub struct FluidPass {
    corners: AnalyticCornersPass,
    images: Vec<Image>,
    handles: FluidImages,
    set: PassSet,
    frames: usize,
    pipelines: Vec<vk::Pipeline>,
    /// Workgroups of a stage over the cells, and of the inflow stage over the ring.
    groups: u32,
    inflow_groups: u32,
    dims: UVec3,
    shared: Shared,
}

/// The images' names, formats and how many of each.
const IMAGES: [(&str, vk::Format); 6] = [
    ("fluid velocity U", vk::Format::R32G32B32A32_SFLOAT),
    ("fluid velocity A", vk::Format::R32G32B32A32_SFLOAT),
    ("fluid velocity B", vk::Format::R32G32B32A32_SFLOAT),
    ("fluid pressure P0", vk::Format::R32_SFLOAT),
    ("fluid pressure P1", vk::Format::R32_SFLOAT),
    ("fluid divergence", vk::Format::R32G32_SFLOAT),
];

/// The inflow's texels: the analytic wind (x, y, z) of a ghost column.
const INFLOW_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// The inflow image's extent for `grid`: the ring of ghost columns round the window
/// (`fluid_ring_texel`), a row per side, each as long as the longer side and its two corners.
pub fn inflow_extent(grid: &FluidGrid) -> vk::Extent3D {
    vk::Extent3D { width: grid.dims[0].max(grid.dims[2]) + 2, height: 4, depth: 1 }
}

/// Per set assignment: the images (indices into `IMAGES`) bound as Src, Rhs, Dst, PIn, POut.
const ASSIGNMENTS: [[usize; 5]; 5] =
    [[1, 1, 0, 4, 3], [0, 0, 1, 3, 4], [1, 1, 2, 3, 4], [2, 1, 0, 3, 4], [1, 1, 0, 3, 4]];

impl FluidPass {
    /// Build the images (their extent and formats checked against the device), the stages'
    /// pipelines and sets, and the corners' pass over `setup`.
    pub fn new(device: &Device, setup: &WindSetup, grid: &FluidGrid, shared: Shared) -> Result<Self> {
        let most = device.limits().max_image_dimension3_d;
        grid.check(most).map_err(|e| crate::error::Error::bad_input(format!("--fluid-grid: {e}")))?;
        device.check_budget(super::grid_bytes(grid), "the fluid wind's grid")?;
        let ring = inflow_extent(grid).width;
        if ring > most {
            let what = format!(
                "--fluid-grid: its inflow ring is {ring} texels across, over the device's 3-D image limit of {most}"
            );
            return Err(crate::error::Error::bad_input(what));
        }
        let [x, y, z] = grid.dims;
        let extent = vk::Extent3D { width: x, height: y, depth: z };
        let usage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
        let mut images = Guard::new(device, Vec::new());
        for (name, format) in IMAGES {
            images.push(Image::new(device, &ImageDesc::volume(name, format, extent, usage))?);
        }
        images.push(Image::new(device, &ImageDesc::volume("fluid inflow", INFLOW_FORMAT, inflow_extent(grid), usage))?);
        let views: Vec<vk::ImageView> = images.iter().map(|i| i.view).collect();
        let variant = CornerVariant::Fluid(views[0], views[6]);
        let corners = AnalyticCornersPass::new(device, setup, shared.params.clone(), variant)?;
        let corners = Guard::new(device, corners);
        let codes: Vec<&[u8]> = shaders::FLUID_STAGES_COMP.iter().map(|s| s.code(device.profile)).collect();
        let named: Vec<(&str, &[u8])> = codes.iter().map(|c| ("fluid.comp", *c)).collect();
        // The enter stage's fill; the pressure stage's weight over its first bytes.
        let push = [camera_grid::push_constant_range()];
        let frames = setup.frames.len();
        let desc = PassSetDesc { name: "fluid wind", shaders: &named, before: &[], push: &push, frames: frames * 5 };
        let set = PassSet::new(device, &desc, |index| {
            let (assignment, slot) = (ASSIGNMENTS[index / frames], index % frames);
            let names = ["Src", "Rhs", "Dst", "PIn", "POut"];
            let mut resources: Vec<(&str, crate::vk::descriptor::Resource)> =
                names.iter().zip(assignment).map(|(n, i)| (*n, storage_image(views[i]))).collect();
            resources.push(("DivDiag", storage_image(views[5])));
            resources.push(("Inflow", storage_image(views[6])));
            resources.push(("WindValues", corners.params_resource(slot)));
            resources.push(("WindControl", corners.params_resource(slot)));
            resources
        })?;
        let set = Guard::new(device, set);
        let mut pipelines = Guard::new(device, Vec::new());
        for (i, code) in codes.iter().enumerate() {
            pipelines.push(pipeline::compute(device, &format!("fluid stage {i}"), code, set.layout, &[])?);
        }
        let cells = u32::try_from(u64::from(x) * u64::from(y) * u64::from(z)).unwrap_or(u32::MAX);
        let raw: Vec<vk::Image> = images.iter().map(|i| i.raw).collect();
        let (velocity, pressure) = ([raw[0], raw[1], raw[2]], [raw[3], raw[4]]);
        let handles = FluidImages { velocity, pressure, divergence: raw[5], inflow: raw[6], extent };
        *shared.images.borrow_mut() = Some(handles);
        Ok(Self {
            corners: corners.take(),
            images: images.take(),
            handles,
            set: set.take(),
            frames,
            pipelines: pipelines.take(),
            groups: cells.div_ceil(gpu::FLUID_GROUP),
            inflow_groups: (inflow_extent(grid).width * 4).div_ceil(gpu::FLUID_GROUP),
            dims: UVec3::new(x, y, z),
            shared,
        })
    }

    /// The images to import into the graph, each with nothing done to it yet.
    pub fn tracked(&self) -> Vec<(Resource, Vec<Access>)> {
        self.images.iter().map(|i| (Resource::color(i.raw), vec![Access::Nothing])).collect()
    }

    /// This frame's stages: the enter stage only when cells entered.
    fn stages(&self) -> Vec<Stage> {
        let entered = self.shared.window.borrow().scroll.is_some();
        let mut stages = vec![Stage::Inflow];
        stages.extend(entered.then_some(Stage::Enter));
        stages.extend([Stage::Forces, Stage::Diffuse(0), Stage::Diffuse(1), Stage::Advect, Stage::Divergence]);
        stages.extend((0..PRESSURE_ITERATIONS).map(Stage::Pressure));
        stages.extend([Stage::Project, Stage::Corners]);
        stages
    }

    /// A stage's pipeline (an index into `FLUID_STAGES_COMP`) and set assignment.
    fn binding(stage: Stage) -> (usize, usize) {
        match stage {
            Stage::Inflow => (7, 0),
            Stage::Enter => (0, 0),
            Stage::Forces => (1, 1),
            Stage::Diffuse(k) => (2, 2 + k as usize),
            Stage::Advect => (3, 1),
            Stage::Divergence => (4, 2),
            Stage::Pressure(k) => (5, if k % 2 == 0 { 1 } else { 0 }),
            Stage::Project | Stage::Corners => (6, 4),
        }
    }

    fn declare_stage(&self, d: Declaration, stage: Stage, slot: usize) -> Declaration {
        let h = &self.handles;
        let ([u, a, b], [p0, p1], div, inflow) = (h.velocity, h.pressure, h.divergence, h.inflow);
        let (read, write) = (Access::ComputeShaderRead, Access::ComputeShaderWrite);
        match stage {
            Stage::Inflow => d.then().image(inflow, write),
            Stage::Enter => d.then().image(u, write).image(p0, write),
            Stage::Forces => d.then().image(u, read).image(a, write),
            Stage::Diffuse(0) => d.then().image(a, read).image(inflow, read).image(b, write),
            Stage::Diffuse(_) => d.then().image(b, read).image(a, read).image(inflow, read).image(u, write),
            Stage::Advect => d.then().image(u, read).image(inflow, read).image(a, write),
            Stage::Divergence => d.then().image(a, read).image(inflow, read).image(p0, read).image(div, write),
            Stage::Pressure(k) => {
                let (from, to) = if k % 2 == 0 { (p0, p1) } else { (p1, p0) };
                d.then().image(from, read).image(div, read).image(to, write)
            }
            Stage::Project => d.then().image(a, read).image(p0, read).image(u, write),
            Stage::Corners => {
                d.step("corners").image(u, read).image(inflow, read).buffer(self.corners.corners(slot), write)
            }
        }
    }
}

impl Pass for FluidPass {
    fn name(&self) -> &'static str {
        "fluid wind"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let stages = self.stages();
        Some(stages.iter().fold(Declaration::compute(), |d, s| self.declare_stage(d, *s, ctx.slot)))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let stage = self.stages()[ctx.step];
        if stage == Stage::Corners {
            return self.corners.record(ctx, cmd);
        }
        let device = ctx.device;
        let (pipeline, assignment) = Self::binding(stage);
        let pipeline = self.pipelines[pipeline];
        self.set.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, assignment * self.frames + ctx.slot);
        if stage == Stage::Enter {
            let window = self.shared.window.borrow();
            let scroll = window.scroll.as_ref().expect("the enter stage runs when cells entered");
            camera_grid::record_fill(device, cmd, (self.set.layout, pipeline), scroll, self.dims);
            return Ok(());
        }
        // SAFETY: cmd is recording outside a rendering instance; the set is bound and its images
        // are in GENERAL, as the graph's barriers left them.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            if let Stage::Pressure(k) = stage {
                // ω_k at offset 0 (`fluid.comp`'s `Push` of the pressure stage).
                let weight = [super::pressure_weight(k), 0.0, 0.0, 0.0];
                let bytes = bytemuck::bytes_of(&weight);
                device.raw.cmd_push_constants(cmd, self.set.layout, vk::ShaderStageFlags::COMPUTE, 0, bytes);
            }
            let groups = if stage == Stage::Inflow { self.inflow_groups } else { self.groups };
            device.raw.cmd_dispatch(cmd, groups, 1, 1);
        }
        Ok(())
    }

    fn uniforms(&self, ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        self.corners.uniforms(ctx)
    }

    fn frame_dropped(&self) {
        // The cells that entered were not filled: fill the window whole next frame.
        self.shared.window.borrow_mut().grid.invalidate();
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        let mut images = self.shared.images.borrow_mut();
        if images.is_some_and(|i| i.velocity[0] == self.handles.velocity[0]) {
            images.take();
        }
        drop(images);
        // SAFETY: per the contract.
        unsafe {
            for pipeline in self.pipelines {
                crate::vk::live::destroyed(pipeline);
                device.raw.destroy_pipeline(pipeline, None);
            }
            self.set.destroy(device);
            for image in self.images {
                image.destroy(device);
            }
            Box::new(self.corners).destroy(device);
        }
    }
}
