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
    /// Robot kinematics and IK (Pinocchio), articulation estimation.
    #[error("kinematics: {0}")]
    Kinematics(#[from] crate::kinematics::Error),
    /// Base and arm motion planning and optimisation (OMPL, CasADi/IPOPT).
    #[cfg(any(feature = "ompl", feature = "casadi"))]
    #[error("motion: {0}")]
    Motion(#[from] crate::motion::Error),
    /// The hierarchical planner (task search refined by motion planning).
    #[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
    #[error("planner: {0}")]
    Planner(#[from] crate::planner::PlannerError),
    /// The articulation discovery stage.
    #[error("discovery: {0}")]
    Discovery(#[from] crate::discovery::DiscoveryError),
}

/// A setting out of its documented range: which field, the value given, what it must be.
///
/// Every layer's error enum carries it as its `InvalidSetting` variant, so a settings check
/// reads the same in every layer. It renders as one sentence:
///
/// ```
/// use kinscene::InvalidSetting;
///
/// let e = InvalidSetting::new("sampling.samples", 0.0, "at least 1");
/// assert_eq!(e.to_string(), "setting sampling.samples = 0: must be at least 1");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("setting {field} = {value}: must be {requirement}")]
pub struct InvalidSetting {
    /// The field, by its path where it is nested (`"sampling.samples"`, `"stow[2]"`).
    pub field: String,
    /// The value given: counts as `f64`, durations in seconds.
    pub value: f64,
    /// What the field must be, in words, phrased to follow "must be": `"finite and > 0"`,
    /// `"at least 1"`, `"greater than displacement_threshold"`.
    pub requirement: String,
}

impl InvalidSetting {
    /// The setting `field` given `value`, which must be `requirement` (see the fields).
    pub fn new(field: impl Into<String>, value: f64, requirement: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            value,
            requirement: requirement.into(),
        }
    }
}

/// Lets `?` lift a backend error straight into the crate error.
macro_rules! lift {
    ($feature:meta, $backend:ty => $layer:ident :: $variant:ident => $outer:ident) => {
        #[cfg($feature)]
        impl From<$backend> for Error {
            fn from(e: $backend) -> Self {
                Error::$outer(crate::$layer::Error::$variant(e))
            }
        }
    };
}
lift!(feature = "pinocchio", kinscene_pinocchio::Error => kinematics::Pinocchio => Kinematics);
lift!(feature = "pinocchio", crate::kinematics::robot::RobotError => kinematics::Robot => Kinematics);
lift!(feature = "pinocchio", crate::kinematics::ik::IkError => kinematics::Ik => Kinematics);
lift!(all(), crate::kinematics::articulation::ArticulationError => kinematics::Articulation => Kinematics);
lift!(feature = "ompl", kinscene_ompl::Error => motion::Ompl => Motion);
lift!(feature = "casadi", kinscene_casadi::Error => motion::Casadi => Motion);
lift!(all(feature = "ompl", feature = "pinocchio", feature = "casadi"), crate::motion::paths::PathError => motion::Path => Motion);
lift!(all(feature = "ompl", feature = "pinocchio", feature = "casadi"), crate::motion::timing::TimingError => motion::Timing => Motion);
lift!(all(feature = "ompl", feature = "pinocchio", feature = "casadi"), crate::motion::placement::PlacementError => motion::Placement => Motion);
