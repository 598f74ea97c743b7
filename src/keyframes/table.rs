//! The keyframe table (thesis 3.2.3–3.2.6): poses indexed by force magnitude and by the angle
//! between the force and the blade's normal, a quarter of them stored thanks to the mirror
//! symmetry of fig. 3.8–3.9, and the selection and smoothing the vertex shader performs
//! (`shaders/animation/keyframes.glsl` mirrors `select` and `blend`).

use std::f32::consts::FRAC_PI_2;

use glam::Vec3;

use crate::keyframes::pose::{self, BladeModel, Pose, MAX_FORCE};

/// How in-between poses are made (thesis 3.2.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Smoothing {
    /// The nearest stored pose (the thesis' choice with 1000 poses).
    #[default]
    Nearest,
    /// Linear interpolation of displacements, eq. 3.13.
    Linear,
    /// Spherical linear interpolation, eq. 3.14 (keeps the blade's length).
    Slerp,
}

impl Smoothing {
    /// Index used by the shaders.
    pub fn code(self) -> u32 {
        match self {
            Smoothing::Nearest => 0,
            Smoothing::Linear => 1,
            Smoothing::Slerp => 2,
        }
    }
}

/// Shape of the stored quarter: `magnitudes × angles` poses, angles spanning [0, π/2] from the
/// normal towards the blade's width, magnitudes [0, MAX_FORCE].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyframeLayout {
    /// Force magnitudes sampled.
    pub magnitudes: u32,
    /// Angles sampled in the quarter.
    pub angles: u32,
}

impl KeyframeLayout {
    /// Layout for about `poses` poses over the full circle, a quarter stored: the angle count is
    /// about √(poses/4)/1.6 (1000 poses: 25 magnitudes × 10 angles = 250 stored).
    pub fn for_poses(poses: u32) -> Self {
        let quarter = poses.div_ceil(4).max(1);
        let angles = ((quarter as f32).sqrt() / 1.6).round().clamp(1.0, 64.0) as u32;
        let magnitudes = quarter.div_ceil(angles).max(2);
        Self { magnitudes, angles }
    }

    /// Poses stored.
    pub fn stored(&self) -> u32 {
        self.magnitudes * self.angles
    }

    /// Poses represented over the full circle (4 mirror images of each stored one).
    pub fn represented(&self) -> u32 {
        4 * self.stored()
    }

    /// Row of the pose with magnitude index `m` and angle index `a`.
    pub fn row(&self, m: u32, a: u32) -> u32 {
        m * self.angles + a
    }

    /// Force magnitude of magnitude index `m`.
    pub fn magnitude(&self, m: u32) -> f32 {
        MAX_FORCE * m as f32 / (self.magnitudes - 1) as f32
    }

    /// Angle (radians from the normal towards the width) of angle index `a`.
    pub fn angle(&self, a: u32) -> f32 {
        if self.angles == 1 {
            0.0
        } else {
            FRAC_PI_2 * a as f32 / (self.angles - 1) as f32
        }
    }
}

/// One stored level of one pose: backbone displacement from the straight unit blade (xyz) and the
/// twist of the width about +y (w, radians).
pub type Keyframe = [f32; 4];

/// What one stored record describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Representation {
    /// The thesis': one record per moving vertex pair (level 1..=S), displacement and twist.
    #[default]
    Vertex,
    /// Beyond the thesis: the three displaced Bézier control points P1..P3 of the pose (P0 is
    /// the root), the tip twist in the first record's w; usable at any segment count.
    Curve,
}

/// Segments of the chain a curve pose is fitted to.
pub const CURVE_FIT_SEGMENTS: u32 = 16;

/// Stored poses of the reference blade: `layout.stored()` rows of `records` records each
/// (vertex: the levels 1..=S, the root never moves and is not stored, thesis 3.3; curve: P1..P3).
#[derive(Clone, Debug)]
pub struct KeyframeTable {
    /// Table shape.
    pub layout: KeyframeLayout,
    /// Segments of the chain the poses were solved with.
    pub segments: u32,
    /// What a record is.
    pub representation: Representation,
    /// Records per pose.
    pub records: u32,
    /// `stored × records` keyframes, row-major.
    pub frames: Vec<Keyframe>,
}

