//! The camera grid on the GPU (`render::camera_grid`, `shaders/common/camera_grid.glsl`), through
//! a test shader of its own (`tests/shaders/camera_grid/probe.comp`): a 3-D grid of two nested
//! levels follows a camera that moves by one cell, by several along every axis, by all but one of
//! a window, by a whole window and more, and then 100 km away and on.
//! After every move each level is read back at every world cell of its window, through the
//! addressing the grid's readers use: each holds its own world cell, as the fill wrote it when
//! it entered, and the cells marked once keep their mark for as long as they stay in the window
//! (a value written at a world cell is read back there after the camera moves). Validation and
//! synchronization validation at 0.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;
use bytemuck::Zeroable;
use glam::{DVec3, I64Vec3, IVec4, UVec3, UVec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::camera_grid::{CameraGrid, FillPush, GridShape};
use meadow::render::gpu_constants as gpu;
use meadow::vk::descriptor::{self, Binding, Resource};
use meadow::vk::profile::Shader;
use meadow::vk::{commands, pipeline, sync, Access, Buffer, BufferDesc, Device, DeviceSelector};

const MODE_FILL: u32 = 0;
const MODE_MARK: u32 = 1;
const MODE_READ: u32 = 2;

/// Two levels of 9 × 4 × 6 cells of 0.5 × 0.25 × 2 m (level 1's twice that).
const SHAPE: GridShape =
    GridShape { dims: UVec3::new(9, 4, 6), cell: DVec3::new(0.5, 0.25, 2.0), levels: 2, texel_bytes: 16 };
/// World cells one read or mark takes: a level's window.
const MOST_AT: usize = 9 * 4 * 6;

fn options() -> GpuOptions {
    GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") }
}

/// The probe, compiled by `build.rs` with the library's headers on its include path.
const PROBE: Shader = meadow::spirv_shader!("tests/camera_grid/probe.comp");

/// The probe's pipeline, its set and buffers: the grid, the control block, the cells read.
struct Probe {
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipe: vk::Pipeline,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    grid: Buffer,
    control: Buffer,
    read: Buffer,
}

impl Probe {
    fn new(device: &Device, spirv: &[u8]) -> meadow::Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let grid = Buffer::new(device, &BufferDesc::gpu_only("camera grid", SHAPE.bytes(), storage))?;
        let control = Buffer::new(device, &BufferDesc::upload("control", 32 + 16 * MOST_AT as u64, storage))?;
        let read = Buffer::new(device, &BufferDesc::readback("read", 16 * MOST_AT as u64, storage))?;
        let bindings: Vec<Binding> = (0..3)
            .map(|binding| Binding {
                binding,
                kind: vk::DescriptorType::STORAGE_BUFFER,
                stages: vk::ShaderStageFlags::COMPUTE,
            })
            .collect();
        let set_layout = descriptor::set_layout(device, "probe set layout", &bindings)?;
        let range = meadow::render::camera_grid::push_constant_range();
        let layout = pipeline::layout(device, "probe layout", &[set_layout], &[range])?;
        let pipe = pipeline::compute(device, "camera grid probe", spirv, layout, &[])?;
        let (pool, sets) = descriptor::allocate_sets(device, "probe", set_layout, &bindings, 1)?;
        let kind = vk::DescriptorType::STORAGE_BUFFER;
        let writes =
            [(0, &grid), (1, &control), (2, &read)].map(|(b, buffer)| (b, kind, Resource::Buffer(buffer.descriptor())));
        descriptor::write(device, sets[0], &writes);
        Ok(Self { set_layout, layout, pipe, pool, set: sets[0], grid, control, read })
    }

    /// Run the probe in `mode` over `at` (world cells) or, to fill, over the cells `push` names.
    fn run(
        &mut self,
        device: &Arc<Device>,
        (mode, mark): (u32, u32),
        first: I64Vec3,
        at: &[I64Vec3],
        push: &FillPush,
    ) -> meadow::Result<Vec<IVec4>> {
        let cell = |c: I64Vec3| {
            IVec4::new(i32::try_from(c.x).unwrap(), i32::try_from(c.y).unwrap(), i32::try_from(c.z).unwrap(), 0)
        };
        let mut control = vec![cell(first), bytemuck::cast(UVec4::new(mode, at.len() as u32, mark, 0))];
        control.extend(at.iter().map(|&c| cell(c)));
        self.control.write(0, &control);
        let invocations = if mode == MODE_FILL { push.dims.w } else { at.len() as u32 };
        let (grid, read) = (self.grid.raw, self.read.raw);
        commands::submit_and_wait(device, "camera grid probe", |cmd| {
            // The previous run's grid writes before this one's reads and writes; the host's read
            // of the last results before this run writes them again.
            let before = [
                sync::buffer_barrier(
                    grid,
                    &[Access::ComputeShaderWrite],
                    &[Access::ComputeShaderRead, Access::ComputeShaderWrite],
                ),
                sync::buffer_barrier(read, &[Access::HostRead], &[Access::ComputeShaderWrite]),
            ];
            sync::cmd_barriers(device, cmd, &before, &[]);
            // SAFETY: all objects are live; the control block's host writes are visible at submission.
            unsafe {
                device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipe);
                device.raw.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.layout,
                    0,
                    &[self.set],
                    &[],
                );
                device.raw.cmd_push_constants(
                    cmd,
                    self.layout,
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    bytemuck::bytes_of(push),
                );
                device.raw.cmd_dispatch(cmd, invocations.div_ceil(gpu::CAMERA_GRID_GROUP).max(1), 1, 1);
            }
            let after = [sync::buffer_barrier(read, &[Access::ComputeShaderWrite], &[Access::HostRead])];
            sync::cmd_barriers(device, cmd, &after, &[]);
            Ok(())
        })?;
        Ok(bytemuck::cast_slice::<u8, IVec4>(self.read.mapped())[..at.len()].to_vec())
    }

    /// # Safety
    /// No pending work may use it.
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            device.raw.destroy_descriptor_pool(self.pool, None);
            device.raw.destroy_pipeline(self.pipe, None);
            device.raw.destroy_pipeline_layout(self.layout, None);
            device.raw.destroy_descriptor_set_layout(self.set_layout, None);
            for buffer in [self.grid, self.control, self.read] {
                buffer.destroy(device);
            }
        }
    }
}

