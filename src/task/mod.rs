//! The task layer: which joints to change, in which order (the paper's Π = [θ1 … θT]).
//!
//! Given a [`SceneModel`], a start state Θ0, a [`Goal`] (per-joint target intervals) and a
//! [`Robot`], [`plan`] returns an [`Outcome`]: `Solved(plan)`, `Infeasible(reason)` or
//! `Timeout(best partial plan)`. `Err` is reserved for bad input.
//!
//! # The lattice
//! The search moves on a finite [`Lattice`]: each joint takes values from a small set (start,
//! limits, closed value, goal value, evenly spaced interior values — see [`Lattice`]). An
//! **action** moves one joint to another value of its set, all other joints fixed. Actions
//! on joints outside the goal are allowed: closing an initially open door that blocks the
//! path, opening a door part-way, re-opening at the end.
//!
//! # Feasibility of an action
//! See the predicate in `check/mod.rs`, summarised: (1) the moving part and its descendants sweep
//! without touching any other part or the base, **certified over the whole continuous
//! motion** by [`check_joint_motion`](crate::scene::collision::check_joint_motion) (samples
//! spaced by the scene's motion bound, exact parry distances, adaptive refinement — not the
//! paper's boxes at 6 samples, which miss thin obstacles); (2) some base position in the
//! [manipulation region](ManipulationSettings) of one of the part's handles is free, outside
//! the part's swept footprint, reachable from the robot through the free space of the current
//! state (open doors and drawers occupy cells; the robot disc is inflated by its radius), and
//! still connected to the robot's start afterwards; (3) the [`Refiner`] accepts it.
//!
//! # The search and its cost
//! A best-first search over lattice states with lazy edge evaluation: a move is checked only when
//! it is the next open entry, then re-queued with its true cost; each state is closed once (closed
//! set on the joint values). The order is *focal* (A*ε): every open entry carries a lower bound `f
//! = g + h` on the cost of a plan through it, and the search takes, among the entries with `f` at
//! most `w` times the least open `f` (`w` = [`TaskSettings::heuristic_weight`], default 1), the one
//! with the fewest unmet goal targets (then the lowest `f`). With `w = 1` this is A*. The cost of a
//! plan is `Σ action + actuation·(handle arc length) + travel·(base path length)` ([`CostWeights`],
//! metres). The heuristic has two parts: for each unmet goal joint, one action plus its handle's
//! minimum travel to the target; and, with `travel > 0`, a lower bound on the base travel still
//! ahead — the robot must still reach, for every unmet goal joint, a cell within reach of that
//! part's handle at its target (the larger of the distance to the farthest such set and the
//! distance to the nearest plus a minimum spanning tree over them; see `heuristic.rs`). It never
//! overestimates (admissible) and is consistent except on moves that take a goal joint out of its
//! target (which can raise the travel bound by more than they cost). When a move comes up, its
//! priority is first tightened with the travel to its own manipulation region and on from there (a
//! cheap bound, never above the key of a node the move produces:
//! `proofs/theories/Task/RequeueKey.v`), and the move is checked at once only if that did not raise
//! its key (otherwise it goes back to the open list). The robot's position is part of a search node
//! (it sets the travel cost) but not of the closed set: feasibility does not depend on it (the
//! robot is always in the start's free component), so closing a state on first arrival keeps the
//! search complete, while the cost is minimal only with respect to the base poses of that first
//! arrival, and only among plans that move the joints active when the plan is found (see below):
//! with `travel = 0` and `w = 1`, no cheaper plan moves only those joints, but a cheaper plan may
//! move a joint the search never had to activate (closing a second door instead of the goal door).
//! With `w > 1` the same statements hold with "at most `w` times the minimum" instead of "minimal"
//! (a goal node is taken when its cost is at most `w` times the least open lower bound). The
//! default `w = 1` keeps the cost minimal. With `travel > 0`, A* must close most subsets of the
//! goal joints whose lower bound lies below the plan's cost, and the travel bound stays far
//! below the length of the route (100 parts / 20 goal joints: none of 5 generated instances
//! within 2 s), whereas the focal order with `w = 2` dives toward the goal (the same instances:
//! a plan in 0.1–0.3 s); hence the anytime passes below. Soundness and completeness do not
//! depend on the order (the proofs let the search pop any open entry).
//!
//! # Anytime
//! With `travel > 0` and [`TaskSettings::first_pass_weight`] (default 2) above
//! `heuristic_weight`, the search is *restarting weighted A\**: a first pass with the focal
//! weight `first_pass_weight` finds a plan; it is returned at once when its cost is already at
//! most `heuristic_weight` times the least lower bound still open, otherwise it becomes the
//! *incumbent* and a second pass with `heuristic_weight` starts over (with the active joints
//! and the memo of the first; refiner verdicts are not asked again), dropping every open item
//! whose lower bound reaches the incumbent's cost. The second pass either returns a cheaper
//! plan (within `heuristic_weight` of its least open bound, the usual focal guarantee), or
//! exhausts its items (the incumbent is then minimal over the active joints), or is stopped by
//! the budget or the cancel flag: then the incumbent is returned as `Solved`, not `Timeout`.
//! [`SearchStats::suboptimality`] states the factor every returned plan is proven within (1:
//! minimal, with the caveats above; on a stop, the smaller of the first pass's factor and the
//! incumbent's cost over the least open bound), [`SearchStats::first_plan`] when the first
//! plan was found and [`SearchStats::passes`] how many passes ran. So a budgeted call returns
//! a plan as soon as any plan has been found and the budget ends, and the minimum when the
//! budget allows the proof; an unbudgeted call returns the proven minimum (as a single pass
//! of `heuristic_weight` would; its cost may differ from that pass's only by the first-arrival
//! caveat). The first pass's verdict `Infeasible` is final (completeness does not depend on
//! the order). Without travel the heuristic is close to the cost, a single pass of
//! `heuristic_weight` is usually faster, and it is what runs.
//!
//! **The dive.** Before the passes, with [`TaskSettings::dive`] (default on), a greedy
//! depth-first dive moves the unmet goal joints straight to their targets, the handle nearest
//! the robot first, each move checked by the same predicate, backing up from states where no
//! goal move is feasible, within 16 + 8 move evaluations per goal joint (`greedy.rs`). On a
//! large room where most orders work this is the first plan after a few evaluations per goal
//! joint, where the passes may expand many states before their first goal. Its plan is
//! returned at once when its cost is within `heuristic_weight` of the start's lower bound;
//! otherwise it is the incumbent of the passes (each then keeps only items below its cost).
//! A pass above `heuristic_weight` that exhausts its items below the incumbent proves it
//! within that pass's weight only (it closes states on first arrival in focal order), so the
//! final pass then runs below it as well. The dive moves no joint outside the goal and no joint
//! to an intermediate value, so it is not complete; the passes are, and its plans are made of
//! moves the passes would accept, so verdicts and proofs are those of the passes.
//!
//! The robot's start cell anchors reachability: a move is feasible only if its base pose is
//! connected to the start cell both before and after the move. A move whose part comes to
//! cover the start cell is therefore `Trapped` (the robot could not get back to where it
//! started); give a start pose clear of the parts' sweeps.
//!
//! **Active joints.** The search starts with the goal joints (and their ancestors) movable.
//! Every failed check names the joints whose values it depends on (the bodies in a collision
//! and their ancestors; for a blocked path, the parts whose footprints make the difference).
//! When the restricted lattice is exhausted, the named joints outside the set join it and
//! the search runs again (checks are memoised across rounds). It reports `Infeasible` only
//! when a round names no new joint: then no plan exists in the full lattice, because any
//! plan, with its steps on inactive joints dropped, would pass every check the round made.
//! A round that finds blockers outside the set may also give way to the next round before it
//! is exhausted (after 32·2^(r−1) expansions in round `r`), since it can no longer end
//! `Infeasible`.
//!
//! **Static proofs of infeasibility.** Before the rounds, two cheap tests may return
//! `Infeasible` directly, each sound for the whole lattice: a goal joint whose part has no
//! free base cell within reach of its handle at any lattice value inside the target
//! (whatever its ancestors do; tested when `travel > 0`, with the heuristic's sets), and a pair of bodies placed only by goal joints that collide
//! at every combination of those joints' lattice values inside their targets but not at the
//! start (the last move that changes their relative pose would have to end in that
//! collision, which its certified sweep excludes; see `conflict.rs`). The second is
//! machine-checked (`proofs/theories/Task/Conflict.v`); the first is argued here and taken as
//! a premise by the proofs.
//!
//! **Partial-order reduction.** With [`TaskSettings::reduction`] (default on; only for a
//! [`Refiner::local`] refiner), a state whose goal is unmet pushes only the moves of the joints
//! in the [`Interaction`] component of one unmet goal joint: moves of joints that do not
//! interact commute, so any plan can be reordered to start with such a move
//! (`proofs/theories/Task/Reduction.v`: sound, and complete over all joints). Since the
//! base-pose check reads the start's free component, every joint whose parts can block floor
//! cells interacts with every joint that has a handle: rooms whose doors and drawers open
//! into the navigation band form one component and nothing is pruned; the reduction acts
//! between parts above the band and between joints whose sweeps are apart. With travel it
//! is used only until the first plan (the order changes travel costs).
//!
//! **Memo and parallelism.** Sweep verdicts are memoised by (joint, from, to, the values of
//! the joints that can influence that sweep — found with conservative reach spheres); the
//! sweeps of the next few open moves are checked in parallel (rayon) before they are needed.
//! The occupancy grid of a state is assembled from per-part inflated footprints cached by
//! the part's pose (its own and its ancestors' joint values; equal to inflating the whole
//! state's footprint, as inflation distributes over unions), and the start's free component
//! and the robot's travel distances are explored only as far as a check needs them.
//!
//! # Baselines
//! [`Strategy`] selects the paper's *Random* and *Paper* planners for comparison through the
//! same API.