/// What the selection decided for one force: up to four stored poses with weights, and the
/// mirror signs that map the stored quarter onto the force's quadrant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Selection {
    /// Rows of the poses blended.
    pub rows: [u32; 4],
    /// Their weights (sum 1), in (magnitude, angle) bilinear order: (m,a) (m+1,a) (m,a+1) (m+1,a+1).
    pub weights: [f32; 4],
    /// Magnitude blend parameter (for slerp).
    pub t_magnitude: f32,
    /// Angle blend parameter (for slerp).
    pub t_angle: f32,
    /// Sign of the force's component across the blade (x mirror).
    pub sign_x: f32,
    /// Sign of the force's component along the normal: front (+) or back (−), eq. 3.10–3.11.
    pub sign_z: f32,
}

impl KeyframeTable {
    /// Generate every stored pose with the chain solver (vertex representation).
    pub fn generate(model: &BladeModel, layout: KeyframeLayout) -> Self {
        let s = model.segments as usize;
        let neutral = Pose::neutral(model.segments);
        let mut frames = Vec::with_capacity(layout.stored() as usize * s);
        for m in 0..layout.magnitudes {
            for a in 0..layout.angles {
                let (f, phi) = (layout.magnitude(m), layout.angle(a));
                let pose = pose::solve(model, f * phi.sin(), f * phi.cos());
                for level in 1..=s {
                    let d = pose.backbone[level] - neutral.backbone[level];
                    frames.push([d.x, d.y, d.z, pose.twist[level]]);
                }
            }
        }
        Self {
            layout,
            segments: model.segments,
            representation: Representation::Vertex,
            records: model.segments,
            frames,
        }
    }

    /// Generate the curve representation: each pose solved on a `CURVE_FIT_SEGMENTS` chain and
    /// fitted with a cubic Bézier (root fixed, tip pinned to the chain's tip, P1 and P2 by least
    /// squares at t = k/n); records are the control points' displacements from the straight
    /// blade's (0, i/3, 0), the tip twist in the first record's w.
    pub fn generate_curve(layout: KeyframeLayout) -> Self {
        let model = BladeModel::new(CURVE_FIT_SEGMENTS);
        let mut frames = Vec::with_capacity(layout.stored() as usize * 3);
        for m in 0..layout.magnitudes {
            for a in 0..layout.angles {
                let (f, phi) = (layout.magnitude(m), layout.angle(a));
                let pose = pose::solve(&model, f * phi.sin(), f * phi.cos());
                let control = fit_bezier(&pose.backbone);
                for (i, p) in control.iter().enumerate() {
                    let d = *p - Vec3::new(0.0, (i + 1) as f32 / 3.0, 0.0);
                    let w = if i == 0 { *pose.twist.last().expect("levels") } else { 0.0 };
                    frames.push([d.x, d.y, d.z, w]);
                }
            }
        }
        Self { layout, segments: CURVE_FIT_SEGMENTS, representation: Representation::Curve, records: 3, frames }
    }

    /// Root-relative position of record `record` (1-based) on the straight blade.
    pub fn straight(&self, record: u32) -> Vec3 {
        Vec3::new(0.0, record as f32 / self.records as f32, 0.0)
    }

    /// The stored keyframe of `row`, record `level` (1..=records).
    pub fn keyframe(&self, row: u32, level: u32) -> Keyframe {
        self.frames[(row * self.records + level - 1) as usize]
    }

