//! The far field's atlas (issue #37 item 2), baked by meadow's own blades in two run-once passes:
//!
//! - [`AtlasBakePass`] draws the block's blades (the ones a block field repeats over the world)
//!   from the side, orthographic, neutral, with the blade outline's alpha test and the blades'
//!   diffuse colour and rim (`shaders/far_field/atlas_bake.vert`, `.frag`, sharing
//!   `blades/blade_place.glsl` and the outline texture with the blade pass): `TILES` tiles, tile k
//!   the blades rooted in the block's metre k along z, their roots folded into one metre across
//!   so a tile repeats without a seam. One image holds the premultiplied albedo and the coverage,
//!   the other the premultiplied height along the blade (Belyaev's l of §2.3, for the far field's
//!   l⁶ terms). Level 0 is supersampled: about 2 mm a texel, eight texels across the widest blade,
//!   where the far field samples its coarser levels.
//! - [`AtlasMipsPass`] box-filters each level from the one before, one step per level
//!   (`atlas_mips.comp`): the atlas is premultiplied, so the mean is right for every channel and
//!   each level's mean coverage is level 0's (the far field's hashed coverage test keeps it on
//!   screen too, `far.frag`; no alpha scaling per level is needed).
//!
//! With flowers, tiles 0 and 1 are grass alone and tiles 2 and 3 hold flowers at the share the
//! cover allows at most (`scene::Scene::far_flower_share`): a far plant takes the flower tiles
//! where the share at its place calls for them (`far.vert`), so the far field's flowers follow the
//! covering map's green as the near ones do.
//!
//! Both run once (`Runs::OnChange`), keyed on the blades they draw (`bake_key`: their count, shape,
//! colours and density, and the flower tiles' share): a rebuild of the renderer whose blades have the same key keeps the baked
//! atlas and adds no bake (`Atlas::baked`; the viewer's view distance, far-field mesh, wind or
//! LOD), one with another key (another scene, density, clumps or segments) bakes a new one. The
//! bake's GPU time is the first frame's `far atlas` and `far atlas mips` passes (`meadow render`
//! prints it).

use std::rc::Rc;

use ash::vk;

use crate::error::{Result, VkContext};
use crate::render::graph::{Attachment, Declaration, Load, Pass, PassContext, Rendering, Runs};
use crate::render::passes::PipelineTarget;
use crate::render::recording::{self, PassSet, PassSetDesc};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::image::{Image, ImageDesc};
use crate::vk::{pipeline, Access, Device, Guard, Resource};

/// Tiles of patches of blades.
pub const TILES: u32 = 4;
/// A tile's width (m): one metre of the block across.
pub const TILE_WIDTH_M: f32 = 1.0;
/// A tile's height (m): the tallest blade, with room for its lean.
pub const TILE_HEIGHT_M: f32 = 0.6;
/// A tile's texels across and up.
pub const TILE_TEXELS: (u32, u32) = (512, 256);
/// Each of the atlas's two images: the tiles side by side.
pub const EXTENT: vk::Extent2D = vk::Extent2D { width: TILES * TILE_TEXELS.0, height: TILE_TEXELS.1 };
/// Mip levels: down to 8 × 1 texels.
pub const MIPS: u32 = 9;
/// The texels' format: premultiplied, linear, half floats (8-bit steps would be a third of a
/// root's premultiplied albedo at 30 % coverage).
pub const FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// Segments of a baked blade.
pub const BAKE_SEGMENTS: u32 = 8;
/// What each image holds, in the order of `Atlas::images`: the bake's `output`.
const OUTPUTS: [&str; 2] = ["far atlas albedo", "far atlas height"];

const _: () = assert!(TILE_TEXELS.1 >> (MIPS - 1) >= 1);

/// The atlas: two images of the same tiles (the albedo and coverage; the height along the blade
/// and coverage: two images, not two rows of one, so no level blends one into the other), a view
/// of each level of each, the bake's depth and the sampler the far field reads them with
/// (trilinear; the tiles repeat across in the shader). Owned by the passes that bake it (`Rc`):
/// the last to go destroys it; the far field's draw names its handles (`AtlasHandles`).
pub struct Atlas {
    images: [Image; 2],
    levels: [Vec<vk::ImageView>; 2],
    depth: Image,
    sampler: vk::Sampler,
    /// The key of the bake whose frame was recorded (the mips, its last pass), `None` before it or
    /// when that frame was dropped: a rebuilt graph keeps the atlas only if it holds this bake.
    baked: std::cell::Cell<Option<u64>>,
}

