//! Settings of the task planner: strategy, lattice, cost, feasibility checks, budget.

use serde::{Deserialize, Serialize};

use super::Error;
use crate::InvalidSetting;
use crate::scene::collision::SweepSettings;

/// Which planner [`plan`](super::plan) runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// The complete lattice search of this crate (lazy A* with an active joint set).
    #[default]
    Search,
    /// The paper's *Random* baseline: one uniformly random order of the goal joints whose
    /// start value misses the target, each moved once from its start value to the nearest
    /// point of its target, accepted iff every step passes the search's feasibility predicate
    /// (certified sweep, base pose and path); otherwise `Infeasible` with the failing step.
    /// `stats.samples` is 1. Moves no other joint and does not consult the refiner.
    Random {
        /// Seed of the order's random generator (SplitMix64); equal seeds give equal orders.
        seed: u64,
    },
    /// The paper's planner ("Scene-Level Planning"): the same moves as [`Strategy::Random`],
    /// in orders drawn at random without repetition, up to [`TaskSettings::max_samples`]
    /// orders. For each goal joint the axis-aligned boxes of its part and descendants are
    /// computed once, at 6 values from its start value towards its target by up to 90°
    /// (revolute) or 15 cm (prismatic), clamped to the limits. An order is rejected if at
    /// some step a box of the moving part overlaps the box of another goal part in its
    /// current configuration (at its target once moved, else at its start) or of a base
    /// shape (pairs in one kinematic chain and allowed pairs exempt), or if the robot's
    /// path is blocked (the search's base-pose and path rule, without its sweep check).
    /// First accepted order: `Solved`; limit or termination first: `Timeout` with the
    /// longest accepted prefix; every order rejected: `Infeasible`. `stats.samples` counts
    /// the orders tried. By design it misses collisions between its samples and beyond
    /// 90° / 15 cm, and ignores parts outside the goal. Does not consult the refiner.
    Paper {
        /// Seed of the order sampler (SplitMix64).
        seed: u64,
    },
}

/// Which joint values the search may use (the lattice L = L_1 × … × L_n).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LatticeSettings {
    /// Interior values per joint, evenly spaced strictly between the limits (`k` values at
    /// `lower + i·(upper − lower)/(k + 1)`, `i = 1..=k`), for part-way openings. Default 1.
    pub interior_values: usize,
}

impl Default for LatticeSettings {
    fn default() -> Self {
        LatticeSettings { interior_values: 1 }
    }
}

/// Weights of the plan cost (all terms in metres).
///
/// The cost of a plan is the sum over its steps of
/// `action + actuation · (handle travel) + travel · (base travel)`, where handle travel is
/// the arc length the grasp point moves (`r·|Δφ|` for revolute, `|Δd|` for prismatic, `r`
/// the handle's distance from the axis) and base travel the length of the grid path the robot
/// drives to the step's base pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CostWeights {
    /// Fixed cost per action (m), `>= 0`. Default 0.5: one extra action costs as much as
    /// half a metre of driving.
    pub action: f64,
    /// Weight of the handle travel, `>= 0`. Default 1.
    pub actuation: f64,
    /// Weight of the base travel, `>= 0`. Default 1.
    pub travel: f64,
}

impl Default for CostWeights {
    fn default() -> Self {
        CostWeights {
            action: 0.5,
            actuation: 1.0,
            travel: 1.0,
        }
    }
}

