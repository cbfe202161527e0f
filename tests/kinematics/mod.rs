//! Kinematics layer: the robot model and inverse kinematics.

mod ik;
mod ik_fast;
mod robot;
mod third_party;
