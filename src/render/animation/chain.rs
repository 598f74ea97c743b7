//! Belyaev's inertial segment chain (§3.1) on the CPU: the mirror, step for step, of
//! `shaders/animation/chain.glsl`, which `shaders/animation/inertial.comp` steps on the GPU. The
//! tests measure the GPU's chain against it. The shader's header gives the equations, and what
//! meadow chose where the paper is silent.
//!
//! Everything is in the blade's frame (x across, y up, z along the normal): the planting frame
//! T₀ of the paper's dummy segment 0 is the blade's own, so the state does not depend on which
//! way the blade faces. Rotations are unit quaternions.

use glam::{Quat, Vec3};

use crate::scene::{bezier, BladeInstance};

/// Segments the chain simulates, whatever `--segments` draws (chain.glsl's `CHAIN_SEGMENTS`).
pub const CHAIN_SEGMENTS: usize = 4;
/// The drag's exponent γ of f = k_w·|W − v|^γ (Belyaev §3.2: 4/3 for sedge).
pub const GAMMA: f32 = 4.0 / 3.0;
/// The drag per unit mass, k_w / m, in (m/s)^(1−γ)/s: at 8 m/s a 0.4 m blade with the default
/// stiffness bends by about 0.2 rad a joint (chain.glsl's `DRAG`).
pub const DRAG: f32 = 0.08;
/// Fixed-point iterations of the static-equilibrium solve per joint (Belyaev §3.3: "three
/// iterations are enough").
pub const EQUILIBRIUM_ITERATIONS: u32 = 3;
/// Chords the drawn curve's arc length is measured over (chain.glsl's `CHAIN_ARC_SAMPLES`).
pub const ARC_SAMPLES: u32 = 8;

/// The stiffness flag's range, the Verlet blades' (one flag sets both): for the chain's k/J,
/// √(k/J)·Δt ≤ 1.33 at 1/15 s, where the semi-implicit step is stable.
pub const STIFFNESS_RANGE: (f32, f32) = crate::render::animation::verlet::STIFFNESS_RANGE;
/// The damping flag's range, the Verlet blades' (one flag sets both): the chain's damper d/J is
/// taken implicitly, so any rate is stable.
pub const DAMPING_RANGE: (f32, f32) = crate::render::animation::verlet::DAMPING_RANGE;

/// The chain's constants, per unit of a joint's moment of inertia J.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainParams {
    /// k/J (1/s²): each joint's spring; its natural period is 2π/√(k/J).
    pub stiffness: f32,
    /// A joint's damper d/J (1/s), meadow's addition (the paper damps only through the drag).
    pub damping: f32,
}

impl ChainParams {
    /// Refuse constants outside the flags' ranges ([`STIFFNESS_RANGE`], [`DAMPING_RANGE`]).
    pub fn check(&self) -> crate::error::Result<()> {
        let ((lo, hi), (dlo, dhi)) = (STIFFNESS_RANGE, DAMPING_RANGE);
        if !(lo..=hi).contains(&self.stiffness) || !(dlo..=dhi).contains(&self.damping) {
            return Err(crate::error::Error::bad_input(format!(
                "--stiffness {} / --damping {}: outside {lo}..={hi} (1/s²) / {dlo}..={dhi} (1/s)",
                self.stiffness, self.damping
            )));
        }
        Ok(())
    }

    /// How far the tip of a unit upright blade moves at its equilibrium under `wind` (m/s, its
    /// frame the world's): `BladeResponse::tip_offset` of the chain responses.
    pub fn tip_offset(&self, wind: Vec3) -> Vec3 {
        let upright = Chain::upright(1.0);
        let state = upright.equilibrium(Vec3::new(wind.x, 0.0, wind.z), *self);
        upright.controls(&state)[2] - Vec3::Y
    }
}

impl Default for ChainParams {
    fn default() -> Self {
        Self { stiffness: 100.0, damping: 4.0 }
    }
}

/// A blade's chain at rest: its segments, and the Bézier controls the drawn curve is fitted by.
#[derive(Clone, Copy, Debug)]
pub struct Chain {
    /// R⁰ₖ: segment k's rest rotation relative to the one below (about x, in the blade's plane).
    pub rest: [Quat; CHAIN_SEGMENTS],
    /// Half of each segment's length, l (metres).
    pub half: [f32; CHAIN_SEGMENTS],
    /// The neutral Bézier's controls P1..P3.
    pub controls: [Vec3; 3],
    /// The neutral curve's arc length over `ARC_SAMPLES` chords.
    pub rest_arc: f32,
}

