//! State spaces and planning problems (OMPL's `StateSpace` and `ProblemDefinition`).

use crate::Error;

/// A configuration space with its bounds.
///
/// Distances (goal tolerance, cost threshold, planner range) are OMPL's distance of the space:
/// - SE(2): `‖(Δx, Δy)‖ + 0.5·|Δyaw|`, with `Δyaw` the shortest angle (metres + radians, OMPL's
///   `SE2StateSpace` weights its R² and SO(2) parts 1 and 0.5);
/// - real vector: the Euclidean distance.
///
/// Its *maximum extent*, which the motion-check resolution is a fraction of, is
/// `‖(x_hi − x_lo, y_hi − y_lo)‖ + 0.5·π` for SE(2) and `‖upper − lower‖` for a real vector space.
#[derive(Debug, Clone, PartialEq)]
pub enum StateSpace {
    /// A planar pose `[x, y, yaw]`: `x` and `y` bounded (metres, `[low, high]`), yaw free
    /// (radians: any value, start and goal taken to their representative in OMPL's `[-π, π)`,
    /// π included; states coming back from OMPL have yaw in `[-π, π]`).
    Se2 {
        /// Bounds of x, `[low, high]`.
        x: [f64; 2],
        /// Bounds of y, `[low, high]`.
        y: [f64; 2],
    },
    /// A box `lower ≤ q ≤ upper` in Rⁿ, e.g. an arm's joint space (radians or metres per joint).
    RealVector {
        /// Lower bound per dimension.
        lower: Vec<f64>,
        /// Upper bound per dimension.
        upper: Vec<f64>,
    },
}

impl StateSpace {
    /// Number of values in a state: 3 for SE(2), `lower.len()` for a real vector space.
    pub fn dimension(&self) -> usize {
        match self {
            StateSpace::Se2 { .. } => 3,
            StateSpace::RealVector { lower, .. } => lower.len(),
        }
    }

    /// The bounded coordinates' limits as `(lower, upper)` (x and y only for SE(2)).
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        match self {
            StateSpace::Se2 { x, y } => (vec![x[0], y[0]], vec![x[1], y[1]]),
            StateSpace::RealVector { lower, upper } => (lower.clone(), upper.clone()),
        }
    }

    /// Checks the bounds: at least one dimension, equal lengths, finite, `lower ≤ upper`.
    ///
    /// A space whose every bound has `lower == upper` passes this check but has zero extent;
    /// OMPL rejects it with an exception, reported as [`Error::Backend`].
    ///
    /// # Errors
    /// [`Error::ZeroDimension`], [`Error::DimensionMismatch`], [`Error::NonFinite`],
    /// [`Error::InvalidBounds`].
    pub fn validate(&self) -> Result<(), Error> {
        let (lower, upper) = self.bounds();
        if lower.is_empty() {
            return Err(Error::ZeroDimension);
        }
        if upper.len() != lower.len() {
            return Err(Error::DimensionMismatch {
                what: "upper bounds",
                expected: lower.len(),
                got: upper.len(),
            });
        }
        if !lower.iter().chain(&upper).all(|v| v.is_finite()) {
            return Err(Error::NonFinite { what: "bounds" });
        }
        match lower.iter().zip(&upper).position(|(l, u)| l > u) {
            Some(axis) => Err(Error::InvalidBounds {
                axis,
                lower: lower[axis],
                upper: upper[axis],
            }),
            None => Ok(()),
        }
    }
}

/// One planning query: from `start` to within `goal_tolerance` of `goal` in `space`.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// The configuration space.
    pub space: StateSpace,
    /// Start state (`[x, y, yaw]` for SE(2)).
    pub start: Vec<f64>,
    /// Goal state.
    pub goal: Vec<f64>,
    /// A path ending within this distance (the space's distance, see [`StateSpace`]) of the
    /// goal is an exact solution. 0 means OMPL's minimum, machine epsilon.
    pub goal_tolerance: f64,
}

impl Problem {
    /// Default goal tolerance: 1e-6 (space distance units).
    pub const DEFAULT_GOAL_TOLERANCE: f64 = 1e-6;

    /// A problem with the default goal tolerance.
    pub fn new(space: StateSpace, start: Vec<f64>, goal: Vec<f64>) -> Problem {
        Problem {
            space,
            start,
            goal,
            goal_tolerance: Self::DEFAULT_GOAL_TOLERANCE,
        }
    }

    /// Checks the space, the sizes and finiteness of start and goal, and the tolerance.
    ///
    /// A start or goal outside the bounds is not an error: planning reports it as
    /// [`PlanStatus::InvalidStart`](crate::PlanStatus::InvalidStart) /
    /// [`InvalidGoal`](crate::PlanStatus::InvalidGoal), as OMPL does.
    ///
    /// # Errors
    /// Those of [`StateSpace::validate`], then [`Error::DimensionMismatch`] or
    /// [`Error::NonFinite`] for `start`/`goal`, [`Error::InvalidSetting`] for the tolerance.
    pub fn validate(&self) -> Result<(), Error> {
        self.space.validate()?;
        let dim = self.space.dimension();
        for (what, q) in [("start", &self.start), ("goal", &self.goal)] {
            if q.len() != dim {
                return Err(Error::DimensionMismatch {
                    what,
                    expected: dim,
                    got: q.len(),
                });
            }
            if !q.iter().all(|v| v.is_finite()) {
                return Err(Error::NonFinite { what });
            }
        }
        if !(self.goal_tolerance.is_finite() && self.goal_tolerance >= 0.0) {
            return Err(Error::InvalidSetting {
                name: "goal_tolerance",
                value: self.goal_tolerance,
                requirement: "finite and >= 0",
            });
        }
        Ok(())
    }
}
