//! egui's textures on the GPU, by `egui::TextureId`: the images (`R8G8B8A8_UNORM`, egui's
//! gamma-space sRGB bytes as they are, see `shaders/overlay/overlay.frag`), one descriptor set each
//! (its own small pool: a replaced texture's set is freed with it, behind the frames that may
//! still bind it), the samplers egui's `TextureOptions` ask for, and the copies and frees
//! waiting for a frame (the copies kept disjoint per texture: `uploads`).
//!
//! A delta is checked whole before anything changes (`check`): bad input is refused with an
//! error, never a panic or an out-of-bounds read on the GPU.

use std::collections::HashMap;

use ash::vk;
use egui::epaint::{ImageData, Primitive};
use egui::TextureId;
use egui::{TextureFilter, TextureOptions, TextureWrapMode};

use crate::error::{Error, Result, VkContext};
use crate::render::overlay::uploads::{queue, Upload};
use crate::render::overlay::OverlayFrame;
use crate::vk::descriptor::{self, Binding, Resource as Descriptor};
use crate::vk::{Device, Guard, Image, ImageDesc};

/// Most vertices of one overlay frame (a `vkCmdDrawIndexed` vertex offset is an `i32`; egui's
/// panels use thousands).
pub const MAX_VERTICES: usize = 1 << 24;

/// One texture: the image, its set (binding 0: the image with its sampler) and options.
pub struct Texture {
    /// The image, `R8G8B8A8_UNORM`, sampled and copied into.
    pub image: Image,
    pool: vk::DescriptorPool,
    /// The set the overlay pass binds as set 1 for meshes of this texture.
    pub set: vk::DescriptorSet,
    options: TextureOptions,
}

impl Texture {
    /// Destroy the image and the set's pool.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            self.image.destroy(device);
        }
    }
}

/// What applying a delta changed in the images the graph tracks.
#[derive(Default)]
pub struct TextureChanges {
    /// New images: the graph must import them (`Access::Nothing`) before a pass uses them.
    pub created: Vec<vk::Image>,
    /// Replaced or freed textures: the graph forgets them; destroyed behind the frames in flight.
    pub retired: Vec<Texture>,
}

/// Samplers are shared by the textures with the same filters and wrap mode.
type SamplerKey = (TextureFilter, TextureFilter, TextureWrapMode);

/// The textures, their samplers, and the copies and frees not yet done.
pub struct Textures {
    /// Layout of a texture's set.
    pub set_layout: vk::DescriptorSetLayout,
    samplers: Vec<(SamplerKey, vk::Sampler)>,
    live: HashMap<TextureId, Texture>,
    /// Copies for the next frame that draws the overlay, in the order egui sent them.
    pub uploads: Vec<Upload>,
    /// Textures to free after the next submitted frame.
    pub frees: Vec<TextureId>,
}

/// The one binding of a texture's set.
pub fn texture_bindings() -> [Binding; 1] {
    let fs = vk::ShaderStageFlags::FRAGMENT;
    [Binding { binding: 0, kind: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages: fs }]
}

fn bad(message: String) -> Error {
    Error::BadInput(format!("overlay: {message}"))
}

impl Textures {
    /// No textures yet; sets of `set_layout`.
    pub fn new(set_layout: vk::DescriptorSetLayout) -> Self {
        Self { set_layout, samplers: Vec::new(), live: HashMap::new(), uploads: Vec::new(), frees: Vec::new() }
    }

    /// The texture `id`, if set and not freed.
    pub fn get(&self, id: TextureId) -> Option<&Texture> {
        self.live.get(&id)
    }

    /// Refuse a frame the overlay cannot draw: a scale that is not a positive number, an image
    /// whose texel count is not its size or larger than the device's images, a region outside
    /// its texture or of a texture never set, a mesh of an unknown texture or with an index past
    /// its vertices, a paint callback (meadow runs none), more than `MAX_VERTICES` vertices.
    pub fn check(&self, frame: &OverlayFrame, max_dimension: u32) -> Result<()> {
        let ppp = frame.pixels_per_point;
        if !(ppp.is_finite() && ppp > 0.0) {
            return Err(bad(format!("pixels_per_point must be a positive number, not {ppp}")));
        }
        let mut sizes: HashMap<TextureId, [usize; 2]> = self
            .live
            .iter()
            .map(|(id, t)| (*id, [t.image.extent.width as usize, t.image.extent.height as usize]))
            .collect();
        for (id, delta) in &frame.textures.set {
            let ImageData::Color(image) = &delta.image;
            let [width, height] = image.size;
            if width == 0 || height == 0 || image.pixels.len() != width * height {
                return Err(bad(format!("texture {id:?}: {} texels for a {width}×{height} image", image.pixels.len())));
            }
            match delta.pos {
                None if width.max(height) > max_dimension as usize => {
                    return Err(bad(format!("texture {id:?} of {width}×{height} exceeds the device's {max_dimension}")))
                }
                None => {
                    sizes.insert(*id, [width, height]);
                }
                Some([x, y]) => {
                    let Some(size) = sizes.get(id) else {
                        return Err(bad(format!("texture {id:?} is updated but was never set")));
                    };
                    let fits =
                        |at: usize, length: usize, whole: usize| at.checked_add(length).is_some_and(|e| e <= whole);
                    if !fits(x, width, size[0]) || !fits(y, height, size[1]) {
                        return Err(bad(format!(
                            "texture {id:?}: region at {x},{y} of {width}×{height} outside its {}×{}",
                            size[0], size[1]
                        )));
                    }
                }
            }
        }
        let mut vertices = 0usize;
        for clipped in &frame.primitives {
            let Primitive::Mesh(mesh) = &clipped.primitive else {
                return Err(bad("paint callbacks are not supported".into()));
            };
            if !sizes.contains_key(&mesh.texture_id) {
                return Err(bad(format!("a mesh uses texture {:?}, never set", mesh.texture_id)));
            }
            if mesh.indices.iter().any(|&i| i as usize >= mesh.vertices.len()) {
                return Err(bad(format!("a mesh indexes past its {} vertices", mesh.vertices.len())));
            }
            vertices += mesh.vertices.len();
        }
        if vertices > MAX_VERTICES {
            return Err(bad(format!("{vertices} vertices in one frame (at most {MAX_VERTICES})")));
        }
        Ok(())
    }

