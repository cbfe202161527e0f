//! Errors of the time parameterisation: bad input only.

/// Why [`time_parameterise`](super::time_parameterise) or
/// [`time_optimal`](super::time_optimal) could not be carried out.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TimingError {
    /// The path has no waypoints.
    #[error("the path has no waypoints")]
    EmptyPath,
    /// A waypoint's length differs from the first waypoint's.
    #[error("waypoint {index}: expected {expected} values, got {got}")]
    WaypointDimension {
        /// Index of the waypoint.
        index: usize,
        /// The first waypoint's length.
        expected: usize,
        /// This waypoint's length.
        got: usize,
    },
    /// A waypoint coordinate is NaN or infinite.
    #[error("waypoint {index}, coordinate {coordinate}: {value} is not finite")]
    NonFiniteWaypoint {
        /// Index of the waypoint.
        index: usize,
        /// Index of the coordinate.
        coordinate: usize,
        /// The value given.
        value: f64,
    },
    /// A limit vector's length differs from the waypoints'.
    #[error("{what}: expected {expected} values, got {got}")]
    LimitDimension {
        /// "max_velocity" or "max_acceleration".
        what: &'static str,
        /// The waypoints' length.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A limit is not positive and finite.
    #[error("{what}[{coordinate}] = {value}: limits must be finite and > 0")]
    InvalidLimit {
        /// "max_velocity" or "max_acceleration".
        what: &'static str,
        /// Index of the coordinate.
        coordinate: usize,
        /// The value given.
        value: f64,
    },
    /// The wrapping yaw coordinate does not exist.
    #[error("yaw coordinate {index} does not exist in waypoints of {dimension} values")]
    YawIndexOutOfRange {
        /// The index given.
        index: usize,
        /// The waypoints' length.
        dimension: usize,
    },
    /// A segment of a differential-drive base path is neither a turn in place nor a drive
    /// along the heading (see [`time_differential_drive`](super::time_differential_drive)).
    #[error(
        "segment {segment} moves the base sideways by {lateral:.3e} m or turns by {turn:.3e} rad \
         while driving: a differential-drive base turns in place or drives straight"
    )]
    Sideways {
        /// Index of the segment (waypoint `segment` to `segment + 1`).
        segment: usize,
        /// Its displacement across the heading (m).
        lateral: f64,
        /// Its change of yaw (rad).
        turn: f64,
    },
    /// A [`BlendSettings`](super::BlendSettings) value is not positive and finite.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
}