/// Where the robot base may stand to operate a part: the *manipulation region*.
///
/// A base position `c` (centre of a free grid cell, or the witness point of a cell freed at the
/// grid's boundary, see [`TaskSettings::boundary_clearance`]) is admissible for moving joint `j` from
/// `a` to `b` with handle `h` iff, for each of the `steps + 1` grasp points `p_k` of the
/// Eq. (3)–(5) trajectory: `reach_min <= |c − p_k|_xy <= reach_max` and
/// `height_min <= p_k.z <= height_max`; the handle's outward normal at the start `n_0` is at
/// most `max_normal_elevation` above or below horizontal (`|n_0.z| <= sin`, a side grasp);
/// and `c` lies on the outward side of the handle at the start, `(c − p_0)_xy · n_0 >= 0`;
/// with an [`arm`](Self::arm) reach, the arm can span every `p_k` from `c` too.
///
/// **Segments.** With [`segments`](Self::segments) `S >= 2` the robot may let go and grasp again
/// from another base position during one move, so a cell that covers only a prefix of the motion is
/// admissible too: `c` covers `p_0..=p_e` (each within the annulus and, with an arm reach,
/// spanned), lies on the outward side at `p_0`, and the remaining waypoints `p_e..` (or from any
/// `p_t`, `1 <= t <= e`) are covered by at most `S − 1` further *runs*: consecutive runs share
/// their boundary waypoint (the regrasp), and each run is a stretch of waypoints `p_s..=p_t`
/// covered from one cell that is free in the base map (inflated by the robot radius) and connected
/// there to the robot's start, and on the outward side at `p_s`. The rule is a relaxation of what
/// the motion layer can do (it ignores the parts and the paths between the runs' cells). Such a
/// cell is exempt from the swept-footprint rule of the search (the robot leaves it before the part
/// is done); the move's base cell, the robot's position for the next move's travel, is `c`, and it
/// must still be connected to the start after the move.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ManipulationSettings {
    /// Smallest horizontal base-to-grasp distance (m). Default 0.25.
    pub reach_min: f64,
    /// Largest horizontal base-to-grasp distance (m). Default 0.9.
    pub reach_max: f64,
    /// Lowest grasp height (m). Default 0.0.
    pub height_min: f64,
    /// Highest grasp height (m). Default 2.0.
    pub height_max: f64,
    /// Largest angle (rad) between the handle's outward normal and the horizontal plane at the
    /// start of the motion, in `[0, π/2]`: handles facing up or down more steeply cannot be
    /// grasped from the side. Default 1.0 (57°).
    pub max_normal_elevation: f64,
    /// Steps K of the grasp trajectory checked against the reach limits, `1..=1000`.
    /// Default 16.
    pub steps: usize,
    /// The robot's arm reach: with it, a base cell is admissible only if, at every grasp
    /// point, the arm can span the distance from its shoulder to its wrist
    /// ([`ArmReach::span`] `<= radius`). `None` (default): the annulus and height band alone.
    /// The hierarchical planner fills it from its robot when it is `None`.
    #[serde(default)]
    pub arm: Option<ArmReach>,
    /// The most base positions one move may use (see **Segments** above), `1..=1000`.
    /// Default 1 (one base position per move, the paper's rule). The hierarchical planner
    /// sets it to its `max_segments`.
    #[serde(default = "one_segment")]
    pub segments: usize,
}

fn one_segment() -> usize {
    1
}

/// A conservative bound on where an arm can hold a handle, from the robot's geometry: the
/// tool's origin on the grasp point with its approach axis (+z) along the handle's inward
/// normal and any rotation about it (the placement's side grasp).
///
/// The *wrist point* is a point fixed in the tool frame (a joint origin, e.g. the last
/// joint's). Its distance from the *shoulder* (a joint origin near the arm's base) is at most
/// [`radius`](Self::radius) whatever the joints do (each joint origin is a fixed distance
/// from the previous one); see `kinscene::planner::arm_reach` for how the planner
/// derives them from a robot model. The wrist point is
/// fixed in the tool frame: `wrist_out` out along the handle's normal from the grasp point
/// (the tool's offset behind its origin, plus the grasp's standoff) and `wrist_radius` off
/// the approach axis, in a direction set by the free rotation. Holding grasp point `p`
/// (outward normal `n`) from a base at `c` therefore needs the arm to span at least
/// [`span`](Self::span), and a cell whose span exceeds the radius cannot be a base pose
/// for it: a necessary condition, never ruling out a pose the arm could reach.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ArmReach {
    /// The shoulder in the base frame (m; x forward, y left, z up from the floor).
    pub shoulder: [f64; 3],
    /// Horizontal distance (m) within which the shoulder stays of `shoulder` (a shoulder
    /// point carried round a vertical first axis).
    #[serde(default)]
    pub shoulder_radius: f64,
    /// Upper bound (m) on the shoulder-to-wrist distance over all configurations.
    pub radius: f64,
    /// Least and largest distance (m) of the wrist point's projection on the approach axis
    /// out from the grasp point along the outward normal (the standoff's range).
    pub wrist_out: [f64; 2],
    /// Distance (m) of the wrist point from the approach axis, plus any slack the bound's
    /// derivation needs (subtracted from every span).
    pub wrist_radius: f64,
}

