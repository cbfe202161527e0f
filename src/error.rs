//! The crate-level error: one variant per layer, each wrapping that layer's own error enum.
//!
//! Every error has one place in it, whichever layer it passed through on the way up: a layer
//! that wraps a lower layer's error (the planner wraps IK, paths and placement; paths wrap
//! OMPL; IK and the robot model wrap Pinocchio; the task layer wraps the scene) hands it to
//! the lower layer's variant when it becomes a [`Error`]. An IK error is always
//! `Error::Kinematics(kinematics::Error::Ik(_))`, an OMPL exception always
//! `Error::Motion(motion::Error::Ompl(_))`, an estimator's error always `Error::Articulation(_)`
//! (or, raised during discovery, inside the discovery error that names the handle).
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
    Task(crate::task::Error),
    /// Robot kinematics and IK (Pinocchio).
    #[cfg(feature = "pinocchio")]
    #[error("kinematics: {0}")]
    Kinematics(crate::kinematics::Error),
    /// Articulation estimation: bad observations or settings (always available; pure Rust).
    #[error("articulation: {0}")]
    Articulation(#[from] crate::articulation::ArticulationError),
    /// Base and arm motion planning and optimisation (OMPL, CasADi/IPOPT).
    #[cfg(any(feature = "ompl", feature = "casadi"))]
    #[error("motion: {0}")]
    Motion(crate::motion::Error),
    /// The hierarchical planner (task search refined by motion planning).
    #[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
    #[error("planner: {0}")]
    Planner(crate::planner::PlannerError),
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

impl From<crate::task::Error> for Error {
    fn from(e: crate::task::Error) -> Self {
        match e {
            crate::task::Error::Scene(e) => Error::Scene(e),
            e => Error::Task(e),
        }
    }
}

#[cfg(feature = "pinocchio")]
impl From<crate::kinematics::Error> for Error {
    fn from(e: crate::kinematics::Error) -> Self {
        match e {
            crate::kinematics::Error::Robot(e) => e.into(),
            crate::kinematics::Error::Ik(e) => e.into(),
            e => Error::Kinematics(e),
        }
    }
}

#[cfg(feature = "pinocchio")]
impl From<kinscene_pinocchio::Error> for Error {
    fn from(e: kinscene_pinocchio::Error) -> Self {
        Error::Kinematics(crate::kinematics::Error::Pinocchio(e))
    }
}

#[cfg(feature = "pinocchio")]
impl From<crate::kinematics::robot::RobotError> for Error {
    fn from(e: crate::kinematics::robot::RobotError) -> Self {
        match e {
            crate::kinematics::robot::RobotError::Pinocchio(e) => e.into(),
            e => Error::Kinematics(crate::kinematics::Error::Robot(e)),
        }
    }
}

#[cfg(feature = "pinocchio")]
impl From<crate::kinematics::ik::IkError> for Error {
    fn from(e: crate::kinematics::ik::IkError) -> Self {
        match e {
            crate::kinematics::ik::IkError::Pinocchio(e) => e.into(),
            e => Error::Kinematics(crate::kinematics::Error::Ik(e)),
        }
    }
}

#[cfg(any(feature = "ompl", feature = "casadi"))]
impl From<crate::motion::Error> for Error {
    fn from(e: crate::motion::Error) -> Self {
        #[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
        {
            use crate::motion::Error as M;
            match e {
                M::Path(e) => e.into(),
                M::Placement(e) => e.into(),
                e => Error::Motion(e),
            }
        }
        #[cfg(not(all(feature = "ompl", feature = "pinocchio", feature = "casadi")))]
        Error::Motion(e)
    }
}

#[cfg(feature = "ompl")]
impl From<kinscene_ompl::Error> for Error {
    fn from(e: kinscene_ompl::Error) -> Self {
        Error::Motion(crate::motion::Error::Ompl(e))
    }
}

#[cfg(feature = "casadi")]
impl From<kinscene_casadi::Error> for Error {
    fn from(e: kinscene_casadi::Error) -> Self {
        Error::Motion(crate::motion::Error::Casadi(e))
    }
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
impl From<crate::motion::paths::PathError> for Error {
    fn from(e: crate::motion::paths::PathError) -> Self {
        match e {
            crate::motion::paths::PathError::Ompl(e) => e.into(),
            e => Error::Motion(crate::motion::Error::Path(e)),
        }
    }
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
impl From<crate::motion::timing::TimingError> for Error {
    fn from(e: crate::motion::timing::TimingError) -> Self {
        Error::Motion(crate::motion::Error::Timing(e))
    }
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
impl From<crate::motion::placement::PlacementError> for Error {
    fn from(e: crate::motion::placement::PlacementError) -> Self {
        use crate::motion::placement::PlacementError as P;
        match e {
            P::Scene(e) => Error::Scene(e),
            P::Robot(e) => e.into(),
            P::Ik(e) => e.into(),
            P::Casadi(e) => e.into(),
            P::Pinocchio(e) => e.into(),
            e => Error::Motion(crate::motion::Error::Placement(e)),
        }
    }
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
impl From<crate::planner::PlannerError> for Error {
    fn from(e: crate::planner::PlannerError) -> Self {
        use crate::planner::PlannerError as P;
        match e {
            P::Scene(e) => Error::Scene(e),
            P::Task(e) => e.into(),
            P::Robot(e) => e.into(),
            P::Ik(e) => e.into(),
            P::Placement(e) => e.into(),
            P::Path(e) => e.into(),
            P::Timing(e) => e.into(),
            e => Error::Planner(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_articulation_error_is_its_own_layer() {
        use crate::articulation::ArticulationError;
        let e: Error =
            ArticulationError::InvalidSetting(InvalidSetting::new("x", 0.0, "> 0")).into();
        assert!(
            matches!(e, Error::Articulation(ArticulationError::InvalidSetting(_))),
            "{e:?}"
        );
    }

    #[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
    #[test]
    fn a_lower_layer_error_has_one_place_whatever_layer_it_passed() {
        use crate::kinematics::ik::IkError;
        use crate::planner::PlannerError;
        let ik = || IkError::UnknownFrame { index: 9, count: 3 };
        let direct: Error = ik().into();
        let through_planner: Error = PlannerError::Ik(ik()).into();
        let through_placement: Error =
            PlannerError::Placement(crate::motion::placement::PlacementError::Ik(ik())).into();
        for e in [direct, through_planner, through_placement] {
            assert!(
                matches!(
                    e,
                    Error::Kinematics(crate::kinematics::Error::Ik(IkError::UnknownFrame {
                        index: 9,
                        ..
                    }))
                ),
                "{e:?}"
            );
        }
        let scene = || crate::scene::Error::UnknownJoint { name: "j".into() };
        let through_task: Error = crate::task::Error::Scene(scene()).into();
        let through_planner: Error = PlannerError::Task(crate::task::Error::Scene(scene())).into();
        for e in [through_task, through_planner] {
            assert!(
                matches!(e, Error::Scene(crate::scene::Error::UnknownJoint { .. })),
                "{e:?}"
            );
        }
    }
}