/// A chain's state: per joint the rotation ψ away from its rest (a rotation vector in the
/// segment's frame) and the angular velocity ω relative to the segment below.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChainState {
    /// ψₖ.
    pub psi: [Vec3; CHAIN_SEGMENTS],
    /// ωₖ.
    pub omega: [Vec3; CHAIN_SEGMENTS],
}

impl Chain {
    /// The chain of `blade`'s neutral curve: joints at t = k / 4.
    pub fn new(blade: &BladeInstance) -> Self {
        Self::from_controls(bezier::neutral_control_points(blade))
    }

    /// An upright chain of `height` metres: 4 equal segments along +y (§3.3's virtual blade).
    pub fn upright(height: f32) -> Self {
        Self::from_controls([Vec3::ZERO, Vec3::Y * (height / 3.0), Vec3::Y * (2.0 * height / 3.0), Vec3::Y * height])
    }

    /// The chain through the cubic `n` (n[0] the root at 0).
    pub fn from_controls(n: [Vec3; 4]) -> Self {
        let mut rest = [Quat::IDENTITY; CHAIN_SEGMENTS];
        let mut half = [0.0; CHAIN_SEGMENTS];
        // R⁰ₖ turns the direction of the segment below (ŷ below the first) onto this one's, about
        // x: the half-angle quaternion normalize((a × b)ₓ, 0, 0, 1 + a·b), as `chain_of` takes it.
        let mut below = glam::Vec2::X; // (y, z)
        for k in 0..CHAIN_SEGMENTS {
            let a = bezier::point(&n, k as f32 / CHAIN_SEGMENTS as f32);
            let b = bezier::point(&n, (k + 1) as f32 / CHAIN_SEGMENTS as f32);
            let s = b - a;
            let len = s.length();
            let dir = if len > 0.0 { glam::Vec2::new(s.y, s.z) / len } else { glam::Vec2::X };
            let turn = glam::Vec4::new(below.x * dir.y - below.y * dir.x, 0.0, 0.0, 1.0 + below.dot(dir)).normalize();
            rest[k] = Quat::from_vec4(turn);
            half[k] = 0.5 * len;
            below = dir;
        }
        let controls = [n[1], n[2], n[3]];
        Self { rest, half, controls, rest_arc: arc_length(&controls) }
    }

    /// Segment k's frame Tₖ = Tₖ₋₁·R⁰ₖ·M(ψₖ) for every k (T₀ the blade's frame).
    pub fn frames(&self, state: &ChainState) -> [Quat; CHAIN_SEGMENTS] {
        let mut frame = Quat::IDENTITY;
        std::array::from_fn(|k| {
            frame = frame * self.rest[k] * Quat::from_scaled_axis(state.psi[k]);
            frame
        })
    }

    /// The static equilibrium under the wind `w` (m/s, in the blade's frame), at rest: the still
    /// drag on every joint ([`Chain::equilibrium_under`]).
    pub fn equilibrium(&self, w: Vec3, params: ChainParams) -> ChainState {
        self.equilibrium_under(&[drag(w); CHAIN_SEGMENTS], params)
    }

    /// The static equilibrium at rest under a force per joint (per unit mass, the blade's frame):
    /// joint by joint from the root, the fixed point of k·ψ = l × (Tₖ₋₁ R⁰ₖ M(ψ))′fₖ (§3.3's
    /// solve), `EQUILIBRIUM_ITERATIONS` times from ψ = 0.
    pub fn equilibrium_under(&self, force: &[Vec3; CHAIN_SEGMENTS], params: ChainParams) -> ChainState {
        let mut state = ChainState::default();
        let mut frame = Quat::IDENTITY;
        for (k, f) in force.iter().enumerate() {
            let mut psi = Vec3::ZERO;
            for _ in 0..EQUILIBRIUM_ITERATIONS {
                let q = frame * self.rest[k] * Quat::from_scaled_axis(psi);
                psi = moment(self.half[k], q, *f) / params.stiffness;
            }
            state.psi[k] = psi;
            frame = frame * self.rest[k] * Quat::from_scaled_axis(psi);
        }
        state
    }

