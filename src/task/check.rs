//! The feasibility predicate of a move (one joint, one lattice value to another, all other
//! joints fixed), shared by the search and by [`Feasibility`](super::Feasibility).
//!
//! A move of joint `j` from `a` to `b` in state Θ (robot in the start's free component) is
//! feasible iff
//! 1. **sweep**: [`check_joint_motion`] certifies the moving subtree free of every other
//!    checked body over the closed interval `[a, b]` (which includes the end state, check 3);
//! 2. **base pose**: some grid cell `c` is in the manipulation region of one of the part's
//!    handles ([`ManipulationSettings`](super::ManipulationSettings)), is free in the
//!    inflated occupancy of Θ, lies in the start's free component of Θ (so the robot can
//!    drive there from wherever it is), is outside the inflated footprint swept by the moving
//!    subtree, and lies in the start's free component of the state after the move (the robot
//!    is not trapped);
//! 3. the refiner accepts it.
//!
//! Inflation is by the robot radius; the swept footprint is the union of the subtree's
//! footprints at samples spaced so that no point moves more than one cell between them,
//! inflated by the radius plus half that spacing (so it covers the continuous sweep).

use std::collections::HashMap;
use std::sync::Arc;

use super::Error;
use super::goal::Problem;
use super::grid::Blocked;
use super::lattice::Lattice;
use super::plan::{BodyName, Cause};
use super::reach::{ancestor_joints, sweep_contexts};
use super::refine::{MoveContext, Refinement, Refiner};
use super::settings::TaskSettings;
use crate::scene::collision::{Body, Contact, SweepStatus, check_joint_motion};
use crate::scene::joint_axis;
use crate::scene::motion::{grasp_trajectory, motion_bound};
use crate::scene::nav::{NavGrid, footprint, occupancy, part_footprint};
use crate::scene::{
    HandleId, JointId, JointKind, PartId, SceneData, SceneModel, State, forward_kinematics,
};

/// A lattice state: the index of each joint's value in its lattice set.
pub(crate) type Key = Vec<u16>;

/// Memo key of a sweep: joint, from, to, and the values of the joints in its context.
pub(crate) type SweepKey = (usize, u16, u16, Vec<u16>);

/// Which joints' values a failure depends on: `Known` (possibly empty), `Unknown`, or
/// `Deferred`: a failed base-pose check whose blockers
/// ([`Checker::path_failure_blockers`]) are computed only if the round is exhausted (most
/// rounds end with a plan, and the computation costs a relaxed re-check).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Blockers {
    Known(Vec<JointId>),
    Unknown,
    Deferred,
}

/// A sweep's verdict, memoised.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum SweepVerdict {
    Free,
    Blocked {
        cause: Cause,
        blockers: Vec<JointId>,
    },
}

/// How a feasible move is carried out.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Choice {
    pub handle: HandleId,
    pub cell: usize,
    pub base: [f64; 3],
    /// Base travel (m) from the robot's cell.
    pub travel: f64,
    /// Handle travel (m).
    pub actuation: f64,
}

/// The verdict of a whole move.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Verdict {
    Feasible(Choice),
    Infeasible { cause: Cause, blockers: Blockers },
}

/// The start's free components before and after a move.
type Components = (Vec<bool>, Vec<bool>);

/// Occupancy of one state: blocked cells and the start's free component.
pub(crate) struct Occupancy {
    pub blocked: Blocked,
    pub start_component: Vec<bool>,
}

/// A cell of a move's manipulation region, with the handle it serves and the handle travel.
#[derive(Debug, Clone, Copy)]
struct RegionCell {
    cell: usize,
    handle: HandleId,
    actuation: f64,
    yaw: f64,
}

/// Caches owned by one search (not shared across threads).
#[derive(Default)]
pub(crate) struct Caches {
    pub sweeps: HashMap<SweepKey, SweepVerdict>,
    occupancy: HashMap<Key, Arc<Occupancy>>,
    /// Manipulation regions, keyed like sweeps with the joint's ancestors as context.
    regions: HashMap<SweepKey, Arc<Vec<RegionCell>>>,
    /// Swept footprints, keyed like sweeps with ancestors and subtree as context.
    swept: HashMap<SweepKey, Arc<Vec<bool>>>,
    travel: HashMap<(Key, usize), Arc<Vec<f64>>>,
    /// The refiner's verdicts, per (state, joint, target): asked once per move.
    refinements: HashMap<(Key, usize, u16), Refinement>,
    /// Refiner calls that vetoed.
    pub vetoes: usize,
}

