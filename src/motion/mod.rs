//! Motion layer: how the base and the arm move.
//!
//! [`ompl`] plans base paths in SE(2) and arm paths in joint space with OMPL's geometric
//! planners, checking validity with a Rust callback; [`casadi`] writes nonlinear programs (such
//! as whole-body base placement) as symbolic expressions and solves them with IPOPT.

#[cfg(feature = "casadi")]
pub use kinscene_casadi as casadi;
#[cfg(feature = "ompl")]
pub use kinscene_ompl as ompl;

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
}
