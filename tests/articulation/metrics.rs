//! The DiTH metrics on hand-computed cases.

use super::*;

#[test]
fn axis_angle_error_hand_cases() {
    // Perpendicular: arccos(0) = 90°.
    assert!((axis_angle_error(&Vector3::x(), &Vector3::z()) - 90.0).abs() < 1e-12);
    // Anti-parallel: min(arccos(−1), arccos(1)) = 0°, and unnormalised inputs are normalised.
    assert_eq!(
        axis_angle_error(&Vector3::new(0.0, 0.0, 3.0), &Vector3::new(0.0, 0.0, -0.5)),
        0.0
    );
    // 45° apart in the xy plane; the flipped estimate is 45° too (135° folds to 45°).
    let d = Vector3::new(1.0, 1.0, 0.0);
    assert!((axis_angle_error(&d, &Vector3::x()) - 45.0).abs() < 1e-12);
    assert!((axis_angle_error(&-d, &Vector3::x()) - 45.0).abs() < 1e-12);
    // Nearly parallel: the clamped dot product keeps the result finite (no NaN from acos(1+ε)).
    let e = axis_angle_error(&Vector3::new(1.0, 1e-9, 0.0), &Vector3::x());
    assert!(e.is_finite() && e < 1e-6);
    // A zero vector has no direction.
    assert!(axis_angle_error(&Vector3::zeros(), &Vector3::x()).is_nan());
}

#[test]
fn axis_position_error_hand_cases() {
    // Skew: the x axis and the line through (0, 0, 2) along y are 2 m apart (common normal z).
    let d = axis_position_error(
        &Point3::new(3.0, 0.0, 0.0),
        &Vector3::x(),
        &Point3::new(-1.0, 7.0, 2.0),
        &Vector3::y(),
    );
    assert!((d - 2.0).abs() < 1e-12, "{d}");
    // Skew at an angle: line 2 through (0, 0, 1.5) along (1, 1, 0); common normal z, 1.5 m.
    let d = axis_position_error(
        &Point3::origin(),
        &Vector3::x(),
        &Point3::new(0.0, 0.0, 1.5),
        &Vector3::new(1.0, 1.0, 0.0),
    );
    assert!((d - 1.5).abs() < 1e-12, "{d}");
    // Intersecting lines: 0.
    let d = axis_position_error(
        &Point3::new(1.0, 1.0, 1.0),
        &Vector3::x(),
        &Point3::new(1.0, 1.0, 1.0),
        &Vector3::z(),
    );
    assert!(d.abs() < 1e-12);
    // Parallel (and anti-parallel): vertical lines through (0,0) and (0.3, 0.4) are 0.5 m apart.
    let d = axis_position_error(
        &Point3::origin(),
        &Vector3::z(),
        &Point3::new(0.3, 0.4, 9.0),
        &Vector3::z(),
    );
    assert!((d - 0.5).abs() < 1e-12, "{d}");
    let d = axis_position_error(
        &Point3::origin(),
        &Vector3::z(),
        &Point3::new(0.3, 0.4, -2.0),
        &(-2.0 * Vector3::z()),
    );
    assert!((d - 0.5).abs() < 1e-12, "{d}");
    // Degenerate direction.
    assert!(
        axis_position_error(
            &Point3::origin(),
            &Vector3::zeros(),
            &Point3::origin(),
            &Vector3::z()
        )
        .is_nan()
    );
}

#[test]
fn joint_type_accuracy_counts() {
    use JointKindEstimate::*;
    assert_eq!(
        joint_type_accuracy([
            (Revolute, Revolute),
            (Prismatic, Revolute),
            (Prismatic, Prismatic),
            (Unknown, Unknown)
        ]),
        Some(0.5)
    );
    assert_eq!(joint_type_accuracy(std::iter::empty()), None);
}
