#version 460
// The egui overlay (`render::overlay`, `render/passes/overlay.rs`): egui's vertices pulled from
// the frame's storage buffer, indexed by `vkCmdDrawIndexed` (`gl_VertexIndex` is the mesh's
// index plus its base vertex). Five 32-bit words a vertex, as `render::overlay` writes them:
// position in points (x, y), texture coordinates (u, v), and the colour as four bytes
// (r, g, b, a: sRGB, premultiplied). Positions go from points to clip space through the screen's
// size in points (push constant): egui's y points down, as Vulkan's does.

layout(set = 0, binding = 0, std430) readonly buffer Vertices {
    uint words[];
};

layout(push_constant) uniform Screen {
    vec2 size_points;
} screen;

layout(location = 0) out vec4 v_color;
layout(location = 1) out vec2 v_uv;

void main() {
    uint base = 5u * uint(gl_VertexIndex);
    vec2 position = uintBitsToFloat(uvec2(words[base], words[base + 1u]));
    v_uv = uintBitsToFloat(uvec2(words[base + 2u], words[base + 3u]));
    v_color = unpackUnorm4x8(words[base + 4u]);
    gl_Position = vec4(2.0 * position / screen.size_points - 1.0, 0.0, 1.0);
}