impl ArmReach {
    /// A lower bound (m) on the shoulder-to-wrist distance needed to hold grasp point `p` with
    /// outward unit normal `n` from a base centred at `c` (x, y), whatever the base's yaw:
    /// the shoulder lies within `|shoulder_xy| + shoulder_radius` of `c` at the shoulder's
    /// height, the wrist within `wrist_radius` of the segment `p + t·n`, `t` in `wrist_out`.
    pub fn span(&self, c: [f64; 2], p: &nalgebra::Point3<f64>, n: &nalgebra::Vector3<f64>) -> f64 {
        let w = p + n * self.wrist_out[0];
        let offset = self.shoulder[0].hypot(self.shoulder[1]) + self.shoulder_radius;
        let horizontal = ((w.x - c[0]).hypot(w.y - c[1]) - offset).max(0.0);
        let vertical = w.z - self.shoulder[2];
        // Moving along the segment or off the axis changes the distance by at most as much.
        horizontal.hypot(vertical) - (self.wrist_out[1] - self.wrist_out[0]) - self.wrist_radius
    }

    /// Whether the arm may hold `p` (normal `n`) from a base at `c`: [`span`](Self::span) `<=
    /// radius + slack`.
    pub fn admits(
        &self,
        c: [f64; 2],
        p: &nalgebra::Point3<f64>,
        n: &nalgebra::Vector3<f64>,
        slack: f64,
    ) -> bool {
        self.span(c, p, n) <= self.radius + slack
    }

    /// Checks the fields: finite, `radius > 0`, `wrist_out[0] <= wrist_out[1]`,
    /// `wrist_radius >= 0`.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |field: &str, value: f64, requirement: &str| {
            Error::from(InvalidSetting::new(
                format!("manipulation.arm.{field}"),
                value,
                requirement,
            ))
        };
        for (k, v) in self.shoulder.iter().enumerate() {
            if !v.is_finite() {
                return Err(bad(
                    ["shoulder[0]", "shoulder[1]", "shoulder[2]"][k],
                    *v,
                    "finite",
                ));
            }
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(bad("radius", self.radius, "finite and > 0"));
        }
        let [lo, hi] = self.wrist_out;
        if !lo.is_finite() {
            return Err(bad("wrist_out[0]", lo, "finite"));
        }
        if !(hi.is_finite() && hi >= lo) {
            return Err(bad("wrist_out[1]", hi, "finite and at least wrist_out[0]"));
        }
        if !(self.wrist_radius.is_finite() && self.wrist_radius >= 0.0) {
            return Err(bad("wrist_radius", self.wrist_radius, "finite and >= 0"));
        }
        if !(self.shoulder_radius.is_finite() && self.shoulder_radius >= 0.0) {
            return Err(bad(
                "shoulder_radius",
                self.shoulder_radius,
                "finite and >= 0",
            ));
        }
        Ok(())
    }
}

impl Default for ManipulationSettings {
    fn default() -> Self {
        ManipulationSettings {
            reach_min: 0.25,
            reach_max: 0.9,
            height_min: 0.0,
            height_max: 2.0,
            max_normal_elevation: 1.0,
            steps: 16,
            arm: None,
            segments: 1,
        }
    }
}

