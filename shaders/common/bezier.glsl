// Blade geometry, thesis 4.1: two parallel cubic Bézier splines. Mirrors `scene::bezier`.
#ifndef MEADOW_BEZIER_GLSL
#define MEADOW_BEZIER_GLSL

vec3 bezier_point(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
    float s = 1.0 - t;
    return p0 * (s * s * s) + p1 * (3.0 * s * s * t) + p2 * (3.0 * s * t * t) + p3 * (t * t * t);
}

vec3 bezier_tangent(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
    float s = 1.0 - t;
    return (p1 - p0) * (3.0 * s * s) + (p2 - p1) * (6.0 * s * t) + (p3 - p2) * (3.0 * t * t);
}

float unpack_variation(uint packed, int i) {
    return float((packed >> (8 * i)) & 0xffu) / 255.0;
}

// Neutral control points in the blade frame (x across, y up, z along the normal).
void neutral_control_points(float height, float lean01, out vec3 p[4]) {
    float lean = 0.45 * lean01 * height;
    float tip_y = sqrt(max(height * height - lean * lean, 0.0));
    p[0] = vec3(0.0);
    p[1] = vec3(0.0, 0.4 * tip_y, 0.0);
    p[2] = vec3(0.0, 0.8 * tip_y, 0.35 * lean);
    p[3] = vec3(0.0, tip_y, lean);
}

#endif
