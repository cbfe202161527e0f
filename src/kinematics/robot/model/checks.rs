//! Checks of the values given to a robot model: lengths, finiteness and positive limits.

use crate::kinematics::robot::RobotError;

pub(super) fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), RobotError> {
    if expected == got {
        Ok(())
    } else {
        Err(RobotError::DimensionMismatch {
            what,
            expected,
            got,
        })
    }
}

pub(super) fn check_finite(what: &'static str, values: &[f64]) -> Result<(), RobotError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(RobotError::NonFiniteValue { what, index }),
        None => Ok(()),
    }
}

pub(in crate::kinematics::robot) fn check_positive_limit(
    joint: &str,
    what: &'static str,
    value: f64,
) -> Result<(), RobotError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(RobotError::NonPositiveLimit {
            joint: joint.to_owned(),
            what,
            value,
        })
    }
}
