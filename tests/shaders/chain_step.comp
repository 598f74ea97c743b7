#version 450
// A test pass's chain of three dependent dispatches over a ping-pong buffer (tests/graph_pass.rs),
// one shader, the step in a push constant: step 0 gathers the previous frame's values into the
// scratch, step 1 scales the scratch into this frame's side, step 2 mixes that side in place.
// Unsigned arithmetic wraps, as the test's CPU reference does. The scale and bias are the pass's
// own uniform block (`render::graph::uniforms::PassUniforms`), which the graph writes each frame;
// the set's layout is reflected from this file and its resources are given by these block names.

layout(local_size_x = 64) in;

layout(set = 0, binding = 0) readonly buffer Previous { uint previous[]; };
layout(set = 0, binding = 1) buffer Current { uint current[]; };
layout(set = 0, binding = 2) buffer Scratch { uint scratch[]; };
layout(set = 0, binding = 3, std140) uniform Params {
    uint scale;
    uint bias;
} params;

layout(push_constant) uniform Push {
    uint step;
    uint count;
    uint frame;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = push.count;
    if (i >= n) {
        return;
    }
    if (push.step == 0u) {
        scratch[i] = previous[(i + 1u) % n] + i + push.frame;
    } else if (push.step == 1u) {
        current[i] = scratch[(i + 7u) % n] * params.scale + params.bias;
    } else {
        current[i] = current[i] ^ (current[i] >> 5u);
    }
}