impl Atlas {
    /// Create the atlas (not yet baked: the graph imports its levels as never written).
    pub fn new(device: &Device) -> Result<Self> {
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC; // read back by `Renderer::far_atlas_coverage`
        let image = |name| Image::new(device, &ImageDesc::color(name, FORMAT, EXTENT, usage).with_mips(MIPS));
        let albedo = Guard::new(device, image(OUTPUTS[0])?);
        // If the second fails, the guard destroys the first.
        let height = image(OUTPUTS[1])?;
        let images = Guard::new(device, (albedo.take(), height));
        let mut levels = Guard::new(device, (Vec::new(), Vec::new()));
        for level in 0..MIPS {
            levels.0.push(images.0.mip_view(device, level, OUTPUTS[0])?);
            levels.1.push(images.1.mip_view(device, level, OUTPUTS[1])?);
        }
        let depth =
            Guard::new(device, Image::new(device, &ImageDesc::depth("far atlas depth", device.depth_format, EXTENT))?);
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(MIPS as f32);
        // SAFETY: valid create info.
        let sampler = unsafe { device.raw.create_sampler(&info, None) }.vk("vkCreateSampler")?;
        let sampler = crate::vk::live::created(sampler);
        device.set_name(sampler, "far atlas sampler");
        let (images, levels) = (images.take(), levels.take());
        let (depth, baked) = (depth.take(), Default::default());
        Ok(Self { images: [images.0, images.1], levels: [levels.0, levels.1], depth, sampler, baked })
    }

    /// The key of the bake it holds, once that bake's frame is recorded (`AtlasMipsPass`).
    pub fn baked(&self) -> Option<u64> {
        self.baked.get()
    }

    /// Its handles, for the passes that read it.
    pub fn handles(&self) -> AtlasHandles {
        let sampled = |image: &Image| vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        AtlasHandles {
            images: [self.images[0].raw, self.images[1].raw],
            sampled: [sampled(&self.images[0]), sampled(&self.images[1])],
        }
    }

    /// Its depth attachment.
    pub fn depth(&self) -> Resource {
        Resource::depth(self.depth.raw)
    }
}

impl crate::vk::Destroy for Atlas {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            for view in self.levels.into_iter().flatten() {
                crate::vk::live::destroyed(view);
                device.raw.destroy_image_view(view, None);
            }
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            let [albedo, height] = self.images;
            albedo.destroy(device);
            height.destroy(device);
            self.depth.destroy(device);
        }
    }
}

/// The atlas as the passes that read it name it: its images and the whole of each sampled.
#[derive(Clone, Copy, Debug)]
pub struct AtlasHandles {
    images: [vk::Image; 2],
    sampled: [vk::DescriptorImageInfo; 2],
}

impl AtlasHandles {
    /// Image `image` (0 the albedo and coverage, 1 the height and coverage).
    pub fn image(&self, image: usize) -> vk::Image {
        self.images[image]
    }

    /// Level `level` of image `image` (0 the albedo, 1 the height) as a tracked resource.
    pub fn level(&self, image: usize, level: u32) -> Resource {
        Resource::Image { raw: self.images[image], aspect: vk::ImageAspectFlags::COLOR, base_mip: level, mips: 1 }
    }

    /// Every level of both images as tracked resources.
    pub fn levels(&self) -> impl Iterator<Item = Resource> + '_ {
        (0..2).flat_map(move |image| (0..MIPS).map(move |level| self.level(image, level)))
    }

    /// Image `image` as the far field samples it.
    pub fn sampled(&self, image: usize) -> Descriptor {
        Descriptor::Image(self.sampled[image])
    }
}