    /// Apply the `set`s of a delta (checked by `check`): a whole image replaces the texture's
    /// contents (a new image when the size or options changed), a region updates it; the texels
    /// are copied by the next frame that draws. The frees wait for the next submitted frame.
    /// What changed is added to `changes` even when a later set fails.
    pub fn apply(&mut self, device: &Device, delta: egui::TexturesDelta, changes: &mut TextureChanges) -> Result<()> {
        for (id, image_delta) in delta.set {
            let ImageData::Color(image) = &image_delta.image;
            let [width, height] = image.size.map(|n| n as u32);
            let extent = vk::Extent2D { width, height };
            let texels: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
            let origin = match image_delta.pos {
                Some([x, y]) => [x as u32, y as u32],
                None => {
                    // The whole texture: earlier copies into it are superseded.
                    self.uploads.retain(|u| u.id != id);
                    let options = image_delta.options;
                    let reusable = self.live.get(&id).is_some_and(|t| t.image.extent == extent && t.options == options);
                    if !reusable {
                        let texture = self.create(device, id, extent, options)?;
                        changes.created.push(texture.image.raw);
                        changes.retired.extend(self.live.insert(id, texture));
                    }
                    [0, 0]
                }
            };
            queue(&mut self.uploads, Upload { id, origin, extent, texels });
        }
        self.frees.extend(delta.free);
        Ok(())
    }

    /// Remove the textures freed since the last submitted frame (with their pending copies):
    /// to be destroyed behind the frames that may still sample them.
    pub fn take_frees(&mut self) -> Vec<Texture> {
        let frees = std::mem::take(&mut self.frees);
        self.uploads.retain(|u| !frees.contains(&u.id));
        frees.iter().filter_map(|id| self.live.remove(id)).collect()
    }

    /// A texture's image, its set pointing at it with the sampler for `options`.
    fn create(
        &mut self,
        device: &Device,
        id: TextureId,
        extent: vk::Extent2D,
        options: TextureOptions,
    ) -> Result<Texture> {
        let sampler = self.sampler(device, options)?;
        let name = format!("overlay texture {id:?}");
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let desc = ImageDesc::color(&name, vk::Format::R8G8B8A8_UNORM, extent, usage);
        let image = Guard::new(device, Image::new(device, &desc)?);
        let bindings = texture_bindings();
        let (pool, sets) = descriptor::allocate_sets(device, &format!("{name} set"), self.set_layout, &bindings, 1)?;
        let (image, set) = (image.take(), sets[0]);
        let info = vk::DescriptorImageInfo {
            sampler,
            image_view: image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        descriptor::write(device, set, &[(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, Descriptor::Image(info))]);
        Ok(Texture { image, pool, set, options })
    }

    /// The sampler for `options`' filters and wrap mode (no mipmaps: egui's textures have one
    /// level), made on first use.
    fn sampler(&mut self, device: &Device, options: TextureOptions) -> Result<vk::Sampler> {
        let key = (options.magnification, options.minification, options.wrap_mode);
        if let Some((_, sampler)) = self.samplers.iter().find(|(k, _)| *k == key) {
            return Ok(*sampler);
        }
        let filter = |f: TextureFilter| match f {
            TextureFilter::Nearest => vk::Filter::NEAREST,
            TextureFilter::Linear => vk::Filter::LINEAR,
        };
        let address = match options.wrap_mode {
            TextureWrapMode::ClampToEdge => vk::SamplerAddressMode::CLAMP_TO_EDGE,
            TextureWrapMode::Repeat => vk::SamplerAddressMode::REPEAT,
            TextureWrapMode::MirroredRepeat => vk::SamplerAddressMode::MIRRORED_REPEAT,
        };
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter(options.magnification))
            .min_filter(filter(options.minification))
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(address)
            .address_mode_v(address)
            .address_mode_w(address)
            .max_lod(0.0);
        // SAFETY: valid create info.
        let sampler =
            crate::vk::live::created(unsafe { device.raw.create_sampler(&info, None) }.vk("vkCreateSampler")?);
        device.set_name(sampler, &format!("overlay sampler {key:?}"));
        self.samplers.push((key, sampler));
        Ok(sampler)
    }

