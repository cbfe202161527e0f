//! The per-handle log of Algorithm 1: what happened to each handle, for the paper's Fig. 6
//! error analysis (which share of handles passes mapping, navigation, exploration and
//! estimation).

use nalgebra::{Isometry2, Point3, Vector3};
use serde::{Deserialize, Serialize};

use super::interface::HardwareFailure;
#[cfg(doc)]
use crate::articulation::Uncertainty;
use crate::articulation::{Estimate, JointEstimate};

/// The stages a handle passes through, in order. A failure is attributed to the stage it
/// happened in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Stage {
    /// The mapped handle is real and re-detected from the approach pose.
    Mapping,
    /// The robot reaches the approach and pre-interaction poses.
    Navigation,
    /// Grasping and pulling move the part (DetectFailure passes).
    Exploration,
    /// The estimator returns a joint and it is registered into the scene model.
    Estimation,
}

/// How the exploration of one handle ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Exploration {
    /// A part and joint were registered into the scene model.
    Registered {
        /// The new part's name.
        part: String,
        /// Its joint's name.
        joint: String,
        /// The part it is nested on, `None` for the base map.
        parent: Option<String>,
    },
    /// The handle failed at `stage`.
    Failed {
        /// Where it failed.
        stage: Stage,
        /// Why, for people.
        reason: String,
    },
}

/// The joint type as classified from the motion seen during an attempt (Reposition's input):
/// the tracked plane's rotation, or the contact's translation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum MotionClass {
    /// Rotation about a roughly vertical axis, clockwise seen from above: the part swings to
    /// the robot's left (a left-hinged door).
    RevoluteLeft,
    /// Rotation about a roughly vertical axis, counter-clockwise seen from above: the part
    /// swings to the robot's right.
    RevoluteRight,
    /// Rotation about a roughly horizontal axis (a door opening downwards).
    RevoluteHorizontal,
    /// Translation without rotation.
    Prismatic,
    /// Too little motion to tell.
    NoMotion,
}

/// How one attempt (grasp + pull) ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum AttemptEnd {
    /// The contact reached `target_pull` from the first grasp point, or all steps were done
    /// with the part displaced.
    Success,
    /// A failure signal came once the contact was `sufficient_pull` from the first grasp
    /// point with the part displaced: accepted as a success (enough motion for the estimator).
    SuccessAfter {
        /// The signal.
        failure: HardwareFailure,
    },
    /// Local navigation to the pre-interaction pose failed.
    Navigation {
        /// The signal.
        failure: HardwareFailure,
    },
    /// An observation could not be taken.
    Sensor {
        /// The sensor's message.
        reason: String,
    },
    /// The grasp failed.
    Grasp {
        /// The signal.
        failure: HardwareFailure,
    },
    /// A pull step failed before enough motion.
    Pull {
        /// The signal.
        failure: HardwareFailure,
    },
    /// DetectFailure: the observation near the contact did not change.
    NoDisplacement {
        /// Mean nearest-neighbour displacement (m) at the last check.
        displacement: f64,
    },
}

impl AttemptEnd {
    /// Whether the attempt counts as a successful interaction.
    pub fn is_success(&self) -> bool {
        matches!(self, AttemptEnd::Success | AttemptEnd::SuccessAfter { .. })
    }
}

/// One attempt at one handle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AttemptLog {
    /// The pre-interaction base pose used.
    pub world_from_base: Isometry2<f64>,
    /// Pull steps applied.
    pub steps: usize,
    /// Distance (m) the contact moved from this attempt's grasp point.
    pub pull_distance: f64,
    /// Last DetectFailure displacement (m), if one was computed.
    pub displacement: Option<f64>,
    /// Tracked rotation (rad) of the surface (or of the end effector, when the surface could
    /// not be tracked) since the grasp.
    pub rotation: f64,
    /// The motion class from this attempt.
    pub motion: MotionClass,
    /// How it ended.
    pub end: AttemptEnd,
}

/// The estimate of one handle's joint, as logged.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EstimateLog {
    /// The estimator's name.
    pub estimator: String,
    /// `"revolute"`, `"prismatic"` or `"unknown"`.
    pub kind: String,
    /// Unit axis (map frame), if known.
    pub axis: Option<Vector3<f64>>,
    /// Point on the axis (map frame) for a revolute joint.
    pub pivot: Option<Point3<f64>>,
    /// Motion pre → post: angle (rad) or distance (m), as estimated (before the sign is
    /// normalised to positive opening).
    pub motion: Option<f64>,
    /// The reason of an unknown estimate.
    pub reason: Option<String>,
    /// Number of moving points segmented.
    pub moving_points: usize,
    /// Number of part points returned.
    pub part_points: usize,
    /// Estimator confidence in [0, 1].
    pub score: f64,
    /// Model-selection details.
    pub details: String,
    /// The 95 % confidence half-angle of the axis (rad,
    /// [`Uncertainty::axis_half_angle_95`]), if the estimate carries an uncertainty.
    pub axis_half_angle_95: Option<f64>,
    /// The 95 % pivot radius (m, [`Uncertainty::pivot_radius_95`]) of a revolute estimate
    /// with an uncertainty.
    pub pivot_radius_95: Option<f64>,
    /// The probability of the estimated joint type ([`Uncertainty::type_probability`]), if
    /// the estimate carries an uncertainty.
    pub type_probability: Option<f64>,
}

