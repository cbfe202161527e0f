//! Kinematics layer: the robot model and inverse kinematics.

mod ik;
mod robot;
mod third_party;
