//! Pose error, measured (issue 13, item 3): how far the pose the keyframe table gives for a force
//! — selection of thesis 3.2.5 (eq. 3.10–3.12, the mirrors of fig. 3.9) and smoothing of 3.2.6
//! (nearest, linear eq. 3.13, SLERP eq. 3.14) — lies from a direct static-equilibrium solve for
//! the same force (`pose::solve`, Belyaev §3.3, the solve that generates the table).
//!
//! - Forces: seeded, uniform over the disc the table covers (|f| ≤ `MAX_FORCE`, every direction of
//!   the full circle, so every mirror quadrant).
//! - Tables: `KeyframeTable::generate(&BladeModel::new(S), KeyframeLayout::for_poses(K))`, the
//!   renderer's vertex table (`render::animation::KeyframeTexture::new`), read with `pose_for`, the
//!   CPU mirror of `kf_select` + `kf_level` in `shaders/animation/keyframes.glsl`, in f32 (the GPU reads
//!   the table through a 16- or 32-bit encoding: 4.4, its errors are reported apart;
//!   `tests/keyframe_pose.rs` runs the shader's functions for these forces and compares).
//! - Error of one pose: the largest distance between corresponding backbone points (levels
//!   0..=S) in % of the blade's length — the reference blade is unit length, S rigid segments of
//!   1/S (`Pose::neutral`, and `solve` only rotates them). The twist is measured apart, in
//!   degrees: it turns the width about the backbone, and how far that moves a vertex depends on
//!   the blade's width, not its length.

use std::f32::consts::TAU;
use std::fmt;

use crate::keyframes::pose::{self, BladeModel, Pose, MAX_FORCE};
use crate::keyframes::{KeyframeLayout, KeyframeTable, Smoothing};
use crate::scene::rng::Rng;

/// Poses over the full circle the report measures (a quarter of each stored), whatever `--poses`.
pub const REPORT_POSES: [u32; 3] = [250, 1000, 4000];
/// Seeded forces per measurement.
pub const SAMPLES: usize = 1024;
/// Seed of the forces.
pub const SEED: u64 = 13;
/// The bound the README quotes: largest backbone error, % of blade length.
pub const MAX_ERROR_BOUND: f32 = 0.5;
/// The smoothings measured, in column order.
pub const SMOOTHINGS: [Smoothing; 3] = [Smoothing::Nearest, Smoothing::Linear, Smoothing::Slerp];

/// `count` forces `(fx, fz)` uniform over the disc |f| ≤ `MAX_FORCE` (radius √u, angle over the
/// full circle), from `seed`.
pub fn sample_forces(seed: u64, count: usize) -> Vec<(f32, f32)> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let r = MAX_FORCE * rng.unit().sqrt();
            let angle = rng.range(0.0, TAU);
            (r * angle.sin(), r * angle.cos())
        })
        .collect()
}

/// Largest distance between corresponding backbone points of two poses of the unit blade, in %
/// of its length.
pub fn backbone_error(a: &Pose, b: &Pose) -> f32 {
    let worst = a.backbone.iter().zip(&b.backbone).map(|(p, q)| (*p - *q).length()).fold(0.0f32, f32::max);
    100.0 * worst
}

/// Largest difference of the twist at corresponding levels, in degrees.
pub fn twist_error(a: &Pose, b: &Pose) -> f32 {
    a.twist.iter().zip(&b.twist).map(|(p, q)| (p - q).abs()).fold(0.0f32, f32::max).to_degrees()
}

/// Mean and max over the samples of one error.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorStats {
    /// Mean over the samples.
    pub mean: f32,
    /// Largest over the samples.
    pub max: f32,
}

impl ErrorStats {
    /// Mean (summed in f64) and max of `errors`.
    pub fn of(errors: impl IntoIterator<Item = f32>) -> Self {
        let (mut sum, mut count, mut max) = (0.0f64, 0usize, 0.0f32);
        for e in errors {
            sum += f64::from(e);
            count += 1;
            max = max.max(e);
        }
        Self { mean: if count == 0 { 0.0 } else { (sum / count as f64) as f32 }, max }
    }
}

/// The errors of one smoothing at one pose count.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SmoothingError {
    /// Backbone error, % of blade length.
    pub backbone: ErrorStats,
    /// Twist error, degrees.
    pub twist: ErrorStats,
}

/// One pose count: its layout and the errors of each smoothing (in `SMOOTHINGS` order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseErrorRow {
    /// Poses over the full circle asked for.
    pub poses: u32,
    /// The table's shape (a quarter stored).
    pub layout: KeyframeLayout,
    /// Nearest, linear, SLERP.
    pub errors: [SmoothingError; 3],
}

/// The pose errors of the renderer's vertex tables at several pose counts.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseErrorReport {
    /// Segments of the blade.
    pub segments: u32,
    /// Seed of the forces.
    pub seed: u64,
    /// Forces measured.
    pub samples: usize,
    /// One row per pose count.
    pub rows: Vec<PoseErrorRow>,
}

