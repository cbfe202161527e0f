//! The crate-level error: one variant per layer, each wrapping that layer's own error enum.
//!
//! `Err` is for bad input and broken backends only. "No plan exists", "IK did not converge",
//! "the time budget ran out" are outcomes inside `Ok` (see each layer's status types).

/// Any error kinscene reports. Match on the layer, then on the layer's enum.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene model: building it, states, queries (always available; pure Rust).
    #[error("scene: {0}")]
    Scene(#[from] crate::scene::Error),
    /// Task-level sequencing: goals, settings, plan documents.
    #[error("task: {0}")]
    Task(#[from] crate::task::Error),
    /// Robot and scene kinematics (Pinocchio).
    #[cfg(feature = "pinocchio")]
    #[error("kinematics: {0}")]
    Kinematics(#[from] crate::kinematics::Error),
    /// Base and arm motion planning and optimisation (OMPL, CasADi/IPOPT).
    #[cfg(any(feature = "ompl", feature = "casadi"))]
    #[error("motion: {0}")]
    Motion(#[from] crate::motion::Error),
}

/// Lets `?` lift a backend error straight into the crate error.
macro_rules! lift {
    ($feature:literal, $backend:ty => $layer:ident :: $variant:ident => $outer:ident) => {
        #[cfg(feature = $feature)]
        impl From<$backend> for Error {
            fn from(e: $backend) -> Self {
                Error::$outer(crate::$layer::Error::$variant(e))
            }
        }
    };
}
lift!("pinocchio", kinscene_pinocchio::Error => kinematics::Pinocchio => Kinematics);
lift!("ompl", kinscene_ompl::Error => motion::Ompl => Motion);
lift!("casadi", kinscene_casadi::Error => motion::Casadi => Motion);
