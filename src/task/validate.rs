//! The independent plan validator: replays a plan with dense checks and the goal test.
//!
//! [`validate`] shares no code path with the search's feasibility predicate (`check/`,
//! `scene/nav/search.rs`, `reach.rs`, [`check_joint_motion`](crate::scene::collision::check_joint_motion)):
//! it uses only the scene layer's state queries ([`collisions_of`], [`occupancy`],
//! [`part_footprint`], [`grasp_trajectory`], [`max_displacement`]) and its own grid search, so
//! that a bug in the search's memo, keys or certified sweep shows up as a rejected plan.
//! (Underneath, [`collisions_of`] and `check_joint_motion` build their pair lists and exact
//! distances from the same scene-layer primitives; the scene tests check [`collisions_of`]
//! against [`collisions`](crate::scene::collision::collisions) over all pairs.)
//!
//! What is checked, and how it differs from the search: see [`validate`].

use std::collections::VecDeque;

use nalgebra::Point2;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::Error;
use super::goal::Problem;
use super::plan::Step;
use super::settings::TaskSettings;
use crate::scene::collision::{Body, collisions_of};
use crate::scene::motion::{grasp_trajectory, max_displacement};
use crate::scene::nav::{NavGrid, occupancy, part_footprint};
use crate::scene::{HandleId, JointId, PartId, SceneData, SceneModel, State, forward_kinematics};

/// Largest number of collision samples per step of the dense sweep check.
pub const MAX_SWEEP_SAMPLES: usize = 200_000;

/// Largest number of footprint samples per step of the swept-footprint check.
const MAX_FOOTPRINT_SAMPLES: usize = 20_000;

/// Tolerance (rad or m) of the continuity check `from == current value`.
const FROM_TOLERANCE: f64 = 1e-9;

/// The verdict of [`validate`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Validation {
    /// Whether every step passed and the final state satisfies the goal.
    pub valid: bool,
    /// The first failing step (zero-based index) and why; `None` if every step passed.
    pub first_failure: Option<(usize, String)>,
    /// Goal joints whose target the replayed state misses (the final state, or the state
    /// before the first failing step).
    pub unmet: Vec<String>,
    /// Number of joint values checked for collisions over all replayed steps: `n + 1` per
    /// passed step, and up to the first colliding sample for a step that fails its sweep
    /// (samples are checked in parallel; the count does not depend on the scheduling).
    pub checked_samples: usize,
}

