//! The task layer's error enum.
//!
//! `Err` is for bad input only: a goal naming an unknown joint, a target outside the joint's
//! limits, invalid settings, an unparsable goal or plan file. "No plan exists" and "the budget
//! ran out" are [`Outcome`](super::Outcome)s, not errors.

/// Errors of the task layer. Every variant names the offending element.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// The scene layer rejected an input (unknown joint, invalid state, …).
    #[error(transparent)]
    Scene(#[from] crate::scene::Error),
    /// A goal target is malformed: NaN, `min > max`, a tolerance `< 0`, or both an exact value
    /// and bounds.
    #[error("goal for joint {joint:?}: {message}")]
    InvalidTarget {
        /// The joint.
        joint: String,
        /// What is wrong.
        message: String,
    },
    /// A goal interval does not meet the joint's limits.
    #[error("goal for joint {joint:?} is [{min}, {max}], outside its limits [{lower}, {upper}]")]
    TargetOutsideLimits {
        /// The joint.
        joint: String,
        /// Requested lower end.
        min: f64,
        /// Requested upper end.
        max: f64,
        /// The joint's lower limit.
        lower: f64,
        /// The joint's upper limit.
        upper: f64,
    },
    /// The robot description is invalid (non-finite pose, radius `<= 0`, …).
    #[error("robot: {message}")]
    InvalidRobot {
        /// What is wrong.
        message: String,
    },
    /// The robot's start pose is outside the navigation grid's explicit bounds or inside an
    /// obstacle.
    #[error("robot start ({x}, {y}) is {why}")]
    InvalidRobotStart {
        /// Start x (m).
        x: f64,
        /// Start y (m).
        y: f64,
        /// "outside the navigation grid" or "in an occupied cell".
        why: String,
    },
    /// A setting is out of its documented range.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// A goal or plan document could not be parsed.
    #[error("cannot parse {what}: {message}")]
    Parse {
        /// Which document ("goal TOML", "plan JSON", …).
        what: String,
        /// The parser's message, with line and column where it gives them.
        message: String,
    },
    /// A goal or plan file could not be read (or is not UTF-8).
    #[error("cannot read {}: {message}", path.display())]
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// The operating system's message.
        message: String,
    },
    /// The goal or plan file at `path` was read but its contents were rejected.
    #[error("{}: {source}", path.display())]
    InFile {
        /// The file.
        path: std::path::PathBuf,
        /// Why it was rejected.
        #[source]
        source: Box<Error>,
    },
    /// Bodies already collide in the start state: a modelling error (a drawer inside its
    /// counter, a door through its carcass) that no plan can repair, since every sweep starts
    /// in contact. Lists every colliding pair.
    #[error("the start state is in collision: {}", list_pairs(pairs))]
    StartInCollision {
        /// The colliding pairs, by name.
        pairs: Vec<super::CollidingPair>,
    },
    /// A plan refers to a step that does not fit the model (unknown joint, value outside the
    /// limits, `from` not equal to the current value).
    #[error("plan step {step}: {message}")]
    InvalidStep {
        /// Zero-based step index.
        step: usize,
        /// What is wrong.
        message: String,
    },
}

/// "a and b; c and d" for the message of [`Error::StartInCollision`], with the usual cause
/// when some pair touches: a closed part modelled flush against its frame.
fn list_pairs(pairs: &[super::CollidingPair]) -> String {
    let shown: Vec<String> = pairs.iter().take(8).map(ToString::to_string).collect();
    let more = pairs.len().saturating_sub(shown.len());
    let mut text = if more > 0 {
        format!("{} and {more} more pairs", shown.join("; "))
    } else {
        shown.join("; ")
    };
    if pairs.iter().any(|p| p.distance <= 0.0) {
        text += " (touching counts: leave a few millimetres between a closed part and its \
                 frame or its neighbour, or allow the pair)";
    }
    text
}
