//! Integration tests, compiled as one binary.

mod articulation;
mod backends;
mod discovery;
#[cfg(feature = "pinocchio")]
pub(crate) mod kinematics;
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
mod motion;
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
mod planner;
mod scene;
mod task;
