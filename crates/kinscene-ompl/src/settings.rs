//! Planner choice, planning settings and termination conditions.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use crate::Error;

/// An OMPL geometric planner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Planner {
    /// Bidirectional RRT (`og::RRTConnect`): fast for feasibility, the default.
    #[default]
    RrtConnect,
    /// RRT (`og::RRT`).
    Rrt,
    /// Asymptotically optimal RRT* (`og::RRTstar`); optimising.
    RrtStar,
    /// Probabilistic roadmap (`og::PRM`); stops at the first solution unless a cost threshold
    /// is set.
    Prm,
    /// PRM* (`og::PRMstar`); optimising.
    PrmStar,
    /// KPIECE1 (`og::KPIECE1`), using the space's default projection.
    Kpiece1,
    /// Bidirectional KPIECE (`og::BKPIECE1`).
    Bkpiece1,
    /// Lazy bidirectional KPIECE (`og::LBKPIECE1`).
    Lbkpiece1,
    /// Expansive space trees (`og::EST`).
    Est,
    /// Single-query bidirectional lazy planner (`og::SBL`).
    Sbl,
    /// Batch informed trees (`og::BITstar`); optimising.
    BitStar,
}

impl Planner {
    /// Every planner, in declaration order.
    pub const ALL: [Planner; 11] = [
        Planner::RrtConnect,
        Planner::Rrt,
        Planner::RrtStar,
        Planner::Prm,
        Planner::PrmStar,
        Planner::Kpiece1,
        Planner::Bkpiece1,
        Planner::Lbkpiece1,
        Planner::Est,
        Planner::Sbl,
        Planner::BitStar,
    ];

    /// True for the asymptotically optimal planners (RRT*, PRM*, BIT*), which keep improving
    /// the path until the budget runs out unless [`PlanSettings::cost_threshold`] is met.
    pub fn is_optimizing(self) -> bool {
        matches!(self, Planner::RrtStar | Planner::PrmStar | Planner::BitStar)
    }

    /// True when [`PlanSettings::range`] applies (all but PRM, PRM* and BIT*).
    pub fn has_range(self) -> bool {
        !matches!(self, Planner::Prm | Planner::PrmStar | Planner::BitStar)
    }

    /// The id in `cpp/shim.h`.
    pub(crate) fn to_ffi(self) -> i32 {
        match self {
            Planner::RrtConnect => 0,
            Planner::Rrt => 1,
            Planner::RrtStar => 2,
            Planner::Prm => 3,
            Planner::PrmStar => 4,
            Planner::Kpiece1 => 5,
            Planner::Bkpiece1 => 6,
            Planner::Lbkpiece1 => 7,
            Planner::Est => 8,
            Planner::Sbl => 9,
            Planner::BitStar => 10,
        }
    }
}

/// How [`PlanSettings::simplify`] shortens a solution path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum Simplifier {
    /// OMPL's `PathSimplifier::simplify`: shortcutting, B-spline smoothing, a repair pass and
    /// vertex reduction, repeated while they shorten the path and time is left. The default:
    /// the shortest, smoothest paths, usually costing more motion checks than planning did.
    #[default]
    Full,
    /// One pass of `PathSimplifier::reduceVertices` (random vertex pairs joined directly) and
    /// one of `shortcutPath` (random points on the path joined directly): most of the
    /// shortening for a fraction of the checks, no smoothing.
    Shortcut,
}