/// The push constants that address `level`'s window at `first` with nothing to fill.
fn addressing(level: u32, first: I64Vec3) -> FillPush {
    let base = first.rem_euclid(SHAPE.dims.as_i64vec3()).as_uvec3();
    FillPush { base: base.extend(level), dims: SHAPE.dims.extend(0), ..FillPush::zeroed() }
}

/// Every world cell of the window at `first`.
fn window_cells(first: I64Vec3) -> Vec<I64Vec3> {
    let d = SHAPE.dims.as_i64vec3();
    let mut cells = Vec::new();
    for z in 0..d.z {
        for y in 0..d.y {
            for x in 0..d.x {
                cells.push(first + I64Vec3::new(x, y, z));
            }
        }
    }
    cells
}

/// What a run saw: cells read back and checked, reads of a marked cell, scrolls that filled part
/// of a level (the rest kept).
struct Seen {
    checked: usize,
    marked: usize,
    partial: usize,
}

/// Follow the camera through its moves, filling, marking and reading back as the module says.
fn follow_and_read(device: &Arc<Device>, probe: &mut Probe) -> meadow::Result<Seen> {
    let mut grid = CameraGrid::new(SHAPE).expect("shape");
    let cell = SHAPE.cell;
    let far = DVec3::new(100_000.2, 3.1, -100_000.7);
    // (camera, mark the window's middle cells after the move)
    let path = [
        (DVec3::new(0.2, 0.1, 0.3), true),
        (DVec3::new(0.2 + 0.5, 0.1, 0.3), false),
        (DVec3::new(0.2 - 1.0, 0.1 + 0.25, 0.3 + 4.0), false),
        (DVec3::new(0.2 - 1.0 + 8.0 * 0.5, 0.1 + 0.75, 0.3 + 14.0), false),
        (DVec3::new(0.2 + 3.0, 0.85, 14.3 - 2.0), false),
        (DVec3::new(3.2 + 9.0 * 0.5, 0.85 + 1.0, 12.3 + 12.0), false),
        (DVec3::new(-7.0, 0.85, 30.0), false),
        (far, true),
        (far + DVec3::new(0.5, 0.0, 0.0), false),
        (far + DVec3::new(1.5, -0.25, 6.0), false),
        (far + DVec3::new(-2.5, 0.5, -4.0), false),
    ];
    let mut marks: HashMap<(u32, I64Vec3), u32> = HashMap::new();
    let (mut checked, mut partial, mut marked) = (0, 0, 0);
    for (step, &(camera, mark)) in path.iter().enumerate() {
        for scroll in grid.follow(camera) {
            partial += usize::from(scroll.cells() < SHAPE.cells_per_level());
            probe.run(device, (MODE_FILL, 0), scroll.first, &[], &scroll.push(SHAPE.dims))?;
            // A marked cell that left the window is gone; its slot holds a cell that entered.
            marks.retain(|&(level, w), _| level != scroll.level || grid.slot_of(level, w).is_some());
        }
        for level in 0..SHAPE.levels {
            let first = grid.window(level).expect("filled");
            if mark {
                let middle = first + (SHAPE.dims / 2).as_i64vec3();
                let tag = 100 + 10 * step as u32 + level;
                probe.run(device, (MODE_MARK, tag), first, &[middle], &addressing(level, first))?;
                marks.insert((level, middle), tag);
            }
            let cells = window_cells(first);
            let read = probe.run(device, (MODE_READ, 0), first, &cells, &addressing(level, first))?;
            for (w, got) in cells.iter().zip(&read) {
                let tag = marks.get(&(level, *w)).copied().unwrap_or(0);
                marked += usize::from(tag != 0);
                let want = IVec4::new(w.x as i32, w.y as i32, w.z as i32, tag as i32);
                assert_eq!(*got, want, "step {step}, level {level}: world cell {w} (camera {camera}, cell {cell})");
                checked += 1;
            }
        }
    }
    Ok(Seen { checked, marked, partial })
}

#[test]
fn a_value_written_at_a_world_cell_reads_back_there_after_any_moves_and_100_km_out() {
    let (result, messages) = with_device(&options(), false, |device| {
        let mut probe = Probe::new(device, PROBE.code(device.profile))?;
        let seen = follow_and_read(device, &mut probe);
        // SAFETY: submit_and_wait waited for every run.
        unsafe { probe.destroy(device) };
        seen
    });
    let seen = result.expect("the probe ran");
    assert_eq!(messages, Some(0), "validation messages");
    assert_eq!(seen.checked, 11 * 2 * MOST_AT);
    // Marks read back after moves, at the origin and 100 km out (each read once where it was made).
    assert!(seen.marked >= 10, "{} reads of a marked cell", seen.marked);
    // Most moves kept part of a level and filled the rest.
    assert!(seen.partial >= 10, "{} scrolls kept part of a level", seen.partial);
}