impl EstimateLog {
    /// The log entry of `estimate` by `estimator`.
    pub fn new(estimator: &str, estimate: &Estimate) -> Self {
        let u = estimate.uncertainty.as_ref();
        let (kind, axis, pivot, motion, reason) = match &estimate.joint {
            JointEstimate::Revolute { axis, pivot, angle } => (
                "revolute",
                Some(axis.into_inner()),
                Some(*pivot),
                Some(*angle),
                None,
            ),
            JointEstimate::Prismatic { axis, distance } => (
                "prismatic",
                Some(axis.into_inner()),
                None,
                Some(*distance),
                None,
            ),
            JointEstimate::Unknown { reason } => {
                ("unknown", None, None, None, Some(reason.clone()))
            }
        };
        EstimateLog {
            estimator: estimator.to_string(),
            kind: kind.to_string(),
            axis,
            pivot,
            motion,
            reason,
            moving_points: estimate.moving.len(),
            part_points: estimate.part_points.len(),
            score: estimate.score,
            details: estimate.details.clone(),
            axis_half_angle_95: u.map(|u| u.axis_half_angle_95()),
            pivot_radius_95: u.and_then(|u| u.pivot_radius_95()),
            type_probability: u.map(|u| u.type_probability),
        }
    }
}

/// What happened to one handle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HandleLog {
    /// Index of the handle in the input.
    pub index: usize,
    /// The mapped position (m), map frame.
    pub mapped: Point3<f64>,
    /// The re-detected position (m), if the handle was re-detected.
    pub detected: Option<Point3<f64>>,
    /// The outcome.
    pub outcome: Exploration,
    /// Every attempt, in order.
    pub attempts: Vec<AttemptLog>,
    /// Distance (m) from the first grasp point to the last contact: how far the handle was
    /// pulled over all attempts.
    pub pull_distance: f64,
    /// The last estimate, if the estimator ran (the one the part was registered from).
    pub estimate: Option<EstimateLog>,
    /// How the keep-pulling loop ended (see [`discover`](super::discover), step 6), if the
    /// estimator ran.
    pub pulling: Option<PullingLog>,
    /// Notes on degraded but non-fatal steps (a fallback segmentation, a skipped step back).
    pub notes: Vec<String>,
}

impl HandleLog {
    /// Whether the handle passed `stage` (a registered handle passed every stage).
    pub fn passed(&self, stage: Stage) -> bool {
        match &self.outcome {
            Exploration::Registered { .. } => true,
            Exploration::Failed { stage: failed, .. } => stage < *failed,
        }
    }

    /// Whether a part was registered.
    pub fn succeeded(&self) -> bool {
        matches!(self.outcome, Exploration::Registered { .. })
    }
}

/// Why the keep-pulling loop ([`discover`](super::discover), step 6) stopped pulling a handle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum PullEnd {
    /// The estimate's uncertainty is within the settings' limits.
    Confident,
    /// The arm holding the part reached a limit ([`HardwareFailure::JointLimit`]) and no
    /// further pull could go on: no free base pose in front of the last contact other than
    /// the one it stopped at, a pull from there that moved nothing (the part's own limit, or
    /// the arm's again), `reposition_at_arm_limit` off, or `max_extra_pulls` reached at the
    /// limit.
    JointLimit,
    /// A further pull failed otherwise (its attempt's end).
    Failure {
        /// How the last further pull ended.
        end: AttemptEnd,
    },
    /// `max_extra_pulls` further pulls were made and the estimate is still not confident.
    Budget,
}

/// A confidence limit the estimate does not meet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Doubt {
    /// The estimate carries no uncertainty (an unknown joint, or a singular fit).
    NoUncertainty,
    /// The axis's 95 % half-angle (rad) exceeds `confident_axis_95`.
    Axis {
        /// The half-angle (rad).
        half_angle_95: f64,
        /// The limit (rad).
        limit: f64,
    },
    /// The pivot's 95 % radius (m) exceeds `confident_pivot_95`.
    Pivot {
        /// The radius (m).
        radius_95: f64,
        /// The limit (m).
        limit: f64,
    },
    /// The joint type's probability is below `confident_type_probability`: the models nearly
    /// tie (or a check other than the evidence chose the type).
    Type {
        /// The probability.
        probability: f64,
        /// The limit.
        limit: f64,
    },
}

/// The keep-pulling loop of one handle: why it stopped, how many further pulls it made, and
/// the limits the kept estimate does not meet (empty when confident).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PullingLog {
    /// Why pulling stopped.
    pub end: PullEnd,
    /// Further pulls (grasp at the last contact and pull on) after the first successful
    /// attempt, each followed by a new post-interaction observation and estimate.
    pub extra_pulls: usize,
    /// After how many further pulls the kept estimate was made: the most confident one
    /// (`extra_pulls` unless a later view made the estimate worse; then the kept one's opening
    /// is re-measured to the last contact, and the log notes it).
    pub estimate_round: usize,
    /// The limits the kept estimate does not meet; its uncertainty is in
    /// [`HandleLog::estimate`].
    pub doubts: Vec<Doubt>,
}
