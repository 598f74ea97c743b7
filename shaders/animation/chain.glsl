// Belyaev's inertial segment chain (§3.1), mirrored on the CPU by
// `render::animation::chain::Chain`, step for step. A blade is a chain of CHAIN_SEGMENTS straight
// segments joined by spherical springs, its joints at t = k / CHAIN_SEGMENTS of the neutral
// Bézier (so a blade rests at its neutral curve), whatever --segments draws. Everything is in the
// blade's frame (x across, y up, z along the normal): the dummy segment 0's T₀, the planting
// frame, is the blade's own. Per joint k the state is ψₖ, the rotation away from the segment's
// rest rotation R⁰ₖ relative to the segment below (a rotation vector in the segment's frame), and
// ωₖ, its angular velocity. Frames: Tₖ = Tₖ₋₁·R⁰ₖ·M(ψₖ).
//
// A step (§3.1's simplified algorithm: small angular velocities, and the segments above do not act
// on the ones below), joint by joint from the root, each per unit of the joint's inertia J:
//   J ω̇ = −g + l × T' f,   g = k·ψ (the spring: k·V(Rₖ) about the rest rotation),
//   f = k_w·|W − v|^(γ−1)·(W − v) (§3.2's drag, as a vector along W − v, γ = 4/3, per unit mass),
//   v = v*ₖ₋₁ − T(l × ω) at the segment's centre,  v*ₖ = v*ₖ₋₁ − 2T(l × ω) at its top (§3.2),
//   ψ̇ = ω:  R ← R·M(ω Δt),
// l = (0, l, 0) half the segment (meadow's segments run along y), J = 4 m l² / 3 about the joint,
// so l × f / J = (3 / 4l)·ŷ × f/m. meadow's choices where the paper is silent or too costly:
//   - a joint damper −d·ω (meadow's addition, `--damping`): the drag alone damps a blade by about
//     ζ = 0.01, and it rang for seconds after a gust;
//   - semi-implicit Euler, with the damper and the drag's part in ω (−(3/4)·k_w·|W − v|^(γ−1)·ω
//     across the segment) taken implicitly: stable at --dt 1/15 s for every constant in range;
//   - gravity is left out, as in the Verlet blades: a constant weight only moves the springs' rest
//     rotations (the neutral blade stands against it), and the change of its moment as a segment
//     tips is a negative stiffness of 3g/4l ≈ 150 /s² for 5 cm segments, which the default
//     k/J = 100 /s² could not hold;
//   - W is the wind at the root (the wind field's, with the colliders' push as a local wind).
// The static equilibrium (the start of a restart, and the stateless shape past the store) is §3.3's
// solve with the wind's force in place of the virtual moments: per joint from the root, the fixed
// point of k·ψ = l × (Tₖ₋₁ R⁰ₖ M(ψ))' f, CHAIN_EQUILIBRIUM_ITERATIONS iterations from ψ = 0.
// The drawn curve (every LOD bucket samples it): the cubic Bézier with P3 the chain's tip, P1
// carried by the first segment and P2 by the last, each where the neutral curve has it in that
// segment's rest frame, scaled about the root to the neutral curve's arc length and kept above the
// root. The width turns with the segments: a level takes its segment's across axis, projected
// onto the ground.
#ifndef MEADOW_CHAIN_GLSL
#define MEADOW_CHAIN_GLSL
#include "common/bezier.glsl"

const uint CHAIN_SEGMENTS = 4u;           // render::animation::chain::CHAIN_SEGMENTS
const float CHAIN_GAMMA = 4.0 / 3.0;      // render::animation::chain::GAMMA
const float CHAIN_DRAG = 0.08;            // render::animation::chain::DRAG
const uint CHAIN_EQUILIBRIUM_ITERATIONS = 3u; // render::animation::chain::EQUILIBRIUM_ITERATIONS
const uint CHAIN_ARC_SAMPLES = 8u;        // render::animation::chain::ARC_SAMPLES

