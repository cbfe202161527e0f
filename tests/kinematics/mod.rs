//! Kinematics layer: the robot model and inverse kinematics.

mod base_joints;
mod description;
mod ik;
mod robot;
mod third_party;