    /// Destroy every texture, sampler and the set layout.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(&mut self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            for (_, texture) in self.live.drain() {
                texture.destroy(device);
            }
            for (_, sampler) in self.samplers.drain(..) {
                crate::vk::live::destroyed(sampler);
                device.raw.destroy_sampler(sampler, None);
            }
            crate::vk::live::destroyed(self.set_layout);
            device.raw.destroy_descriptor_set_layout(self.set_layout, None);
            self.set_layout = vk::DescriptorSetLayout::null();
        }
        self.uploads.clear();
        self.frees.clear();
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use egui::epaint::{ClippedPrimitive, ColorImage, ImageDelta, Mesh, PaintCallback, Vertex};
    use egui::{Color32, Rect, TexturesDelta};

    use super::*;

    const FONT: TextureId = TextureId::Managed(0);

    fn image(width: usize, height: usize) -> ColorImage {
        ColorImage::new([width, height], vec![Color32::WHITE; width * height])
    }

    fn mesh(texture: TextureId, indices: Vec<u32>) -> ClippedPrimitive {
        let mut mesh = Mesh::with_texture(texture);
        mesh.vertices = vec![Vertex::default(); 3];
        mesh.indices = indices;
        ClippedPrimitive { clip_rect: Rect::EVERYTHING, primitive: Primitive::Mesh(mesh) }
    }

    fn frame(set: Vec<(TextureId, ImageDelta)>, primitives: Vec<ClippedPrimitive>) -> OverlayFrame {
        OverlayFrame { primitives, textures: TexturesDelta { set, free: Vec::new() }, pixels_per_point: 1.0 }
    }

    fn refusal(frame: &OverlayFrame) -> String {
        let textures = Textures::new(vk::DescriptorSetLayout::null());
        match textures.check(frame, 4096) {
            Err(Error::BadInput(message)) => message,
            other => panic!("not refused as bad input: {other:?}"),
        }
    }

    #[test]
    fn a_font_set_with_meshes_and_a_region_inside_it_is_accepted() {
        let full = (FONT, ImageDelta::full(image(8, 4), TextureOptions::LINEAR));
        let part = (FONT, ImageDelta::partial([6, 2], image(2, 2), TextureOptions::LINEAR));
        let textures = Textures::new(vk::DescriptorSetLayout::null());
        assert!(textures.check(&frame(vec![full, part], vec![mesh(FONT, vec![0, 1, 2])]), 4096).is_ok());
    }

    #[test]
    fn bad_frames_are_refused_with_a_reason() {
        let full = || (FONT, ImageDelta::full(image(8, 4), TextureOptions::LINEAR));
        let mut scaled = frame(vec![full()], Vec::new());
        scaled.pixels_per_point = f32::NAN;
        assert!(refusal(&scaled).contains("pixels_per_point"));
        let short = ColorImage { size: [8, 4], source_size: egui::Vec2::ZERO, pixels: vec![Color32::WHITE; 3] };
        let short = (FONT, ImageDelta::full(short, TextureOptions::LINEAR));
        assert!(refusal(&frame(vec![short], Vec::new())).contains("3 texels for a 8×4"));
        let huge = (FONT, ImageDelta::full(image(5000, 1), TextureOptions::LINEAR));
        assert!(refusal(&frame(vec![huge], Vec::new())).contains("exceeds"));
        let orphan = (FONT, ImageDelta::partial([0, 0], image(2, 2), TextureOptions::LINEAR));
        assert!(refusal(&frame(vec![orphan], Vec::new())).contains("never set"));
        let outside = (FONT, ImageDelta::partial([7, 0], image(2, 2), TextureOptions::LINEAR));
        assert!(refusal(&frame(vec![full(), outside], Vec::new())).contains("outside"));
        let far = (FONT, ImageDelta::partial([usize::MAX, 0], image(2, 2), TextureOptions::LINEAR));
        assert!(refusal(&frame(vec![full(), far], Vec::new())).contains("outside"));
        let unknown = mesh(TextureId::User(7), vec![0, 1, 2]);
        assert!(refusal(&frame(vec![full()], vec![unknown])).contains("never set"));
        let past = mesh(FONT, vec![0, 1, 3]);
        assert!(refusal(&frame(vec![full()], vec![past])).contains("past its 3 vertices"));
        let callback = PaintCallback { rect: Rect::EVERYTHING, callback: Arc::new(0u8) };
        let callback = ClippedPrimitive { clip_rect: Rect::EVERYTHING, primitive: Primitive::Callback(callback) };
        assert!(refusal(&frame(vec![full()], vec![callback])).contains("callbacks"));
    }
}
