//! The scene layer: the paper's scene-level articulation model M = ⟨B, V, E⟩ and state Θ.
//!
//! - **B**, the static base map ([`BaseMap`]): collision shapes in the world frame and the
//!   navigation grid derived from them ([`nav`]).
//! - **V**, the articulated parts ([`Part`]): collision geometry in the part frame
//!   ([`Collider`], [`Shape`]) and interaction points ([`Handle`]).
//! - **E**, the joints ([`Joint`]): revolute or prismatic, with an axis, an origin and
//!   limits. Each part has exactly one joint to its parent, which is the base or another part,
//!   so the scene is a kinematic tree of any depth (a dishwasher rack riding on the dishwasher
//!   door).
//! - **Θ**, the joint values ([`State`]), and forward kinematics ([`forward_kinematics`]) into
//!   caller-owned scratch data ([`SceneData`]).
//!
//! On top: one-joint motions with the grasp trajectory of Eq. (3)–(5) and a provable motion
//! bound ([`motion`]), collision queries with a continuous-sound sampled sweep check
//! ([`collision`]), and footprints on the navigation grid ([`nav`]).
//!
//! Conventions: SI units (metres, radians), world z up (REP 103), frames in names
//! (`world_from_part` maps part coordinates to world coordinates). Models are built with
//! [`SceneModelBuilder`], validated once, and immutable afterwards.

mod base;
mod builder;
pub mod collision;
mod error;
mod ids;
mod joint;
mod kinematics;
mod model;
pub mod motion;
pub mod nav;
mod part;
mod shape;
mod state;
mod tree;
pub mod urdf;
mod validate;

pub use base::{BaseMap, BaseShape};
pub use builder::SceneModelBuilder;
pub use error::{ElementKind, Error};
pub use ids::{BaseShapeId, HandleId, JointId, Parent, PartId};
pub use joint::{Joint, JointKind, Limits};
pub use kinematics::{
    HandlePose, JointAxis, SceneData, forward_kinematics, joint_axis, world_from_handle,
};
pub use model::SceneModel;
pub use part::{Handle, Part, PartSpec};
pub use shape::{BoundingSphere, Collider, MeshSource, Shape};
pub use state::State;
pub use validate::{MAX_MAGNITUDE, MIN_AXIS_NORM};