/// How to plan. `Default` gives RRTConnect, OMPL's default range and resolution, and
/// simplification on.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanSettings {
    /// The planner.
    pub planner: Planner,
    /// Maximum length of one tree extension (the space's distance, see
    /// [`StateSpace`](crate::StateSpace)); `None` keeps OMPL's default (a fifth of the space's
    /// maximum extent for most planners). Ignored by planners without a range
    /// ([`Planner::has_range`]).
    pub range: Option<f64>,
    /// Motion-check resolution as a *fraction* of the space, OMPL's
    /// `setStateValidityCheckingResolution`: a motion is checked at states no further apart
    /// than `resolution_fraction × maximum extent` of the space (see
    /// [`StateSpace`](crate::StateSpace)). In (0, 1) (OMPL rejects 1 and values within machine
    /// epsilon of 0 or 1); OMPL's default is 0.01. An obstacle thinner than that step may be
    /// jumped over. (`kinscene::motion::paths::PathSettings::resolution` is the same spacing
    /// in the space's distance.)
    pub resolution_fraction: f64,
    /// Shorten the solution with OMPL's `PathSimplifier` as [`PlanSettings::simplifier`] says
    /// (the full simplifier for the time left in the budget, at least one pass even when the
    /// planner used the whole budget). Skipped when cancelled. The path's first and last
    /// states are kept.
    pub simplify: bool,
    /// What simplification does when [`PlanSettings::simplify`] is on. Default
    /// [`Simplifier::Full`].
    pub simplifier: Simplifier,
    /// Interpolate the final path to this many states (OMPL's `PathGeometric::interpolate`,
    /// more states on longer segments); a path that already has as many is left alone.
    /// At least 2.
    pub interpolate_to: Option<usize>,
    /// Path-length cost threshold for the optimisation objective (the space's distance).
    /// `None`: no objective is set and each planner uses its default: RRT*, PRM* and BIT* run
    /// until the budget, the others stop at the first solution. `Some(c)`: planning stops as
    /// soon as a path of length ≤ `c` is found (`Some(f64::INFINITY)` stops the optimising
    /// planners at their first solution); this also makes PRM look for such a path.
    pub cost_threshold: Option<f64>,
    /// Iteration budget of the planner: `solve` also ends after this many checks of its
    /// termination condition, which OMPL's planners make once per iteration. Unlike the wall
    /// clock, it ends a seeded search at the same point whatever the machine's load. `None`
    /// (default): the wall clock and the cancel flag only. At least 1.
    pub max_iterations: Option<u64>,
}

impl Default for PlanSettings {
    fn default() -> Self {
        PlanSettings {
            planner: Planner::default(),
            range: None,
            resolution_fraction: 0.01,
            simplify: true,
            simplifier: Simplifier::Full,
            interpolate_to: None,
            cost_threshold: None,
            max_iterations: None,
        }
    }
}

impl PlanSettings {
    /// The default settings with another planner.
    pub fn with_planner(planner: Planner) -> Self {
        PlanSettings {
            planner,
            ..PlanSettings::default()
        }
    }

    /// Checks every field's domain.
    ///
    /// # Errors
    /// [`Error::ResolutionOutOfRange`], or [`Error::InvalidSetting`] for `range` (finite, > 0),
    /// `interpolate_to` (2 ..= u32::MAX) or `cost_threshold` (≥ 0, not NaN).
    pub fn validate(&self) -> Result<(), Error> {
        // OMPL's own check (StateSpace::setLongestValidSegmentFraction).
        if !(self.resolution_fraction >= f64::EPSILON
            && self.resolution_fraction <= 1.0 - f64::EPSILON)
        {
            return Err(Error::ResolutionOutOfRange {
                resolution_fraction: self.resolution_fraction,
            });
        }
        if let Some(range) = self.range {
            if !(range.is_finite() && range > 0.0) {
                return Err(Error::InvalidSetting {
                    name: "range",
                    value: range,
                    requirement: "finite and > 0",
                });
            }
        }
        if let Some(n) = self.interpolate_to {
            if n < 2 || u32::try_from(n).is_err() {
                return Err(Error::InvalidSetting {
                    name: "interpolate_to",
                    value: n as f64,
                    requirement: "in 2 ..= u32::MAX",
                });
            }
        }
        if let Some(c) = self.cost_threshold {
            if c.is_nan() || c < 0.0 {
                return Err(Error::InvalidSetting {
                    name: "cost_threshold",
                    value: c,
                    requirement: ">= 0 (infinity allowed)",
                });
            }
        }
        if self.max_iterations == Some(0) {
            return Err(Error::InvalidSetting {
                name: "max_iterations",
                value: 0.0,
                requirement: ">= 1",
            });
        }
        Ok(())
    }
}

/// When to stop: after `budget` of wall-clock time, or as soon as `cancel` is set, whichever
/// comes first (OMPL's `plannerOrTerminationCondition`). The budget covers planning and
/// simplification.
#[derive(Debug, Clone, Copy)]
pub struct Termination<'a> {
    /// Wall-clock time allowed; must be positive.
    pub budget: Duration,
    /// A flag OMPL polls while planning (typically set by another thread); `None` for none.
    pub cancel: Option<&'a AtomicBool>,
}

impl<'a> Termination<'a> {
    /// Stop after `budget`.
    pub fn after(budget: Duration) -> Self {
        Termination {
            budget,
            cancel: None,
        }
    }

    /// Also stop when `flag` becomes true.
    pub fn with_cancel(self, flag: &'a AtomicBool) -> Self {
        Termination {
            cancel: Some(flag),
            ..self
        }
    }

    /// Checks that the budget is positive.
    ///
    /// # Errors
    /// [`Error::NonPositiveBudget`].
    pub fn validate(&self) -> Result<(), Error> {
        if self.budget.is_zero() {
            return Err(Error::NonPositiveBudget);
        }
        Ok(())
    }
}