/// A digest of the blades a bake draws and the share of them the flowers claim in the flower
/// tiles (`scene::Scene::far_flower_share`): the key it runs again on.
pub fn bake_key(blades: &[crate::scene::blades::BladeInstance], flower_share: f32) -> u64 {
    let bytes: &[u8] = bytemuck::cast_slice(blades);
    let share = flower_share.to_bits().to_le_bytes();
    let all = bytes.iter().chain(&share);
    all.fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// One image's bake (`output`: 0 the albedo, 1 the height): its pipeline and the atlas.
pub struct AtlasBakePass {
    pipeline: vk::Pipeline,
    /// With flowers: their heads' (the shaders' variant `heads`), drawn after the blades.
    heads: Option<vk::Pipeline>,
    layout: vk::PipelineLayout,
    atlas: Rc<Atlas>,
    output: u32,
    blades: (vk::Buffer, u32),
    /// The flower tiles' share in 16 bits (`atlas_bake.vert`'s `BakePush`), 0 without flowers.
    flower_tiles: u32,
    key: u64,
}

impl AtlasBakePass {
    /// Build the bake of `scene`'s blades (`key`: `bake_key` of them) into image `output` of `atlas`.
    pub fn new(
        device: &Device,
        (target, constants): (PipelineTarget, &Specialization),
        scene: &SceneGpu,
        (atlas, output): (Rc<Atlas>, u32),
        key: u64,
    ) -> Result<Self> {
        let bake = |heads: bool| {
            let (vertex, fragment) = match heads {
                true => (shaders::ATLAS_BAKE_HEADS_VERT, shaders::ATLAS_BAKE_HEADS_FRAG),
                false => (shaders::ATLAS_BAKE_VERT, shaders::ATLAS_BAKE_FRAG),
            };
            bake_pipeline(device, (target, constants), OUTPUTS[output as usize], (vertex, fragment))
        };
        let pipeline = Guard::new(device, bake(false)?);
        let heads = (constants.flower_share != 0).then(|| bake(true)).transpose()?;
        let blades = (scene.blades.raw, scene.blade_count);
        let flower_tiles = (scene.far_flower_share.clamp(0.0, 1.0) * 65535.0).round() as u32;
        let layout = target.layout;
        Ok(Self { pipeline: pipeline.take(), heads, layout, atlas, output, blades, flower_tiles, key })
    }
}

/// A bake's pipeline (`name`), of `stages`: the blades' or the flowers' heads'.
fn bake_pipeline(
    device: &Device,
    (target, constants): (PipelineTarget, &Specialization),
    name: &str,
    (vertex, fragment): (crate::vk::profile::Shader, crate::vk::profile::Shader),
) -> Result<vk::Pipeline> {
    pipeline::graphics(
        device,
        &pipeline::GraphicsDesc {
            name,
            vertex: vertex.code(device.profile),
            fragment: fragment.code(device.profile),
            topology: vk::PrimitiveTopology::TRIANGLE_STRIP,
            cull: vk::CullModeFlags::NONE,
            polygon: vk::PolygonMode::FILL,
            depth_compare: vk::CompareOp::LESS,
            depth_write: true,
            color_format: FORMAT,
            depth_format: device.depth_format,
            layout: target.layout,
            constants: &constants.named(),
            vertex_stride: 0,
            samples: vk::SampleCountFlags::TYPE_1,
            blend: pipeline::Blend::Opaque,
        },
    )
}

impl Pass for AtlasBakePass {
    fn name(&self) -> &'static str {
        OUTPUTS[self.output as usize]
    }

    fn runs(&self, _ctx: &PassContext) -> Runs {
        Runs::OnChange(self.key)
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let color = Load::Clear(vk::ClearValue { color: vk::ClearColorValue { float32: [0.0; 4] } });
        let far = Load::Clear(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } });
        let (image, view) = (self.atlas.images[self.output as usize].raw, self.atlas.levels[self.output as usize][0]);
        let depth = &self.atlas.depth;
        let rendering = Rendering {
            extent: EXTENT,
            color: Some(Attachment { image, view, load: color, store: true }),
            depth: Some(Attachment { image: depth.raw, view: depth.view, load: far, store: false }),
            depth_write: true,
            pipeline: self.pipeline,
            secondary: false,
        };
        Some(Declaration::graphics(rendering).buffer(self.blades.0, ctx.device.profile.vertex_fetch()))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        recording::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::GRAPHICS);
        // SAFETY: cmd is recording inside this pass's rendering instance.
        unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline) };
        let (w, h) = TILE_TEXELS;
        for tile in 0..TILES {
            let viewport = vk::Viewport {
                x: (tile * w) as f32,
                y: 0.0,
                width: w as f32,
                height: h as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            };
            let area = vk::Rect2D {
                offset: vk::Offset2D { x: (tile * w) as i32, y: 0 },
                extent: vk::Extent2D { width: w, height: h },
            };
            let code = tile | (self.output << 8) | (self.flower_tiles << 16);
            // SAFETY: as above; the push range is the scene layout's (vertex, 4 bytes).
            unsafe {
                device.raw.cmd_set_viewport(cmd, 0, &[viewport]);
                device.raw.cmd_set_scissor(cmd, 0, &[area]);
                device.raw.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::VERTEX, 0, &code.to_ne_bytes());
                device.raw.cmd_draw(cmd, 2 * (BAKE_SEGMENTS + 1), 3 * self.blades.1, 0, 0);
                if let Some(heads) = self.heads {
                    // The flowers' heads over the tile's stems: a square of 4 vertices a blade.
                    device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, heads);
                    device.raw.cmd_draw(cmd, 4, 3 * self.blades.1, 0, 0);
                    device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
                }
            }
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract; the atlas goes with its last pass.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::Destroy::destroy(self.heads, device);
            crate::vk::Destroy::destroy(self.atlas, device);
        }
    }
}

