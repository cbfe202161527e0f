//! Inverse kinematics: Pinocchio frame Jacobians, damped-least-squares steps, and a
//! box-constrained QP (a dense active-set method, Clarabel as its fallback) for the steps that
//! a joint limit or the trust region cuts.
//!
//! [`IkSolver`] places one frame of a [`kinscene_pinocchio::Model`] (for a robot, its tool
//! frame) at an [`IkTarget`]: a full pose, or a position plus an approach axis with the roll
//! about the axis free. Not converging is an outcome ([`IkOutcome`] `Infeasible` or `Timeout`, with the
//! best configuration found), not an error; [`IkError`] is for bad input and failed backends.
//!
//! # Example
//! ```
//! use kinscene::kinematics::ik::{IkOutcome, IkSettings, IkSolution, IkSolver, IkTarget};
//! use kinscene::kinematics::pinocchio::{self as pin, JointIndex, JointKind, JointLimits};
//! use nalgebra::{DVector, Isometry3, Point3, Vector3};
//!
//! // A planar 2-link arm (two 0.5 m links about z) and its tip.
//! let mut b = pin::ModelBuilder::new();
//! let limits = JointLimits::position(-3.0, 3.0);
//! let j1 = b.add_joint("j1", JointIndex::UNIVERSE, Isometry3::identity(),
//!     JointKind::Revolute { axis: Vector3::z() }, limits)?;
//! let j2 = b.add_joint("j2", j1, Isometry3::translation(0.5, 0.0, 0.0),
//!     JointKind::Revolute { axis: Vector3::z() }, limits)?;
//! let tip = b.add_frame("tip", j2, Isometry3::translation(0.5, 0.0, 0.0))?;
//! let model = b.build()?;
//!
//! let solver = IkSolver::new(&model, tip, IkSettings::default())?;
//! // Tip at (0.5, 0.5, 0), pointing +z: reachable with q = (π/2, −π/2) or (0, π/2).
//! let target = IkTarget::PositionAxis { position: Point3::new(0.5, 0.5, 0.0), axis: Vector3::z_axis() };
//! let IkOutcome::Solved(IkSolution { q, .. }) = solver.solve(&target, &model.neutral())? else {
//!     panic!("reachable");
//! };
//! let mut data = pin::Data::new(&model)?;
//! pin::forward_kinematics(&model, &mut data, &q)?;
//! let tip_pose = pin::frame_placement(&model, &data, tip)?;
//! assert!((tip_pose.translation.vector - Vector3::new(0.5, 0.5, 0.0)).norm() < 1e-5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod dense;
mod error;
mod qp;
mod settings;
mod solver;
mod step;
mod target;

pub use error::IkError;
pub use settings::{IkSettings, StepSolver};
pub use solver::{
    IkBest, IkData, IkFailure, IkOutcome, IkSolution, IkSolver, IkStats, NoConvergence,
};
pub use target::IkTarget;
