// The one source of truth for the integer constants the shaders and Rust share: set 1's descriptor
// bindings, flag bits, mode codes and limits. build.rs parses this
// file and writes each `#define NAME VALUE // doc` as `pub const NAME: u32 = VALUE;` with the doc
// into `render::gpu_constants`; Rust uses those, never a copy. The parser is strict: besides
// `#define` lines it accepts only `//` comments, blank lines and the include guard, and a define
// needs a name in upper case, a decimal value (a `u` suffix is allowed) and a doc comment.
#ifndef MEADOW_SHARED_GLSL
#define MEADOW_SHARED_GLSL

// Descriptor sets of the scene pipelines.
#define SET_SCENE 0 // The scene and this frame's uniforms and forces (`render::layouts::scene_bindings`).
#define SET_POSES 1 // The blade pass's input from a blade response: pose records and placed levels, the renderer's (`render::animation::poses::PoseRecords`).
#define SET_PASS 2 // A pass's own set (`render::recording::pass_set::PassSet`): its bindings numbered in its own header, given by name.

// Set `SET_SCENE`'s bindings are not here: each resource is declared by its owner's header as
// `layout(SCENE(Name), …)` and numbered by build.rs (`build/scene_set.rs`, common/profile.glsl).

// Set `SET_POSES` (bindings.glsl). A response's own resources are in the own sets (`SET_PASS`) of
// its passes and of the blade pass, given by name (`render::animation::response`).
#define BINDING_POSES 0 // Per-blade pose records written by a blade response's compute pass.
#define BINDING_LEVELS 1 // With the cull and pose records: each drawn blade's strip levels placed and lit, written by blade_levels.comp (blade.vert reads `BINDING_LEVEL_TEXELS`).
#define BINDING_LEVEL_TEXELS 2 // The placed levels again as RG32UI texels, as blade.vert fetches them (`level_word` in bindings.glsl).

// Specialization constants are not numbered here: each is declared `layout(constant_id =
// SPEC(NAME))` (common.glsl), build.rs numbers the ids and `render::specialization::Specialization`
// gives each value by NAME.

// `RENDER_FLAGS` bits.
#define FLAG_DEBUG_FORCE 1u // Colour blades by force magnitude (thesis fig. 4.5 / 6.1c).
#define FLAG_EVAL_BLADE 2u // Pose records come from the blade-pose compute pass, once per blade.
#define FLAG_CLUSTER_PUSH 4u // Per-cluster draws push their first blade (`meadow overhead`).
#define FLAG_CULLED 8u // Instances are entries of the cull's visible list, not blade indices.
#define FLAG_DEBUG_LOD 16u // Colour blades by their LOD bucket (`--debug-view lod`).
#define FLAG_DEBUG_TILES 64u // Colour blades by the tile they belong to (`--debug-view tiles`).
#define FLAG_DEBUG_FRESNEL 256u // Blades show Belyaev's Fresnel term alone (`--debug-view fresnel`).
#define FLAG_BLOCKS 128u // A block field (`scene::field`): blades are a stored block's, placed per cell around the origin.
#define FLAG_LEVELS 512u // blade.vert reads each drawn blade's levels placed and lit by blade_levels.comp (with the cull and pose records).
#define FLAG_GROUND_BOUNDS 4096u // The clipmap's tiles bound the heights of a block field's cells in the cull (`render::ground::tiles`; off: the slope's spread alone).
#define FLAG_POSE_CLASS 2048u // A pose pipeline over bucket LOD_BUCKET of a further draw class whose entries the response poses (`render::draw_class::DrawClass::posed`).
#define FLAG_DEBUG_COVER 1024u // The ground's cover as colour, on the terrain and the blades (`--debug-view cover`).
#define FLAG_DEBUG_PRESSED 8192u // The pressed map's bend and cut as colour on the blades (`--debug-view pressed`).
#define FLAG_DEBUG_FAR 32768u // The far field apart from the blades (`--debug-view far`): blades blue-green, those in the band where they thin out orange, the far field's plants magenta.
#define FLAG_DEBUG_PATCHES 16384u // The interaction patches' chains' share as colour on the blades (`--debug-view patches`).
#define FLAG_SOLID_OUTLINE 32u // Far LOD buckets: the outline tapered in the geometry, no alpha test (early depth writes).

