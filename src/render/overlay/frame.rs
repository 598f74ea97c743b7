//! One frame in flight of the overlay: its host-visible vertex, index and staging buffers (grown
//! as needed, never shrunk), the set that points the vertex shader at its vertices, and what the
//! overlay passes record for it — the meshes' draws and the texture copies — worked out when the
//! frame is prepared (`OverlayGpu::prepare`), after the slot's fence: its previous use of these
//! buffers and of the set has finished.
//!
//! Vertices are pulled from a storage buffer (the project's style, `shaders/overlay/overlay.vert`), five
//! words each, written field by field from egui's `Vertex` (so neither its layout nor its
//! `bytemuck` feature matters); the meshes share one index buffer and one vertex buffer per
//! frame, each draw at its own first index and vertex offset.

use ash::vk;
use egui::epaint::{Primitive, Vertex};

use crate::error::Result;
use crate::render::overlay::textures::Textures;
use crate::vk::descriptor::{self, Resource as Descriptor};
use crate::vk::{Buffer, BufferDesc, Device};

/// 32-bit words of one vertex in the storage buffer (`shaders/overlay/overlay.vert`).
pub const VERTEX_WORDS: usize = 5;
/// The smallest buffer made (then doubled as needed).
const MIN_BUFFER_BYTES: u64 = 64 << 10;

/// One mesh's draw.
#[derive(Clone, Copy, Debug)]
pub struct Draw {
    /// Its clip rectangle in pixels, inside the target.
    pub scissor: vk::Rect2D,
    /// Its first index in the frame's index buffer.
    pub first_index: u32,
    /// Its index count.
    pub index_count: u32,
    /// Its first vertex in the frame's vertex buffer.
    pub vertex_offset: i32,
    /// Its texture's set.
    pub set: vk::DescriptorSet,
    /// Its texture's image (sampled by the draw).
    pub image: vk::Image,
}

/// One texture copy from the frame's staging buffer.
#[derive(Clone, Copy, Debug)]
pub struct Copy {
    /// The texture's image.
    pub image: vk::Image,
    /// Where the texels are and where they go.
    pub region: vk::BufferImageCopy,
}

/// A frame in flight's buffers and what its passes record.
pub struct SlotFrame {
    /// Binding 0: the vertex buffer (set 0 of the overlay's pipeline layout).
    pub set: vk::DescriptorSet,
    /// egui's vertices, `VERTEX_WORDS` words each.
    pub vertices: Option<Buffer>,
    /// egui's indices, `u32`.
    pub indices: Option<Buffer>,
    /// Texels copied into the textures.
    pub staging: Option<Buffer>,
    /// Whether the frame draws the overlay.
    pub shown: bool,
    /// The screen's size in points (the vertex shader's push constant).
    pub screen_points: [f32; 2],
    /// The meshes' draws, in egui's order.
    pub draws: Vec<Draw>,
    /// The texture copies, in egui's order.
    pub copies: Vec<Copy>,
}

/// The scissor of a clip rectangle in points: in pixels, rounded, clamped to the target; `None`
/// when nothing of it is inside (a NaN or infinite edge clamps to the target's).
pub fn scissor(clip: egui::Rect, pixels_per_point: f32, extent: vk::Extent2D) -> Option<vk::Rect2D> {
    let (width, height) = (extent.width as f32, extent.height as f32);
    let pixel = |points: f32, limit: f32| (points * pixels_per_point).round().max(0.0).min(limit) as i32;
    let (x0, x1) = (pixel(clip.min.x, width), pixel(clip.max.x, width));
    let (y0, y1) = (pixel(clip.min.y, height), pixel(clip.max.y, height));
    (x1 > x0 && y1 > y0).then(|| vk::Rect2D {
        offset: vk::Offset2D { x: x0, y: y0 },
        extent: vk::Extent2D { width: (x1 - x0) as u32, height: (y1 - y0) as u32 },
    })
}