/// Settings of [`plan`](super::plan).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskSettings {
    /// Which planner.
    pub strategy: Strategy,
    /// The lattice of joint values.
    pub lattice: LatticeSettings,
    /// The cost.
    pub cost: CostWeights,
    /// The continuous-sound sweep check (margin, resolution, collision predicate).
    pub sweep: SweepSettings,
    /// The manipulation region.
    pub manipulation: ManipulationSettings,
    /// Edges evaluated concurrently per batch (0: one per available thread). Default 0.
    pub parallelism: usize,
    /// Candidate orders the [`Strategy::Paper`] sampler draws before giving up. Default 10 000.
    pub max_samples: usize,
    /// Suboptimality bound `w >= 1` of the search's focal order (A*ε): the search pops, among
    /// the open items whose lower bound `f = g + h` is at most `w` times the least open `f`,
    /// the one with the fewest unmet goal targets. A returned plan then costs at most `w`
    /// times the minimum the search guarantees with `w = 1` (the caveats of the
    /// [module docs](super#the-search-and-its-cost): over the active joints, exact with
    /// `travel = 0`). 1 (default) is A* (ties broken by progress) and keeps the cost minimal.
    /// With `travel > 0` the base-travel term makes A* explore a large share of the subsets
    /// of goal joints, since its lower bound stays far below the route length (100 parts / 20
    /// goal joints: none of 5 generated instances within 2 s); 2 dives toward the goal and
    /// keeps the bound (the same instances: 0.1–0.3 s each) — the setting for large rooms when
    /// a plan within twice the minimum cost is good enough. With `travel = 0`, 1 is often
    /// faster (the same instances: 5/5 within 2 s with 1, 3/5 with 2). Completeness and
    /// soundness do not depend on it.
    pub heuristic_weight: f64,
    /// Weight of the anytime search's first pass (`>= 1`). When it is above
    /// [`heuristic_weight`](Self::heuristic_weight), the search first runs its focal order
    /// with this weight; a plan it finds is returned at once if it is already proven within
    /// `heuristic_weight` of the least open bound, otherwise it becomes the incumbent and a
    /// second pass with `heuristic_weight` looks only for cheaper plans (open items whose
    /// bound reaches the incumbent's cost are dropped). When the budget or the cancel flag
    /// stops the second pass, the incumbent is returned as `Solved`, with the factor it is
    /// proven within in [`SearchStats::suboptimality`](super::SearchStats::suboptimality)
    /// (restarting weighted A*; Richter, Thayer and Ruml 2010). Default 2: a first plan
    /// quickly where the base-travel bound is weak (large rooms), the minimum when the budget
    /// allows the proof. Set it to `heuristic_weight` for a single pass. Used only when
    /// `cost.travel > 0`: without base travel the heuristic is close to the cost and one pass
    /// of `heuristic_weight` is usually faster (100 parts / 20 goal joints, planted, travel
    /// 0: 3 of 5 instances solved within 2 s with a first pass at 2, 5 of 5 with one pass at
    /// 1; with travel: 5 of 5 first plans within 0.2 s with the first pass, none within 2 s
    /// with one pass at 1).
    #[serde(default = "default_first_pass_weight")]
    pub first_pass_weight: f64,
    /// Whether the search starts with its greedy dive (default true): goal joints moved
    /// straight to their targets, the nearest handle first, each move checked by the search's
    /// own predicate, backing up from dead states, within a small number of move evaluations
    /// (16 plus 8 per goal joint). A plan it finds is returned at once if it is proven within
    /// `heuristic_weight` of the start's lower bound, else it is the incumbent of the anytime
    /// passes, which then only look for cheaper plans. On rooms where most orders work it
    /// gives the first plan in a few evaluations per goal joint; it never changes the verdict
    /// (the lattice search still proves infeasibility and minimality).
    #[serde(default = "default_dive")]
    pub dive: bool,
    /// Whether the search prunes interchangeable move orders (default true): in a state whose
    /// goal is unmet it pushes only the moves of the joints that interact (through sweeps,
    /// regions, footprints; see [`Interaction`](super::Interaction)) with one unmet goal
    /// joint, the one whose set of interacting joints is smallest. Sound and complete (every
    /// plan is made of moves the unreduced search accepts; a goal reachable without the
    /// reduction is reachable with it: `proofs/theories/Task/Reduction.v`), for refiners that
    /// are [`Refiner::local`](super::Refiner::local); otherwise it is off. It reorders plans
    /// without changing their moves, which keeps costs only when they do not depend on where
    /// the robot stands: with `cost.travel > 0` it is used only until the first plan (whose
    /// proven factor is then its cost over the start's lower bound), and the passes that
    /// improve on a plan run without it. [`SearchStats::pruned`](super::SearchStats::pruned)
    /// counts the moves it did not push.
    #[serde(default = "default_reduction")]
    pub reduction: bool,
    /// The exact decision at the navigation grid's boundary: `Some(clearance)` (m, finite,
    /// `>= 0`) frees a cell that the inflated base map blocks only by rasterisation when a
    /// point in it keeps the robot's disc at least `clearance` from every in-band base shape
    /// (exact 2-D distances to the shapes' shadows); that point is the base pose the plan
    /// records for the cell, and the straight moves to its side neighbours keep the disc off
    /// every shape. Parts stay conservative near such cells (see the module docs of the
    /// check). `None`: the grid alone. Default `Some(0.01)`: a gap 2 cm wider than the
    /// robot's disc is open, which the 5 cm grid can close.
    #[serde(default = "default_boundary_clearance")]
    pub boundary_clearance: Option<f64>,
}

