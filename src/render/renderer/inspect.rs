//! Read-backs of the renderer's GPU state after a frame, for tests and diagnostics: what a pass
//! wrote, as the GPU holds it.

use super::Renderer;
use crate::error::Result;
use crate::vk::{commands, sync, Access, Buffer, BufferDesc};

/// A wind field's grid read back: its texels in image order, its extent, its toroidal base.
pub type WindState = (Vec<[f32; 4]>, ash::vk::Extent3D, glam::UVec3);

impl Renderer {
    /// The ground's clipmap (`render::ground`) as the last frame left it: its texels in slot order
    /// (a camera grid, `render::camera_grid::slot`, level after level), each the height, the next
    /// level's mesh's height and the rise along x and z over its level's run at its vertex. Call
    /// it between frames (after `render_offscreen`, which waits): it copies the buffer and waits
    /// for the copy.
    pub fn read_ground(&self) -> Result<Vec<[f32; 4]>> {
        let ground = &self.scene_gpu().ground;
        self.read_buffer("ground texels", ground.texels.raw, ground.texels.size)
    }

    /// The cull's visible list as the last frame left it, every entry of its capacity (blade,
    /// packed root height and scale: `shaders/cull/visible.glsl`), and the `draws` buffer's
    /// words (each LOD bucket's indexed draw first). Call it between frames, as
    /// `read_ground`.
    pub fn read_visible_list(&self) -> Result<(Vec<[u32; 2]>, Vec<u32>)> {
        let scene = self.scene_gpu();
        let words = |bytes: Vec<u8>| -> Vec<u32> {
            bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect()
        };
        let size = 8 * u64::from(scene.visible_capacity);
        let visible = words(self.read_bytes("visible list", scene.visible.raw, size)?);
        let draws = words(self.read_bytes("cull draws", scene.draws.raw, scene.draws.size)?);
        Ok((visible.chunks_exact(2).map(|e| [e[0], e[1]]).collect(), draws))
    }

    /// The wind at the cluster corners of frame slot `slot` (a renderer's first frame is slot 0)
    /// as the wind field left it (`shaders/wind/analytic_corners.comp` with the cull, the CPU with
    /// `--brute-force`): velocity (x, y, z) in m/s and exposure per corner. Call it between
    /// frames, as `read_ground`.
    pub fn read_wind_corners(&self, slot: usize) -> Result<Vec<[f32; 4]>> {
        let corners = &self.forces[slot].corners;
        let size = 16 * u64::from(self.scene_gpu().wind_corner_count());
        self.read_buffer("wind corners", corners.raw, size)
    }

    /// A stateful wind field's grid as its passes last left it (`WindField::state`; the fluid's
    /// velocities): each texel's (x, y, z, 0) in image order, the window's toroidal base; `None`
    /// for a field with none. Call it between frames, as `read_ground`.
    pub fn read_wind_state(&self) -> Result<Option<WindState>> {
        let Some((image, extent, base)) = self.wind.state() else { return Ok(None) };
        let size = 16 * u64::from(extent.width * extent.height * extent.depth);
        let usage = ash::vk::BufferUsageFlags::TRANSFER_DST;
        let out = Buffer::new(&self.device, &BufferDesc::readback("wind state read-back", size, usage))?;
        let range = crate::vk::image::COLOR_RANGE;
        let copied = commands::submit_and_wait(&self.device, "wind state read-back", |cmd| {
            let general = [Access::ComputeShaderWrite];
            let before = sync::image_barrier(image, range, &general, &[Access::TransferRead]);
            sync::cmd_barriers(&self.device, cmd, &[], &[before]);
            crate::vk::image::record_copy_to_buffer(&self.device, cmd, image, extent, out.raw);
            // Back to GENERAL, as the graph's tracker holds it.
            let back = sync::image_barrier(image, range, &[Access::TransferRead], &general);
            let host = sync::buffer_barrier(out.raw, &[Access::TransferWrite], &[Access::HostRead]);
            sync::cmd_barriers(&self.device, cmd, &[host], &[back]);
            Ok(())
        });
        let texels = out.mapped()[..size as usize]
            .chunks_exact(16)
            .map(|v| std::array::from_fn(|i| f32::from_le_bytes(v[4 * i..4 * i + 4].try_into().expect("4 bytes"))))
            .collect();
        // SAFETY: submit_and_wait waited for the copy (or never submitted it).
        unsafe { out.destroy(&self.device) };
        copied.map(|()| Some((texels, extent, base)))
    }

