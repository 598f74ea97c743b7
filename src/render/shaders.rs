//! The library's shaders, compiled by `build.rs` from `shaders/` (a folder per concern) and
//! embedded in the binary, each in every backend profile (`vk::profile::Shader::code`). The
//! tests' own shaders (`tests/shaders/`) are compiled by the same script and are not embedded here.

use crate::spirv_shader;
use crate::vk::profile::Shader;

/// Blade vertex shader (vertex pulling, Bézier strips): neutral blades, or a response's pose records.
pub const BLADE_VERT: Shader = spirv_shader!("blades/blade.vert");
/// Its variant `keyframes`: the keyframe response's per-vertex path (thesis 4.4).
pub const BLADE_KEYFRAMES_VERT: Shader = spirv_shader!("blades/blade.vert.keyframes");
/// Its variant `tiles`: the blade class's per-tile rows, one draw per visible tile (`render::draw_rows`).
pub const BLADE_TILES_VERT: Shader = spirv_shader!("blades/blade.vert.tiles");
/// Blade fragment shader (alpha test, lighting).
pub const BLADE_FRAG: Shader = spirv_shader!("blades/blade.frag");
/// Its variant `coverage`, with `--msaa` and alpha to coverage: the outline's coverage per sample.
pub const BLADE_COVERAGE_FRAG: Shader = spirv_shader!("blades/blade.frag.coverage");
/// With the cull and pose records: each drawn blade's levels placed and lit once.
pub const BLADE_LEVELS_COMP: Shader = spirv_shader!("blades/blade_levels.comp");
/// `--eval blade`: per-blade pose records.
pub const BLADE_POSE_COMP: Shader = spirv_shader!("animation/blade_pose.comp");
/// Push-out (Zhang Xia §6.2, `render::animation::push_out`): recorded backbones moved out of the colliders.
pub const PUSH_OUT_COMP: Shader = spirv_shader!("animation/push_out.comp");
/// The interaction patches (Belyaev §3.4, `render::animation::patch_pass`): listed blades' chains stepped.
pub const PATCH_COMP: Shader = spirv_shader!("animation/patch.comp");
/// The pressed map's press pass (`render::animation::pressed`): colliders and cuts swept into it.
pub const PRESS_COMP: Shader = spirv_shader!("animation/press.comp");
/// Pelzer's sine animation (`render::animation::sine`), its phase per object: pose records.
pub const SINE_COMP: Shader = spirv_shader!("animation/sine.comp");
/// The same, its phase per vertex (the variant `vertex`).
pub const SINE_VERTEX_COMP: Shader = spirv_shader!("animation/sine.comp.vertex");
/// The same, its phase per cluster: the blade's tile of the cull (the variant `cluster`).
pub const SINE_CLUSTER_COMP: Shader = spirv_shader!("animation/sine.comp.cluster");
/// Zhang Xia's Verlet blades (`render::animation::verlet`): stepped in the blade-state store.
pub const VERLET_COMP: Shader = spirv_shader!("animation/verlet.comp");
/// Belyaev's inertial blades (`render::animation::inertial`): segment chains in the blade-state store.
pub const INERTIAL_COMP: Shader = spirv_shader!("animation/inertial.comp");
/// Belyaev's virtual blades at the wind corners (`render::animation::virtual_blades`).
pub const VIRTUAL_BLADES_COMP: Shader = spirv_shader!("animation/virtual_blades.comp");
/// Belyaev's virtually-inertial drawn blades (`render::animation::virtual_inertial`).
pub const VIRTUAL_INERTIAL_COMP: Shader = spirv_shader!("animation/virtual_inertial.comp");
/// The analytic wind field at the cluster corners, each step (`render::wind`).
pub const ANALYTIC_CORNERS_COMP: Shader = spirv_shader!("wind/analytic_corners.comp");
/// Its variant `perlin`: Belyaev's Perlin field (`render::wind::perlin`).
pub const PERLIN_CORNERS_COMP: Shader = spirv_shader!("wind/analytic_corners.comp.perlin");
/// Its variant `fluid`: the fluid wind's grid blended into the analytic field (`render::wind::fluid`).
pub const FLUID_CORNERS_COMP: Shader = spirv_shader!("wind/analytic_corners.comp.fluid");
/// One stage of the fluid wind's step, a variant each (`render::wind::fluid::pass`).
pub const FLUID_STAGES_COMP: [Shader; 8] = [
    spirv_shader!("wind/fluid.comp.enter"),
    spirv_shader!("wind/fluid.comp.forces"),
    spirv_shader!("wind/fluid.comp.diffuse"),
    spirv_shader!("wind/fluid.comp.advect"),
    spirv_shader!("wind/fluid.comp.divergence"),
    spirv_shader!("wind/fluid.comp.pressure"),
    spirv_shader!("wind/fluid.comp.project"),
    spirv_shader!("wind/fluid.comp.inflow"),
];
/// The flowers' pass (`render::flowers`): a head of petals on each posed stem.
pub const FLOWER_VERT: Shader = spirv_shader!("flowers/flower.vert");
/// The flowers' pass: the lit colour, fogged and encoded.
pub const FLOWER_FRAG: Shader = spirv_shader!("flowers/flower.frag");
/// The far field's placement (`render::far_field`): the plants of every ring that stand and are seen.
pub const FAR_PLACE_COMP: Shader = spirv_shader!("far_field/far_place.comp");
/// Its variant `ordered` (`--fade blend`): every lattice point's slot, far to near.
pub const FAR_PLACE_ORDERED_COMP: Shader = spirv_shader!("far_field/far_place.comp.ordered");
/// `--fade blend`: the ordered slots compacted in their order, one workgroup.
pub const FAR_ORDER_COMP: Shader = spirv_shader!("far_field/far_order.comp");
/// The far field's plants: billboards or stars, leaning in the wind.
pub const FAR_VERT: Shader = spirv_shader!("far_field/far.vert");
/// The far field's plants: the atlas lit with the height terms, the dither's fades.
pub const FAR_FRAG: Shader = spirv_shader!("far_field/far.frag");
/// Its variant `blend` (`--fade blend`): each plant's rectangles far to near.
pub const FAR_BLEND_VERT: Shader = spirv_shader!("far_field/far.vert.blend");
/// Its variant `blend` (`--fade blend`): the coverage and the fades as alpha, premultiplied.
pub const FAR_BLEND_FRAG: Shader = spirv_shader!("far_field/far.frag.blend");
/// Its variants `pressed` and `blend_pressed`: the plants as tall as the pressed map leaves them.
pub const FAR_PRESSED_FRAG: Shader = spirv_shader!("far_field/far.frag.pressed");
pub const FAR_BLEND_PRESSED_FRAG: Shader = spirv_shader!("far_field/far.frag.blend_pressed");
/// The far field's atlas bake: the block's blades from the side.
pub const ATLAS_BAKE_VERT: Shader = spirv_shader!("far_field/atlas_bake.vert");
/// The far field's atlas bake: albedo or height, alpha-tested.
pub const ATLAS_BAKE_FRAG: Shader = spirv_shader!("far_field/atlas_bake.frag");
/// Their variants `heads`: the flowers' heads (`--flowers`).
pub const ATLAS_BAKE_HEADS_VERT: Shader = spirv_shader!("far_field/atlas_bake.vert.heads");
pub const ATLAS_BAKE_HEADS_FRAG: Shader = spirv_shader!("far_field/atlas_bake.frag.heads");
/// The far field's atlas mips: the mean of 2 × 2 texels.
pub const ATLAS_MIPS_COMP: Shader = spirv_shader!("far_field/atlas_mips.comp");
/// Terrain vertex shader (height-field pulling).
pub const TERRAIN_VERT: Shader = spirv_shader!("terrain/terrain.vert");
/// Terrain fragment shader.
pub const TERRAIN_FRAG: Shader = spirv_shader!("terrain/terrain.frag");
/// A block field's ground clipmap: the relief's height, the next level's and the slope at each
/// vertex that enters a level's window (`render::ground::ReliefGround`).
pub const RELIEF_FILL_COMP: Shader = spirv_shader!("terrain/relief_fill.comp");
/// The same from a heightmap's texels (`render::ground::HeightmapGround`).
pub const HEIGHTMAP_FILL_COMP: Shader = spirv_shader!("terrain/heightmap_fill.comp");
/// The ground's tiles after a fill: each tile's lowest and highest height and most cover
/// (`render::ground::tiles`, `passes::ground_fill`).
pub const GROUND_TILES_COMP: Shader = spirv_shader!("terrain/ground_tiles.comp");
/// Floor reference: transform only.
pub const FLOOR_VERT: Shader = spirv_shader!("debug/floor.vert");
/// Floor reference: flat colour.
pub const FLOOR_FRAG: Shader = spirv_shader!("debug/floor.frag");
/// Debug view: the cluster grid as lines (`--debug-view bounds`).
pub const CLUSTER_BOUNDS_VERT: Shader = spirv_shader!("debug/cluster_bounds.vert");
/// Debug view: the wind on the slice the grass feels, as arrows (`--debug-view wind`).
pub const WIND_ARROWS_VERT: Shader = spirv_shader!("debug/wind_arrows.vert");
/// Debug views' lines: their colour.
pub const DEBUG_LINES_FRAG: Shader = spirv_shader!("debug/lines.frag");
/// The depth pyramid of the terrain (Hi-Z) the cull's occlusion test reads.
pub const HIZ_COMP: Shader = spirv_shader!("depth_pyramid/hiz.comp");
/// `--msaa`: the depth pyramid over a multisampled depth image.
pub const HIZ_MS_COMP: Shader = spirv_shader!("depth_pyramid/hiz_ms.comp");
/// Cull step 1: the tile tests of every ring slot, the list of slots with candidates.
pub const CULL_TILES_COMP: Shader = spirv_shader!("cull/cull_tiles.comp");
/// Cull step 2: per listed slot, the blade tests and the counts per LOD bucket.
pub const CULL_COUNT_COMP: Shader = spirv_shader!("cull/cull_count.comp");
/// Cull step 2: offsets by prefix sum, the indirect draws and the frame's counts.
pub const CULL_SCAN_COMP: Shader = spirv_shader!("cull/cull_scan.comp");
/// Cull step 3: the visible list.
pub const CULL_EMIT_COMP: Shader = spirv_shader!("cull/cull_emit.comp");
/// `--msaa`: the resolve pass's full-target triangle.
pub const RESOLVE_VERT: Shader = spirv_shader!("resolve/resolve.vert");
/// `--msaa`: the resolve in linear space, then the target's encoding.
pub const RESOLVE_FRAG: Shader = spirv_shader!("resolve/resolve.frag");
/// Its variant `single`: the single-sampled linear scene of `--fade blend`.
pub const RESOLVE_SINGLE_FRAG: Shader = spirv_shader!("resolve/resolve.frag.single");
/// The egui overlay: egui's vertices pulled from a storage buffer, points to clip space.
pub const OVERLAY_VERT: Shader = spirv_shader!("overlay/overlay.vert");
/// The egui overlay: vertex colour times texel, gamma-space sRGB, premultiplied alpha.
pub const OVERLAY_FRAG: Shader = spirv_shader!("overlay/overlay.frag");

/// The scene shaders: the library's shaders that read a set-0 declaration (`layout(SCENE(Name),
/// …)`, found by `build.rs`), whose sets `SET_SCENE` and `SET_POSES` together make the scene's
/// layouts (`render::layouts::scene_layouts`). A new scene shader joins by including a header
/// that declares one (`common/bindings.glsl`, or a resource's own).
pub const SCENE: &[Shader] = include!(concat!(env!("OUT_DIR"), "/scene_shaders.rs"));