mod baseline;
mod check;
mod conflict;
mod diagnose;
mod error;
mod goal;
mod greedy;
mod heuristic;
mod interaction;
mod lattice;
mod plan;
mod reach;
mod refine;
mod search;
mod settings;
mod shortfall;
mod start;
mod validate;

pub use diagnose::conflicting_targets;
pub use error::Error;
pub use goal::{
    DEFAULT_ROBOT_RADIUS, DEFAULT_TOLERANCE, Goal, GoalSpec, Interval, Problem, Robot, RobotSpec,
    TargetSpec, TargetTable,
};
pub use interaction::Interaction;
pub use lattice::Lattice;
pub use plan::{
    BodyName, Cause, Failure, Infeasibility, Outcome, Partial, Plan, PlanFile, PlanResult,
    PlanStatus, ReachLimit, ReachShortfall, SearchStats, Step,
};
pub use refine::{MoveContext, NoRefinement, Refinement, Refiner};
pub use settings::{
    ArmReach, CostWeights, LatticeSettings, ManipulationSettings, Strategy, TaskSettings,
};
pub use start::{CollidingPair, colliding_pairs};
pub use validate::{MAX_SWEEP_SAMPLES, Validation, validate};

/// The crate's one termination condition ([`crate::control`]), re-exported where the task
/// search has always taken it.
pub use crate::control::Termination;

