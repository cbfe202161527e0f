#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod articulation;
pub mod control;
pub mod discovery;
pub mod error;
pub mod prelude;
pub mod scene;
pub mod task;
pub use control::{Outcome, Termination};
pub use error::{Error, InvalidSetting};

#[cfg(feature = "pinocchio")]
pub mod kinematics;
#[cfg(any(feature = "ompl", feature = "casadi"))]
pub mod motion;
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
pub mod planner;