// Culling and LOD switches (`cull_lod.z` of the frame uniforms, `render::culling::Culling`).
#define CULL_FRUSTUM 1u // Tiles and blades outside the culling camera's frustum.
#define CULL_DISTANCE 2u // Tiles and blades beyond the view distance.
#define CULL_ORIENTATION 4u // Blades seen edge-on (Jahrmann & Wimmer 2017).
#define CULL_OCCLUSION 8u // Tiles and blades behind the terrain of this frame (the depth pyramid).
#define LOD_DENSITY 16u // Belyaev's smooth density F(z, phi) (§2.2): a prefix of each tile, faded and widened.
#define LOD_SEGMENTS 32u // Segment buckets by projected height.

// The cull's counts: `SLOT_WORDS` per ring slot, and the frame's totals in the same layout.
#define SLOT_WORDS 16u // Words per slot: `MAX_LOD_BUCKETS` drawn counts, then the `STAT_*` counts.
#define STAT_CONSIDERED 8u // Blades of the tiles in the grid.
#define STAT_TILES 9u // Blades of the tiles that pass the tile tests (frustum, distance).
#define STAT_DENSITY 10u // ... kept by the density LOD.
#define STAT_FRUSTUM 11u // ... inside the frustum (bent-blade bounding sphere).
#define STAT_ORIENTATION 12u // ... not seen edge-on.
#define STAT_OCCLUSION 13u // ... not behind the terrain.
#define STAT_TILES_VISIBLE 14u // Tiles that pass the tile tests (frustum, distance, occlusion).
#define STAT_TILES_TOTAL 15u // Tiles in the grid.
// The frame's totals only (`cull_stats`, after the `SLOT_WORDS` of the slot layout).
#define CULL_STATS_WORDS 20u // Words of the frame's totals.
#define STAT_WANTED 16u // Blades the blade tests kept, before the visible list's capacity thinned them.
#define STAT_SCALE 17u // The capacity scale the emit pass thinned by, 0.32 fixed point (`THIN_WORD`).
#define STAT_NO_ROOM 18u // Candidates of a block field's slots that found no room for their verdicts (not tested, not drawn).
#define STAT_TILE_DRAWS 19u // With per-tile rows (`render::draw_rows`): the draws of the blade class, one per visible tile and LOD bucket that draws.

// The depth pyramid: three levels over the whole picture in screen space (uv), whatever its size
// and aspect, each texel the farthest (smallest, reversed Z) terrain depth it covers.
#define PYRAMID_SIDE 256u // Texels per side of level 0 (level l has PYRAMID_SIDE >> 2l).
#define PYRAMID_LEVELS 3u // Levels: 256², 64², 16² texels.
#define PYRAMID_FLOATS 69888u // 256² + 64² + 16².

// Block fields (`scene::field`).
#define RELIEF_WAVES 8u // Sine waves of the relief.
#define FIELD_TERRAIN_CELLS 80u // Cells per side of a level of a block field's ground clipmap (`render::ground_clipmap`).
#define GROUND_SNAP_CELLS 16u // A ground clipmap level's window moves by whole multiples of this many of its cells (`render::ground_clipmap`).
#define GROUND_TILE_CELLS 2u // Cells per side of a ground clipmap tile (a block cell at level 0's usual 2 m): the source keeps each tile's lowest and highest height and most cover (`render::ground::tiles`).
#define GROUND_MORPH_FULL 1u // Within this many cells of a level's window edge its odd vertices lie on the next level's mesh,
#define GROUND_MORPH_END 8u // and from this many on they are the relief's.
#define PERIOD_CELLS 5000 // Block cells in the world's period (`scene::field::PERIOD_CELLS`).

// Camera-following grids (`render::camera_grid`, common/camera_grid.glsl).
#define CAMERA_GRID_BOXES 3u // Boxes of cells that enter a window when it scrolls: one slab per axis.
#define CAMERA_GRID_MAX_LEVELS 8u // Nested levels of one grid.
#define CAMERA_GRID_GROUP 64u // Invocations of a fill workgroup (one cell each).

