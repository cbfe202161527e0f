//! One-joint motion: the value of one joint goes from `a` to `b`, all others stay fixed.
//!
//! The moving set is the joint's part and all its descendants; it moves rigidly, by the
//! rotation about (revolute) or translation along (prismatic) the joint's world axis
//! ([`JointAxis`](crate::scene::JointAxis)). This module gives the grasp-point trajectory of
//! the paper's Eq. (3)–(5) and the motion bound that makes sampled collision checks
//! continuous-sound ([`crate::scene::collision::check_joint_motion`]).

mod axis;
mod bound;
mod trajectory;

pub use bound::{MotionBound, max_displacement, motion_bound, sweep_radius};
pub(crate) use trajectory::check_joint_value;
pub use trajectory::{MAX_TRAJECTORY_STEPS, grasp_trajectory};