/// Entries kept per cache before it is cleared (bounds memory on long searches).
const CACHE_LIMIT: usize = 4096;

fn bounded<K: std::hash::Hash + Eq, V>(m: &mut HashMap<K, V>) {
    if m.len() >= CACHE_LIMIT {
        m.clear();
    }
}

/// Everything fixed for one problem: the model, the lattice, and derived tables.
pub(crate) struct Checker<'a> {
    pub model: &'a SceneModel,
    pub settings: &'a TaskSettings,
    pub lattice: &'a Lattice,
    pub radius: f64,
    pub start_cell: usize,
    base_blocked: NavGrid,
    contexts: Vec<Vec<JointId>>,
    ancestors: Vec<Vec<JointId>>,
    /// Ancestors and subtree of each joint: what its swept footprint depends on.
    shape_context: Vec<Vec<JointId>>,
}

impl<'a> Checker<'a> {
    pub fn new(
        model: &'a SceneModel,
        problem: &Problem,
        settings: &'a TaskSettings,
        lattice: &'a Lattice,
    ) -> Result<Self, Error> {
        let radius = problem.robot.radius;
        let base_blocked = model.base_grid().inflate(radius)?;
        let gap = settings.sweep.collision.contact_distance + 2.0 * settings.sweep.margin + 1e-6;
        let ancestors: Vec<Vec<JointId>> = model
            .parts()
            .iter()
            .map(|p| ancestor_joints(model, p.id()))
            .collect();
        let shape_context = model
            .parts()
            .iter()
            .map(|p| {
                let mut v = ancestors[p.id().index()].clone();
                v.extend(p.subtree().map(|q| q.joint()));
                v
            })
            .collect();
        let mut checker = Checker {
            model,
            settings,
            lattice,
            radius,
            start_cell: 0,
            base_blocked,
            contexts: sweep_contexts(model, gap),
            ancestors,
            shape_context,
        };
        checker.start_cell = checker.locate_start(problem)?;
        Ok(checker)
    }

