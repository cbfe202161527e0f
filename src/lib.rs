#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod error;
pub mod scene;
pub mod task;
pub use error::Error;

#[cfg(feature = "pinocchio")]
pub mod kinematics;
#[cfg(any(feature = "ompl", feature = "casadi"))]
pub mod motion;