    /// §3.3's virtual moments mₖ = k·ψₖ of `state` (gravity left out), each as the horizontal
    /// force per unit mass in the chain's frame whose moment l × T′f on its segment it is: across
    /// the segment (4l/3)·Tₖ(mₖ × ŷ), plus the part along the segment sₖ (no moment) that makes it
    /// horizontal (|sₖ.y| taken as at least 0.1). Under a steady wind this gives back the drag.
    pub fn virtual_forces(&self, state: &ChainState, params: ChainParams) -> [Vec3; CHAIN_SEGMENTS] {
        let frames = self.frames(state);
        std::array::from_fn(|k| {
            let m = params.stiffness * state.psi[k];
            let across = frames[k] * (m.cross(Vec3::Y) * (4.0 / 3.0 * self.half[k]));
            let along = frames[k] * Vec3::Y;
            across - along * (across.y / along.y.max(0.1))
        })
    }

    /// One step of `dt` seconds under the wind `w` (m/s, in the blade's frame): §3.1's
    /// simplified algorithm, joint by joint from the root.
    pub fn step(&self, state: &mut ChainState, w: Vec3, params: ChainParams, dt: f32) {
        let mut frame = Quat::IDENTITY;
        let mut top_velocity = Vec3::ZERO;
        for k in 0..CHAIN_SEGMENTS {
            let l = self.half[k];
            let lever = Vec3::Y * l;
            let q = frame * self.rest[k] * Quat::from_scaled_axis(state.psi[k]);
            // v = v*ₖ₋₁ − Tₖ(l × ωₖ) at the segment's centre (§3.2).
            let centre = top_velocity + q * state.omega[k].cross(lever);
            let s = DRAG * (w - centre).length().powf(GAMMA - 1.0);
            // J ω̇ = −g + l × T' f, the drag's part in ω taken implicitly.
            let driven = moment(l, q, s * (w - top_velocity));
            let across = 0.75 * s;
            let rhs = state.omega[k] + dt * (driven - params.stiffness * state.psi[k]);
            let divisor = Vec3::new(across, 0.0, across) + Vec3::splat(params.damping);
            state.omega[k] = rhs / (Vec3::ONE + dt * divisor);
            // ψ̇ = ω: Rₖ = Rₖ M(ψ̇ Δt).
            let turned = Quat::from_scaled_axis(state.psi[k]) * Quat::from_scaled_axis(state.omega[k] * dt);
            state.psi[k] = scaled_axis(turned);
            let q = frame * self.rest[k] * Quat::from_scaled_axis(state.psi[k]);
            // v*ₖ = v*ₖ₋₁ − 2Tₖ(l × ωₖ).
            top_velocity += 2.0 * (q * state.omega[k].cross(lever));
            frame = q;
        }
    }

    /// The drawn curve's controls P1..P3 (the root at 0): P3 the chain's tip, P1 carried by the
    /// first segment and P2 by the last, each where the neutral curve has it in that segment's
    /// rest frame (so the chain at rest draws the neutral curve), then scaled about the root to
    /// the neutral curve's arc length, and kept above the root.
    pub fn controls(&self, state: &ChainState) -> [Vec3; 3] {
        let rest = self.frames(&ChainState::default());
        let now = self.frames(state);
        let tip_of = |frames: &[Quat; CHAIN_SEGMENTS]| -> Vec3 {
            frames.iter().zip(self.half).map(|(q, l)| *q * (Vec3::Y * (2.0 * l))).sum()
        };
        let (rest_tip, tip) = (tip_of(&rest), tip_of(&now));
        let last = CHAIN_SEGMENTS - 1;
        let mut p = [
            now[0] * (rest[0].inverse() * self.controls[0]),
            tip + now[last] * (rest[last].inverse() * (self.controls[1] - rest_tip)),
            tip,
        ];
        let scale = self.rest_arc / arc_length(&p).max(1e-6);
        for point in &mut p {
            *point *= scale;
            point.y = point.y.max(0.0);
        }
        p
    }
}

/// The drag per unit mass of a still segment in the wind `w`: k_w/m · |w|^(γ−1) · w.
fn drag(w: Vec3) -> Vec3 {
    DRAG * w.length().powf(GAMMA - 1.0) * w
}