/// Replays `steps` from `problem.start` and checks each against the feasibility rules and
/// the final state against the goal, independently of the search.
///
/// # What is checked
/// Replaying from `problem.start`, for each step `i` moving joint `j` from `a` (the current
/// value) to `b`:
/// 1. **input**: `j` names a joint and `b` is finite and within its limits — otherwise the
///    plan does not fit the model and [`validate`] returns [`Error::InvalidStep`] (checked for
///    every step before the replay starts);
/// 2. **continuity**: `|from − a| <= 1e-9`;
/// 3. **sweep** (dense sampling): no checked pair between the moving subtree (the joint's
///    part and its descendants) and another body collides under
///    [`SweepSettings::collision`](crate::scene::collision::SweepSettings::collision)
///    ([`collisions_of`] with the joint's part) at `n + 1` equally spaced values from `a` to
///    `b`, where `n = ⌈L·|b − a| / min_margin⌉`, `L·|b − a|` the scene layer's
///    [`max_displacement`] bound and `min_margin` =
///    [`SweepSettings::min_margin`](crate::scene::collision::SweepSettings::min_margin): no
///    point of the moving subtree travels more than `min_margin` between samples. At most
///    [`MAX_SWEEP_SAMPLES`] per step (beyond the cap the spacing is
///    `L·|b − a| / MAX_SWEEP_SAMPLES`). Pairs inside the subtree are rigid and pairs of
///    fixed bodies do not change, so neither is checked, as in the search. The samples are
///    checked in parallel and the check stops at the first colliding one in order;
/// 4. **base pose**: some handle `h` of the joint's part (the step's `handle` if it names
///    one) and a base position `c` — the step's recorded `base`, or, if none is recorded,
///    any grid cell centre (brute force) — satisfy
///    - the [manipulation region](super::ManipulationSettings): at the `K + 1` grasp points
///      `p_k` of [`grasp_trajectory`], `height_min <= p_k.z <= height_max`, the start normal
///      at most `max_normal_elevation` from horizontal, and
///      `reach_min <= |c − p_k|_xy <= reach_max` (and, with an arm reach set,
///      [`ArmReach::admits`](super::ArmReach::admits) at every `p_k`), and
///      `(c − p_0)_xy · n_0 >= 0`;
///    - `c`'s cell is free in the occupancy of the state before the move
///      ([`occupancy`] inflated by the robot radius) and connected to the robot's start cell
///      through free cells (8-connected, a diagonal step needs both side cells free);
///    - `c`'s cell is outside the part's swept footprint: the union of the subtree's
///      [`part_footprint`]s at values spaced so that no point moves more than half a cell,
///      inflated by `max(radius − resolution·√2, 0)` (see below);
///    - `c`'s cell is free and connected to the start cell in the state after the move;
/// 5. **goal**: after the last step, [`Goal::is_satisfied`](super::Goal::is_satisfied);
///    `unmet` lists the goal joints outside their target.
///
/// The replay stops at the first failing step (2–4): `first_failure` holds its index and the
/// reason, and `unmet` is evaluated in the state before it. The robot's start cell follows
/// the search's rule (the cell of `problem.robot.base`, snapped to the nearest free cell
/// within one radius plus one cell; without a base pose, the free cell nearest the grid
/// centre). Refinement vetoes are not replayed: the validator knows no refiner.
///
/// # How it differs from the search
/// - The search **certifies** each sweep over the continuous interval (Lipschitz bound,
///   exact distances, adaptive refinement); the validator samples **densely** at a fixed
///   spacing, so it can miss a collision narrower than `min_margin` of travel (or than the
///   capped spacing). A certified-free sweep passes every sample (up to the exact distance
///   query's own tolerance, about `5e-8` relative), so a plan the search returns validates;
///   the converse can fail only for sweeps that pass within the resolution of another body,
///   which the search declares `Inconclusive` (and treats as blocked) while dense samples
///   find no contact.
/// - The swept footprint: the search inflates its samples' footprints by
///   `radius + spacing/2` (sound for the continuous sweep). Different samples rasterise to
///   different cells, so the validator's own footprint is not comparable cell by cell; it
///   inflates by `radius − resolution·√2` instead. Every value of the motion lies within half
///   a search spacing of a search sample, and a rasterised cell is within its diagonal of the
///   shadow that marks it, so every cell the validator marks is marked by the search too: a
///   search plan passes (assuming no collider of the subtree enters or leaves the grid's
///   height band or the grid itself during the motion). The price is a tolerance: the
///   validator accepts a base disc that reaches up to `resolution·√2 + resolution/4` into
///   the continuous sweep's shadow.
/// - Occupancy, connectivity and the region are the same rules, recomputed independently.
///
/// # Errors
/// Bad input only: [`Error::InvalidStep`] for a step naming an unknown joint or a `to`
/// value that is not finite or outside the joint's limits; [`Error::InvalidSetting`] and
/// scene errors for invalid settings or a start state that does not fit the model;
/// [`Error::InvalidRobotStart`] as for [`plan`](super::plan). A plan that breaks a rule is
/// `Ok` with `valid == false`.
///
/// # Example
/// ```
/// use kinscene::scene::{Handle, Joint, Limits, PartSpec, SceneModelBuilder, Shape};
/// use kinscene::task::{GoalSpec, Problem, Step, TaskSettings, validate};
/// use nalgebra::{Isometry3, Point3, Vector3};
///
/// let mut b = SceneModelBuilder::new();
/// b.add_part(
///     PartSpec::on_base("door", Joint::revolute("hinge", Point3::origin(), Vector3::z(), Limits::new(0.0, 1.6)))
///         .with_collider(Shape::box_size(Vector3::new(0.5, 0.02, 0.7)), Isometry3::translation(0.25, 0.0, 0.35))
///         .with_handle(Handle::new("door_handle", Point3::new(0.45, -0.03, 0.35), -Vector3::y())),
/// );
/// let model = b.build()?;
/// let spec = GoalSpec::from_toml("[goal]\nhinge = { min = 1.2 }\n[robot]\nbase = [0.8, -0.8, 0.0]")?;
/// let problem = Problem::from_spec(&model, &spec)?;
/// let step = |to: f64| Step {
///     joint: "hinge".into(), from: 0.0, to,
///     handle: None, base: None, travel: 0.0, cost: 0.0,
/// };
/// let settings = TaskSettings::default();
/// assert!(validate(&model, &problem, &[step(1.3)], &settings)?.valid);
/// // Opening only to 1.0 rad leaves the goal unmet.
/// assert_eq!(validate(&model, &problem, &[step(1.0)], &settings)?.unmet, ["hinge"]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn validate(
    model: &SceneModel,
    problem: &Problem,
    steps: &[Step],
    settings: &TaskSettings,
) -> Result<Validation, Error> {
    settings.validate()?;
    problem.start.validate(model)?;
    // 1. Every step must fit the model before anything is replayed.
    let mut joints = Vec::with_capacity(steps.len());
    for (i, s) in steps.iter().enumerate() {
        let bad = |message: String| Error::InvalidStep { step: i, message };
        let joint = model
            .joint_id(&s.joint)
            .map_err(|_| bad(format!("unknown joint {:?}", s.joint)))?;
        let limits = model.joints()[joint.index()].limits;
        if !(s.to.is_finite() && limits.contains(s.to)) {
            return Err(bad(format!(
                "target {} of joint {:?} is outside its limits [{}, {}]",
                s.to, s.joint, limits.lower, limits.upper
            )));
        }
        joints.push(joint);
    }
    let mut replay = Replay::new(model, problem, settings)?;
    let mut state = problem.start.clone();
    let mut first_failure = None;
    for (i, (s, &joint)) in steps.iter().zip(&joints).enumerate() {
        let a = state.q[joint.index()];
        let failure = if (s.from - a).abs() <= FROM_TOLERANCE {
            replay.step(&state, joint, s)?
        } else {
            Some(format!(
                "joint {:?} is at {a} but the step starts from {}",
                s.joint, s.from
            ))
        };
        if let Some(why) = failure {
            first_failure = Some((i, why));
            break;
        }
        state.q[joint.index()] = s.to;
    }
    let unmet: Vec<String> = problem
        .goal
        .targets()
        .iter()
        .filter(|(j, t)| !t.contains(state.q[j.index()]))
        .map(|(j, _)| model.joints()[j.index()].name.clone())
        .collect();
    debug_assert_eq!(
        unmet.is_empty(),
        problem.goal.is_satisfied(&state),
        "unmet agrees with the goal test"
    );
    Ok(Validation {
        valid: first_failure.is_none() && problem.goal.is_satisfied(&state),
        first_failure,
        unmet,
        checked_samples: replay.samples,
    })
}

