//! The crate's error type: bad input and broken backends. Planning failures are not errors;
//! they are a [`PlanStatus`](crate::PlanStatus) inside `Ok`.

/// Why a call could not be carried out.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The OMPL shim could not be loaded.
    #[error(transparent)]
    Load(#[from] kinscene_shim::LoadError),
    /// OMPL threw a C++ exception (its message is kept), or the shim rejected its input.
    #[error(transparent)]
    Backend(#[from] kinscene_shim::CallError),
    /// A real vector space without dimensions.
    #[error("a real vector space needs at least one dimension")]
    ZeroDimension,
    /// A vector has the wrong length.
    #[error("{what}: expected {expected} values, got {got}")]
    DimensionMismatch {
        /// Which input ("start", "goal", "upper bounds").
        what: &'static str,
        /// The length required by the state space.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// An input contains NaN or an infinity.
    #[error("{what} contains a NaN or infinite value")]
    NonFinite {
        /// Which input ("start", "goal", "bounds").
        what: &'static str,
    },
    /// A lower bound exceeds its upper bound.
    #[error("bounds of axis {axis}: lower {lower} > upper {upper}")]
    InvalidBounds {
        /// Index of the bounded coordinate (0 = x, 1 = y for SE(2)).
        axis: usize,
        /// The lower bound given.
        lower: f64,
        /// The upper bound given.
        upper: f64,
    },
    /// The time budget is zero.
    #[error("the time budget must be positive")]
    NonPositiveBudget,
    /// The motion-check resolution fraction is outside (0, 1).
    #[error("motion-check resolution fraction {resolution_fraction} is not in (0, 1)")]
    ResolutionOutOfRange {
        /// The fraction given.
        resolution_fraction: f64,
    },
    /// Another setting is out of its domain.
    #[error("{name} = {value} is invalid: must be {requirement}")]
    InvalidSetting {
        /// The setting's field name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// Its domain, in words.
        requirement: &'static str,
    },
}
