//! Errors of the path layer: bad input only. Not finding a path is a
//! [`PathOutcome`](super::PathOutcome), not an error.

/// Why [`plan_base`](super::plan_base) or [`plan_arm`](super::plan_arm) could not be carried out.
#[non_exhaustive]
#[derive(Debug, Clone, thiserror::Error)]
pub enum PathError {
    /// A joint-space problem without coordinates.
    #[error("an arm path needs at least one joint")]
    ZeroDimension,
    /// A vector has the wrong length.
    #[error("{what}: expected {expected} values, got {got}")]
    DimensionMismatch {
        /// Which input ("goal", "lower bounds", "upper bounds").
        what: &'static str,
        /// The length required (that of `start`).
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A value is NaN, or infinite where only finite values make sense.
    #[error("{what}[{index}] = {value} is not allowed (NaN, or infinite)")]
    NonFinite {
        /// Which input ("start", "goal", "lower bounds", "upper bounds", "xy bounds").
        what: &'static str,
        /// Index of the offending coordinate.
        index: usize,
        /// The value given.
        value: f64,
    },
    /// A lower bound exceeds its upper bound (or is `+inf`, or the upper bound is `-inf`).
    #[error("bounds of coordinate {axis}: lower {lower} > upper {upper}")]
    InvalidBounds {
        /// Index of the coordinate (0 = x, 1 = y for the base).
        axis: usize,
        /// The lower bound given.
        lower: f64,
        /// The upper bound given.
        upper: f64,
    },
    /// The start lies outside the bounds (by more than machine epsilon, OMPL's own tolerance):
    /// the robot is somewhere the caller's bounds exclude, which is a modelling error rather
    /// than a planning failure.
    #[error("start coordinate {axis} = {value} is outside [{lower}, {upper}]")]
    StartOutOfBounds {
        /// Index of the coordinate.
        axis: usize,
        /// The start's value.
        value: f64,
        /// The lower bound.
        lower: f64,
        /// The upper bound.
        upper: f64,
    },
    /// A field of [`PathSettings`](super::PathSettings) is out of its domain.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// The OMPL backend rejected its input, failed to load, or threw.
    #[error("OMPL: {0}")]
    Ompl(#[from] kinscene_ompl::Error),
}