// `ANIMATION_MODE` codes.
#define MODE_STATIC 0u // No animation.
#define MODE_TEXTURE 1u // Keyframes from the keyframe texture.
#define MODE_UNIFORM 2u // Keyframes from the keyframe uniform array (thesis 4.4.2).

// `ATTENUATION` codes (thesis 4.5).
#define ATTENUATION_CLUSTER 0u // Point sources attenuated at the cluster corners.
#define ATTENUATION_BLADE 1u // Point sources evaluated at every blade.

// `REPRESENTATION` codes.
#define REPRESENTATION_LEVELS 0u // Keyframe vertex levels.
#define REPRESENTATION_CURVE 1u // A Bézier curve fitted to the keyframe.

// Limits.
#define MAX_SEGMENTS 16u // Segments per blade; shader arrays of levels hold `MAX_SEGMENTS + 1`.
#define MAX_SOURCES 64u // Point sources a renderer can hold.
#define MAX_COLLIDERS 128u // Colliders a renderer can hold, apart from the sources (issue #34).
#define EMITTER_ELEMENTS 320u // The per-frame emitter buffers' vec4s before the collider bins: a source takes one, a collider two (MAX_SOURCES + 2 MAX_COLLIDERS).
#define MAX_CALM_AREAS 64u // Calm areas the analytic wind field holds (its parameter block's capacity).
#define PERLIN_TEXELS 128u // Texels per side of the Perlin wind's noise at its finest level (`render::wind::perlin`).
#define WIND_GROUP 64u // Invocations per workgroup of the analytic wind field's corner pass.
#define MAX_FLUID_SOURCES 8u // Point sources the fluid wind injects (its parameter block's capacity).
#define MAX_FLUID_COLLIDERS 8u // Colliders the fluid wind holds as solid cells.
#define FLUID_GROUP 64u // Invocations per workgroup of a fluid step (one cell each).
#define WIND_LEVELS 8u // Nested levels of a block field's wind (each twice the spacing and extent of the one inside).
#define WIND_LEVEL_CLUSTERS 64u // Clusters per side of one wind level (WIND_LEVEL_CLUSTERS + 1 corners).
#define POSE_WORDS 3u // 32-bit words of one level of a `--eval blade` pose record.
#define MAX_LOD_BUCKETS 8u // The cull's buckets, of every draw class: the blade class's segment LOD buckets (`--lod-segments`) first (`render::draw_class`).
#define MAX_DRAW_CLASSES 5u // Draw classes the cull sorts into: the blades and four more (`render::draw_class`).
#define DRAW_WORDS 5u // Words of one LOD bucket's draw in the cull's `draws` (a `VkDrawIndexedIndirectCommand`).
#define DRAW_INSTANCES 1u // Its instanceCount word.
#define DRAW_FIRST_INSTANCE 4u // Its firstInstance word.
#define BUCKET_DISPATCH_WORD 40u // In the cull's `draws`, after the buckets' draws: per LOD bucket, the blade-pose and levels passes' indirect dispatch (x, y, z) over its entries.
#define EMIT_DISPATCH_WORD 64u // In the cull's `draws`: the emit pass's indirect dispatch (x, y, z), one workgroup per ring slot that draws.
#define THIN_WORD 67u // In the cull's `draws`: the capacity scale, 0.32 fixed point (0xffffffff: keep all), written by the scan, read by the emit pass.
#define EMIT_SLOTS_WORD 68u // In the cull's `draws`, from here: the ring slots that draw, near to far (written by the scan, read by the emit pass).
#define TILE_RECORD_WORDS 3u // Words of one per-tile draw's record (`render::draw_rows::TileRows`): its first and end entries in the visible list, its ring slot.
#define POSE_GROUP 64u // Invocations of a blade-pose workgroup.
#define LEVEL_UVEC2S 3u // `uvec2`s of one strip level of a drawn blade (bindings.glsl, `Levels`).

#endif