use crate::scene::{JointId, SceneData, SceneModel};

/// Plans the order of single-joint changes that takes `problem.start` to `problem.goal`.
///
/// # Errors
/// Only for bad input: [`Error::InvalidSetting`], a robot start outside explicit grid bounds
/// or inside an obstacle ([`Error::InvalidRobotStart`]; a start off automatic bounds grows the
/// grid, see [`SceneModel::covering`]), a start state that does not fit the model, a start
/// state in which bodies collide ([`Error::StartInCollision`], checked before any search).
/// Infeasible goals and exhausted budgets are [`Outcome`]s.
///
/// # Example
/// ```
/// use kinscene::scene::{Handle, Joint, Limits, PartSpec, SceneModelBuilder, Shape};
/// use kinscene::task::{plan, GoalSpec, NoRefinement, Outcome, Problem, TaskSettings, Termination};
/// use nalgebra::{Isometry3, Point3, Vector3};
///
/// // A door hinged at the origin about z, 0.5 m wide, handle near its free edge.
/// let mut b = SceneModelBuilder::new();
/// b.add_part(
///     PartSpec::on_base("door", Joint::revolute("hinge", Point3::origin(), Vector3::z(), Limits::new(0.0, 1.6)))
///         .with_collider(Shape::box_size(Vector3::new(0.5, 0.02, 0.7)), Isometry3::translation(0.25, 0.0, 0.35))
///         .with_handle(Handle::new("door_handle", Point3::new(0.45, -0.03, 0.35), -Vector3::y())),
/// );
/// let model = b.build()?;
/// let spec = GoalSpec::from_toml("[goal]\nhinge = { min = 1.2 }\n[robot]\nbase = [0.8, -0.8, 0.0]")?;
/// let problem = Problem::from_spec(&model, &spec)?;
/// let result = plan(&model, &problem, &TaskSettings::default(), &NoRefinement, &Termination::none())?;
/// let Outcome::Solved(p) = result.outcome else { panic!("expected a plan") };
/// assert_eq!(p.steps.len(), 1);
/// assert!(p.steps[0].to >= 1.2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn plan(
    model: &SceneModel,
    problem: &Problem,
    settings: &TaskSettings,
    refiner: &dyn Refiner,
    termination: &Termination<'_>,
) -> Result<PlanResult, Error> {
    settings.validate()?;
    problem.start.validate(model)?;
    let model = &*model.covering(&problem.robot.start_point())?;
    start::check_start(model, &problem.start, &settings.sweep.collision)?;
    let mut result = match settings.strategy {
        Strategy::Search => search::run(model, problem, settings, refiner, termination),
        Strategy::Random { seed } => baseline::random(model, problem, settings, termination, seed),
        Strategy::Paper { seed } => baseline::paper(model, problem, settings, termination, seed),
    }?;
    // The strategies report any stop as a timeout; say which condition stopped them.
    if let Outcome::Timeout(partial) = result.outcome {
        result.outcome = Outcome::stopped(termination, partial);
    }
    Ok(result)
}