/// The moment per unit J of `force` (per unit mass) at the centre of a segment of half length
/// `l` in frame `q`: l × T' f / J, with J = 4 m l² / 3 about the joint.
fn moment(l: f32, q: Quat, force: Vec3) -> Vec3 {
    Vec3::Y.cross(q.inverse() * force) * (0.75 / l)
}

/// V(q): the rotation vector of `q`, the shorter way round.
fn scaled_axis(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    q.to_scaled_axis()
}

/// The Bézier curve's length from the root through `p`, over `ARC_SAMPLES` chords.
pub fn arc_length(p: &[Vec3; 3]) -> f32 {
    let controls = [Vec3::ZERO, p[0], p[1], p[2]];
    let points: Vec<Vec3> =
        (0..=ARC_SAMPLES).map(|k| bezier::point(&controls, k as f32 / ARC_SAMPLES as f32)).collect();
    points.windows(2).map(|pair| (pair[1] - pair[0]).length()).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 0.4 m blade leaning forward by 0.09 m.
    fn blade() -> Chain {
        let n = [Vec3::ZERO, Vec3::new(0.0, 0.16, 0.0), Vec3::new(0.0, 0.32, 0.03), Vec3::new(0.0, 0.39, 0.09)];
        let chain = Chain::from_controls(n);
        let length = 2.0 * chain.half.iter().sum::<f32>();
        assert!(
            (length - chain.rest_arc).abs() < 0.01 * chain.rest_arc,
            "chain {length} m, curve {} m",
            chain.rest_arc
        );
        chain
    }

    #[test]
    fn at_rest_the_chain_draws_the_neutral_curve() {
        let chain = blade();
        let p = chain.controls(&ChainState::default());
        for (a, b) in p.iter().zip(chain.controls) {
            assert!((*a - b).length() < 1e-5, "{a} against {b}");
        }
    }

    #[test]
    fn the_equilibrium_is_a_rest_of_the_step() {
        let chain = blade();
        let params = ChainParams::default();
        let w = Vec3::new(8.0, 0.0, 0.0);
        let mut state = chain.equilibrium(w, params);
        let start = chain.controls(&state)[2];
        assert!(start.x > 0.05, "tip {start} under 8 m/s +x");
        for _ in 0..120 {
            chain.step(&mut state, w, params, 1.0 / 60.0);
        }
        let end = chain.controls(&state)[2];
        assert!((end - start).length() < 0.02 * 0.4, "tip {start} moved to {end} under a steady wind");
    }

    #[test]
    fn an_upright_chains_virtual_forces_give_back_its_shape() {
        // §3.3: the moments k·ψ, given as forces, hold a blade of the same shape where it is.
        let chain = Chain::upright(0.4);
        let params = ChainParams::default();
        let state = chain.equilibrium(Vec3::new(8.0, 0.0, -3.0), params);
        let again = chain.equilibrium_under(&chain.virtual_forces(&state, params), params);
        let (tip, back) = (chain.controls(&state)[2], chain.controls(&again)[2]);
        assert!(tip.x > 0.05 && tip.z < -0.01, "tip {tip} under the wind");
        assert!((tip - back).length() < 0.01 * 0.4, "tip {tip} against {back} from the virtual forces");
    }

    #[test]
    fn a_released_chain_swings_at_its_joints_period() {
        let chain = blade();
        let params = ChainParams { stiffness: 100.0, damping: 0.0 };
        let mut state = chain.equilibrium(Vec3::new(4.0, 0.0, 0.0), params);
        let dt = 1.0 / 240.0;
        let rest = chain.controls(&ChainState::default())[2].x;
        let trace: Vec<f32> = (0..480)
            .map(|_| {
                chain.step(&mut state, Vec3::ZERO, params, dt);
                chain.controls(&state)[2].x - rest
            })
            .collect();
        let ups: Vec<usize> = (1..trace.len()).filter(|&k| trace[k - 1] < 0.0 && trace[k] >= 0.0).collect();
        let period = (ups[ups.len() - 1] - ups[0]) as f32 / (ups.len() - 1) as f32 * dt;
        let expected = std::f32::consts::TAU / params.stiffness.sqrt();
        assert!((period - expected).abs() < 0.05 * expected, "period {period} s against {expected} s");
    }
}
