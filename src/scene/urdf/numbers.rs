//! Numbers in URDF text: the `rpy` convention, exact float formatting, and the canonical forms
//! that make export → import → export a textual fixed point.
//!
//! - Lengths, limits and scales are written with Rust's shortest round-trip formatting, so they
//!   import bit for bit.
//! - Angles cannot round-trip exactly: `rpy` → quaternion → `rpy` loses bits. They are written
//!   on a grid: pitch and roll to 12 decimals (1e-12 rad), yaw to 12 decimals unless the
//!   rotation is near gimbal lock, where yaw is individually ill-conditioned and is written on
//!   the coarser grid `10^-d ≥ 1e-12 / cos(pitch)` (its effect on the rotation stays below
//!   1e-12 rad there). Angles are computed from well-conditioned formulas, so re-deriving them
//!   from the imported rotation lands on the same grid point: the text is a fixed point. The
//!   rotation written differs from the model's by at most about 1e-11 rad.
//! - Axes are written as the unit vector whose floating-point norm is exactly 1, so the scene
//!   builder's normalisation leaves them unchanged.

use std::f64::consts::PI;

use nalgebra::{Isometry3, Rotation3, Translation3, UnitQuaternion, Vector3};

use crate::scene::{MAX_MAGNITUDE, MIN_AXIS_NORM};

/// Decimal places of roll and pitch (and of yaw away from gimbal lock).
const ANGLE_DECIMALS: i32 = 12;
/// Largest pitch magnitude written: the grid point just below π/2, so `cos(pitch) > 0` and
/// the yaw of the written angles is the yaw the importer recovers. (Deliberately not π/2.)
#[allow(clippy::approx_constant)]
const MAX_PITCH: f64 = 1.570_796_326_794;
/// Angle resolution the yaw grid keeps on the rotation (rad).
const YAW_EFFECT: f64 = 1e-12;

/// `v` as text that parses back to the same `f64`: Rust's shortest round-trip form, `-0` as
/// `0`, exponent notation outside `[1e-5, 1e16)`.
pub(super) fn number(v: f64) -> String {
    let v = v + 0.0;
    if v == 0.0 {
        "0".to_string()
    } else if (1e-5..1e16).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `"x y z"` with [`number`].
pub(super) fn vector(v: &Vector3<f64>) -> String {
    format!("{} {} {}", number(v.x), number(v.y), number(v.z))
}

/// The URDF `rpy` convention: fixed-axis roll, pitch, yaw, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
pub(super) fn rotation_from_rpy(rpy: &[f64; 3]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2])
}

/// A URDF `<origin xyz rpy>` as the isometry `parent_from_child`.
pub(super) fn isometry_from_origin(xyz: &[f64; 3], rpy: &[f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        rotation_from_rpy(rpy),
    )
}

/// `rpy` text of a rotation (see the module docs for the grid).
pub(super) fn rpy_text(rotation: &UnitQuaternion<f64>) -> String {
    let m = rotation.to_rotation_matrix();
    let column = m.matrix().column(0).into_owned();
    let (pitch, yaw) = pitch_yaw(&column);
    let yaw_pitch = Rotation3::from_euler_angles(0.0, pitch.1, yaw.1);
    let roll_matrix = yaw_pitch.inverse() * m;
    let roll = roll_matrix[(2, 1)].atan2(roll_matrix[(2, 2)]);
    let roll = snap_angle(roll, ANGLE_DECIMALS);
    format!("{} {} {}", roll.0, pitch.0, yaw.0)
}

/// `rpy` text of a frame whose +x axis is the unit vector `normal` (roll 0).
pub(super) fn normal_rpy_text(normal: &Vector3<f64>) -> String {
    let (pitch, yaw) = pitch_yaw(normal);
    format!("0 {} {}", pitch.0, yaw.0)
}

/// Pitch and yaw (text, value) of a frame whose +x axis is `x_axis` (a unit vector).
fn pitch_yaw(x_axis: &Vector3<f64>) -> ((String, f64), (String, f64)) {
    // atan2 forms: well-conditioned for pitch everywhere (asin is not near ±π/2).
    let pitch = (-x_axis.z)
        .atan2(x_axis.x.hypot(x_axis.y))
        .clamp(-MAX_PITCH, MAX_PITCH);
    let pitch = snap(pitch, ANGLE_DECIMALS);
    let yaw = x_axis.y.atan2(x_axis.x);
    let yaw = snap_angle(yaw, yaw_decimals(pitch.1.cos()));
    (pitch, yaw)
}

/// Decimals of the yaw grid: the finest `d ≤ 12` with `10^-d ≥ YAW_EFFECT / cos(pitch)`,
/// at least 1.
fn yaw_decimals(cos_pitch: f64) -> i32 {
    let mut d = ANGLE_DECIMALS;
    while d > 1 && 10f64.powi(-d) < YAW_EFFECT / cos_pitch {
        d -= 1;
    }
    d
}

/// `v` rounded to `decimals` decimals: the shortest text and the value it parses to.
fn snap(v: f64, decimals: i32) -> (String, f64) {
    let d = decimals.max(0) as usize;
    let text = format!("{v:.d$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    let text = if text == "-0" { "0".to_string() } else { text };
    let value = text.parse().unwrap_or(0.0);
    (text, value)
}

/// The point of the symmetric angle grid `k·10^-d`, `|k| ≤ ⌊π·10^d⌋`, nearest to `v` on the
/// circle. Symmetric and circular, so angles near ±π snap to one canonical point.
fn snap_angle(v: f64, decimals: i32) -> (String, f64) {
    let scale = 10f64.powi(decimals);
    let k_max = (PI * scale).floor();
    let k = (v * scale).round().clamp(-k_max, k_max);
    let k =
        if k.abs() == k_max && circular_distance(v, -k / scale) < circular_distance(v, k / scale) {
            -k
        } else {
            k
        };
    snap(k / scale, decimals)
}

/// Distance between two angles on the circle (rad).
fn circular_distance(a: f64, b: f64) -> f64 {
    ((a - b + PI).rem_euclid(2.0 * PI) - PI).abs()
}

/// The unit vector along `v` whose floating-point norm is exactly 1, so that normalising it
/// again (as the scene builder does) returns it unchanged. Vectors the builder rejects (not
/// finite, too large, too short) are returned as they are, for the builder to report.
pub(super) fn canonical_axis(v: &Vector3<f64>) -> Vector3<f64> {
    if v.iter().any(|c| !c.is_finite() || c.abs() > MAX_MAGNITUDE) {
        return *v;
    }
    let norm = v.norm();
    if norm < MIN_AXIS_NORM {
        return *v;
    }
    let mut u = (v / norm).map(|c| c + 0.0);
    // Nudge the largest component (≥ 1/√3 in magnitude) by one ulp at a time until the
    // computed norm is exactly 1; one or two steps suffice in practice.
    let i = u.iamax();
    for _ in 0..8 {
        let n = u.norm();
        if n == 1.0 {
            break;
        }
        let bits = u[i].to_bits();
        u[i] = f64::from_bits(if n > 1.0 { bits - 1 } else { bits + 1 });
    }
    u
}