/// The feasibility predicate of the search, exposed for brute-force comparisons and tools:
/// whether one move passes checks 1–3 in a lattice state (no memo).
pub struct Feasibility<'a> {
    checker: check::Checker<'a>,
    caches: check::Caches,
    data: SceneData,
}

/// The verdict of [`Feasibility::check`].
#[derive(Debug, Clone, PartialEq)]
pub enum MoveCheck {
    /// The move is feasible from base pose `base` (x, y, yaw) grasping `handle`.
    Feasible {
        /// Base pose x (m), y (m), yaw (rad).
        base: [f64; 3],
        /// The handle's name.
        handle: String,
    },
    /// The move is infeasible.
    Infeasible(Cause),
}

impl<'a> Feasibility<'a> {
    /// The predicate for `problem` on `model` with `lattice` (build it with
    /// [`Lattice::new`] from the same problem and `settings.lattice`).
    ///
    /// The predicate borrows `model` and cannot grow its grid as [`plan`] does: for a robot
    /// start off the automatic navigation grid, build it on
    /// [`SceneModel::covering`]`(&[start])`, the model [`plan`] searches.
    ///
    /// # Errors
    /// As [`plan`], except that a start off the automatic grid is
    /// [`Error::InvalidRobotStart`] naming the remedy.
    pub fn new(
        model: &'a SceneModel,
        problem: &Problem,
        settings: &'a TaskSettings,
        lattice: &'a Lattice,
    ) -> Result<Self, Error> {
        settings.validate()?;
        problem.start.validate(model)?;
        let start = problem.robot.start_point();
        if let (std::borrow::Cow::Owned(_), Some(p)) = (model.covering(&start)?, start.first()) {
            return Err(Error::InvalidRobotStart {
                x: p.x,
                y: p.y,
                why: "outside the automatic navigation grid (build the predicate on \
                      `SceneModel::covering(&[start])`, the model `plan` searches)"
                    .into(),
            });
        }
        Ok(Feasibility {
            checker: check::Checker::new(model, problem, settings, lattice)?,
            caches: check::Caches::default(),
            data: SceneData::new(model),
        })
    }

    /// Whether moving `joint` to its lattice value number `to` is feasible in the lattice
    /// state `values` (one index per joint into [`Lattice::values`]), the robot anywhere in
    /// the start's free component. Uses [`NoRefinement`].
    ///
    /// # Errors
    /// [`Error::InvalidStep`] for indices out of range.
    pub fn check(
        &mut self,
        values: &[usize],
        joint: JointId,
        to: usize,
    ) -> Result<MoveCheck, Error> {
        let lattice = self.checker.lattice;
        let bad = |message: String| Error::InvalidStep { step: 0, message };
        if values.len() != lattice.len() || joint.index() >= lattice.len() {
            return Err(bad(format!("expected {} joint indices", lattice.len())));
        }
        let mut key = Vec::with_capacity(values.len());
        for (k, &v) in values.iter().enumerate() {
            if v >= lattice.values(JointId(k)).len() {
                return Err(bad(format!("value index {v} out of range for joint {k}")));
            }
            key.push(v as u16);
        }
        if to >= lattice.values(joint).len() {
            return Err(bad(format!("target index {to} out of range")));
        }
        // Memo-free: every call starts from empty caches.
        self.caches = check::Caches::default();
        let verdict = self.checker.evaluate(
            &mut self.caches,
            &mut self.data,
            &key,
            self.checker.start_cell,
            joint,
            to as u16,
            &NoRefinement,
        )?;
        Ok(match verdict {
            check::Verdict::Feasible(c) => MoveCheck::Feasible {
                base: c.base,
                handle: self
                    .checker
                    .model
                    .handle(c.handle)
                    .map(|h| h.name.clone())
                    .unwrap_or_default(),
            },
            check::Verdict::Infeasible { cause, .. } => MoveCheck::Infeasible(cause),
        })
    }
}