/// Cells of a grid that the robot centre may not occupy, row-major.
struct Cells {
    width: usize,
    height: usize,
    blocked: Vec<bool>,
}

impl Cells {
    fn of(grid: &NavGrid) -> Self {
        let (width, height) = (grid.width(), grid.height());
        let mut blocked = vec![false; width * height];
        for (i, j) in grid.occupied_cells() {
            blocked[j * width + i] = true;
        }
        Cells {
            width,
            height,
            blocked,
        }
    }

    /// Cells reachable from `from` through free cells: breadth-first, 8 neighbours, a
    /// diagonal step allowed only when both cells it passes between are free.
    fn reachable_from(&self, from: usize) -> Vec<bool> {
        let mut seen = vec![false; self.blocked.len()];
        if self.blocked[from] {
            return seen;
        }
        let free = |i: isize, j: isize| {
            i >= 0
                && j >= 0
                && (i as usize) < self.width
                && (j as usize) < self.height
                && !self.blocked[j as usize * self.width + i as usize]
        };
        seen[from] = true;
        let mut queue = VecDeque::from([from]);
        while let Some(c) = queue.pop_front() {
            let (i, j) = ((c % self.width) as isize, (c / self.width) as isize);
            for dj in -1..=1 {
                for di in -1..=1 {
                    let (ni, nj) = (i + di, j + dj);
                    if (di, dj) == (0, 0) || !free(ni, nj) {
                        continue;
                    }
                    if di != 0 && dj != 0 && !(free(ni, j) && free(i, nj)) {
                        continue;
                    }
                    let n = nj as usize * self.width + ni as usize;
                    if !seen[n] {
                        seen[n] = true;
                        queue.push_back(n);
                    }
                }
            }
        }
        seen
    }
}