    fn locate_start(&self, problem: &Problem) -> Result<usize, Error> {
        let mut data = SceneData::new(self.model);
        forward_kinematics(self.model, &mut data, &problem.start)?;
        let grid = occupancy(self.model, &data)?.inflate(self.radius)?;
        let blocked = Blocked::from_grid(&grid);
        let (i, j) = match problem.robot.base {
            Some([x, y, _]) => grid.cell_of(nalgebra::Point2::new(x, y)).ok_or_else(|| {
                Error::InvalidRobotStart {
                    x,
                    y,
                    why: "outside the navigation grid".into(),
                }
            })?,
            None => (grid.width() / 2, grid.height() / 2),
        };
        let cell = j * blocked.width + i;
        if !blocked.cells[cell] {
            return Ok(cell);
        }
        // Snap to the nearest free cell within one robot radius (a start pose touching the
        // inflated border is common); farther means the start is really inside an obstacle.
        let snap = blocked.nearest_free(i, j);
        let res = grid.resolution();
        match (snap, problem.robot.base) {
            (Some(c), Some([x, y, _])) => {
                let p = grid.cell_center(c % blocked.width, c / blocked.width);
                if (p.x - x).hypot(p.y - y) <= self.radius + res {
                    Ok(c)
                } else {
                    Err(Error::InvalidRobotStart {
                        x,
                        y,
                        why: "inside an obstacle (inflated by the robot radius)".into(),
                    })
                }
            }
            (Some(c), None) => Ok(c),
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

    /// The state of a key.
    pub fn state_of(&self, key: &[u16]) -> State {
        let q: Vec<f64> = key
            .iter()
            .enumerate()
            .map(|(k, &i)| self.lattice.values(JointId(k))[i as usize])
            .collect();
        State { q }
    }

    /// The centre of a grid cell.
    pub fn cell_xy(&self, cell: usize) -> [f64; 2] {
        let w = self.base_blocked.width();
        let p = self.base_blocked.cell_center(cell % w, cell / w);
        [p.x, p.y]
    }

    fn values_of(key: &[u16], joints: &[JointId]) -> Vec<u16> {
        joints.iter().map(|j| key[j.index()]).collect()
    }

    /// The memo key of the sweep of `joint` from its value in `key` to value index `to`.
    pub fn sweep_key(&self, key: &[u16], joint: JointId, to: u16) -> SweepKey {
        (
            joint.index(),
            key[joint.index()],
            to,
            Self::values_of(key, &self.contexts[joint.index()]),
        )
    }

    /// Runs the sweep check (no memo; callable from any thread).
    pub fn sweep(
        &self,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<SweepVerdict, Error> {
        let state = self.state_of(key);
        let a = state.q[joint.index()];
        let b = self.lattice.values(joint)[to as usize];
        let out = check_joint_motion(self.model, data, &state, joint, a, b, &self.settings.sweep)?;
        let (contacts, value, conclusive) = match out.status {
            SweepStatus::Free => return Ok(SweepVerdict::Free),
            SweepStatus::Collision { value, contacts } => (contacts, value, true),
            SweepStatus::Inconclusive { value, nearest, .. } => (nearest, value, false),
        };
        let mut blockers = Vec::new();
        for c in &contacts {
            for body in [c.a, c.b] {
                if let Body::Part(p) = body {
                    blockers.push(p.joint());
                }
            }
        }
        let (moving, other) = contacts
            .first()
            .map(|c: &Contact| (self.body_name(c.a), self.body_name(c.b)))
            .unwrap_or_else(|| {
                let n = BodyName::Part(self.model.parts()[joint.index()].name().into());
                (n.clone(), n)
            });
        let cause = if conclusive {
            Cause::Collision {
                moving,
                other,
                value,
            }
        } else {
            Cause::Inconclusive {
                moving,
                other,
                value,
            }
        };
        Ok(SweepVerdict::Blocked { cause, blockers })
    }

    pub fn body_name(&self, b: Body) -> BodyName {
        match b {
            Body::Part(p) => BodyName::Part(self.model.parts()[p.index()].name().into()),
            Body::Base(s) => BodyName::Base(self.model.base().shapes[s.index()].name.clone()),
        }
    }

    /// Occupancy of a state, with every part (`all`) or only the parts `include` accepts.
    fn occupancy_of(
        &self,
        data: &mut SceneData,
        state: &State,
        all: bool,
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Occupancy, Error> {
        forward_kinematics(self.model, data, state)?;
        // Inflation distributes over unions: inflate the parts' footprints alone (few cells)
        // and add the base map's inflated grid, computed once.
        let parts = if all {
            footprint(self.model, data)?
        } else {
            let mut grid = self.model.base_grid().cleared();
            for p in self.model.parts() {
                if include(p.id()) {
                    grid.union_with(&part_footprint(self.model, data, p.id())?)?;
                }
            }
            grid
        };
        let mut blocked = Blocked::from_grid(&self.base_blocked);
        blocked.union_with(parts.inflate(self.radius)?.cells());
        let start_component = blocked.component(self.start_cell);
        Ok(Occupancy {
            blocked,
            start_component,
        })
    }

    fn cached_occupancy(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
    ) -> Result<Arc<Occupancy>, Error> {
        if let Some(o) = caches.occupancy.get(key) {
            return Ok(o.clone());
        }
        let o = Arc::new(self.occupancy_of(data, &self.state_of(key), true, &|_| true)?);
        bounded(&mut caches.occupancy);
        caches.occupancy.insert(key.to_vec(), o.clone());
        Ok(o)
    }

    /// The manipulation region of a move: geometric conditions only (reach, height, front).
    fn region(
        &self,
        data: &mut SceneData,
        state: &State,
        joint: JointId,
        b: f64,
    ) -> Result<Vec<RegionCell>, Error> {
        let m = &self.settings.manipulation;
        let part = &self.model.parts()[joint.index()];
        let a = state.q[joint.index()];
        let grid = &self.base_blocked;
        let (w, h, res) = (grid.width(), grid.height(), grid.resolution());
        let mut out: Vec<RegionCell> = Vec::new();
        for index in 0..part.handles().len() {
            let handle = HandleId {
                part: part.id(),
                index,
            };
            let traj = grasp_trajectory(self.model, data, state, handle, joint, a, b, m.steps)?;
            if traj
                .iter()
                .any(|p| !(m.height_min..=m.height_max).contains(&p.position.z))
                || traj[0].normal.z.abs() > m.max_normal_elevation.sin()
            {
                continue;
            }
            let p0 = traj[0].position;
            let n0 = traj[0].normal;
            // Handle travel: the arc length r·|b − a| (r the grasp point's distance from the
            // axis, constant along the motion) or |b − a| for prismatic joints.
            let actuation = match self.model.joints()[joint.index()].kind {
                JointKind::Prismatic => (b - a).abs(),
                JointKind::Revolute => {
                    // `grasp_trajectory` left `data` at the state with the joint at `a`.
                    let axis = joint_axis(self.model, data, joint)?;
                    axis.distance_to_axis(&p0) * (b - a).abs()
                }
            };
            let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
            for p in &traj {
                x0 = x0.min(p.position.x - m.reach_max);
                y0 = y0.min(p.position.y - m.reach_max);
                x1 = x1.max(p.position.x + m.reach_max);
                y1 = y1.max(p.position.y + m.reach_max);
            }
            let o = grid.origin();
            let idx = |v: f64, o: f64, n: usize| {
                (((v - o) / res).floor().max(0.0) as usize).min(n.saturating_sub(1))
            };
            for j in idx(y0, o.y, h)..=idx(y1, o.y, h) {
                for i in idx(x0, o.x, w)..=idx(x1, o.x, w) {
                    let c = grid.cell_center(i, j);
                    let ok = traj.iter().all(|p| {
                        let d = (c.x - p.position.x).hypot(c.y - p.position.y);
                        d >= m.reach_min && d <= m.reach_max
                    }) && (c.x - p0.x) * n0.x + (c.y - p0.y) * n0.y >= 0.0;
                    if ok && !grid.is_occupied(i, j) {
                        out.push(RegionCell {
                            cell: j * w + i,
                            handle,
                            actuation,
                            yaw: (p0.y - c.y).atan2(p0.x - c.x),
                        });
                    }
                }
            }
        }
        Ok(out)
    }

    /// Cells covered by the moving subtree (only parts `include` accepts) during the motion,
    /// inflated by the robot radius plus half the sample spacing.
    fn swept_cells(
        &self,
        data: &mut SceneData,
        state: &State,
        joint: JointId,
        b: f64,
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Vec<bool>, Error> {
        let a = state.q[joint.index()];
        forward_kinematics(self.model, data, state)?;
        let lipschitz = motion_bound(self.model, data, joint)?.lipschitz();
        let res = self.base_blocked.resolution();
        let n = ((lipschitz * (b - a).abs() / res).ceil() as usize).clamp(1, 1000);
        let spacing = lipschitz * (b - a).abs() / n as f64;
        let mut grid = self.base_blocked.cleared();
        let mut s = state.clone();
        for k in 0..=n {
            s.q[joint.index()] = a + (b - a) * k as f64 / n as f64;
            forward_kinematics(self.model, data, &s)?;
            for p in self.model.parts()[joint.index()].subtree() {
                if include(p) {
                    grid.union_with(&part_footprint(self.model, data, p)?)?;
                }
            }
        }
        Ok(Blocked::from_grid(&grid.inflate(self.radius + 0.5 * spacing)?).cells)
    }

    /// Base-pose check of a move (check 2), with only parts `include` accepts, uncached.
    fn base_pose_ok(
        &self,
        data: &mut SceneData,
        state: &State,
        joint: JointId,
        b: f64,
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<bool, Error> {
        Ok(self
            .base_pose_witness(data, state, joint, b, include)?
            .is_some())
    }

    /// As [`Checker::base_pose_ok`]; when it passes, also the start's free components before
    /// and after the move (the cells whose blocking could make it fail).
    fn base_pose_witness(
        &self,
        data: &mut SceneData,
        state: &State,
        joint: JointId,
        b: f64,
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Option<Components>, Error> {
        let region = self.region(data, state, joint, b)?;
        if region.is_empty() {
            return Ok(None);
        }
        let before = self.occupancy_of(data, state, false, include)?;
        let swept = self.swept_cells(data, state, joint, b, include)?;
        let mut after_state = state.clone();
        after_state.q[joint.index()] = b;
        let after = self.occupancy_of(data, &after_state, false, include)?;
        let ok = region.iter().any(|r| {
            !before.blocked.cells[r.cell]
                && before.start_component[r.cell]
                && !swept[r.cell]
                && after.start_component[r.cell]
        });
        Ok(ok.then_some((before.start_component, after.start_component)))
    }

    /// The inactive joints a failed base-pose check depends on.
    ///
    /// If the check fails even with only the active parts' footprints, no inactive joint
    /// matters (more footprint only blocks more): none. Otherwise: every inactive part of the
    /// moving subtree, and every other inactive part whose footprint, inflated by the robot
    /// radius, before or after the move, touches the start's free component of the relaxed
    /// check (before or after). A part whose inflated footprint misses those components cannot
    /// change them, wherever the other inactive parts are, so the failure is determined by the
    /// active joints and the named ones.
    pub fn path_failure_blockers(
        &self,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
        active: &[bool],
    ) -> Result<Vec<JointId>, Error> {
        let state = &self.state_of(key);
        let b = self.lattice.values(joint)[to as usize];
        let Some((comp_before, comp_after)) =
            self.base_pose_witness(data, state, joint, b, &|p| active[p.index()])?
        else {
            return Ok(Vec::new());
        };
        let subtree = &self.model.parts()[joint.index()];
        // A footprint inflated by r touches the components iff the footprint touches the
        // components inflated by r (cell-to-square distances are symmetric on the grid).
        let mut comps = self.model.base_grid().cleared();
        let w = comps.width();
        for (k, (x, y)) in comp_before.iter().zip(&comp_after).enumerate() {
            if *x || *y {
                comps.set_occupied(k % w, k / w, true);
            }
        }
        let reach = comps.inflate(self.radius)?;
        let mut named = vec![false; self.model.nq()];
        let mut after = state.clone();
        after.q[joint.index()] = b;
        for st in [state, &after] {
            forward_kinematics(self.model, data, st)?;
            for p in self.model.parts() {
                let k = p.id().index();
                if active[k] || named[k] {
                    continue;
                }
                if subtree.subtree_contains(p.id()) {
                    named[k] = true;
                    continue;
                }
                let fp = part_footprint(self.model, data, p.id())?;
                named[k] = fp.cells().iter().zip(reach.cells()).any(|(a, b)| *a && *b);
            }
        }
        Ok((0..named.len())
            .filter(|&k| named[k])
            .map(JointId)
            .collect())
    }

    /// The full verdict of moving `joint` to lattice value `to` in state `key` with the robot
    /// at `robot_cell`. Failures carry the joints they depend on (closed over ancestors by the
    /// caller), or defer that computation ([`Blockers::Deferred`]).
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        robot_cell: usize,
        joint: JointId,
        to: u16,
        refiner: &dyn Refiner,
    ) -> Result<Verdict, Error> {
        let part = &self.model.parts()[joint.index()];
        if part.handles().is_empty() {
            return Ok(Verdict::Infeasible {
                cause: Cause::NoHandle,
                blockers: Blockers::Known(Vec::new()),
            });
        }
        // 1. Sweep (memoised).
        let sk = self.sweep_key(key, joint, to);
        let verdict = match caches.sweeps.get(&sk) {
            Some(v) => v.clone(),
            None => {
                let v = self.sweep(data, key, joint, to)?;
                caches.sweeps.insert(sk, v.clone());
                v
            }
        };
        if let SweepVerdict::Blocked { cause, blockers } = verdict {
            return Ok(Verdict::Infeasible {
                cause,
                blockers: Blockers::Known(blockers),
            });
        }
        // 2. Base pose.
        let state = self.state_of(key);
        let b = self.lattice.values(joint)[to as usize];
        let ctx = Self::values_of(key, &self.ancestors[joint.index()]);
        let rkey = (joint.index(), key[joint.index()], to, ctx);
        let region = match caches.regions.get(&rkey) {
            Some(r) => r.clone(),
            None => {
                let r = Arc::new(self.region(data, &state, joint, b)?);
                bounded(&mut caches.regions);
                caches.regions.insert(rkey, r.clone());
                r
            }
        };
        if region.is_empty() {
            return Ok(Verdict::Infeasible {
                cause: Cause::NoBasePose,
                blockers: Blockers::Known(Vec::new()),
            });
        }
        let before = self.cached_occupancy(caches, data, key)?;
        let skey = (
            joint.index(),
            key[joint.index()],
            to,
            Self::values_of(key, &self.shape_context[joint.index()]),
        );
        let swept = match caches.swept.get(&skey) {
            Some(s) => s.clone(),
            None => {
                let s = Arc::new(self.swept_cells(data, &state, joint, b, &|_| true)?);
                bounded(&mut caches.swept);
                caches.swept.insert(skey, s.clone());
                s
            }
        };
        let mut after_key = key.to_vec();
        after_key[joint.index()] = to;
        let after = self.cached_occupancy(caches, data, &after_key)?;
        let tkey = (key.to_vec(), robot_cell);
        let travel = match caches.travel.get(&tkey) {
            Some(t) => t.clone(),
            None => {
                let t = Arc::new(before.blocked.distances(robot_cell));
                bounded(&mut caches.travel);
                caches.travel.insert(tkey, t.clone());
                t
            }
        };
        let res = self.base_blocked.resolution();
        let clear: Vec<&RegionCell> = region
            .iter()
            .filter(|r| !before.blocked.cells[r.cell] && !swept[r.cell])
            .collect();
        let reachable: Vec<&&RegionCell> = clear
            .iter()
            .filter(|r| travel[r.cell].is_finite())
            .collect();
        let best = reachable
            .iter()
            .filter(|r| after.start_component[r.cell])
            .min_by(|x, y| {
                let cost = |r: &RegionCell| {
                    self.settings.cost.travel * travel[r.cell] * res
                        + self.settings.cost.actuation * r.actuation
                };
                cost(x).total_cmp(&cost(y)).then(x.cell.cmp(&y.cell))
            });
        let Some(best) = best else {
            let cause = if clear.is_empty() && region.iter().all(|r| swept[r.cell]) {
                Cause::NoBasePose
            } else if reachable.is_empty() {
                Cause::PathBlocked {
                    blockers: Vec::new(),
                }
            } else {
                Cause::Trapped
            };
            return Ok(Verdict::Infeasible {
                cause,
                blockers: Blockers::Deferred,
            });
        };
        let [x, y] = self.cell_xy(best.cell);
        let choice = Choice {
            handle: best.handle,
            cell: best.cell,
            base: [x, y, best.yaw],
            travel: travel[best.cell] * res,
            actuation: best.actuation,
        };
        // 3. Refinement.
        let [rx, ry] = self.cell_xy(robot_cell);
        let ctx = MoveContext {
            model: self.model,
            state: &state,
            joint,
            from: state.q[joint.index()],
            to: b,
            handle: choice.handle,
            base: choice.base,
            robot_from: [rx, ry],
        };
        let rkey = (key.to_vec(), joint.index(), to);
        let refinement = match caches.refinements.get(&rkey) {
            Some(r) => r.clone(),
            None => {
                let r = refiner.refine(&ctx);
                if r != Refinement::Accept {
                    caches.vetoes += 1;
                }
                caches.refinements.insert(rkey, r.clone());
                r
            }
        };
        match refinement {
            Refinement::Accept => Ok(Verdict::Feasible(choice)),
            Refinement::Veto { reason, blockers } => Ok(Verdict::Infeasible {
                cause: Cause::Vetoed { reason },
                blockers: match blockers {
                    Some(parts) => Blockers::Known(parts.iter().map(|p| p.joint()).collect()),
                    None => Blockers::Unknown,
                },
            }),
        }
    }

    /// Parts whose footprint alone blocks the base-pose check of a move (for reports).
    pub fn path_blockers(
        &self,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<Vec<String>, Error> {
        let state = self.state_of(key);
        let b = self.lattice.values(joint)[to as usize];
        let mut out = Vec::new();
        let subtree = &self.model.parts()[joint.index()];
        for p in self.model.parts() {
            if subtree.subtree_contains(p.id()) {
                continue;
            }
            forward_kinematics(self.model, data, &state)?;
            let mut after = state.clone();
            after.q[joint.index()] = b;
            let before_fp = part_footprint(self.model, data, p.id())?.occupied_count();
            if before_fp == 0 {
                forward_kinematics(self.model, data, &after)?;
                if part_footprint(self.model, data, p.id())?.occupied_count() == 0 {
                    continue;
                }
            }
            if self.base_pose_ok(data, &state, joint, b, &|q| q != p.id())? {
                out.push(p.name().to_string());
            }
        }
        Ok(out)
    }
}