/// The mips: a step per image and level, each the mean of the level before.
pub struct AtlasMipsPass {
    pipeline: vk::Pipeline,
    /// Set `image · (MIPS - 1) + l` reads level l of `image` and writes level l + 1.
    sets: PassSet,
    atlas: Rc<Atlas>,
    key: u64,
    /// The frame being recorded holds the bake (reset when the next frame is planned).
    recording: std::cell::Cell<bool>,
}

impl AtlasMipsPass {
    /// Build the pass over `atlas`'s levels.
    pub fn new(device: &Device, atlas: Rc<Atlas>, key: u64) -> Result<Self> {
        let shader = shaders::ATLAS_MIPS_COMP.code(device.profile);
        let steps = (2 * (MIPS - 1)) as usize;
        let desc =
            PassSetDesc { name: "far atlas mips", shaders: &[("mips", shader)], before: &[], push: &[], frames: steps };
        let storage = |view| {
            let image_layout = vk::ImageLayout::GENERAL;
            Descriptor::Image(vk::DescriptorImageInfo { sampler: vk::Sampler::null(), image_view: view, image_layout })
        };
        let per_image = (MIPS - 1) as usize;
        let sets = PassSet::new(device, &desc, |step| {
            let (image, level) = (step / per_image, step % per_image);
            let levels = &atlas.levels[image];
            vec![("finer", storage(levels[level])), ("coarser", storage(levels[level + 1]))]
        })?;
        let sets = Guard::new(device, sets);
        let pipeline = pipeline::compute(device, "far atlas mips", shader, sets.layout, &[])?;
        Ok(Self { pipeline, sets: sets.take(), atlas, key, recording: Default::default() })
    }
}

impl Pass for AtlasMipsPass {
    fn name(&self) -> &'static str {
        "far atlas mips"
    }

    fn runs(&self, _ctx: &PassContext) -> Runs {
        // A frame is planned: the one before was submitted, or told it was dropped.
        self.recording.set(false);
        Runs::OnChange(self.key)
    }

    fn declare(&self, _ctx: &PassContext) -> Option<Declaration> {
        let handles = self.atlas.handles();
        let mut declaration = Declaration::compute();
        for image in 0..2 {
            for level in 1..MIPS {
                declaration = declaration
                    .step("level")
                    .uses(handles.level(image, level - 1), Access::ComputeShaderRead)
                    .uses(handles.level(image, level), Access::ComputeShaderWrite);
            }
        }
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let level = (ctx.step as u32) % (MIPS - 1) + 1;
        let extent = ((EXTENT.width >> level).max(1), (EXTENT.height >> level).max(1));
        // SAFETY: cmd is recording outside a rendering instance; set `step` matches the layout.
        unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline) };
        self.sets.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.step);
        // SAFETY: as above.
        unsafe { device.raw.cmd_dispatch(cmd, extent.0.div_ceil(8), extent.1.div_ceil(8), 1) };
        self.atlas.baked.set(Some(self.key));
        self.recording.set(true);
        Ok(())
    }

    fn frame_dropped(&self) {
        // The bake's frame will not run: the graph runs it again, and until then the atlas holds
        // no bake. (A later frame dropped leaves the bake.)
        if self.recording.get() {
            self.atlas.baked.set(None);
        }
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract; the atlas goes with its last pass.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.sets.destroy(device);
            crate::vk::Destroy::destroy(self.atlas, device);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::field::FieldSpec;
    use crate::scene::Scene;

    #[test]
    fn the_bake_runs_again_when_the_blades_change_and_only_then() {
        // The key is a digest of the block's blades: another density (or seed) is another look,
        // the same scene built again the same key (the graph's `Runs::OnChange` reruns on it).
        let key = |density, seed| bake_key(&Scene::blocks(FieldSpec { size: None, density }, seed).blades, 0.0);
        assert_eq!(key(400.0, 1), key(400.0, 1));
        assert_ne!(key(400.0, 1), key(200.0, 1));
        assert_ne!(key(400.0, 1), key(400.0, 2));
        // Flowers claim blades: another look.
        let blades = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1).blades;
        assert_ne!(bake_key(&blades, 0.0), bake_key(&blades, 0.05));
    }
}
