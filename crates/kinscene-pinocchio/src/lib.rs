//! Safe Rust binding to [Pinocchio](https://github.com/stack-of-tasks/pinocchio) 4 kinematics.
//!
//! What it wraps: models built **programmatically from Rust** ([`ModelBuilder`]: revolute,
//! unbounded revolute, prismatic and planar joints, bodies, fixed frames) or **parsed from URDF
//! by Pinocchio's own parser** ([`Model::from_urdf_str`], fixed base), forward kinematics
//! ([`forward_kinematics`], [`frame_placement`]), frame Jacobians in the three Pinocchio
//! reference frames ([`frame_jacobian`], [`ReferenceFrame`]) and the configuration-space
//! operations ([`integrate`], [`difference`], [`normalize`], [`set_joint_value`]).
//!
//! Shape, after Pinocchio's own: an immutable [`Model`] (`Send + Sync`, share it between
//! threads) and a mutable scratch [`Data`] per thread; algorithms are free functions
//! `f(&model, &mut data, q)`. `q` has [`Model::nq`] entries and `v` [`Model::nv`]; they differ
//! when a joint's configuration is a `(cos, sin)` pair (see [`configuration`]).
//!
//! # How it is isolated
//! The C++ side is a small shim (`cpp/shim.{h,cpp}`) with a C ABI, compiled by `build.rs` into
//! its own shared object against the `libpinocchio` wheel's cmeel prefix, and loaded lazily on
//! first use with `dlopen(RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND)` (crate `kinscene-shim`). The
//! deep binding keeps Pinocchio's boost 1.90 apart from the boost 1.74 that OMPL brings into the
//! same process. Inputs are validated in Rust before they reach C++ (typed [`Error`]s), and any
//! C++ exception is caught in the shim and returned as [`Error::Backend`]. Set
//! `KINSCENE_PINOCCHIO_SHIM` to load another build of the shim, `KINSCENE_PINOCCHIO_PREFIX` at
//! build time to use another Pinocchio prefix.
//!
//! # Example
//! ```
//! use kinscene_pinocchio::*;
//! use nalgebra::{DVector, Isometry3, Vector3};
//!
//! let mut b = ModelBuilder::new();
//! let base = b.add_joint("base", JointIndex::UNIVERSE, Isometry3::identity(), JointKind::Planar, JointLimits::NONE)?;
//! let arm = b.add_joint(
//!     "arm",
//!     base,
//!     Isometry3::translation(0.0, 0.0, 0.5),
//!     JointKind::Revolute { axis: Vector3::z() },
//!     JointLimits::position(-3.0, 3.0),
//! )?;
//! let tool = b.add_frame("tool", arm, Isometry3::translation(0.4, 0.0, 0.0))?;
//! let model = b.build()?;
//! assert_eq!((model.nq(), model.nv()), (5, 4));
//!
//! let mut data = Data::new(&model)?;
//! let q = DVector::from_vec(vec![1.0, 2.0, 1.0, 0.0, std::f64::consts::FRAC_PI_2]);
//! forward_kinematics(&model, &mut data, &q)?;
//! let world_from_tool = frame_placement(&model, &data, tool)?;
//! assert!((world_from_tool.translation.vector - Vector3::new(1.0, 2.4, 0.5)).norm() < 1e-12);
//!
//! let jacobian = frame_jacobian(&model, &mut data, &q, tool, ReferenceFrame::LocalWorldAligned)?;
//! assert_eq!(jacobian.shape(), (6, 4));
//! # Ok::<(), kinscene_pinocchio::Error>(())
//! ```

#![warn(missing_docs)]

mod builder;
pub mod configuration;
mod construct;
mod data;
mod error;
mod ffi;
mod frame;
mod inertia;
mod joint;
mod kinematics;
mod model;
mod urdf;

#[cfg(feature = "bench")]
pub mod bench;

pub use builder::{ModelBuilder, UNIVERSE_NAME};
pub use configuration::{
    UNIT_NORM_TOLERANCE, check_configuration, difference, integrate, normalize, set_joint_value,
};
pub use data::Data;
pub use error::Error;
pub use frame::{Frame, FrameIndex, FrameKind, ReferenceFrame};
pub use inertia::Inertia;
pub use joint::{Joint, JointIndex, JointKind, JointLimits};
pub use kinematics::{
    forward_kinematics, frame_jacobian, frame_placement, frame_placement_and_jacobian,
    joint_placement,
};
pub use model::Model;

/// The version of the Pinocchio library the shim was built against (e.g. `"4.1.0"`).
///
/// # Errors
/// [`Error::Load`] when the shim cannot be loaded.
pub fn pinocchio_version() -> Result<String, Error> {
    let api = ffi::api()?;
    let mut buf = [0 as std::ffi::c_char; 64];
    // SAFETY: the shim writes at most `buf.len()` bytes, NUL-terminated.
    unsafe { (api.version)(buf.as_mut_ptr(), buf.len()) };
    // SAFETY: NUL-terminated within the buffer (zeroed, and ks::set_error terminates).
    let version = unsafe { std::ffi::CStr::from_ptr(buf.as_ptr()) };
    Ok(version.to_string_lossy().into_owned())
}
