//! The discovery layer's error enum.
//!
//! `Err` is for bad input and broken contracts only: invalid settings, NaN in detections,
//! observations or poses, an invalid base map, an estimator rejecting its input. Hardware
//! failures, lost handles and `Unknown` estimates are outcomes, recorded in the per-handle log
//! ([`HandleLog`](super::HandleLog)).

use crate::InvalidSetting;
use crate::articulation::ArticulationError;

/// Errors of the discovery layer. Every variant names the offending input.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DiscoveryError {
    /// A settings field is out of its valid range.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// A number of an input (detection, handle, observation, pose) is NaN or infinite.
    #[error("non-finite {what}")]
    NonFinite {
        /// Which input, e.g. `"detection 3 of view 1"`.
        what: String,
    },
    /// A confidence outside [0, 1].
    #[error("{what}: confidence {value} outside [0, 1]")]
    ConfidenceOutOfRange {
        /// Which input.
        what: String,
        /// The rejected confidence.
        value: f64,
    },
    /// [`discover`](super::discover) got a handle without a base-map attachment (run
    /// [`register_handles`](super::register_handles) first).
    #[error("handle {index} is not registered to the base map")]
    UnregisteredHandle {
        /// Index of the handle in the input.
        index: usize,
    },
    /// The base map is invalid (the scene layer's check).
    #[error("base map: {0}")]
    Scene(#[from] crate::scene::Error),
    /// The estimator rejected its input: a broken contract between perception and estimator
    /// (for example NaN points or colour lists that do not match).
    #[error("estimator {estimator:?} on handle {handle}: {source}")]
    Estimator {
        /// The estimator's name.
        estimator: String,
        /// Index of the handle being explored.
        handle: usize,
        /// The estimator's error.
        source: ArticulationError,
    },
}

/// `Err(InvalidSetting)` unless `value` is finite and > 0.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<(), DiscoveryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(InvalidSetting::new(name, value, "finite and > 0").into())
    }
}

/// `Err(InvalidSetting)` unless `value` is finite and >= 0.
pub(crate) fn check_nonneg(name: &'static str, value: f64) -> Result<(), DiscoveryError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(InvalidSetting::new(name, value, "finite and >= 0").into())
    }
}

/// `Err(InvalidSetting)` unless `lo <= value <= hi`; `requirement` says so in words.
pub(crate) fn check_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    requirement: &'static str,
) -> Result<(), DiscoveryError> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(InvalidSetting::new(name, value, requirement).into())
    }
}

/// `Err(NonFinite)` unless every value is finite.
pub(crate) fn check_finite(
    values: impl IntoIterator<Item = f64>,
    what: impl FnOnce() -> String,
) -> Result<(), DiscoveryError> {
    if values.into_iter().all(f64::is_finite) {
        Ok(())
    } else {
        Err(DiscoveryError::NonFinite { what: what() })
    }
}
