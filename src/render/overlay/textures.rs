//! egui's textures on the GPU, by `egui::TextureId`: the images (`R8G8B8A8_UNORM`, egui's
//! gamma-space sRGB bytes as they are, see `shaders/overlay/overlay.frag`), one descriptor set each
//! (its own small pool: a replaced texture's set is freed with it, behind the frames that may
//! still bind it), the samplers egui's `TextureOptions` ask for, and the copies and frees
//! waiting for a frame.
//!
//! A delta is checked whole before anything changes (`check`): bad input is refused with an
//! error, never a panic or an out-of-bounds read on the GPU.

use std::collections::HashMap;

use ash::vk;
use egui::epaint::{ImageData, Primitive};
use egui::TextureId;
use egui::{TextureFilter, TextureOptions, TextureWrapMode};

use crate::error::{Error, Result, VkContext};
use crate::render::overlay::OverlayFrame;
use crate::vk::descriptor::{self, Binding, Resource as Descriptor};
use crate::vk::{Device, Image, ImageDesc};

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

/// Texels waiting to be copied into a texture by the next frame that draws the overlay. The
/// pending uploads of one texture never overlap (`queue`): one frame's copies into an image
/// write disjoint texels, so they need no order among themselves.
#[derive(Clone, Debug, PartialEq)]
pub struct Upload {
    /// The texture (looked up when the copy is staged: the image may have been replaced since).
    pub id: TextureId,
    /// Top-left texel of the region.
    pub origin: [u32; 2],
    /// Size of the region.
    pub extent: vk::Extent2D,
    /// RGBA8 texels, rows tightly packed.
    pub texels: Vec<u8>,
}

/// What applying a delta changed in the images the graph tracks.
#[derive(Default)]
pub struct TextureChanges {
    /// New images: the graph must import them (`Access::Nothing`) before a pass uses them.
    pub created: Vec<vk::Image>,
    /// Replaced or freed textures: the graph forgets them; destroyed behind the frames in flight.
    pub retired: Vec<Texture>,
}

/// A region in texels: [x0, y0, x1, y1), x1 > x0 and y1 > y0.
type Rect = [u32; 4];

impl Upload {
    fn rect(&self) -> Rect {
        let [x, y] = self.origin;
        [x, y, x + self.extent.width, y + self.extent.height]
    }

    /// Where in `texels` the texel at texture coordinates (x, y) starts (inside the region).
    fn offset(&self, x: u32, y: u32) -> usize {
        4 * ((y - self.origin[1]) as usize * self.extent.width as usize + (x - self.origin[0]) as usize)
    }

    /// The part of the region inside `rect` (which lies inside it), with its texels.
    fn crop(&self, rect: Rect) -> Upload {
        let [x0, y0, x1, y1] = rect;
        let row = 4 * (x1 - x0) as usize;
        let mut texels = Vec::with_capacity(row * (y1 - y0) as usize);
        for y in y0..y1 {
            let start = self.offset(x0, y);
            texels.extend_from_slice(&self.texels[start..start + row]);
        }
        Upload { id: self.id, origin: [x0, y0], extent: vk::Extent2D { width: x1 - x0, height: y1 - y0 }, texels }
    }

    /// Write `later`'s texels inside `rect` (in both regions) over this region's.
    fn overwrite(&mut self, later: &Upload, rect: Rect) {
        let [x0, y0, x1, _] = rect;
        let row = 4 * (x1 - x0) as usize;
        for y in y0..rect[3] {
            let (to, from) = (self.offset(x0, y), later.offset(x0, y));
            self.texels[to..to + row].copy_from_slice(&later.texels[from..from + row]);
        }
    }
}

/// Where `a` and `b` overlap, if they do.
fn overlap(a: Rect, b: Rect) -> Option<Rect> {
    let r = [a[0].max(b[0]), a[1].max(b[1]), a[2].min(b[2]), a[3].min(b[3])];
    (r[0] < r[2] && r[1] < r[3]).then_some(r)
}

/// `outer` without `inner` (inside it): the bands above and below it, and either side of it.
fn around(outer: Rect, inner: Rect) -> impl Iterator<Item = Rect> {
    let [ox0, oy0, ox1, oy1] = outer;
    let [ix0, iy0, ix1, iy1] = inner;
    [[ox0, oy0, ox1, iy0], [ox0, iy1, ox1, oy1], [ox0, iy0, ix0, iy1], [ix1, iy0, ox1, iy1]]
        .into_iter()
        .filter(|r| r[0] < r[2] && r[1] < r[3])
}

