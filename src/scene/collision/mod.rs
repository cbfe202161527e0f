//! Collision queries with parry3d (f64): part–part and part–base at a state, and along a
//! one-joint motion with a continuous-sound sampled check.
//!
//! Geometry is compiled into parry shapes once, when the model is built; parry's glam types
//! stay inside this module (`convert.rs` is the only place that converts). Every query first
//! compares bounding spheres (the queries at a state also world-aligned boxes) and computes
//! exact parry distances only for collider pairs that can be within the distance of interest.
//!
//! The collision predicate is documented on [`CollisionSettings`]; the sweep guarantee on
//! [`check_joint_motion`].

pub(crate) mod convert;
pub(crate) mod geometry;
mod hull;
mod query;
mod search;
mod settings;
mod standoff;
mod sweep;

pub use geometry::parry_shape;
/// The parry crate the collision checks use ([`parry_shape`] returns its shapes).
pub use parry3d_f64 as parry;
pub use query::{Contact, collisions, collisions_of, distances, is_collision_free};
pub use settings::{AllowedCollisions, Body, BodyName, CollisionSettings, SweepSettings};
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
pub(crate) use standoff::handle_front_shapes;
pub use standoff::{handle_bar_axis, handle_standoff, handle_standoff_along};
pub use sweep::{InconclusiveReason, SweepOutcome, SweepStatus, check_joint_motion};
