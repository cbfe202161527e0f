//! Input validation shared by the pictures: finite values, lengths, non-empty lists.

use super::{Series, SvgError};

pub(super) fn check_finite(what: impl FnOnce() -> String, value: f64) -> Result<f64, SvgError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SvgError::NonFinite {
            what: what(),
            value,
        })
    }
}

pub(super) fn check_len(
    what: impl FnOnce() -> String,
    expected: usize,
    got: usize,
) -> Result<(), SvgError> {
    if expected == got {
        Ok(())
    } else {
        Err(SvgError::DimensionMismatch {
            what: what(),
            expected,
            got,
        })
    }
}

pub(super) fn check_nonempty(what: &str, len: usize) -> Result<(), SvgError> {
    if len == 0 {
        Err(SvgError::Empty { what: what.into() })
    } else {
        Ok(())
    }
}

/// Every series has one finite value per category; with `non_negative`, none is negative.
pub(super) fn check_series(
    kind: &str,
    series: &[Series],
    n: usize,
    non_negative: bool,
) -> Result<(), SvgError> {
    for s in series {
        check_len(|| format!("{kind} {:?}", s.label), n, s.values.len())?;
        for (j, &v) in s.values.iter().enumerate() {
            check_finite(|| format!("{kind} {:?} value {}", s.label, j + 1), v)?;
            if non_negative && v < 0.0 {
                return Err(SvgError::OutOfRange {
                    what: format!("{kind} {:?} value {}", s.label, j + 1),
                    requirement: "non-negative",
                    value: v,
                });
            }
        }
    }
    Ok(())
}
