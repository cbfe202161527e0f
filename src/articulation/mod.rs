//! Articulation estimation: a part's joint (type, axis, pivot) from observations of its motion.
//!
//! One exploratory interaction ([`Interaction`]: pre/post point clouds, contact points, the
//! end-effector poses recorded while pulling) goes into an [`ArticulationEstimator`], which
//! returns an [`Estimate`]: a [`JointEstimate`] (revolute, prismatic, or unknown with the reason),
//! the moving part's segmentation and points, a score (finite, in [0, 1]), model-selection
//! details and the [`Uncertainty`] of the axis, pivot and type (Gaussian covariances in the
//! axis's tangent plane and the pivot's plane, with 95 % regions). [`Proprioceptive`] also
//! takes the poses alone ([`Proprioceptive::estimate_poses`]).
//!
//! - [`TwoView`]: segment the moving part from the two clouds, register it rigidly (robust ICP
//!   with closed-form Kabsch steps), decompose the motion into a screw and select the joint type
//!   by BIC, checked against the end effector's recorded path when there is one; the chosen
//!   model is refined (point-to-plane for a translation).
//! - [`Proprioceptive`]: fit prismatic (line) and rotational (circle) models to the end-effector
//!   poses with MLESAC and select by BIC (Sturm, Stachniss, Burgard 2011).
//! - A learned estimator (the paper's DiTH network) implements [`ArticulationEstimator`] from
//!   outside the crate.
//!
//! [`metrics`] holds the DiTH error metrics; [`synthetic`] renders depth observations of box
//! scenes for tests, benchmarks and simulation. Pure Rust; imports only point down to the scene
//! layer.
//!
//! The layer is about the scene's parts, not the robot: it sits beside `crate::kinematics`
//! (the robot model and IK, which need Pinocchio) and shares nothing with it; an end-effector
//! pose is just an [`Isometry3`](nalgebra::Isometry3) here. [`crate::discovery`] is its user.

mod cloud;
mod error;
mod estimate;
mod fused;
mod icp;
mod kdtree;
pub mod metrics;
mod pose_circle;
mod proprioceptive;
mod screw;
pub mod synthetic;
mod two_view;
mod uncertainty;
mod visibility;

pub use cloud::PointCloud;
pub use error::{ArticulationError, InputKind};
pub use estimate::{
    ArticulationEstimator, Estimate, Interaction, JointEstimate, JointKindEstimate, unit_score,
    validate_ee_poses,
};
pub use fused::{Fused, FusedSettings};
pub use metrics::{axis_angle_error, axis_position_error, joint_type_accuracy};
pub use proprioceptive::{
    MIN_NOISE_POSES, MIN_ORIENTATION_SIGMA, MIN_POSITION_SIGMA, NoiseSource, OrientationModel,
    PathNoise, Proprioceptive, ProprioceptiveSettings, path_noise,
};
pub use screw::Screw;
pub use two_view::{TwoView, TwoViewSettings};
pub use uncertainty::{CHI2_2DOF_95, PlaneCovariance, Uncertainty};
