//! The end-effector pose noise estimated from the path's smoothness.

use nalgebra::{Isometry3, Point3, Vector3};

/// The median of the χ² distribution with 3 degrees of freedom.
const CHI2_3DOF_MEDIAN: f64 = 2.365_973_884_375_34;
/// The median of the χ² distribution with 2 degrees of freedom, `2 ln 2`.
const CHI2_2DOF_MEDIAN: f64 = std::f64::consts::LN_2 * 2.0;
/// `1² + 3² + 3² + 1²`: the variance of a third difference of white noise, in units of the
/// noise's variance.
const THIRD_DIFFERENCE_VARIANCE: f64 = 20.0;
/// Fewest poses for an estimate: five third differences.
pub const MIN_NOISE_POSES: usize = 8;
/// The smallest position σ (m) the fits use when estimating the noise from the path: 0.5 mm,
/// the repeatability of a mobile manipulator's arm; exact poses (a simulator's) would make
/// the likelihood degenerate.
pub const MIN_POSITION_SIGMA: f64 = 0.0005;
/// The smallest orientation σ (rad) the fits use when estimating the noise: 0.005 (0.3°).
pub const MIN_ORIENTATION_SIGMA: f64 = 0.005;

/// End-effector pose noise: standard deviations per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathNoise {
    /// Position noise σ per axis (m).
    pub position: f64,
    /// Orientation noise σ per axis of the small rotation vector (rad), measured on the tool
    /// z axis (the approach direction).
    pub orientation: f64,
}

/// The pose noise of a path sampled along a smooth motion, from its third differences.
///
/// A compliant pull moves the end effector along a smooth curve (an arc or a line) in
/// roughly equal steps, so the third difference `Δ³pᵢ = pᵢ₊₃ − 3pᵢ₊₂ + 3pᵢ₊₁ − pᵢ` of the
/// true path is tiny (`s³ / r²` for steps `s` on a circle of radius `r`: 0.2 mm for 2 cm
/// steps at 0.2 m, against 2 mm noise), while that of white noise σ per axis has variance
/// `20 σ²` per axis. So `|Δ³p|² ≈ 20 σ² χ²₃`, and `σ² = median |Δ³p|² / (20 · 2.366)`
/// (the median of χ²₃; the median, not the mean, so that a slip or a regrasp jump does not
/// count). The orientation: the tool z axis `z = R(δ) z₀` moves by `δ × z₀`, two components
/// of variance `σ_o²` each, so `|Δ³z|² ≈ 20 σ_o² χ²₂` and the median of χ²₂ is `2 ln 2`.
/// Neighbouring differences share poses and are correlated, which widens the estimate's
/// spread but does not bias the median of each.
///
/// `None` with fewer than [`MIN_NOISE_POSES`] poses.
pub fn path_noise(ee_poses: &[(f64, Isometry3<f64>)]) -> Option<PathNoise> {
    if ee_poses.len() < MIN_NOISE_POSES {
        return None;
    }
    let positions: Vec<Vector3<f64>> = ee_poses
        .iter()
        .map(|(_, p)| Point3::from(p.translation.vector).coords)
        .collect();
    let approach: Vec<Vector3<f64>> = ee_poses
        .iter()
        .map(|(_, p)| p.rotation * Vector3::z())
        .collect();
    let third = |v: &[Vector3<f64>]| -> Vec<f64> {
        v.windows(4)
            .map(|w| (w[3] - w[2] * 3.0 + w[1] * 3.0 - w[0]).norm_squared())
            .collect()
    };
    let position = median(third(&positions)) / (THIRD_DIFFERENCE_VARIANCE * CHI2_3DOF_MEDIAN);
    let orientation = median(third(&approach)) / (THIRD_DIFFERENCE_VARIANCE * CHI2_2DOF_MEDIAN);
    Some(PathNoise {
        position: position.sqrt(),
        orientation: orientation.sqrt(),
    })
}

/// The median of `v` (not empty, finite).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}