/// The storage-buffer words of `vertices`.
fn push_vertices(words: &mut Vec<u32>, vertices: &[Vertex]) {
    words.reserve(VERTEX_WORDS * vertices.len());
    for v in vertices {
        let color = u32::from_le_bytes(v.color.to_array());
        words.extend([v.pos.x.to_bits(), v.pos.y.to_bits(), v.uv.x.to_bits(), v.uv.y.to_bits(), color]);
    }
}

/// The frame's geometry: vertex words, indices and one draw per visible mesh. A mesh whose
/// texture was freed since (egui no longer draws it) or whose clip is empty is left out.
pub fn geometry(
    primitives: &[egui::ClippedPrimitive],
    pixels_per_point: f32,
    extent: vk::Extent2D,
    textures: &Textures,
) -> (Vec<u32>, Vec<u32>, Vec<Draw>) {
    let (mut words, mut indices, mut draws) = (Vec::new(), Vec::new(), Vec::new());
    for clipped in primitives {
        let Primitive::Mesh(mesh) = &clipped.primitive else { continue };
        let texture = textures.get(mesh.texture_id);
        let scissor = scissor(clipped.clip_rect, pixels_per_point, extent);
        let (Some(texture), Some(scissor), false) = (texture, scissor, mesh.indices.is_empty()) else { continue };
        draws.push(Draw {
            scissor,
            first_index: indices.len() as u32,
            index_count: mesh.indices.len() as u32,
            vertex_offset: (words.len() / VERTEX_WORDS) as i32,
            set: texture.set,
            image: texture.image.raw,
        });
        indices.extend_from_slice(&mesh.indices);
        push_vertices(&mut words, &mesh.vertices);
    }
    (words, indices, draws)
}

impl SlotFrame {
    /// A frame with no buffers yet, its vertices bound through `set` (`allocate` makes them).
    pub fn new(set: vk::DescriptorSet) -> Self {
        Self {
            set,
            vertices: None,
            indices: None,
            staging: None,
            shown: false,
            screen_points: [0.0; 2],
            draws: Vec::new(),
            copies: Vec::new(),
        }
    }

    /// Make the frame's buffers at their smallest size (`MIN_BUFFER_BYTES`), each stored as it
    /// is made (on an error, `take_buffers` returns what was). Made up front, not at the first
    /// frame that needs them: which frames upload texels depends on the text the overlay shows
    /// (new glyphs), so buffers made on demand would make the count of live objects (`vk::live`,
    /// the soak's measure) depend on the run's pace.
    pub fn allocate(&mut self, device: &Device, slot: usize) -> Result<()> {
        let mut retired = Vec::new();
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        grow(device, &mut self.vertices, &format!("overlay vertices #{slot}"), 0, storage, &mut retired)?;
        let info = self.vertices.as_ref().expect("grown").descriptor();
        descriptor::write(device, self.set, &[(0, vk::DescriptorType::STORAGE_BUFFER, Descriptor::Buffer(info))]);
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        grow(device, &mut self.indices, &format!("overlay indices #{slot}"), 0, usage, &mut retired)?;
        let usage = vk::BufferUsageFlags::TRANSFER_SRC;
        grow(device, &mut self.staging, &format!("overlay staging #{slot}"), 0, usage, &mut retired)?;
        debug_assert!(retired.is_empty(), "nothing was there to replace");
        Ok(())
    }

    /// Nothing to draw or copy.
    pub fn clear(&mut self) {
        self.shown = false;
        self.draws.clear();
        self.copies.clear();
    }

