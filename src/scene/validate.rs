//! Small validation helpers shared by the builder and the settings types.

use nalgebra::{Isometry3, Unit, UnitQuaternion, Vector3};

use super::Error;
use crate::InvalidSetting;

/// Axes and normals with a Euclidean norm below this are rejected as zero (unitless: the
/// vectors are directions, normalised after the check).
pub const MIN_AXIS_NORM: f64 = 1e-9;

/// Largest magnitude (m, rad or unitless) accepted for any number in a scene description:
/// coordinates, lengths, limits, axis components. Larger values are rejected with
/// [`Error::OutOfRange`]; they keep geometry queries well inside floating-point range.
pub const MAX_MAGNITUDE: f64 = 1e6;

/// Tolerance on the norm of a rotation quaternion before it is renormalised.
const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

/// Fails with [`Error::NonFinite`] if any value is NaN or infinite, and with
/// [`Error::OutOfRange`] if one exceeds [`MAX_MAGNITUDE`].
pub(crate) fn check_finite(
    values: impl IntoIterator<Item = f64>,
    what: impl FnOnce() -> String,
) -> Result<(), Error> {
    let mut big = None;
    for v in values {
        if !v.is_finite() {
            return Err(Error::NonFinite { what: what() });
        }
        if v.abs() > MAX_MAGNITUDE && big.is_none() {
            big = Some(v);
        }
    }
    match big {
        None => Ok(()),
        Some(value) => Err(Error::OutOfRange {
            what: what(),
            value,
            max: MAX_MAGNITUDE,
        }),
    }
}

/// Fails unless `value` is finite, at most [`MAX_MAGNITUDE`] and strictly positive.
pub(crate) fn check_positive(value: f64, what: impl FnOnce() -> String) -> Result<(), Error> {
    if !value.is_finite() {
        Err(Error::NonFinite { what: what() })
    } else if value > MAX_MAGNITUDE {
        Err(Error::OutOfRange {
            what: what(),
            value,
            max: MAX_MAGNITUDE,
        })
    } else if value <= 0.0 {
        Err(Error::NonPositive {
            what: what(),
            value,
        })
    } else {
        Ok(())
    }
}

/// Checks an isometry is finite with a unit quaternion (within 1e-6).
pub(crate) fn check_isometry(iso: &Isometry3<f64>, what: &str) -> Result<(), Error> {
    let q = iso.rotation.quaternion();
    check_finite(
        iso.translation
            .vector
            .iter()
            .chain(q.coords.iter())
            .copied(),
        || what.to_string(),
    )?;
    let norm = q.norm();
    if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        return Err(Error::InvalidRotation {
            what: what.to_string(),
            norm,
        });
    }
    Ok(())
}

/// Renormalises the rotation of an isometry that passed [`check_isometry`].
pub(crate) fn renormalized(iso: &Isometry3<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(
        iso.translation,
        UnitQuaternion::new_normalize(*iso.rotation.quaternion()),
    )
}

/// Checks a direction is finite and not zero, and normalises it.
pub(crate) fn unit_direction(
    v: &Vector3<f64>,
    what: impl FnOnce() -> String,
    zero: impl FnOnce() -> Error,
) -> Result<Unit<Vector3<f64>>, Error> {
    check_finite(v.iter().copied(), what)?;
    let norm = v.norm();
    if norm < MIN_AXIS_NORM {
        return Err(zero());
    }
    Ok(Unit::new_unchecked(v / norm))
}

/// Checks a setting is finite and `>= 0`.
pub(crate) fn check_setting_nonneg(value: f64, what: &str) -> Result<(), Error> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(InvalidSetting::new(what, value, "finite and >= 0").into())
    }
}

/// Checks a setting is finite and `> 0`.
pub(crate) fn check_setting_pos(value: f64, what: &str) -> Result<(), Error> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(InvalidSetting::new(what, value, "finite and > 0").into())
    }
}
