//! What the hierarchical planner answers: the plan, its outcome with structured reasons, and
//! the statistics.

use std::fmt;
use std::ops::Range;

use super::{StepFailure, StepMotion};
use crate::task::{Infeasibility, Partial, Plan, SearchStats};

/// An executable plan: the task plan and, step by step, its motion.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionPlan {
    /// The order of single-joint changes.
    pub task: Plan,
    /// The motion of every step, in order, one entry per segment: a step executed from one
    /// base pose has one entry, a segmented step one per segment (see [`MotionPlan::segments`]
    /// for which entries refine which step). Without segmented steps `steps[i]` refines
    /// `task.steps[i]`.
    pub steps: Vec<StepMotion>,
}

impl MotionPlan {
    /// Total execution time (s): base and arm motions of all steps (and segments), executed
    /// one after another.
    pub fn duration(&self) -> f64 {
        self.steps.iter().map(|s| s.timing.total()).sum()
    }

    /// Which entries of [`steps`](Self::steps) refine each task step: for `task.steps[i]`, the
    /// range `segments()[i]` of consecutive entries that move its joint from its `from` to its
    /// `to`, each starting where the previous ended (`steps[j + 1].from == steps[j].to`), the
    /// last ending at the task step's `to`. The ranges cover `steps` in order.
    ///
    /// `None` when `steps` does not chain like this (a plan the planner returned always does;
    /// a hand-edited one may not). The values are compared exactly: the planner copies them.
    pub fn segments(&self) -> Option<Vec<Range<usize>>> {
        let mut out = Vec::with_capacity(self.task.steps.len());
        let mut next = 0;
        for task in &self.task.steps {
            let start = next;
            let mut from = task.from;
            loop {
                let s = self.steps.get(next)?;
                if s.joint != task.joint || s.from != from {
                    return None;
                }
                next += 1;
                if s.to == task.to {
                    break;
                }
                from = s.to;
            }
            out.push(start..next);
        }
        (next == self.steps.len()).then_some(out)
    }
}

/// The verdict of the hierarchical planner: [`Solved`](crate::Outcome::Solved) when every step
/// refined, [`Infeasible`](crate::Outcome::Infeasible) when no order of moves refines (the task
/// search ran out of orders once the vetoes were added), or
/// [`Timeout`](crate::Outcome::Timeout) / [`Cancelled`](crate::Outcome::Cancelled) with where
/// the planner was and the vetoes found so far.
pub type MotionOutcome = crate::Outcome<MotionPlan, MotionInfeasibility, Progress>;

/// Why no order of moves refines.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionInfeasibility {
    /// The task search's infeasibility report (after the vetoes).
    pub task: Infeasibility,
    /// The motion failures that vetoed moves, in the order they were found; `task` is about
    /// the orders left after them.
    pub vetoes: Vec<StepFailure>,
}

impl fmt::Display for MotionInfeasibility {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.vetoes.first() {
            // The motion layer's verdict leads: the task search's own explanation is about the
            // orders left after the vetoes.
            Some(first) => write!(
                f,
                "{first}; the motion layer vetoed {} move(s) in all, and then {}",
                self.vetoes.len(),
                self.task
            ),
            None => write!(f, "{}", self.task),
        }
    }
}

/// What the hierarchical planner hands back when its [`Termination`](crate::Termination)
/// stopped it.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    /// Where it stopped.
    pub at: StopPoint,
    /// The motion failures found so far, in the order found.
    pub vetoes: Vec<StepFailure>,
}

/// Where the hierarchical planner was when it stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum StopPoint {
    /// Between a vetoed order and the next task search.
    BetweenTaskPlans,
    /// In the task search, with the plan to the explored state closest to the goal.
    TaskSearch(Partial),
    /// Refining a step of an order: the step, with [`Check::Stopped`](super::Check::Stopped) and the phase it was
    /// in.
    Refining(Box<StepFailure>),
}

impl fmt::Display for StopPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopPoint::BetweenTaskPlans => f.write_str("stopped between task plans"),
            StopPoint::TaskSearch(partial) => write!(f, "stopped in the task search; {partial}"),
            StopPoint::Refining(step) => write!(f, "stopped refining {step}"),
        }
    }
}

impl fmt::Display for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.at)?;
        if let Some(first) = self.vetoes.first() {
            write!(
                f,
                "; the motion layer had vetoed {} move(s), first: {first}",
                self.vetoes.len()
            )?;
        }
        Ok(())
    }
}

/// [`MotionOutcome`] plus statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannerResult {
    /// The verdict.
    pub outcome: MotionOutcome,
    /// Task plans proposed (1 when the first order refined).
    pub task_plans: usize,
    /// Statistics of the last task search.
    pub task_stats: SearchStats,
    /// Time spent in the task search (s).
    pub task_time: f64,
    /// Time spent refining (s).
    pub motion_time: f64,
}

/// How refining one given order ended
/// ([`HierarchicalPlanner::refine`](super::HierarchicalPlanner::refine)):
/// [`Solved`](crate::Outcome::Solved) when every step refined,
/// [`Infeasible`](crate::Outcome::Infeasible) with the step that failed and its check (the steps
/// before it refined), or [`Timeout`](crate::Outcome::Timeout) /
/// [`Cancelled`](crate::Outcome::Cancelled) with the step being refined ([`Check::Stopped`](super::Check::Stopped)).
pub type RefineOutcome = crate::Outcome<MotionPlan, StepFailure, StepFailure>;
