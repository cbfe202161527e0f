//! The articulation discovery stage (the paper's Sec. III-B and Algorithm 1): from detected
//! handles and a static base map to a scene-level articulation model M.
//!
//! The robot does not know the scene's joints a priori. This layer explores every detected
//! handle physically and registers what it learns into a [`SceneModel`](crate::scene::SceneModel)
//! the planner uses. It is library code over two small traits, so a ROS driver or a simulator
//! plugs in without knowing the planner:
//!
//! - [`Perception`]: depth observations ([`PointCloud`], map frame) from a head or wrist
//!   [`Camera`], and [`HandleDetection`]s.
//! - [`Hardware`]: global navigation to a base pose, local navigation relative to a tracked
//!   target ([`LocalGoal`]), grasp, one compliant pull step (the admittance-controlled action),
//!   retract, the end-effector and base poses, a clock; failures are a typed
//!   [`HardwareFailure`].
//!
//! [`discover`] drives a [`Robot`]: anything implementing both traits (a simulator's world),
//! or two separate objects combined with [`Split`].
//!
//! The stages:
//! 1. **Mapping** ([`fuse_detections`], [`register_handles`]): detections from many views
//!    fused by 3D non-maximum suppression and clustering with confidence, then registered
//!    against the base map (handles inside or far from its solids dropped; each attached to a
//!    base-map face, whose outward normal it takes).
//! 2. **Discovery** ([`discover`]): Algorithm 1 — PlanBase, GlobalNavTo, DetectHandle,
//!    LocalNavTo, the pre-interaction observation, the exploratory loop (GetComplianceAction,
//!    DetectFailure, Reposition), the post-interaction observation from a step back,
//!    PredArticulation through an
//!    [`ArticulationEstimator`](crate::articulation::ArticulationEstimator), and
//!    registration of the part and joint into the scene model (nested on an earlier part
//!    when the handle lies on it). The rules are documented on [`discover`].
//! 3. **The log** ([`HandleLog`]): per handle the stage reached and the failure category —
//!    mapping, navigation, exploration, estimation ([`Stage`]) — the attempts, the pull
//!    distance and the estimate, serialisable for reports (the paper's Fig. 6).
//!
//! `Err` ([`DiscoveryError`]) is for bad input and broken contracts; hardware failures, lost
//! handles and unknown estimates are outcomes in the log. Pure Rust; imports point down to
//! [`crate::articulation`] and [`crate::scene`].
//!
//! # Example
//! Mapping: two views of one handle and a stray weak detection, registered against a cabinet.
//! ```
//! use kinscene::discovery::{
//!     FusionSettings, HandleDetection, RegistrationSettings, fuse_detections, register_handles,
//! };
//! use kinscene::scene::{BaseMap, BaseShape, Shape};
//! use nalgebra::{Isometry3, Point3, Vector3};
//!
//! let det = |x: f64, c: f64| HandleDetection {
//!     position: Point3::new(x, -0.03, 0.7),
//!     half_extents: Vector3::new(0.01, 0.02, 0.06),
//!     confidence: c,
//!     stamp: 0.0,
//! };
//! let views = vec![vec![det(0.50, 0.8)], vec![det(0.51, 0.7), det(1.5, 0.2)]];
//! let handles = fuse_detections(&views, &FusionSettings::default())?;
//! assert_eq!(handles.len(), 1); // the weak stray detection is dropped
//!
//! // A carcass whose front face is the plane y = 0, facing -y.
//! let mut base = BaseMap::default();
//! base.shapes.push(BaseShape::new(
//!     "carcass",
//!     Shape::cuboid(Vector3::new(0.5, 0.3, 0.45)),
//!     Isometry3::translation(0.5, 0.3, 0.45),
//! ));
//! let registered = register_handles(&handles, &base, &RegistrationSettings::default())?;
//! let a = registered.handles[0].attachment.as_ref().unwrap();
//! assert!((a.normal - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-9);
//! # Ok::<(), kinscene::discovery::DiscoveryError>(())
//! ```

mod algorithm;
mod cloud;
mod error;
mod explore;
mod front;
mod fusion;
mod interface;
mod log;
mod part;
mod placement;
mod prediction;
mod reconcile;
mod registration;
mod run;
mod settings;
mod shapes;

pub use algorithm::{Discovery, discover};
pub use error::DiscoveryError;
pub use fusion::{FusionSettings, MappedHandle, fuse_detections};
pub use interface::{
    Camera, HandleDetection, Hardware, HardwareFailure, LocalGoal, Perception, PointCloud, Robot,
    SensorFailure, Split,
};
pub use log::{
    AttemptEnd, AttemptLog, Doubt, EstimateLog, Exploration, HandleLog, MotionClass, PullEnd,
    PullingLog, Stage,
};
pub use reconcile::{BoxCut, CUTS, Conflict, Observation, Reconciliation, reconcile};
pub use registration::{
    Attachment, Registration, RegistrationSettings, Rejection, register_handles,
};
pub use settings::DiscoverySettings;
