//! Articulation error metrics as Ditto in the House (DiTH) defines them, so numbers compare with
//! the paper's Table II.

use nalgebra::{Point3, Vector3};

use super::estimate::JointKindEstimate;

/// Below this `|sin|` of the angle between two axis lines they count as parallel.
const PARALLEL_SIN: f64 = 1e-9;

/// Axis angle error in degrees: `min(arccos(â·a), arccos(−â·a))`.
///
/// Both vectors are normalised first and the dot product is clamped to [−1, 1] (rounding can
/// push it just outside), so the result lies in [0°, 90°]; the sign of the axis does not matter.
/// Returns NaN if either vector is zero or not finite.
///
/// # Example
/// ```
/// use kinscene::articulation::axis_angle_error;
/// use nalgebra::Vector3;
/// assert_eq!(axis_angle_error(&Vector3::z(), &-Vector3::z()), 0.0);
/// assert!((axis_angle_error(&Vector3::x(), &Vector3::y()) - 90.0).abs() < 1e-12);
/// ```
pub fn axis_angle_error(estimated: &Vector3<f64>, truth: &Vector3<f64>) -> f64 {
    let (Some(e), Some(t)) = (unit(estimated), unit(truth)) else {
        return f64::NAN;
    };
    let dot = e.dot(&t).clamp(-1.0, 1.0);
    dot.acos().min((-dot).acos()).to_degrees()
}

/// Axis position error in metres: the distance between the estimated and the true axis lines.
///
/// Each line is taken in Plücker form `(d, m = p × d)` with unit `d`; for non-parallel lines the
/// distance is `|d₁·m₂ + d₂·m₁| / |d₁ × d₂|`. Parallel lines (`|d₁ × d₂| < 1e-9`) use the
/// distance from `true_point` to the estimated line. Returns NaN if a direction is zero or any
/// input is not finite.
///
/// # Example
/// ```
/// use kinscene::articulation::axis_position_error;
/// use nalgebra::{Point3, Vector3};
/// // The x axis and the line {z = 2} along y are skew, 2 m apart.
/// let d = axis_position_error(&Point3::origin(), &Vector3::x(), &Point3::new(5.0, 0.0, 2.0), &Vector3::y());
/// assert!((d - 2.0).abs() < 1e-12);
/// ```
pub fn axis_position_error(
    est_point: &Point3<f64>,
    est_dir: &Vector3<f64>,
    true_point: &Point3<f64>,
    true_dir: &Vector3<f64>,
) -> f64 {
    let (Some(d1), Some(d2)) = (unit(est_dir), unit(true_dir)) else {
        return f64::NAN;
    };
    if !(est_point.coords.iter().chain(true_point.coords.iter())).all(|v| v.is_finite()) {
        return f64::NAN;
    }
    let cross = d1.cross(&d2);
    let sin = cross.norm();
    if sin < PARALLEL_SIN {
        return (true_point - est_point).cross(&d1).norm();
    }
    let m1 = est_point.coords.cross(&d1);
    let m2 = true_point.coords.cross(&d2);
    (d1.dot(&m2) + d2.dot(&m1)).abs() / sin
}

/// Joint-type accuracy: the fraction of `(estimated, truth)` pairs whose types agree
/// ([`JointKindEstimate::Unknown`] never agrees with a true type). `None` for no pairs.
///
/// # Example
/// ```
/// use kinscene::articulation::{joint_type_accuracy, JointKindEstimate::*};
/// let acc = joint_type_accuracy([(Revolute, Revolute), (Unknown, Prismatic)]);
/// assert_eq!(acc, Some(0.5));
/// ```
pub fn joint_type_accuracy(
    pairs: impl IntoIterator<Item = (JointKindEstimate, JointKindEstimate)>,
) -> Option<f64> {
    let (mut right, mut n) = (0usize, 0usize);
    for (estimated, truth) in pairs {
        n += 1;
        if estimated == truth && estimated != JointKindEstimate::Unknown {
            right += 1;
        }
    }
    (n > 0).then(|| right as f64 / n as f64)
}

fn unit(v: &Vector3<f64>) -> Option<Vector3<f64>> {
    let n = v.norm();
    (n.is_finite() && n > 0.0).then(|| v / n)
}
