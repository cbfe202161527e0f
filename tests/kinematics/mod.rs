//! Kinematics layer: the robot model and inverse kinematics.

mod base_joints;
mod continuous;
mod description;
mod ik;
mod ik_fast;
mod robot;
mod spheres;
pub(crate) mod third_party;
mod walk;