    /// Choose the stored poses for a force `(fx, fz)` in the blade's frame, already divided by
    /// the blade's stiffness (eq. 3.10–3.12 with the mirror symmetry of fig. 3.9).
    pub fn select(&self, fx: f32, fz: f32, smoothing: Smoothing) -> Selection {
        let l = self.layout;
        let magnitude = (fx * fx + fz * fz).sqrt();
        let magnitude = if magnitude.is_finite() { magnitude.min(MAX_FORCE) } else { 0.0 };
        // ω of eq. 3.12 folded into the stored quarter by the mirrors.
        let phi = if magnitude > 0.0 { fx.abs().atan2(fz.abs()) } else { 0.0 };
        let sign_x = if fx < 0.0 { -1.0 } else { 1.0 };
        let sign_z = if fz < 0.0 { -1.0 } else { 1.0 };
        let mf = magnitude / MAX_FORCE * (l.magnitudes - 1) as f32;
        let af = if l.angles > 1 { phi / FRAC_PI_2 * (l.angles - 1) as f32 } else { 0.0 };
        match smoothing {
            Smoothing::Nearest => {
                // floor(x + 0.5), as the shader: ties round up on both sides.
                let m = ((mf + 0.5).floor() as u32).min(l.magnitudes - 1);
                let a = ((af + 0.5).floor() as u32).min(l.angles - 1);
                let row = l.row(m, a);
                Selection {
                    rows: [row; 4],
                    weights: [1.0, 0.0, 0.0, 0.0],
                    t_magnitude: 0.0,
                    t_angle: 0.0,
                    sign_x,
                    sign_z,
                }
            }
            Smoothing::Linear | Smoothing::Slerp => {
                let m0 = (mf.floor() as u32).min(l.magnitudes - 2);
                let a0 = (af.floor() as u32).min(l.angles.saturating_sub(2));
                let a1 = (a0 + 1).min(l.angles - 1);
                let tm = (mf - m0 as f32).clamp(0.0, 1.0);
                let ta = if a1 > a0 { (af - a0 as f32).clamp(0.0, 1.0) } else { 0.0 };
                Selection {
                    rows: [l.row(m0, a0), l.row(m0 + 1, a0), l.row(m0, a1), l.row(m0 + 1, a1)],
                    weights: [(1.0 - tm) * (1.0 - ta), tm * (1.0 - ta), (1.0 - tm) * ta, tm * ta],
                    t_magnitude: tm,
                    t_angle: ta,
                    sign_x,
                    sign_z,
                }
            }
        }
    }

    /// Root-relative position and twist of `level` for a selection, mirrored into the force's
    /// quadrant: the CPU reference of the vertex shader.
    pub fn blend(&self, selection: &Selection, level: u32, smoothing: Smoothing) -> (Vec3, f32) {
        let neutral = self.straight(level);
        let at = |i: usize| {
            let k = self.keyframe(selection.rows[i], level);
            (neutral + Vec3::new(k[0], k[1], k[2]), k[3])
        };
        let (position, twist) = match smoothing {
            Smoothing::Nearest => at(0),
            // Eq. 3.13: E_ref + Σ δ_i Δ_i.
            Smoothing::Linear => (0..4).fold((Vec3::ZERO, 0.0), |(p, t), i| {
                let (pi, ti) = at(i);
                (p + pi * selection.weights[i], t + ti * selection.weights[i])
            }),
            // Eq. 3.14 on the root-relative vectors P0P, first along magnitude, then along angle.
            Smoothing::Slerp => {
                let (p0, t0) = at(0);
                let (p1, t1) = at(1);
                let (p2, t2) = at(2);
                let (p3, t3) = at(3);
                let tm = selection.t_magnitude;
                let lo = slerp(p0, p1, tm);
                let hi = slerp(p2, p3, tm);
                let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
                (slerp(lo, hi, selection.t_angle), lerp(lerp(t0, t1, tm), lerp(t2, t3, tm), selection.t_angle))
            }
        };
        (
            Vec3::new(position.x * selection.sign_x, position.y, position.z * selection.sign_z),
            twist * selection.sign_x * selection.sign_z,
        )
    }

