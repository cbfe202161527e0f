//! Motion layer: how the base and the arm move.
//!
//! [`ompl`] plans base paths in SE(2) and arm paths in joint space with OMPL's geometric
//! planners, checking validity with a Rust callback; [`casadi`] writes nonlinear programs (such
//! as whole-body base placement) as symbolic expressions and solves them with IPOPT.
//!
//! With all three backends: [`paths`] (OMPL base and arm paths and their independent dense
//! re-check), [`timing`] (time parameterisation under velocity and acceleration limits) and
//! [`placement`] (grasp frames along the handle trajectory, IK along it, sampled and
//! CasADi/IPOPT base placement).

#[cfg(feature = "casadi")]
pub use kinscene_casadi as casadi;
#[cfg(feature = "ompl")]
pub use kinscene_ompl as ompl;

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
pub mod paths;
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
pub mod placement;
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
pub mod timing;

/// Errors of the motion layer.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The OMPL backend rejected its input, failed to load, or threw.
    #[cfg(feature = "ompl")]
    #[error("OMPL: {0}")]
    Ompl(#[from] kinscene_ompl::Error),
    /// The CasADi backend rejected its input, failed to load, or threw.
    #[cfg(feature = "casadi")]
    #[error("CasADi: {0}")]
    Casadi(#[from] kinscene_casadi::Error),
    /// Base and arm paths: bad input to the OMPL layer.
    #[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
    #[error("paths: {0}")]
    Path(#[from] paths::PathError),
    /// Time parameterisation: bad paths or limits.
    #[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
    #[error("timing: {0}")]
    Timing(#[from] timing::TimingError),
    /// Base placement and the manipulation trajectory.
    #[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
    #[error("placement: {0}")]
    Placement(#[from] placement::PlacementError),
}
