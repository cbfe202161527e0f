//! The articulation layer's error enum.
//!
//! `Err` is for bad input only (non-finite numbers, colour lists that do not match their points,
//! invalid settings). Too little motion or too few points is an outcome:
//! [`JointEstimate::Unknown`](super::JointEstimate::Unknown) inside `Ok`.

use std::fmt;

/// Which input of an [`Interaction`](super::Interaction) an error refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InputKind {
    /// The pre-interaction point cloud.
    PreCloud,
    /// The post-interaction point cloud.
    PostCloud,
    /// The pre-interaction contact point `c_pre`.
    ContactPre,
    /// The post-interaction contact point `c_post`.
    ContactPost,
    /// The end-effector pose sequence.
    EePoses,
}

impl fmt::Display for InputKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            InputKind::PreCloud => "pre-interaction cloud",
            InputKind::PostCloud => "post-interaction cloud",
            InputKind::ContactPre => "pre-interaction contact",
            InputKind::ContactPost => "post-interaction contact",
            InputKind::EePoses => "end-effector pose sequence",
        })
    }
}

/// Errors of the articulation layer. Every variant names the offending input.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ArticulationError {
    /// A number of the input is NaN or infinite.
    #[error("{input}: non-finite {what} at index {index}")]
    NonFinite {
        /// Which input.
        input: InputKind,
        /// What is non-finite (`"point"`, `"colour"`, `"origin"`, `"stamp"`, `"pose"`, `"time"`).
        what: &'static str,
        /// Index of the element (0 for single values).
        index: usize,
    },
    /// A cloud's colour list does not have one colour per point.
    #[error("{input}: {colors} colours for {points} points")]
    ColorCountMismatch {
        /// Which cloud.
        input: InputKind,
        /// Number of points.
        points: usize,
        /// Number of colours.
        colors: usize,
    },
    /// The end-effector pose times do not increase.
    #[error("{input}: time {time} at index {index} does not follow {previous}")]
    TimeNotIncreasing {
        /// Which input (always [`InputKind::EePoses`]).
        input: InputKind,
        /// Index of the offending sample.
        index: usize,
        /// Its time (s).
        time: f64,
        /// The time of the sample before it (s).
        previous: f64,
    },
    /// A settings field is out of its valid range.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
}