/// The robot's start cell: the search's rule, re-implemented.
fn start_cell(model: &SceneModel, data: &mut SceneData, problem: &Problem) -> Result<usize, Error> {
    let radius = problem.robot.radius;
    forward_kinematics(model, data, &problem.start)?;
    let grid = occupancy(model, data)?.inflate(radius)?;
    let cells = Cells::of(&grid);
    let (i, j) = match problem.robot.base {
        Some([x, y, _]) => {
            grid.cell_of(Point2::new(x, y))
                .ok_or_else(|| Error::InvalidRobotStart {
                    x,
                    y,
                    why: "outside the navigation grid".into(),
                })?
        }
        None => (grid.width() / 2, grid.height() / 2),
    };
    let cell = j * cells.width + i;
    if !cells.blocked[cell] {
        return Ok(cell);
    }
    // The free cell nearest to (i, j) in cell units, lowest index on ties.
    let mut nearest: Option<(f64, usize)> = None;
    for (c, _) in cells.blocked.iter().enumerate().filter(|(_, b)| !**b) {
        let d = ((c % cells.width) as f64 - i as f64).hypot((c / cells.width) as f64 - j as f64);
        if nearest.is_none_or(|(best, _)| d < best) {
            nearest = Some((d, c));
        }
    }
    match (nearest, problem.robot.base) {
        (Some((_, c)), Some([x, y, _])) => {
            let p = grid.cell_center(c % cells.width, c / cells.width);
            if (p.x - x).hypot(p.y - y) <= radius + grid.resolution() {
                Ok(c)
            } else {
                Err(Error::InvalidRobotStart {
                    x,
                    y,
                    why: "inside an obstacle (inflated by the robot radius)".into(),
                })
            }
        }
        (Some((_, c)), None) => Ok(c),
        (None, _) => {
            let p = grid.cell_center(i, j);
            Err(Error::InvalidRobotStart {
                x: p.x,
                y: p.y,
                why: "on a grid with no free cell".into(),
            })
        }
    }
}

/// The replay's fixed data and scratch.
struct Replay<'a> {
    model: &'a SceneModel,
    settings: &'a TaskSettings,
    radius: f64,
    start: usize,
    data: SceneData,
    samples: usize,
}

/// The occupancy of one state: blocked cells and the cells connected to the start.
struct Free {
    cells: Cells,
    connected: Vec<bool>,
}

impl<'a> Replay<'a> {
    fn new(
        model: &'a SceneModel,
        problem: &Problem,
        settings: &'a TaskSettings,
    ) -> Result<Self, Error> {
        let mut data = SceneData::new(model);
        let start = start_cell(model, &mut data, problem)?;
        Ok(Replay {
            model,
            settings,
            radius: problem.robot.radius,
            start,
            data,
            samples: 0,
        })
    }

    fn name(&self, body: Body) -> String {
        match body {
            Body::Part(p) => format!("part {:?}", self.model.parts()[p.index()].name()),
            Body::Base(b) => format!("base shape {:?}", self.model.base().shapes[b.index()].name),
        }
    }

    /// Checks one step whose `from` matches the state; `Some(reason)` if it fails.
    fn step(&mut self, state: &State, joint: JointId, s: &Step) -> Result<Option<String>, Error> {
        let (a, b) = (state.q[joint.index()], s.to);
        if let Some(why) = self.sweep(state, joint, a, b)? {
            return Ok(Some(why));
        }
        self.base_pose(state, joint, b, s)
    }

