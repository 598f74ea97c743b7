//! Physically generated blade poses (thesis 3.2.4): a blade of S rigid segments in static
//! equilibrium under a horizontal external force and gravity, after the segment chain of
//! Belyaev et al. §3.3 (spring stiffness per joint, solved by iteration).
//!
//! Frame: the blade's local frame — x across the blade, y up, z along its normal. The reference
//! blade is straight, of unit length, rooted at the origin; poses are scaled by each blade's
//! height on the GPU.
//!
//! Two departures from Belyaev's simplified chain, both to make a side wind look right
//! (issue 3, item 2, after Zhang Xia §3.2.5):
//! - every joint carries the moment of all the forces above it, not only of its own segment
//!   (Belyaev neglects "the effect of the upper segment to lower", which gives a blade that
//!   bends almost uniformly; a cantilever bends most at the root);
//! - the joints are anisotropic: a blade is a ribbon, so bending across its face (flapping) is
//!   softer than bending along its edge, and the blade twists to face the wind, linearly from the
//!   root to the tip (Zhang Xia's rotation θ·i/n), the total twist growing with the force.

use glam::{Quat, Vec3};

/// Largest force magnitude of the keyframe table, in keyframe units: a blade of stiffness 1
/// under force 1 bends its tip close to the ground.
pub const MAX_FORCE: f32 = 1.0;

/// Physical parameters of the reference blade.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BladeModel {
    /// Rigid segments.
    pub segments: u32,
    /// Bending stiffness EI at the root (moment × length per radian). A joint between segments
    /// of length l = 1/S gets k = EI / l, so the blade bends the same for every segment count;
    /// joints above taper linearly to `tip_stiffness_ratio` of it.
    pub root_stiffness: f32,
    /// Stiffness of the top joint relative to the root.
    pub tip_stiffness_ratio: f32,
    /// Edgewise stiffness relative to flapping (a ribbon is stiffer along its edge).
    pub edge_ratio: f32,
    /// Gravity per unit length (downwards), relative to the force unit.
    pub gravity: f32,
    /// Force at which the blade has turned 63 % of the way towards facing the wind.
    pub twist_force: f32,
    /// Force per unit length at `MAX_FORCE` (scales the keyframe unit into the chain's).
    pub load_at_max: f32,
}

impl BladeModel {
    /// meadow's blade with `segments` segments.
    pub fn new(segments: u32) -> Self {
        Self {
            segments,
            root_stiffness: 0.25,
            tip_stiffness_ratio: 0.35,
            edge_ratio: 4.0,
            gravity: 0.08,
            twist_force: 0.25,
            load_at_max: 1.4,
        }
    }

    fn joint_stiffness(&self, joint: u32) -> f32 {
        // Taper by the joint's height on the blade, so every segment count sees the same blade.
        let s = joint as f32 / self.segments as f32;
        self.root_stiffness * self.segments as f32 * (1.0 + s * (self.tip_stiffness_ratio - 1.0))
    }
}

/// One pose: backbone points at levels 0..=S and the twist of the blade's width at each level.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Backbone points, level 0 at the root (always the origin).
    pub backbone: Vec<Vec3>,
    /// Rotation of the width about +y at each level (radians); 0 at the root.
    pub twist: Vec<f32>,
}

impl Pose {
    /// The neutral pose: straight up.
    pub fn neutral(segments: u32) -> Self {
        let l = 1.0 / segments as f32;
        Self {
            backbone: (0..=segments).map(|i| Vec3::new(0.0, i as f32 * l, 0.0)).collect(),
            twist: vec![0.0; segments as usize + 1],
        }
    }

    /// Length of segment `i`.
    pub fn segment_length(&self, i: usize) -> f32 {
        (self.backbone[i + 1] - self.backbone[i]).length()
    }

    /// Tip displacement from the neutral pose.
    pub fn tip_displacement(&self) -> Vec3 {
        *self.backbone.last().expect("at least one level") - Vec3::Y
    }
}

/// Total twist towards facing a horizontal force `(fx, fz)` (local frame): the blade turns its
/// normal towards the force or against it, whichever is nearer, so the twist lies in
/// [-π/2, π/2]; it grows with the force as `1 - exp(-|f| / twist_force)`.
pub fn twist_towards(model: &BladeModel, fx: f32, fz: f32) -> f32 {
    let magnitude = (fx * fx + fz * fz).sqrt();
    if magnitude == 0.0 {
        return 0.0;
    }
    // Angle from the normal (+z) towards +x, folded so the nearer of ±normal turns to the force.
    let mut phi = fx.atan2(fz);
    if phi > std::f32::consts::FRAC_PI_2 {
        phi -= std::f32::consts::PI;
    } else if phi < -std::f32::consts::FRAC_PI_2 {
        phi += std::f32::consts::PI;
    }
    phi * (1.0 - (-magnitude / model.twist_force).exp())
}