    /// Write the frame's vertices and indices, growing the buffers as needed (a replaced buffer
    /// goes to `retired`; the set is pointed at a new vertex buffer).
    pub fn write_geometry(
        &mut self,
        device: &Device,
        slot: usize,
        (words, indices): (&[u32], &[u32]),
        retired: &mut Vec<Buffer>,
    ) -> Result<()> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let name = format!("overlay vertices #{slot}");
        if grow(device, &mut self.vertices, &name, std::mem::size_of_val(words), storage, retired)? {
            let info = self.vertices.as_ref().expect("grown").descriptor();
            descriptor::write(device, self.set, &[(0, vk::DescriptorType::STORAGE_BUFFER, Descriptor::Buffer(info))]);
        }
        let name = format!("overlay indices #{slot}");
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        grow(device, &mut self.indices, &name, std::mem::size_of_val(indices), usage, retired)?;
        self.vertices.as_mut().expect("grown").write(0, words);
        self.indices.as_mut().expect("grown").write(0, indices);
        Ok(())
    }

    /// Write the texels of every pending copy whose texture still exists into the staging
    /// buffer, and list the copies.
    pub fn stage_uploads(
        &mut self,
        device: &Device,
        slot: usize,
        textures: &Textures,
        retired: &mut Vec<Buffer>,
    ) -> Result<()> {
        let uploads: Vec<_> = textures.uploads.iter().filter_map(|u| Some((u, textures.get(u.id)?))).collect();
        if uploads.is_empty() {
            return Ok(());
        }
        let bytes = uploads.iter().map(|(u, _)| u.texels.len()).sum();
        let usage = vk::BufferUsageFlags::TRANSFER_SRC;
        grow(device, &mut self.staging, &format!("overlay staging #{slot}"), bytes, usage, retired)?;
        let staging = self.staging.as_mut().expect("grown");
        let mut offset = 0;
        for (upload, texture) in uploads {
            // RGBA8: every offset is a multiple of the texel size, as copies need.
            staging.write(offset, &upload.texels);
            let region = vk::BufferImageCopy::default()
                .buffer_offset(offset as u64)
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_offset(vk::Offset3D { x: upload.origin[0] as i32, y: upload.origin[1] as i32, z: 0 })
                .image_extent(vk::Extent3D { width: upload.extent.width, height: upload.extent.height, depth: 1 });
            self.copies.push(Copy { image: texture.image.raw, region });
            offset += upload.texels.len();
        }
        Ok(())
    }

    /// Every buffer, for destruction.
    pub fn take_buffers(&mut self) -> Vec<Buffer> {
        [self.vertices.take(), self.indices.take(), self.staging.take()].into_iter().flatten().collect()
    }
}

/// Make `buffer` hold at least `bytes` (host-visible, `usage`): a new one twice the size needed
/// (at least `MIN_BUFFER_BYTES`) when it does not, the old one to `retired`. Whether it was made.
fn grow(
    device: &Device,
    buffer: &mut Option<Buffer>,
    name: &str,
    bytes: usize,
    usage: vk::BufferUsageFlags,
    retired: &mut Vec<Buffer>,
) -> Result<bool> {
    if buffer.as_ref().is_some_and(|b| b.size >= bytes as u64) {
        return Ok(false);
    }
    let size = (2 * bytes as u64).max(MIN_BUFFER_BYTES);
    let new = Buffer::new(device, &BufferDesc::upload(name, size, usage))?;
    retired.extend(buffer.replace(new));
    Ok(true)
}

#[cfg(test)]
mod tests {
    use egui::{pos2, Rect};

    use super::*;

    const EXTENT: vk::Extent2D = vk::Extent2D { width: 100, height: 50 };

    fn rect(x: i32, y: i32, width: u32, height: u32) -> Option<vk::Rect2D> {
        Some(vk::Rect2D { offset: vk::Offset2D { x, y }, extent: vk::Extent2D { width, height } })
    }

    #[test]
    fn scissors_are_clips_in_pixels_inside_the_target() {
        let clip = Rect::from_min_max(pos2(10.0, 5.0), pos2(20.0, 15.0));
        assert_eq!(scissor(clip, 1.5, EXTENT), rect(15, 8, 15, 15), "rounded pixels");
        assert_eq!(scissor(Rect::EVERYTHING, 2.0, EXTENT), rect(0, 0, 100, 50), "clamped");
        let nan = Rect::from_min_max(pos2(f32::NAN, 0.0), pos2(10.0, f32::NAN));
        assert_eq!(scissor(nan, 1.0, EXTENT), None, "NaN: nothing");
        let off = Rect::from_min_max(pos2(200.0, 0.0), pos2(300.0, 10.0));
        assert_eq!(scissor(off, 1.0, EXTENT), None, "outside");
        assert_eq!(scissor(Rect::NOTHING, 1.0, EXTENT), None, "empty");
    }
}