    /// Control points P0..P3 (root-relative, unit blade, mirrored) and tip twist a curve table
    /// gives for a force.
    pub fn curve_for(&self, fx: f32, fz: f32, smoothing: Smoothing) -> ([Vec3; 4], f32) {
        assert_eq!(self.representation, Representation::Curve, "curve_for needs a curve table");
        let selection = self.select(fx, fz, smoothing);
        let (p1, twist) = self.blend(&selection, 1, smoothing);
        let (p2, _) = self.blend(&selection, 2, smoothing);
        let (p3, _) = self.blend(&selection, 3, smoothing);
        ([Vec3::ZERO, p1, p2, p3], twist)
    }

    /// The pose the table gives for a force (levels 0..=S), for tests and tools.
    pub fn pose_for(&self, fx: f32, fz: f32, smoothing: Smoothing) -> Pose {
        assert_eq!(self.representation, Representation::Vertex, "pose_for needs a vertex table");
        let selection = self.select(fx, fz, smoothing);
        let mut pose = Pose::neutral(self.segments);
        for level in 1..=self.segments {
            let (p, t) = self.blend(&selection, level, smoothing);
            pose.backbone[level as usize] = p;
            pose.twist[level as usize] = t;
        }
        pose
    }
}

/// Cubic Bézier through the root with its end at the chain's tip, P1 and P2 fitted by least
/// squares to the chain's levels at uniform t: returns P1, P2, P3.
pub fn fit_bezier(levels: &[Vec3]) -> [Vec3; 3] {
    let n = levels.len() - 1;
    let tip = levels[n];
    // B(t) = b1 P1 + b2 P2 + b3 P3 with P0 = 0; minimise Σ |b1 P1 + b2 P2 − (Q − b3 P3)|².
    let (mut a11, mut a12, mut a22) = (0.0f32, 0.0f32, 0.0f32);
    let (mut r1, mut r2) = (Vec3::ZERO, Vec3::ZERO);
    for (k, q) in levels.iter().enumerate() {
        let t = k as f32 / n as f32;
        let s = 1.0 - t;
        let (b1, b2, b3) = (3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
        let target = *q - tip * b3;
        a11 += b1 * b1;
        a12 += b1 * b2;
        a22 += b2 * b2;
        r1 += target * b1;
        r2 += target * b2;
    }
    let det = a11 * a22 - a12 * a12;
    let p1 = (r1 * a22 - r2 * a12) / det;
    let p2 = (r2 * a11 - r1 * a12) / det;
    [p1, p2, tip]
}

/// Spherical linear interpolation of two vectors from the root (eq. 3.14), with the lengths
/// interpolated linearly; falls back to a linear blend for nearly parallel vectors.
pub fn slerp(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    let (la, lb) = (a.length(), b.length());
    if la == 0.0 || lb == 0.0 {
        return a.lerp(b, t);
    }
    let (ua, ub) = (a / la, b / lb);
    let omega = ua.dot(ub).clamp(-1.0, 1.0).acos();
    let direction = if omega < 1e-4 {
        ua.lerp(ub, t).normalize()
    } else {
        (ua * ((1.0 - t) * omega).sin() + ub * (t * omega).sin()) / omega.sin()
    };
    direction * (la + (lb - la) * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(segments: u32) -> KeyframeTable {
        KeyframeTable::generate(&BladeModel::new(segments), KeyframeLayout::for_poses(1000))
    }

    #[test]
    fn curve_fits_the_chain_and_keeps_the_tip() {
        let layout = KeyframeLayout::for_poses(200);
        let curve = KeyframeTable::generate_curve(layout);
        let vertex = KeyframeTable::generate(&BladeModel::new(CURVE_FIT_SEGMENTS), layout);
        assert_eq!(curve.records, 3);
        let (f, phi) = (layout.magnitude(layout.magnitudes - 1), layout.angle(1));
        let (fx, fz) = (f * phi.sin(), -f * phi.cos());
        let (cp, _) = curve.curve_for(fx, fz, Smoothing::Nearest);
        let chain = vertex.pose_for(fx, fz, Smoothing::Nearest);
        assert!((cp[3] - chain.backbone[16]).length() < 1e-5, "the tip is pinned");
        for k in 0..=16 {
            let p = crate::scene::bezier::point(&cp, k as f32 / 16.0);
            assert!((p - chain.backbone[k]).length() < 0.03, "level {k}: curve {p:?} chain {:?}", chain.backbone[k]);
        }
    }

    #[test]
    fn thousand_poses_store_a_quarter() {
        let l = KeyframeLayout::for_poses(1000);
        assert_eq!((l.magnitudes, l.angles), (25, 10));
        assert_eq!(l.stored(), 250);
        assert_eq!(l.represented(), 1000);
    }

    #[test]
    fn every_stored_pose_keeps_its_segment_lengths() {
        let t = table(8);
        for row in 0..t.layout.stored() {
            let mut previous = Vec3::ZERO;
            for level in 1..=8 {
                let k = t.keyframe(row, level);
                let p = Vec3::new(k[0], level as f32 / 8.0 + k[1], k[2]);
                let length = (p - previous).length();
                assert!((length - 0.125).abs() <= 0.125e-3, "row {row} level {level}: {length}");
                previous = p;
            }
        }
    }

    #[test]
    fn tip_displacement_grows_with_the_force_at_every_angle() {
        let t = table(4);
        for a in 0..t.layout.angles {
            let mut last = -1.0;
            for m in 0..t.layout.magnitudes {
                let k = t.keyframe(t.layout.row(m, a), 4);
                let tip = Vec3::new(k[0], k[1], k[2]).length();
                assert!(tip > last || m == 0, "angle {a} magnitude {m}");
                last = tip;
            }
        }
    }

    #[test]
    fn mirrored_poses_equal_a_direct_solve_for_the_mirrored_force() {
        let model = BladeModel::new(4);
        let layout = KeyframeLayout::for_poses(1000);
        let t = KeyframeTable::generate(&model, layout);
        // A force exactly on a stored sample, mirrored into each quadrant.
        let (f, phi) = (layout.magnitude(12), layout.angle(3));
        for (sx, sz) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
            let (fx, fz) = (sx * f * phi.sin(), sz * f * phi.cos());
            let from_table = t.pose_for(fx, fz, Smoothing::Nearest);
            let direct = pose::solve(&model, fx, fz);
            for level in 0..=4 {
                assert!(
                    (from_table.backbone[level] - direct.backbone[level]).length() < 1e-5,
                    "quadrant ({sx}, {sz}) level {level}"
                );
                assert!((from_table.twist[level] - direct.twist[level]).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn smoothing_modes_agree_on_samples_and_slerp_keeps_length_between() {
        let t = table(4);
        let l = t.layout;
        let (f, phi) = (l.magnitude(5), l.angle(2));
        let (fx, fz) = (f * phi.sin(), f * phi.cos());
        let nearest = t.pose_for(fx, fz, Smoothing::Nearest);
        for smoothing in [Smoothing::Linear, Smoothing::Slerp] {
            let p = t.pose_for(fx, fz, smoothing);
            assert!((p.backbone[4] - nearest.backbone[4]).length() < 1e-4, "{smoothing:?}");
        }
        // Half-way between two distant stored magnitudes (a coarse table): slerp keeps the blade's
        // length better than linear interpolation, which shortens it (fig. 3.6).
        let coarse = KeyframeTable::generate(&BladeModel::new(4), KeyframeLayout { magnitudes: 3, angles: 2 });
        let length = |p: &Pose| (0..4).map(|i| p.segment_length(i)).sum::<f32>();
        let f_mid = 0.25 * MAX_FORCE;
        let lin = (length(&coarse.pose_for(0.0, f_mid, Smoothing::Linear)) - 1.0).abs();
        let sl = (length(&coarse.pose_for(0.0, f_mid, Smoothing::Slerp)) - 1.0).abs();
        assert!(sl < lin, "slerp length error {sl} vs linear {lin}");
    }
}
