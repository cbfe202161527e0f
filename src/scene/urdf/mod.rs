//! URDF import and export of scene models: a scene URDF in, a digital twin out.
//!
//! # Scene URDF conventions
//!
//! A scene URDF is an ordinary URDF (urdf-rs, urdfdom and Pinocchio read it) with these
//! readings:
//!
//! - **Base map B.** The root link (the only link that is no joint's child) is the static
//!   base; its frame is the world frame. Its collision elements, and those of links attached
//!   to it through chains of `fixed` joints, become base shapes. A base shape is named by its
//!   collision element's `name` attribute, or `<link>#<k>` (the k-th collision element of the
//!   link, from 0) if the attribute is absent or empty. The base map's name is the root
//!   link's name; its navigation settings come from [`ImportOptions::nav`].
//! - **Parts V and joints E.** The child link of a `revolute`, `continuous` or `prismatic`
//!   joint is a part, named like the link; the joint (its name, origin, axis and limits) is
//!   the part's joint. The part's parent is the part owning the joint's parent link, or the
//!   base.
//! - **Fixed merge.** A link attached through a `fixed` joint merges into the part (or the
//!   base) its parent belongs to, through chains of any length: its collision elements move
//!   into the owner's frame, composed with the fixed joints' origins. A movable joint whose
//!   parent link was merged gets its origin composed the same way, so it is expressed in the
//!   owning part's frame. Merged links leave no other trace.
//! - **Handles.** A link whose name ends in [`HANDLE_SUFFIX`] (`_handle`) and is attached by a
//!   `fixed` joint is a handle of the part it merges into: its origin (in the part frame) is
//!   the grasp point, its +x axis the outward surface normal, its name the link name. Its
//!   collision elements, if any, merge into the part like any fixed link's. A handle link on
//!   the base is an error ([`Error::HandleOnBase`]). Tools that know nothing of handles see a
//!   massless fixed link.
//! - **Meshes.** `<mesh filename scale>` is loaded with mesh-loader (STL, OBJ, COLLADA `.dae`,
//!   chosen by extension). `package://NAME/rest` resolves through
//!   [`ImportOptions::package_paths`], `file://path` is the path, a plain path is relative to
//!   [`ImportOptions::base_dir`] (for [`read_file`], the file's directory); other schemes are
//!   errors. Each non-empty sub-mesh becomes one [`Shape::ConvexMesh`] (the convex hull of its
//!   vertices, scaled component-wise) with a [`MeshSource`] keeping the URI and scale for
//!   export; a base shape from a mesh with several sub-meshes is named `<name>/<i>`. A flat
//!   sub-mesh is an error ([`Error::DegenerateMesh`]). Files are read once per import.
//! - **Joint types.** `revolute` and `prismatic` need a `<limit>` with finite `lower` and
//!   `upper` ([`Error::MissingLimits`]; `lower > upper` is [`Error::InvalidLimits`]).
//!   `continuous` joints are revolute with [`Joint::continuous`] set and the working range
//!   [`ImportOptions::continuous_limits`] (default `[-π, π]`); their `<limit>`, if any, is
//!   ignored. `planar`, `floating` and `spherical` are errors
//!   ([`Error::UnsupportedJointType`]). The axis defaults to (1, 0, 0); a zero or NaN axis is
//!   [`Error::ZeroAxis`] / [`Error::NonFinite`] naming the joint.
//! - **Frames.** `<origin xyz rpy>` is the child frame in the parent frame, with fixed-axis
//!   roll-pitch-yaw `R = Rz(yaw)·Ry(pitch)·Rx(roll)`; the part frame is the joint frame at
//!   value 0, as in [`Joint`].
//! - **Ignored.** Visual elements, inertials, materials, velocity and effort limits,
//!   `<dynamics>`, `<mimic>`, `<calibration>`, `<safety_controller>`, and any other element
//!   urdf-rs skips (`<gazebo>`, `<transmission>`).
//!
//! Import validates the tree first (unique link and joint names, supported joint types,
//! existing links, one parent per link, one root, no cycles: the typed errors of
//! [`read_str`]) and then builds through [`SceneModelBuilder::build`], so every check of the
//! scene builder applies. No input makes the importer panic.
//!
//! # Export layout
//!
//! [`write_string`] and [`write_file`] write the base link (named like the base map, or
//! `base`) with one collision element per base shape (`name` attribute = shape name), then
//! for each part, in id order: its link with its colliders, its joint (origin, axis, limits;
//! `continuous` joints without `<limit>`; revolute and prismatic joints with `effort="0"
//! velocity="0"`, which urdfdom requires and the scene model does not have), and per handle
//! a geometry-free link (the handle's name, with `_handle` appended if it lacks the suffix) on
//! a fixed joint `<handle link>_joint` (suffixed `_2`, `_3`, ... if that name is taken) whose
//! origin is the grasp point with +x along the normal. Every collision element is mirrored by
//! an identical visual element so that viewers show the scene. A convex mesh with a source is
//! written as its `<mesh filename scale>` (the sub-meshes of one file at one pose as one
//! element); one without a source is written as an OBJ file of its convex hull into
//! [`ExportOptions::mesh_dir`] and referenced from there.
//!
//! # Round trip
//!
//! Lengths, limits and scales are written so that they import bit for bit. Rotations are
//! written as `rpy` on a grid of 1e-12 rad (coarser for yaw near gimbal lock, where it hardly
//! affects the rotation), so an imported model matches the exported one within about 1e-11
//! rad; axes are written as exact unit vectors. Re-exporting an imported export reproduces the
//! text exactly. A model whose continuous joints have a working range other than
//! [`ImportOptions::continuous_limits`] comes back with that range; a convex mesh without a
//! source comes back as the hull read from the OBJ file (vertices rounded to `f32` by
//! mesh-loader) with the OBJ as its source.
//!
//! # Example
//! ```
//! use kinscene::scene::urdf::{ImportOptions, read_str};
//! use kinscene::scene::{SceneData, State, forward_kinematics, world_from_handle};
//! use nalgebra::{Point3, Vector3};
//!
//! let xml = r#"
//! <robot name="cabinet">
//!   <link name="carcass">
//!     <collision name="box">
//!       <origin xyz="0 0 0.4"/>
//!       <geometry><box size="0.6 0.6 0.8"/></geometry>
//!     </collision>
//!   </link>
//!   <link name="door">
//!     <collision>
//!       <origin xyz="0 -0.3 0.4"/>
//!       <geometry><box size="0.02 0.6 0.8"/></geometry>
//!     </collision>
//!   </link>
//!   <joint name="door_hinge" type="revolute">
//!     <origin xyz="0.31 0.3 0"/>
//!     <parent link="carcass"/>
//!     <child link="door"/>
//!     <axis xyz="0 0 1"/>
//!     <limit lower="0" upper="1.9" effort="0" velocity="0"/>
//!   </joint>
//!   <link name="door_handle"/>
//!   <joint name="door_handle_joint" type="fixed">
//!     <origin xyz="0.03 -0.55 0.5"/>
//!     <parent link="door"/>
//!     <child link="door_handle"/>
//!   </joint>
//! </robot>"#;
//! let model = read_str(xml, &ImportOptions::default())?;
//! assert_eq!(model.nq(), 1);
//! assert_eq!(model.base().shapes[0].name, "box");
//!
//! // The handle in the door frame: the fixed joint's origin and +x.
//! let id = model.handle_id("door_handle")?;
//! let handle = model.handle(id).unwrap();
//! assert_eq!(handle.position, Point3::new(0.03, -0.55, 0.5));
//! assert_eq!(handle.normal, Vector3::x());
//!
//! // Door open by 90°: the handle swings about the hinge at (0.31, 0.3, 0) to
//! // (0.31, 0.3, 0) + Rz(90°)·(0.03, -0.55, 0.5) = (0.86, 0.33, 0.5), facing +y.
//! let state = State::from_values(&model, [("door_hinge", std::f64::consts::FRAC_PI_2)])?;
//! let mut data = SceneData::new(&model);
//! forward_kinematics(&model, &mut data, &state)?;
//! let pose = world_from_handle(&model, &data, id)?;
//! assert!((pose.position - Point3::new(0.86, 0.33, 0.5)).norm() < 1e-12);
//! assert!((pose.normal.into_inner() - Vector3::y()).norm() < 1e-12);
//! # Ok::<(), kinscene::scene::Error>(())
//! ```
//!
//! [`Error::HandleOnBase`]: crate::scene::Error::HandleOnBase
//! [`Error::DegenerateMesh`]: crate::scene::Error::DegenerateMesh
//! [`Error::MissingLimits`]: crate::scene::Error::MissingLimits
//! [`Error::InvalidLimits`]: crate::scene::Error::InvalidLimits
//! [`Error::UnsupportedJointType`]: crate::scene::Error::UnsupportedJointType
//! [`Error::ZeroAxis`]: crate::scene::Error::ZeroAxis
//! [`Error::NonFinite`]: crate::scene::Error::NonFinite
//! [`Shape::ConvexMesh`]: crate::scene::Shape::ConvexMesh
//! [`MeshSource`]: crate::scene::MeshSource
//! [`Joint`]: crate::scene::Joint
//! [`Joint::continuous`]: crate::scene::Joint::continuous
//! [`SceneModelBuilder::build`]: crate::scene::SceneModelBuilder::build

mod collisions;
mod export;
mod import;
pub(crate) mod mesh;
mod numbers;
mod obj;
mod options;
mod scan;
mod tree;
mod xml;

#[cfg(feature = "pinocchio")]
pub(crate) use xml::escape as escape_attribute;

pub use export::{write_file, write_string};
pub use import::{read_file, read_str};
pub use options::{ExportOptions, ImportOptions};

/// Name suffix that marks a fixed child link as a handle (see the module docs).
pub const HANDLE_SUFFIX: &str = "_handle";
