//! The estimator contract: what one exploratory interaction provides, what an estimator returns,
//! and the trait every estimator (analytic or learned) implements.

use nalgebra::{Isometry3, Point3, Unit, Vector3};

use super::cloud::PointCloud;
use super::error::{ArticulationError, InputKind};
use super::uncertainty::Uncertainty;

/// Everything an estimator may use from one exploratory interaction.
#[derive(Debug, Clone, Copy)]
pub struct Interaction<'a> {
    /// Pre-interaction observation `o_pre`.
    pub pre: &'a PointCloud,
    /// Post-interaction observation `o_post`.
    pub post: &'a PointCloud,
    /// Interaction hotspot `c_pre` (grasp point before the pull), map frame, metres.
    pub contact_pre: Point3<f64>,
    /// `c_post` (grasp point after the pull), map frame, metres.
    pub contact_post: Point3<f64>,
    /// `(time s, world_from_ee)` recorded while pulling, times increasing; may be empty.
    /// One rigid grasp: the discovery stage, when it regrasped between attempts, expresses the
    /// later grasps' poses in the first grasp's frame (stitched where each grasp began,
    /// assuming the part did not move in between), so the path is that of one point of the
    /// part.
    pub ee_poses: &'a [(f64, Isometry3<f64>)],
}

impl Interaction<'_> {
    /// Checks every input for bad values (the estimators call this first).
    ///
    /// # Errors
    /// [`ArticulationError::NonFinite`] for any NaN or infinite number,
    /// [`ArticulationError::ColorCountMismatch`] for a colour list of the wrong length,
    /// [`ArticulationError::TimeNotIncreasing`] when the pose times do not strictly increase.
    pub fn validate(&self) -> Result<(), ArticulationError> {
        self.pre.validate(InputKind::PreCloud)?;
        self.post.validate(InputKind::PostCloud)?;
        for (input, c) in [
            (InputKind::ContactPre, &self.contact_pre),
            (InputKind::ContactPost, &self.contact_post),
        ] {
            if !c.coords.iter().all(|v| v.is_finite()) {
                return Err(ArticulationError::NonFinite {
                    input,
                    what: "point",
                    index: 0,
                });
            }
        }
        validate_ee_poses(self.ee_poses)
    }
}

/// Checks a recorded end-effector pose sequence (`(time s, world_from_ee)`): finite times and
/// poses, times strictly increasing.
///
/// # Errors
/// [`ArticulationError::NonFinite`] for any NaN or infinite number,
/// [`ArticulationError::TimeNotIncreasing`] when the times do not strictly increase.
pub fn validate_ee_poses(ee_poses: &[(f64, Isometry3<f64>)]) -> Result<(), ArticulationError> {
    let input = InputKind::EePoses;
    for (index, (t, pose)) in ee_poses.iter().enumerate() {
        if !t.is_finite() {
            return Err(ArticulationError::NonFinite {
                input,
                what: "time",
                index,
            });
        }
        let q = pose.rotation.quaternion();
        let finite = pose
            .translation
            .vector
            .iter()
            .chain(q.coords.iter())
            .all(|v| v.is_finite());
        if !finite {
            return Err(ArticulationError::NonFinite {
                input,
                what: "pose",
                index,
            });
        }
        if index > 0 {
            let previous = ee_poses[index - 1].0;
            if *t <= previous {
                return Err(ArticulationError::TimeNotIncreasing {
                    input,
                    index,
                    time: *t,
                    previous,
                });
            }
        }
    }
    Ok(())
}

/// An estimated joint: the part's motion from the pre to the post observation.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq)]
pub enum JointEstimate {
    /// Rotation about the line through `pivot` along `axis`.
    Revolute {
        /// Unit axis direction (map frame).
        axis: Unit<Vector3<f64>>,
        /// A point on the axis (map frame, m). Estimators return the point closest to the contact.
        pivot: Point3<f64>,
        /// Angle moved pre → post, rad, right-handed about `axis`.
        angle: f64,
    },
    /// Translation along `axis`.
    Prismatic {
        /// Unit axis direction (map frame).
        axis: Unit<Vector3<f64>>,
        /// Distance moved pre → post along `axis`, m.
        distance: f64,
    },
    /// The input does not determine a joint (too little motion, too few points, ...).
    Unknown {
        /// Why, for logs.
        reason: String,
    },
}