    /// The pose records as the response's pose pass last wrote them (`POSE_WORDS` words per
    /// level, `MODEL_SEGMENTS + 1` levels a record; by stored blade without the cull, by
    /// visible-list entry with it); empty when the response writes none. Call it between frames,
    /// as `read_ground`.
    pub fn read_pose_records(&self) -> Result<Vec<u32>> {
        let Some(poses) = self.poses.as_ref().filter(|p| p.written) else {
            return Ok(Vec::new());
        };
        let bytes = self.read_bytes("pose records", poses.poses.raw, poses.poses.size)?;
        Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect())
    }

    /// The interaction patches' store as the last frame left it (`animation::patches`): its words,
    /// the presence grid then the records (`patches::live` reads them); empty without a pressed
    /// map. Call it between frames, as `read_ground`.
    pub fn read_patches(&self) -> Result<Vec<u32>> {
        let Some(map) = self.pressed.as_ref() else { return Ok(Vec::new()) };
        let bytes = self.read_bytes(
            "interaction patches",
            map.patches.buffer.raw,
            crate::render::animation::patches::STORE_BYTES,
        )?;
        Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect())
    }

    /// After a frame that drew step `step`: the blades the push-out walk listed for the patches,
    /// and those that hold a patch (`patches::live`); `None` without a pressed map. Call it between
    /// frames, as `read_ground`.
    pub fn patch_counts(&self, step: u64) -> Result<Option<(u64, u64)>> {
        let Some(map) = self.pressed.as_ref() else { return Ok(None) };
        let head = self.read_bytes("patch list", map.patches.list.raw, 16)?;
        let listed = u32::from_le_bytes([head[12], head[13], head[14], head[15]]);
        let live = crate::render::animation::patches::live(&self.read_patches()?, step).len();
        Ok(Some((u64::from(listed), live as u64)))
    }

    /// What the far field drew in the last frame (`render::far_field`): its plants, read back from
    /// the placement's draw, their triangles and its rings; `None` without a far field. Call it
    /// between frames, as `read_ground`.
    pub fn far_counts(&self) -> Result<Option<crate::render::far_field::FarCounts>> {
        let Some(far) = self.far else { return Ok(None) };
        let head = self.read_bytes("far draw", far.draw, 20)?;
        let plants = u32::from_le_bytes([head[4], head[5], head[6], head[7]]);
        let triangles = plants * 2 * far.pieces;
        Ok(Some(crate::render::far_field::FarCounts { plants, triangles, rings: far.rings }))
    }

    /// The far field's plants as the last frame placed them, in their drawn order; `None`
    /// without a far field. Call it between frames, as `read_ground`.
    pub fn far_plants(&self) -> Result<Option<Vec<crate::render::far_field::PlacedPlant>>> {
        let Some(far) = self.far else { return Ok(None) };
        let Some(counts) = self.far_counts()? else { return Ok(None) };
        if counts.plants == 0 {
            return Ok(Some(Vec::new()));
        }
        let bytes = u64::from(counts.plants) * std::mem::size_of::<crate::render::far_field::PlacedPlant>() as u64;
        let read = self.read_bytes("far plants", far.plants, bytes)?;
        Ok(Some(
            read.chunks_exact(std::mem::size_of::<crate::render::far_field::PlacedPlant>())
                .map(bytemuck::pod_read_unaligned)
                .collect(),
        ))
    }

    /// The mean coverage of each level of the far field's atlas (`far_field::atlas`: the albedo
    /// image's alpha) as the bake left it; `None` without a far field. Call it between frames,
    /// after a frame that drew the far field (the atlas is then sampled-read, as it is left).
    pub fn far_atlas_coverage(&self) -> Result<Option<Vec<f64>>> {
        use crate::render::far_field::atlas::{EXTENT, MIPS};
        let Some(far) = self.far else { return Ok(None) };
        let image = far.atlas.image(0);
        let sizes: Vec<(u32, u32)> =
            (0..MIPS).map(|l| ((EXTENT.width >> l).max(1), (EXTENT.height >> l).max(1))).collect();
        // RGBA16F texels: 8 bytes, the coverage the last half float.
        let bytes: u64 = sizes.iter().map(|&(w, h)| u64::from(w * h * 8)).sum();
        let usage = ash::vk::BufferUsageFlags::TRANSFER_DST;
        let out = Buffer::new(&self.device, &BufferDesc::readback("far atlas read-back", bytes, usage))?;
        let range = ash::vk::ImageSubresourceRange {
            aspect_mask: ash::vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: MIPS,
            base_array_layer: 0,
            layer_count: 1,
        };
        let copied = commands::submit_and_wait(&self.device, "far atlas read-back", |cmd| {
            let sampled = [Access::FragmentShaderSampledRead];
            let before = sync::image_barrier(image, range, &sampled, &[Access::TransferRead]);
            sync::cmd_barriers(&self.device, cmd, &[], &[before]);
            let mut offset = 0;
            let regions: Vec<ash::vk::BufferImageCopy> = sizes
                .iter()
                .enumerate()
                .map(|(level, &(w, h))| {
                    let region = ash::vk::BufferImageCopy::default()
                        .buffer_offset(offset)
                        .image_subresource(ash::vk::ImageSubresourceLayers {
                            aspect_mask: ash::vk::ImageAspectFlags::COLOR,
                            mip_level: level as u32,
                            base_array_layer: 0,
                            layer_count: 1,
                        })
                        .image_extent(ash::vk::Extent3D { width: w, height: h, depth: 1 });
                    offset += u64::from(w * h * 8);
                    region
                })
                .collect();
            let layout = ash::vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            // SAFETY: the image holds every level copied, in TRANSFER_SRC_OPTIMAL after the
            // barrier; the buffer holds them all.
            unsafe { self.device.raw.cmd_copy_image_to_buffer(cmd, image, layout, out.raw, &regions) };
            let back = sync::image_barrier(image, range, &[Access::TransferRead], &sampled);
            let host = sync::buffer_barrier(out.raw, &[Access::TransferWrite], &[Access::HostRead]);
            sync::cmd_barriers(&self.device, cmd, &[host], &[back]);
            Ok(())
        });
        let texels = out.mapped()[..bytes as usize].to_vec();
        // SAFETY: submit_and_wait waited for the copy (or never submitted it).
        unsafe { out.destroy(&self.device) };
        copied?;
        let mut at = 0;
        let means = sizes
            .iter()
            .map(|&(w, h)| {
                let level = &texels[at..at + (w * h * 8) as usize];
                at += level.len();
                level.chunks_exact(8).map(|t| half_to_f64(u16::from_le_bytes([t[6], t[7]]))).sum::<f64>()
                    / f64::from(w * h)
            })
            .collect();
        Ok(Some(means))
    }

    /// The names of the blade response's own passes, as frame timings name them (`PassTime`):
    /// what the response costs, apart from the renderer's passes (the blade-levels pass that
    /// places pose records is the renderer's).
    pub fn response_passes(&self) -> &[&'static str] {
        &self.response_passes
    }

    /// The blade response's name in reports (`BladeResponse::name`).
    pub fn response_name(&self) -> &'static str {
        self.response.as_deref().map_or("none", |r| r.name())
    }

    /// The wind field's name in reports (`WindField::name`).
    pub fn wind_field_name(&self) -> &'static str {
        self.wind.name()
    }

    /// The cluster grid whose corners carry the wind (relative to O for a block field: its
    /// innermost wind level).
    pub fn cluster_grid(&self) -> crate::scene::clusters::ClusterGrid {
        self.scene_gpu().grid
    }

    /// The wind's levels, innermost first, as `read_wind_corners` lays their corners out one
    /// after the other: a stored field's one grid, or a block field's `WIND_LEVELS` nested
    /// levels (`field_gpu::wind_level`).
    pub fn wind_levels(&self) -> Vec<crate::scene::clusters::ClusterGrid> {
        let scene = self.scene_gpu();
        match scene.field {
            Some(_) => (0..scene.wind_levels)
                .map(|l| crate::render::field_gpu::wind_level(scene.grid.cluster_size, l))
                .collect(),
            None => vec![scene.grid],
        }
    }

    /// `size` bytes of `buffer` as vec4s (`read_bytes`).
    fn read_buffer(&self, name: &str, buffer: ash::vk::Buffer, size: u64) -> Result<Vec<[f32; 4]>> {
        let bytes = self.read_bytes(name, buffer, size)?;
        Ok(bytes
            .chunks_exact(16)
            .map(|v| std::array::from_fn(|i| f32::from_le_bytes(v[4 * i..4 * i + 4].try_into().expect("4 bytes"))))
            .collect())
    }

    /// `size` bytes of `buffer`, last written by a compute shader, copied out and waited for.
    fn read_bytes(&self, name: &str, buffer: ash::vk::Buffer, size: u64) -> Result<Vec<u8>> {
        let usage = ash::vk::BufferUsageFlags::TRANSFER_DST;
        let out = Buffer::new(&self.device, &BufferDesc::readback(&format!("{name} read-back"), size, usage))?;
        let grid = buffer;
        let copied = commands::submit_and_wait(&self.device, &format!("{name} read-back"), |cmd| {
            let before = sync::buffer_barrier(grid, &[Access::ComputeShaderWrite], &[Access::TransferRead]);
            sync::cmd_barriers(&self.device, cmd, &[before], &[]);
            let region = ash::vk::BufferCopy { src_offset: 0, dst_offset: 0, size };
            // SAFETY: both buffers are live and at least `size` bytes; the frame that wrote the
            // grid has completed (the caller's contract) and the barrier orders its writes.
            unsafe { self.device.raw.cmd_copy_buffer(cmd, grid, out.raw, &[region]) };
            let after = sync::buffer_barrier(out.raw, &[Access::TransferWrite], &[Access::HostRead]);
            sync::cmd_barriers(&self.device, cmd, &[after], &[]);
            Ok(())
        });
        let texels = out.mapped()[..size as usize].to_vec();
        // SAFETY: submit_and_wait waited for the copy (or never submitted it).
        unsafe { out.destroy(&self.device) };
        copied.map(|()| texels)
    }
}

/// An IEEE 754 half float's value (the far atlas's texels).
fn half_to_f64(bits: u16) -> f64 {
    let (sign, exponent, fraction) = (bits >> 15, i32::from((bits >> 10) & 0x1f), f64::from(bits & 0x3ff));
    let magnitude = match exponent {
        0 => fraction * 2f64.powi(-24),
        31 => f64::INFINITY,
        e => (1.0 + fraction / 1024.0) * 2f64.powi(e - 15),
    };
    if sign == 1 {
        -magnitude
    } else {
        magnitude
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn half_floats_decode() {
        let cases = [(0x0000, 0.0), (0x3c00, 1.0), (0x3800, 0.5), (0xc000, -2.0), (0x0001, 2f64.powi(-24))];
        for (bits, value) in cases {
            assert_eq!(super::half_to_f64(bits), value, "{bits:#06x}");
        }
    }
}