    /// Dense collision samples of the moving subtree from `a` to `b`.
    fn sweep(
        &mut self,
        state: &State,
        joint: JointId,
        a: f64,
        b: f64,
    ) -> Result<Option<String>, Error> {
        let travel = max_displacement(self.model, &mut self.data, state, joint, a, b)?;
        let spacing = self.settings.sweep.min_margin;
        let n = ((travel / spacing).ceil() as usize).clamp(1, MAX_SWEEP_SAMPLES);
        let (model, settings) = (self.model, &self.settings.sweep.collision);
        let part = &model.parts()[joint.index()];
        let (lo, hi) = (a.min(b), a.max(b));
        let value = |k: usize| {
            if k == n {
                b
            } else {
                (a + (b - a) * k as f64 / n as f64).clamp(lo, hi)
            }
        };
        // Samples are independent: check them in parallel, report the first colliding one.
        let first = (0..=n)
            .into_par_iter()
            .map_init(
                || (SceneData::new(model), state.clone()),
                |(data, sample), k| -> Result<Option<(usize, Body, Body)>, Error> {
                    sample.q[joint.index()] = value(k);
                    forward_kinematics(model, data, sample)?;
                    Ok(collisions_of(model, data, settings, part.id())?
                        .first()
                        .map(|c| (k, c.a, c.b)))
                },
            )
            .find_first(|r| !matches!(r, Ok(None)))
            .transpose()?
            .flatten();
        match first {
            None => {
                self.samples += n + 1;
                Ok(None)
            }
            Some((k, m, o)) => {
                self.samples += k + 1;
                Ok(Some(format!(
                    "moving joint {:?} from {a} to {b}: {} collides with {} at {} \
                     (dense sample {k} of {n})",
                    model.joints()[joint.index()].name,
                    self.name(m),
                    self.name(o),
                    value(k)
                )))
            }
        }
    }

    fn free_at(&mut self, state: &State) -> Result<Free, Error> {
        forward_kinematics(self.model, &mut self.data, state)?;
        let cells = Cells::of(&occupancy(self.model, &self.data)?.inflate(self.radius)?);
        let connected = cells.reachable_from(self.start);
        Ok(Free { cells, connected })
    }

    /// The moving subtree's footprints at samples no more than half a cell of travel apart,
    /// inflated by `max(radius − resolution·√2, 0)`.
    fn swept(&mut self, state: &State, joint: JointId, b: f64) -> Result<Cells, Error> {
        let a = state.q[joint.index()];
        let travel = max_displacement(self.model, &mut self.data, state, joint, a, b)?;
        let res = self.model.base_grid().resolution();
        let n = ((travel / (0.5 * res)).ceil() as usize).clamp(1, MAX_FOOTPRINT_SAMPLES);
        let mut grid = self.model.base_grid().cleared();
        let mut sample = state.clone();
        let subtree: Vec<PartId> = self.model.parts()[joint.index()].subtree().collect();
        for k in 0..=n {
            sample.q[joint.index()] = if k == n {
                b
            } else {
                (a + (b - a) * k as f64 / n as f64).clamp(a.min(b), a.max(b))
            };
            forward_kinematics(self.model, &mut self.data, &sample)?;
            for &p in &subtree {
                grid.union_with(&part_footprint(self.model, &self.data, p)?)?;
            }
        }
        let inflation = (self.radius - res * std::f64::consts::SQRT_2).max(0.0);
        Ok(Cells::of(&grid.inflate(inflation)?))
    }