fn default_boundary_clearance() -> Option<f64> {
    Some(0.01)
}

fn default_first_pass_weight() -> f64 {
    2.0
}

fn default_dive() -> bool {
    true
}

fn default_reduction() -> bool {
    true
}

impl Default for TaskSettings {
    fn default() -> Self {
        TaskSettings {
            strategy: Strategy::Search,
            lattice: LatticeSettings::default(),
            cost: CostWeights::default(),
            sweep: SweepSettings::default(),
            manipulation: ManipulationSettings::default(),
            parallelism: 0,
            max_samples: 10_000,
            heuristic_weight: 1.0,
            first_pass_weight: default_first_pass_weight(),
            dive: default_dive(),
            reduction: default_reduction(),
            boundary_clearance: default_boundary_clearance(),
        }
    }
}

impl TaskSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] naming the first field out of range; scene errors for
    /// invalid sweep settings.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |field: &str, value: f64, requirement: &str| {
            Error::from(InvalidSetting::new(field, value, requirement))
        };
        self.sweep.validate()?;
        if !(self.heuristic_weight.is_finite() && self.heuristic_weight >= 1.0) {
            return Err(bad(
                "heuristic_weight",
                self.heuristic_weight,
                "finite and at least 1",
            ));
        }
        if !(self.first_pass_weight.is_finite() && self.first_pass_weight >= 1.0) {
            return Err(bad(
                "first_pass_weight",
                self.first_pass_weight,
                "finite and at least 1",
            ));
        }
        if let Some(c) = self.boundary_clearance
            && !(c.is_finite() && c >= 0.0)
        {
            return Err(bad("boundary_clearance", c, "finite and >= 0"));
        }
        if self.lattice.interior_values > 64 {
            return Err(bad(
                "lattice.interior_values",
                self.lattice.interior_values as f64,
                "at most 64",
            ));
        }
        for (what, v) in [
            ("cost.action", self.cost.action),
            ("cost.actuation", self.cost.actuation),
            ("cost.travel", self.cost.travel),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(bad(what, v, "finite and >= 0"));
            }
        }
        let m = &self.manipulation;
        if !(m.reach_min.is_finite() && m.reach_min >= 0.0) {
            return Err(bad(
                "manipulation.reach_min",
                m.reach_min,
                "finite and >= 0",
            ));
        }
        if !(m.reach_max.is_finite() && m.reach_max > m.reach_min) {
            return Err(bad(
                "manipulation.reach_max",
                m.reach_max,
                "finite and greater than manipulation.reach_min",
            ));
        }
        if !(m.height_min.is_finite() && m.height_max.is_finite() && m.height_max > m.height_min) {
            return Err(bad(
                "manipulation.height_max",
                m.height_max,
                "finite and greater than manipulation.height_min, itself finite",
            ));
        }
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&m.max_normal_elevation) {
            return Err(bad(
                "manipulation.max_normal_elevation",
                m.max_normal_elevation,
                "in [0, π/2]",
            ));
        }
        if !(1..=1000).contains(&m.steps) {
            return Err(bad(
                "manipulation.steps",
                m.steps as f64,
                "between 1 and 1000",
            ));
        }
        if !(1..=1000).contains(&m.segments) {
            return Err(bad(
                "manipulation.segments",
                m.segments as f64,
                "between 1 and 1000",
            ));
        }
        if let Some(arm) = &m.arm {
            arm.validate()?;
        }
        Ok(())
    }
}