/// Solve the static equilibrium of the chain under the horizontal force `(fx, fz)` in keyframe
/// units (local frame), distributed uniformly along the blade, plus gravity.
///
/// Fixed-point iteration with relaxation: joint rotations ψ_i = K_i⁻¹ m_i, where m_i is the
/// moment about joint i of every segment load above it in the current shape (Belyaev §3.3:
/// k_i ψ_i = m_i^W + l × (T M(ψ))' G). The load is applied in steps, each starting from the
/// previous equilibrium, so strong forces converge to the branch the blade actually follows.
pub fn solve(model: &BladeModel, fx: f32, fz: f32) -> Pose {
    let n = model.segments as usize;
    let l = 1.0 / n as f32;
    let twist_total = twist_towards(model, fx, fz);
    let twist: Vec<f32> = (0..=n).map(|i| twist_total * i as f32 / n as f32).collect();
    let full_load = Vec3::new(fx, 0.0, fz) * (model.load_at_max * l) - Vec3::Y * (model.gravity * l);
    const LOAD_STEPS: u32 = 16;

    let mut psi = vec![Vec3::ZERO; n];
    let mut pose = Pose::neutral(model.segments);
    for step in 1..=LOAD_STEPS {
        let load = full_load * (step as f32 / LOAD_STEPS as f32);
        relax(model, &twist, load, l, &mut psi, &mut pose.backbone);
    }
    shape(&psi, l, &mut pose.backbone);
    pose.twist = twist;
    pose
}

/// Iterate the joint rotations to equilibrium under `load` per segment.
fn relax(model: &BladeModel, twist: &[f32], load: Vec3, l: f32, psi: &mut [Vec3], backbone: &mut [Vec3]) {
    let n = psi.len();
    for _ in 0..4000 {
        shape(psi, l, backbone);
        let mut change = 0.0f32;
        for joint in 0..n {
            let pivot = backbone[joint];
            // Moment of every segment load above the joint, applied at segment centres.
            let moment: Vec3 = (joint..n).map(|j| (0.5 * (backbone[j] + backbone[j + 1]) - pivot).cross(load)).sum();
            // Joint axes twisted with the blade: flap about the width, edge about the normal.
            let tw = 0.5 * (twist[joint] + twist[joint + 1]);
            let flap_axis = Vec3::new(tw.cos(), 0.0, -tw.sin());
            let edge_axis = Vec3::new(tw.sin(), 0.0, tw.cos());
            let k = model.joint_stiffness(joint as u32);
            let target =
                flap_axis * (moment.dot(flap_axis) / k) + edge_axis * (moment.dot(edge_axis) / (k * model.edge_ratio));
            let next = psi[joint] + 0.5 * (target - psi[joint]);
            change = change.max((next - psi[joint]).length());
            psi[joint] = next;
        }
        if change < 1e-7 {
            break;
        }
    }
}

/// Backbone of the chain with relative joint rotations `psi` (world-frame rotation vectors).
fn shape(psi: &[Vec3], l: f32, backbone: &mut [Vec3]) {
    let mut orientation = Quat::IDENTITY;
    backbone[0] = Vec3::ZERO;
    for (i, rotation) in psi.iter().enumerate() {
        orientation = Quat::from_scaled_axis(*rotation) * orientation;
        backbone[i + 1] = backbone[i] + orientation * Vec3::Y * l;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neutral_without_force_apart_from_a_slight_sag() {
        let model = BladeModel::new(4);
        let pose = solve(&model, 0.0, 0.0);
        assert!(pose.tip_displacement().length() < 1e-3, "gravity alone barely moves an upright blade");
    }

    #[test]
    fn segments_stay_rigid_and_tip_bends_with_the_force() {
        let model = BladeModel::new(8);
        let mut last = 0.0;
        for step in 1..=20 {
            let f = step as f32 / 20.0 * MAX_FORCE;
            let pose = solve(&model, 0.0, f);
            for i in 0..8 {
                assert!((pose.segment_length(i) - 0.125).abs() < 1.25e-4, "segment {i} at force {f}");
            }
            // The distance the tip moved grows with the force (its z alone does not once the blade
            // curls past horizontal).
            let tip = pose.tip_displacement().length();
            assert!(tip > last, "tip displacement grows with force");
            last = tip;
        }
        assert!(last > 0.6, "the strongest force bends the blade far: {last}");
    }

    #[test]
    fn side_wind_twists_and_bends_the_blade_sideways() {
        let model = BladeModel::new(4);
        let pose = solve(&model, 0.6, 0.0);
        assert!(pose.tip_displacement().x > 0.2, "bends along the force");
        assert!(pose.twist[4].abs() > 1.0, "turns towards the wind");
        assert_eq!(pose.twist[0], 0.0);
    }
}