// Unit quaternions (xyz, w), as glam computes them.
vec4 quat_mul(vec4 a, vec4 b) {
    return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

vec3 quat_rotate(vec4 q, vec3 v) {
    return v * (q.w * q.w - dot(q.xyz, q.xyz)) + q.xyz * (2.0 * dot(v, q.xyz)) + cross(q.xyz, v) * (2.0 * q.w);
}

vec4 quat_inverse(vec4 q) {
    return vec4(-q.xyz, q.w);
}

// M(v): the rotation about v by |v|.
vec4 quat_from_scaled_axis(vec3 v) {
    float angle = length(v);
    if (angle == 0.0) {
        return vec4(0.0, 0.0, 0.0, 1.0);
    }
    return vec4(v / angle * sin(0.5 * angle), cos(0.5 * angle));
}

// V(q): the rotation vector of q, the shorter way round.
vec3 quat_scaled_axis(vec4 q) {
    q = q.w < 0.0 ? -q : q;
    float len = length(q.xyz);
    return len >= 1e-8 ? q.xyz / len * (2.0 * atan(len, q.w)) : vec3(0.0);
}

struct Chain {
    vec4 rest[CHAIN_SEGMENTS];        // R⁰ₖ: the rotation about x from the segment below
    vec4 rest_frames[CHAIN_SEGMENTS]; // Tₖ at ψ = 0 (the neutral curve's segments)
    float half_length[CHAIN_SEGMENTS]; // l (metres)
    vec3 controls[3];                 // the neutral curve's P1..P3
    vec3 carried[2];                  // P1 in T⁰₀'s frame, P2 − the rest tip in T⁰ of the last
    float rest_arc;                   // its arc length over CHAIN_ARC_SAMPLES chords
};

struct ChainState {
    vec3 psi[CHAIN_SEGMENTS];
    vec3 omega[CHAIN_SEGMENTS];
};

// R⁰ₖ, and everything else that depends on the neutral curve alone (the rest frames, the controls
// carried by the first and last segments), is computed once per chain (`chain_of`): the solve,
// the frames and the controls read it up to 20 times a blade.
vec4 chain_rest(Chain c, uint k) {
    return c.rest[k];
}

float chain_arc_length(vec3 p[3]) {
    float sum = 0.0;
    vec3 before = vec3(0.0);
    for (uint k = 1u; k <= CHAIN_ARC_SAMPLES; k++) {
        vec3 at = bezier_point(vec3(0.0), p[0], p[1], p[2], float(k) / float(CHAIN_ARC_SAMPLES));
        sum += length(at - before);
        before = at;
    }
    return sum;
}

// The chain of the neutral cubic n (n[0] the root at 0).
Chain chain_of(vec3 n[4]) {
    Chain c;
    vec3 joints[CHAIN_SEGMENTS + 1u];
    for (uint k = 0u; k <= CHAIN_SEGMENTS; k++) {
        joints[k] = bezier_point(n[0], n[1], n[2], n[3], float(k) / float(CHAIN_SEGMENTS));
    }
    vec4 frame = vec4(0.0, 0.0, 0.0, 1.0);
    vec3 rest_tip = vec3(0.0);
    // R⁰ₖ turns the direction a of the segment below (ŷ below the first) onto this one's, b, about
    // x: for unit a, b in the y-z plane the half-angle quaternion normalize((a × b)ₓ, 0, 0, 1 + a·b)
    // = (sin θ/2, 0, 0, cos θ/2), without an atan, a sin and a cos (the neutral curve turns by
    // far less than 180° a segment).
    vec2 below = vec2(1.0, 0.0); // (y, z) of the direction below
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        vec3 s = joints[k + 1u] - joints[k];
        float len = length(s);
        vec2 dir = len > 0.0 ? s.yz / len : vec2(1.0, 0.0);
        c.rest[k] = normalize(vec4(below.x * dir.y - below.y * dir.x, 0.0, 0.0, 1.0 + dot(below, dir)));
        c.half_length[k] = 0.5 * len;
        below = dir;
        frame = quat_mul(frame, c.rest[k]);
        c.rest_frames[k] = frame;
        rest_tip += quat_rotate(frame, vec3(0.0, 2.0 * c.half_length[k], 0.0));
    }
    c.controls = vec3[3](n[1], n[2], n[3]);
    c.carried[0] = quat_rotate(quat_inverse(c.rest_frames[0]), c.controls[0]);
    c.carried[1] = quat_rotate(quat_inverse(c.rest_frames[CHAIN_SEGMENTS - 1u]), c.controls[1] - rest_tip);
    c.rest_arc = chain_arc_length(c.controls);
    return c;
}

// l × T' f / J for the force f (per unit mass) at the centre of a segment of half length l.
vec3 chain_moment(float l, vec4 q, vec3 force) {
    return cross(vec3(0.0, 1.0, 0.0), quat_rotate(quat_inverse(q), force)) * (0.75 / l);
}

vec3 chain_drag(vec3 w) {
    return CHAIN_DRAG * pow(length(w), CHAIN_GAMMA - 1.0) * w;
}

// Segment k's frame Tₖ for every k.
void chain_frames(Chain c, ChainState s, out vec4 frames[CHAIN_SEGMENTS]) {
    vec4 frame = vec4(0.0, 0.0, 0.0, 1.0);
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        frame = quat_mul(quat_mul(frame, chain_rest(c, k)), quat_from_scaled_axis(s.psi[k]));
        frames[k] = frame;
    }
}

