//! Kinematics layer: the robot model and inverse kinematics.

mod ik;
mod robot;
pub(crate) mod third_party;