impl JointEstimate {
    /// The joint type, for accuracy counts ([`super::metrics::joint_type_accuracy`]).
    pub fn kind(&self) -> JointKindEstimate {
        match self {
            JointEstimate::Revolute { .. } => JointKindEstimate::Revolute,
            JointEstimate::Prismatic { .. } => JointKindEstimate::Prismatic,
            JointEstimate::Unknown { .. } => JointKindEstimate::Unknown,
        }
    }

    /// The axis direction, if the joint is known.
    pub fn axis(&self) -> Option<Unit<Vector3<f64>>> {
        match self {
            JointEstimate::Revolute { axis, .. } | JointEstimate::Prismatic { axis, .. } => {
                Some(*axis)
            }
            JointEstimate::Unknown { .. } => None,
        }
    }
}

/// The type of an estimated joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum JointKindEstimate {
    /// A revolute joint.
    Revolute,
    /// A prismatic joint.
    Prismatic,
    /// No joint was determined.
    Unknown,
}

/// What an estimator returns for one interaction.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// The joint.
    pub joint: JointEstimate,
    /// Indices into `pre.points` segmented as the moving part (empty without segmentation).
    pub moving: Vec<usize>,
    /// The moving part's points in the pre pose (map frame): geometry for collision checks.
    pub part_points: Vec<Point3<f64>>,
    /// Estimator-specific confidence: always finite and in [0, 1] (the estimators build it with
    /// [`unit_score`], which maps NaN to 0).
    pub score: f64,
    /// Model-selection numbers, for logs.
    pub details: String,
    /// The uncertainty of the joint's axis, pivot and type; `None` for an unknown joint or
    /// when the fit's curvature is singular.
    pub uncertainty: Option<Uncertainty>,
}

impl Estimate {
    /// An `Unknown` estimate with the reason and no geometry.
    pub fn unknown(reason: impl Into<String>) -> Self {
        let reason = reason.into();
        Estimate {
            details: reason.clone(),
            joint: JointEstimate::Unknown { reason },
            moving: Vec::new(),
            part_points: Vec::new(),
            score: 0.0,
            uncertainty: None,
        }
    }
}

/// `x` as a score: clamped to [0, 1], NaN (an undefined confidence, e.g. ∞/∞) taken as 0.
///
/// `f64::clamp` alone keeps NaN, so every score goes through this.
pub fn unit_score(x: f64) -> f64 {
    if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
}

/// An articulation estimator: one interaction in, one joint estimate out.
///
/// Implemented here by [`TwoView`](super::TwoView) and [`Proprioceptive`](super::Proprioceptive);
/// a learned estimator (the paper's DiTH network) implements it from outside the crate.
///
/// # Example
/// A user-side estimator (here a stand-in that reads the axis from the contact displacement; a
/// network would run inference instead):
/// ```
/// use kinscene::articulation::{
///     ArticulationError, ArticulationEstimator, Estimate, Interaction, JointEstimate,
/// };
/// use nalgebra::Unit;
///
/// struct Learned;
///
/// impl ArticulationEstimator for Learned {
///     fn name(&self) -> &str {
///         "learned"
///     }
///     fn estimate(&self, i: &Interaction<'_>) -> Result<Estimate, ArticulationError> {
///         i.validate()?;
///         let d = i.contact_post - i.contact_pre;
///         let Some(axis) = Unit::try_new(d, 1e-9) else {
///             return Ok(Estimate::unknown("no contact motion"));
///         };
///         Ok(Estimate {
///             joint: JointEstimate::Prismatic { axis, distance: d.norm() },
///             moving: Vec::new(),
///             part_points: Vec::new(),
///             score: 0.5,
///             details: String::new(),
///             uncertainty: None,
///         })
///     }
/// }
///
/// let estimators: Vec<Box<dyn ArticulationEstimator>> = vec![Box::new(Learned)];
/// assert_eq!(estimators[0].name(), "learned");
/// ```
pub trait ArticulationEstimator: Send + Sync {
    /// A short name for logs and tables.
    fn name(&self) -> &str;

    /// Estimates the joint that moved in `interaction`.
    ///
    /// # Errors
    /// Only for bad input (NaN, mismatched colours, ...); degenerate input gives
    /// `Ok` with [`JointEstimate::Unknown`].
    fn estimate(&self, interaction: &Interaction<'_>) -> Result<Estimate, ArticulationError>;
}
