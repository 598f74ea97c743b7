#version 450
// A run-once test pass (tests/graph.rs): counts its runs on the GPU and keeps the input it ran for.

layout(local_size_x = 1) in;

layout(set = 0, binding = 0) buffer Runs {
    uint runs;
    uint last_input;
};

layout(push_constant) uniform Push {
    uint input_value;
} push;

void main() {
    runs += 1u;
    last_input = push.input_value;
}
