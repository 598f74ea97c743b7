// Set 0: each stored blade's cluster record (`BladeCluster`, `scene::clusters`), owned by
// `render::scene_gpu::SceneGpu`.
#ifndef MEADOW_CLUSTERS_GLSL
#define MEADOW_CLUSTERS_GLSL
#include "common/profile.glsl"

layout(SCENE(Clusters), std430) readonly buffer Clusters { BladeCluster clusters[]; };

#endif