/// Add `upload` to `uploads`, the pending copies of every texture, keeping each texture's
/// disjoint: where it overlaps a pending region of its texture, its texels are written into
/// that region's (the later texels win, as the copies in egui's order would have it), and only
/// the rest is added, as rectangles around each overlap. Without this, a texture set whole and
/// patched before a frame draws — egui's font after `Viewer::replace_renderer` resends it,
/// patched with the frame's new glyphs — would be copied twice into the same texels by one
/// pass, with no barrier between the copies (a write-after-write hazard).
fn queue(uploads: &mut Vec<Upload>, upload: Upload) {
    let id = upload.id;
    let mut pieces = vec![upload];
    for pending in uploads.iter_mut().filter(|u| u.id == id) {
        let mut rest = Vec::with_capacity(pieces.len());
        for piece in pieces {
            match overlap(pending.rect(), piece.rect()) {
                Some(shared) => {
                    pending.overwrite(&piece, shared);
                    rest.extend(around(piece.rect(), shared).map(|r| piece.crop(r)));
                }
                None => rest.push(piece),
            }
        }
        pieces = rest;
        if pieces.is_empty() {
            return;
        }
    }
    uploads.extend(pieces);
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
        let image = Image::new(device, &ImageDesc::color(&name, vk::Format::R8G8B8A8_UNORM, extent, usage))?;
        let bindings = texture_bindings();
        let (pool, set) = match descriptor::allocate_sets(device, &format!("{name} set"), self.set_layout, &bindings, 1)
        {
            Ok((pool, sets)) => (pool, sets[0]),
            Err(e) => {
                // SAFETY: never used by the GPU.
                unsafe { image.destroy(device) };
                return Err(e);
            }
        };
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

    /// An upload of `width`×`height` texels at (x, y), every texel `value`.
    fn region(id: TextureId, [x, y]: [u32; 2], [width, height]: [u32; 2], value: u8) -> Upload {
        let texels = vec![value; 4 * (width * height) as usize];
        Upload { id, origin: [x, y], extent: vk::Extent2D { width, height }, texels }
    }

    /// `uploads` copied in the order given into a `side`² RGBA8 image of `id`.
    fn paint(uploads: &[Upload], id: TextureId, side: u32) -> Vec<u8> {
        let mut image = vec![0u8; 4 * (side * side) as usize];
        for u in uploads.iter().filter(|u| u.id == id) {
            for y in 0..u.extent.height {
                for x in 0..u.extent.width {
                    let to = 4 * ((u.origin[1] + y) * side + u.origin[0] + x) as usize;
                    let from = u.offset(u.origin[0] + x, u.origin[1] + y);
                    image[to..to + 4].copy_from_slice(&u.texels[from..from + 4]);
                }
            }
        }
        image
    }

    #[test]
    fn a_patch_of_a_pending_whole_texture_is_written_into_its_texels() {
        // The font resent whole after a renderer replacement, then the frame's new glyphs.
        let mut uploads = Vec::new();
        queue(&mut uploads, region(FONT, [0, 0], [8, 8], 1));
        queue(&mut uploads, region(FONT, [2, 3], [4, 2], 2));
        assert_eq!(uploads.len(), 1, "one copy into the font");
        let texel = |x: usize, y: usize| uploads[0].texels[4 * (y * 8 + x)];
        assert_eq!((texel(2, 3), texel(5, 4), texel(6, 4), texel(2, 5)), (2, 2, 1, 1));
        // Another texture's pending copy is left alone.
        queue(&mut uploads, region(TextureId::User(1), [0, 0], [4, 4], 3));
        assert_eq!(uploads.len(), 2);
    }

    #[test]
    fn pending_uploads_stay_disjoint_and_paint_what_egui_s_order_paints() {
        let mut rng = crate::scene::rng::Rng::new(7);
        let mut below = |n: u32| (rng.next_u64() % u64::from(n)) as u32;
        for round in 0..200 {
            let (mut queued, mut sent) = (Vec::new(), Vec::new());
            for value in 1..=6u8 {
                let (x, y) = (below(16), below(16));
                let size = [1 + below(16 - x), 1 + below(16 - y)];
                let upload = region(FONT, [x, y], size, value + 10 * (round % 20) as u8);
                sent.push(upload.clone());
                queue(&mut queued, upload);
            }
            for (i, a) in queued.iter().enumerate() {
                for b in &queued[i + 1..] {
                    assert_eq!(overlap(a.rect(), b.rect()), None, "round {round}: {a:?} overlaps {b:?}");
                }
            }
            let in_order = paint(&sent, FONT, 16);
            queued.reverse();
            assert_eq!(paint(&queued, FONT, 16), in_order, "round {round}: the copies' order mattered");
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