// The static equilibrium at rest under a force per joint (per unit mass, blade frame), §3.3's
// solve: per joint from the root, k·ψ = l × (Tₖ₋₁ R⁰ₖ M(ψ))' fₖ by fixed-point iteration. The
// frames Tₖ it ends at (what `chain_frames` gives for it) in `frames`.
ChainState chain_equilibrium_framed(Chain c, vec3 force[CHAIN_SEGMENTS], float stiffness, out vec4 frames[CHAIN_SEGMENTS]) {
    ChainState s;
    vec4 frame = vec4(0.0, 0.0, 0.0, 1.0);
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        vec4 rest = quat_mul(frame, chain_rest(c, k));
        // The first iteration from ψ = 0, where M(ψ) is the identity (exactly: the product with
        // it rounds nothing), then the others.
        vec3 psi = chain_moment(c.half_length[k], rest, force[k]) / stiffness;
        for (uint i = 1u; i < CHAIN_EQUILIBRIUM_ITERATIONS; i++) {
            vec4 q = quat_mul(rest, quat_from_scaled_axis(psi));
            psi = chain_moment(c.half_length[k], q, force[k]) / stiffness;
        }
        s.psi[k] = psi;
        s.omega[k] = vec3(0.0);
        frame = quat_mul(rest, quat_from_scaled_axis(psi));
        frames[k] = frame;
    }
    return s;
}

// The static equilibrium under the wind w (m/s, blade frame), at rest: the still drag on every joint.
ChainState chain_equilibrium(Chain c, vec3 w, float stiffness) {
    vec3 f = chain_drag(w);
    vec3 force[CHAIN_SEGMENTS];
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        force[k] = f;
    }
    vec4 frames[CHAIN_SEGMENTS];
    return chain_equilibrium_framed(c, force, stiffness, frames);
}

// §3.3's virtual moments of a chain: mₖ = k·ψₖ on each segment (gravity left out), given as the
// horizontal force per unit mass, in the chain's frame, whose moment l × T' f on the segment they
// are, so that a blade of another length and lean can take them. The moment fixes the force's
// part across the segment, (4l/3)·Tₖ(mₖ × ŷ) (ŷ × (m × ŷ) is m across the segment); the part along
// the segment sₖ, which has no moment, is what makes it horizontal, as the wind's drag is (for a
// segment within 84° of upright, |sₖ.y| ≥ 0.1). Under a steady wind the virtual chain rests
// where mₖ is the drag's moment, and the force is the drag itself.
void chain_virtual_forces(Chain c, ChainState s, float stiffness, out vec3 force[CHAIN_SEGMENTS]) {
    vec4 frames[CHAIN_SEGMENTS];
    chain_frames(c, s, frames);
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        vec3 m = stiffness * s.psi[k];
        vec3 across = quat_rotate(frames[k], cross(m, vec3(0.0, 1.0, 0.0)) * (4.0 / 3.0 * c.half_length[k]));
        vec3 along = quat_rotate(frames[k], vec3(0.0, 1.0, 0.0));
        force[k] = across - along * (across.y / max(along.y, 0.1));
    }
}

// One step of dt seconds under the wind w (m/s, blade frame); x the stiffness k/J (1/s²), y the
// damper d/J (1/s).
void chain_step(Chain c, inout ChainState s, vec3 w, vec2 constants, float dt) {
    vec4 frame = vec4(0.0, 0.0, 0.0, 1.0);
    vec3 top_velocity = vec3(0.0);
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        float l = c.half_length[k];
        vec3 lever = vec3(0.0, l, 0.0);
        vec4 rest = quat_mul(frame, chain_rest(c, k));
        vec4 q = quat_mul(rest, quat_from_scaled_axis(s.psi[k]));
        vec3 centre = top_velocity + quat_rotate(q, cross(s.omega[k], lever));
        float drag = CHAIN_DRAG * pow(length(w - centre), CHAIN_GAMMA - 1.0);
        vec3 driven = chain_moment(l, q, drag * (w - top_velocity));
        float across = 0.75 * drag;
        vec3 rhs = s.omega[k] + dt * (driven - constants.x * s.psi[k]);
        vec3 divisor = vec3(across, 0.0, across) + vec3(constants.y);
        s.omega[k] = rhs / (vec3(1.0) + dt * divisor);
        vec4 turned = quat_mul(quat_from_scaled_axis(s.psi[k]), quat_from_scaled_axis(s.omega[k] * dt));
        s.psi[k] = quat_scaled_axis(turned);
        q = quat_mul(rest, quat_from_scaled_axis(s.psi[k]));
        top_velocity += 2.0 * quat_rotate(q, cross(s.omega[k], lever));
        frame = q;
    }
}

// The drawn curve's controls P1..P3 (blade frame, the root at 0) from the frames `now` of a state.
void chain_controls(Chain c, vec4 now[CHAIN_SEGMENTS], out vec3 p[3]) {
    vec3 tip = vec3(0.0);
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        tip += quat_rotate(now[k], vec3(0.0, 2.0 * c.half_length[k], 0.0));
    }
    const uint last = CHAIN_SEGMENTS - 1u;
    p[0] = quat_rotate(now[0], c.carried[0]);
    p[1] = tip + quat_rotate(now[last], c.carried[1]);
    p[2] = tip;
    float scale = c.rest_arc / max(chain_arc_length(p), 1e-6);
    for (uint i = 0u; i < 3u; i++) {
        p[i] *= scale;
        p[i].y = max(p[i].y, 0.0);
    }
}

#endif