impl PoseErrorReport {
    /// The report's measurement: `REPORT_POSES`, `SAMPLES` forces from `SEED`.
    pub fn measure(segments: u32) -> Self {
        Self::measure_with(segments, &REPORT_POSES, SEED, SAMPLES)
    }

    /// Measure the tables for `poses` against direct solves of `samples` forces from `seed` (each
    /// force solved once, shared by every table).
    pub fn measure_with(segments: u32, poses: &[u32], seed: u64, samples: usize) -> Self {
        let model = BladeModel::new(segments);
        let forces = sample_forces(seed, samples);
        let direct: Vec<Pose> = forces.iter().map(|&(fx, fz)| pose::solve(&model, fx, fz)).collect();
        let rows = poses
            .iter()
            .map(|&k| {
                let layout = KeyframeLayout::for_poses(k);
                let table = KeyframeTable::generate(&model, layout);
                let errors = SMOOTHINGS.map(|smoothing| {
                    let table_poses: Vec<Pose> =
                        forces.iter().map(|&(fx, fz)| table.pose_for(fx, fz, smoothing)).collect();
                    SmoothingError {
                        backbone: ErrorStats::of(table_poses.iter().zip(&direct).map(|(t, d)| backbone_error(t, d))),
                        twist: ErrorStats::of(table_poses.iter().zip(&direct).map(|(t, d)| twist_error(t, d))),
                    }
                });
                PoseErrorRow { poses: k, layout, errors }
            })
            .collect();
        Self { segments, seed, samples, rows }
    }

    /// The smallest pose count whose largest backbone error with `smoothing` is under `bound` %.
    pub fn smallest_under(&self, smoothing: Smoothing, bound: f32) -> Option<u32> {
        let column = SMOOTHINGS.iter().position(|&s| s == smoothing).expect("a measured smoothing");
        self.rows.iter().filter(|row| row.errors[column].backbone.max < bound).map(|row| row.poses).min()
    }
}

fn smoothing_name(smoothing: Smoothing) -> &'static str {
    match smoothing {
        Smoothing::Nearest => "nearest",
        Smoothing::Linear => "linear",
        Smoothing::Slerp => "slerp",
    }
}

