//! The front door: the items the main use needs, in one import.
//!
//! ```text
//! use kinscene::prelude::*;
//! ```
//!
//! Load a scene URDF ([`SceneModel::from_urdf_file`]) and a goal file
//! ([`Problem::from_goal_file`]), or build them from values ([`SceneModelBuilder`],
//! [`GoalSpec`]); plan the order of joint changes ([`plan_task`]) and read the [`Outcome`];
//! write the document ([`PlanFile`]). Everything stops at a [`Termination`]. The README's
//! first example uses this module alone.
#![cfg_attr(
    all(feature = "ompl", feature = "pinocchio", feature = "casadi"),
    doc = "\nWith the default backends, plan the whole motion with a robot \
           ([`HierarchicalPlanner`]) and write it as a [`MotionDocument`]."
)]

pub use crate::control::{Outcome, Termination};
pub use crate::error::Error;
pub use crate::scene::urdf::ImportOptions;
pub use crate::scene::{SceneModel, SceneModelBuilder, State};
pub use crate::task::{
    GoalSpec, NoRefinement, PlanFile, Problem, Strategy, TaskSettings, conflicting_targets,
    plan as plan_task,
};

#[cfg(feature = "pinocchio")]
pub use crate::kinematics::robot::{RobotImportOptions, RobotModel};

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
pub use crate::planner::{
    HierarchicalPlanner, MotionDocument, MotionOutcome, MotionPlan, PlannerSettings,
};