    /// The base-pose rule of the step (recorded pose, or brute force over the grid).
    fn base_pose(
        &mut self,
        state: &State,
        joint: JointId,
        b: f64,
        s: &Step,
    ) -> Result<Option<String>, Error> {
        let model = self.model;
        let part = &model.parts()[joint.index()];
        let handles: Vec<HandleId> = match &s.handle {
            Some(name) => match part.handles().iter().position(|h| &h.name == name) {
                Some(index) => vec![HandleId {
                    part: part.id(),
                    index,
                }],
                None => {
                    return Ok(Some(format!(
                        "handle {name:?} is not a handle of part {:?}",
                        part.name()
                    )));
                }
            },
            None => (0..part.handles().len())
                .map(|index| HandleId {
                    part: part.id(),
                    index,
                })
                .collect(),
        };
        if handles.is_empty() {
            return Ok(Some(format!("part {:?} has no handle", part.name())));
        }
        let a = state.q[joint.index()];
        let m = self.settings.manipulation;
        // Grasp trajectories of the candidate handles; those leaving the height band drop.
        let mut trajectories = Vec::new();
        for &h in &handles {
            let traj = grasp_trajectory(model, &mut self.data, state, h, joint, a, b, m.steps)?;
            if traj
                .iter()
                .all(|p| p.position.z >= m.height_min && p.position.z <= m.height_max)
                && traj[0].normal.z.abs() <= m.max_normal_elevation.sin()
            {
                trajectories.push(traj);
            }
        }
        let in_region = |x: f64, y: f64| {
            trajectories.iter().any(|traj| {
                let (p0, n0) = (traj[0].position, traj[0].normal);
                traj.iter().all(|p| {
                    let d = (x - p.position.x).hypot(y - p.position.y);
                    d >= m.reach_min
                        && d <= m.reach_max
                        && m.arm
                            .is_none_or(|arm| arm.admits([x, y], &p.position, &p.normal, 0.0))
                }) && (x - p0.x) * n0.x + (y - p0.y) * n0.y >= 0.0
            })
        };
        let before = self.free_at(state)?;
        let mut after_state = state.clone();
        after_state.q[joint.index()] = b;
        let after = self.free_at(&after_state)?;
        let swept = self.swept(state, joint, b)?;
        let grid = model.base_grid();
        let conditions = |c: usize| {
            [
                !before.cells.blocked[c],
                before.connected[c],
                !swept.blocked[c],
                !after.cells.blocked[c] && after.connected[c],
            ]
        };
        const WHAT: [&str; 4] = [
            "is occupied before the move (inflated by the robot radius)",
            "is not connected to the robot's start before the move",
            "is inside the part's swept footprint",
            "is cut off from the robot's start after the move",
        ];
        if let Some([x, y, _]) = s.base {
            let Some((i, j)) = grid.cell_of(Point2::new(x, y)) else {
                return Ok(Some(format!("base pose ({x}, {y}) is outside the grid")));
            };
            if !in_region(x, y) {
                return Ok(Some(format!(
                    "base pose ({x}, {y}) is not in the manipulation region of {} for \
                     joint {:?} from {a} to {b}",
                    match &s.handle {
                        Some(h) => format!("handle {h:?}"),
                        None => "any handle".into(),
                    },
                    s.joint
                )));
            }
            let ok = conditions(j * grid.width() + i);
            if let Some(k) = ok.iter().position(|c| !c) {
                return Ok(Some(format!("base pose ({x}, {y}) {}", WHAT[k])));
            }
            return Ok(None);
        }
        // No recorded pose: some cell must satisfy every condition.
        // counts[k]: region cells passing the first k conditions.
        let mut counts = [0usize; 4];
        for j in 0..grid.height() {
            for i in 0..grid.width() {
                let p = grid.cell_center(i, j);
                if !in_region(p.x, p.y) {
                    continue;
                }
                let ok = conditions(j * grid.width() + i);
                let passed = ok.iter().take_while(|c| **c).count();
                if passed == ok.len() {
                    return Ok(None);
                }
                for c in counts.iter_mut().take(passed + 1) {
                    *c += 1;
                }
            }
        }
        Ok(Some(format!(
            "no base pose for joint {:?} from {a} to {b}: {} cells in the manipulation \
             region, {} of them free, {} reachable, {} outside the sweep, 0 connected after \
             the move",
            s.joint, counts[0], counts[1], counts[2], counts[3]
        )))
    }
}
