//! Set `SET_SCENE`, which every scene pass binds: its binding numbers (`shaders/common/shared.glsl`),
//! descriptor types and stages (`bindings`), and how the upload leaves the blades for the graph
//! (`BLADE_READS`). `render::scene_gpu` fills it with the scene's resources.

use ash::vk;

use crate::vk::descriptor::Binding;
use crate::vk::Access;

/// Binding numbers of set 0, generated from `shaders/common/shared.glsl` (`BINDING_*`).
pub mod binding {
    use crate::render::gpu_constants as gpu;

    /// `FrameUniforms` uniform buffer.
    pub const FRAME: u32 = gpu::BINDING_FRAME;
    /// Terrain heights storage buffer.
    pub const HEIGHTS: u32 = gpu::BINDING_HEIGHTS;
    /// Blade alpha texture.
    pub const BLADE_ALPHA: u32 = gpu::BINDING_BLADE_ALPHA;
    /// `BladeCluster[]` storage buffer.
    pub const CLUSTERS: u32 = gpu::BINDING_CLUSTERS;
    /// Per-frame corner forces.
    pub const CORNERS: u32 = gpu::BINDING_CORNERS;
    /// Per-frame point sources and colliders.
    pub const EMITTERS: u32 = gpu::BINDING_EMITTERS;
    /// `BladeTile[]` storage buffer.
    pub const TILES: u32 = gpu::BINDING_TILES;
    /// The cull's visible list.
    pub const VISIBLE: u32 = gpu::BINDING_VISIBLE;
    /// The cull's per-slot counts and offsets.
    pub const SLOT_COUNTS: u32 = gpu::BINDING_SLOT_COUNTS;
    /// The cull's indirect draws.
    pub const DRAWS: u32 = gpu::BINDING_DRAWS;
    /// Per-frame: the cull's counts of the frame, host-visible.
    pub const CULL_STATS: u32 = gpu::BINDING_CULL_STATS;
    /// The count pass's verdict per candidate blade.
    pub const CULL_RESULTS: u32 = gpu::BINDING_CULL_RESULTS;
    /// A block field's room for verdicts.
    pub const CULL_ALLOC: u32 = gpu::BINDING_CULL_ALLOC;
    /// `FrameUniforms` again, as the cull's passes read it: a storage buffer (shaders/common/bindings.glsl).
    pub const FRAME_STORAGE: u32 = gpu::BINDING_FRAME_STORAGE;
    /// The depth pyramid (`PYRAMID_*`), as the occlusion test reads it: R32 texels (the
    /// depth-pyramid pass writes the buffer through its own set).
    pub const DEPTH_PYRAMID_TEXELS: u32 = gpu::BINDING_DEPTH_PYRAMID_TEXELS;
    /// The blades (`BladeInstance`), as the scene's shaders read them: two RGBA32UI texels each.
    pub const BLADE_TEXELS: u32 = gpu::BINDING_BLADE_TEXELS;
    /// The visible list again, as its readers fetch it: RG32UI texels.
    pub const VISIBLE_TEXELS: u32 = gpu::BINDING_VISIBLE_TEXELS;
    /// A block field's terrain grid (height and normal per vertex), as `relief_grid.comp` writes it.
    pub const RELIEF_GRID: u32 = gpu::BINDING_RELIEF_GRID;
    /// The same grid as RGBA32F texels, as its readers fetch it.
    pub const RELIEF_GRID_TEXELS: u32 = gpu::BINDING_RELIEF_GRID_TEXELS;
    pub const CULL_RESULT_TEXELS: u32 = gpu::BINDING_CULL_RESULT_TEXELS;
}

/// How the blades are left after the upload and imported into each graph: the scene's shaders
/// read them as texels, in the vertex and compute stages.
pub const BLADE_READS: &[Access] = &[Access::VertexShaderSampledRead, Access::ComputeShaderSampledRead];

/// Layout of set `SET_SCENE`, shared by the scene passes and the animation's compute passes.
pub fn bindings() -> [Binding; 20] {
    let vs = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::COMPUTE;
    let cs = vk::ShaderStageFlags::COMPUTE;
    let vs_cs = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::COMPUTE;
    let all = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
    let uniform = vk::DescriptorType::UNIFORM_BUFFER;
    let texels = vk::DescriptorType::UNIFORM_TEXEL_BUFFER;
    [
        Binding { binding: binding::FRAME, kind: uniform, stages: all },
        Binding { binding: binding::HEIGHTS, kind: storage, stages: vs },
        Binding { binding: binding::BLADE_ALPHA, kind: sampled, stages: vk::ShaderStageFlags::FRAGMENT },
        Binding { binding: binding::CLUSTERS, kind: storage, stages: vs_cs },
        Binding { binding: binding::CORNERS, kind: storage, stages: vs_cs },
        Binding { binding: binding::EMITTERS, kind: storage, stages: vs_cs },
        Binding { binding: binding::TILES, kind: storage, stages: cs },
        Binding { binding: binding::VISIBLE, kind: storage, stages: cs },
        Binding { binding: binding::SLOT_COUNTS, kind: storage, stages: cs },
        Binding { binding: binding::DRAWS, kind: storage, stages: cs },
        Binding { binding: binding::CULL_STATS, kind: storage, stages: cs },
        Binding { binding: binding::CULL_RESULTS, kind: storage, stages: cs },
        Binding { binding: binding::CULL_ALLOC, kind: storage, stages: cs },
        Binding { binding: binding::FRAME_STORAGE, kind: storage, stages: cs },
        Binding { binding: binding::DEPTH_PYRAMID_TEXELS, kind: texels, stages: cs },
        Binding { binding: binding::BLADE_TEXELS, kind: texels, stages: vs_cs },
        Binding { binding: binding::VISIBLE_TEXELS, kind: texels, stages: vs_cs },
        Binding { binding: binding::RELIEF_GRID, kind: storage, stages: cs },
        Binding { binding: binding::RELIEF_GRID_TEXELS, kind: texels, stages: vs_cs },
        Binding { binding: binding::CULL_RESULT_TEXELS, kind: texels, stages: cs },
    ]
}
