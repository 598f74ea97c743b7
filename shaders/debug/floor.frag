#version 460
// Floor reference: one flat colour.
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(0.22, 0.42, 0.10, 1.0);
}