impl fmt::Display for PoseErrorReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "pose error against a direct solve ({} segments, {} forces uniform over |f| <= {MAX_FORCE} in every quadrant, seed {}): largest backbone-point distance in % of the blade length, mean and max over the forces; largest twist difference in degrees",
            self.segments, self.samples, self.seed
        )?;
        writeln!(
            f,
            "  poses  stored (mag x ang) | nearest  mean    max | linear  mean    max | slerp  mean    max | twist max  nearest linear slerp"
        )?;
        for row in &self.rows {
            let [n, l, s] = row.errors;
            writeln!(
                f,
                "  {:>5}  {:>6} ({:>4} x {:>2}) | {:>13.3} {:>6.3} | {:>12.3} {:>6.3} | {:>11.3} {:>6.3} | {:>18.2} {:>6.2} {:>5.2}",
                row.poses,
                row.layout.stored(),
                row.layout.magnitudes,
                row.layout.angles,
                n.backbone.mean,
                n.backbone.max,
                l.backbone.mean,
                l.backbone.max,
                s.backbone.mean,
                s.backbone.max,
                n.twist.max,
                l.twist.max,
                s.twist.max,
            )?;
        }
        let counts: Vec<String> = self.rows.iter().map(|r| r.poses.to_string()).collect();
        for smoothing in SMOOTHINGS {
            let name = smoothing_name(smoothing);
            match self.smallest_under(smoothing, MAX_ERROR_BOUND) {
                Some(k) => writeln!(f, "  {name}: {k} poses keep the max error under {MAX_ERROR_BOUND} %")?,
                None => writeln!(
                    f,
                    "  {name}: none of {} poses keeps the max error under {MAX_ERROR_BOUND} %",
                    counts.join(" / ")
                )?,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    /// The report's forces, drawn again from the seed without `sample_forces`.
    fn forces_again() -> Vec<(f32, f32)> {
        let mut rng = Rng::new(SEED);
        (0..SAMPLES)
            .map(|_| {
                let (u, v) = (rng.unit(), rng.unit());
                let (r, angle) = (MAX_FORCE * u.sqrt(), TAU * v);
                (r * angle.sin(), r * angle.cos())
            })
            .collect()
    }

    #[test]
    fn forces_cover_the_disc_in_every_quadrant() {
        let forces = sample_forces(SEED, SAMPLES);
        assert_eq!(forces, forces_again());
        let mut quadrants = [0usize; 4];
        for &(fx, fz) in &forces {
            assert!((fx * fx + fz * fz).sqrt() <= MAX_FORCE);
            quadrants[usize::from(fx < 0.0) + 2 * usize::from(fz < 0.0)] += 1;
        }
        // Uniform over the disc: a quarter in each quadrant, half inside radius 1/√2.
        assert!(quadrants.iter().all(|&q| q > SAMPLES / 5), "{quadrants:?}");
        let inner = forces.iter().filter(|(x, z)| x * x + z * z < 0.5 * MAX_FORCE * MAX_FORCE).count();
        assert!((inner as f32 / SAMPLES as f32 - 0.5).abs() < 0.05, "{inner} of {SAMPLES} inside 1/sqrt(2)");
        assert!(forces.iter().any(|(x, z)| x * x + z * z > 0.98 * MAX_FORCE * MAX_FORCE), "reaches the table's edge");
    }

    #[test]
    fn one_entry_recomputed_from_the_renderers_table_and_the_direct_solve() {
        let report = PoseErrorReport::measure(4);
        assert_eq!(report.rows.iter().map(|r| r.poses).collect::<Vec<_>>(), REPORT_POSES);
        // The 1000-pose linear entry, recomputed: the renderer's table (keyframe_gpu.rs builds it
        // the same way), `pose_for` (select + blend) and `pose::solve`, for the same forces.
        let model = BladeModel::new(4);
        let table = KeyframeTable::generate(&model, KeyframeLayout::for_poses(1000));
        let (mut sum, mut max) = (0.0f64, 0.0f32);
        let mut quadrant_max = [0.0f32; 4];
        for (fx, fz) in forces_again() {
            let direct = pose::solve(&model, fx, fz);
            let length: f32 = (0..4).map(|i| direct.segment_length(i)).sum();
            assert!((length - 1.0).abs() < 1e-4, "the reference blade is unit length: {length}");
            let from_table = table.pose_for(fx, fz, Smoothing::Linear);
            let mut worst = 0.0f32;
            for level in 0..=4 {
                let d: Vec3 = from_table.backbone[level] - direct.backbone[level];
                worst = worst.max(100.0 * d.length());
            }
            sum += f64::from(worst);
            max = max.max(worst);
            let q = usize::from(fx < 0.0) + 2 * usize::from(fz < 0.0);
            quadrant_max[q] = quadrant_max[q].max(worst);
        }
        let entry = report.rows[1].errors[1].backbone;
        assert!(
            (entry.mean - (sum / SAMPLES as f64) as f32).abs() < 1e-6,
            "{entry:?} vs mean {}",
            sum / SAMPLES as f64
        );
        assert_eq!(entry.max, max);
        // The mirrors: every quadrant as close to the direct solve as the bound.
        assert!(quadrant_max.iter().all(|&m| m > 0.0 && m < MAX_ERROR_BOUND), "{quadrant_max:?}");
    }

    #[test]
    fn errors_fall_as_poses_grow_and_interpolation_beats_nearest() {
        let report = PoseErrorReport::measure(4);
        for (column, smoothing) in SMOOTHINGS.iter().enumerate() {
            for pair in report.rows.windows(2) {
                let (coarse, fine) = (pair[0].errors[column], pair[1].errors[column]);
                assert!(fine.backbone.mean < coarse.backbone.mean, "{smoothing:?}: {pair:?}");
                assert!(fine.backbone.max < coarse.backbone.max, "{smoothing:?}: {pair:?}");
                assert!(fine.twist.max < coarse.twist.max, "{smoothing:?}: {pair:?}");
            }
        }
        for row in &report.rows {
            let [nearest, linear, slerp] = row.errors;
            assert!(nearest.backbone.mean > linear.backbone.mean, "{row:?}");
            // SLERP keeps the blade's length (eq. 3.14): closer than linear on average.
            assert!(slerp.backbone.mean < linear.backbone.mean, "{row:?}");
        }
        // The README's sentence.
        assert_eq!(report.smallest_under(Smoothing::Nearest, MAX_ERROR_BOUND), None);
        assert_eq!(report.smallest_under(Smoothing::Linear, MAX_ERROR_BOUND), Some(1000));
        assert_eq!(report.smallest_under(Smoothing::Slerp, MAX_ERROR_BOUND), Some(1000));
    }

    #[test]
    fn smallest_count_under_the_bound_and_its_lines() {
        let row = |poses: u32, max: [f32; 3]| PoseErrorRow {
            poses,
            layout: KeyframeLayout::for_poses(poses),
            errors: max
                .map(|m| SmoothingError { backbone: ErrorStats { mean: m / 3.0, max: m }, ..Default::default() }),
        };
        let report = PoseErrorReport {
            segments: 2,
            seed: 1,
            samples: 3,
            rows: vec![row(4000, [0.6, 0.1, 0.1]), row(250, [2.0, 0.7, 0.4]), row(1000, [1.0, 0.3, 0.2])],
        };
        assert_eq!(report.smallest_under(Smoothing::Nearest, 0.5), None);
        assert_eq!(report.smallest_under(Smoothing::Linear, 0.5), Some(1000));
        assert_eq!(report.smallest_under(Smoothing::Slerp, 0.5), Some(250));
        let text = report.to_string();
        assert!(text.contains("nearest: none of 4000 / 250 / 1000 poses keeps the max error under 0.5 %"), "{text}");
        assert!(text.contains("linear: 1000 poses keep the max error under 0.5 %"), "{text}");
        assert!(text.contains("slerp: 250 poses keep the max error under 0.5 %"), "{text}");
        assert_eq!(ErrorStats::of([1.0, 3.0, 2.0]), ErrorStats { mean: 2.0, max: 3.0 });
    }
}
