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
use std::sync::{Arc, Mutex};

use super::Error;
use super::goal::Problem;
use super::grid::{Blocked, CellMask, Disc, Distances, Flood, set_cells};
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

/// Occupancy of one state: blocked cells, and the start's free component explored on demand.
pub(crate) struct Occupancy {
    pub blocked: Blocked,
    flood: Mutex<Flood>,
}

impl Occupancy {
    fn new(blocked: Blocked, start_cell: usize) -> Self {
        Occupancy {
            flood: Mutex::new(Flood::new(&blocked, start_cell)),
            blocked,
        }
    }

    /// Whether `cell` is in the start's free component.
    pub fn reaches(&self, cell: usize) -> bool {
        let mut flood = self.flood.lock().unwrap_or_else(|e| e.into_inner());
        flood.reaches(&self.blocked, cell)
    }

    /// The start's free component.
    pub fn component(&self) -> Vec<bool> {
        let mut flood = self.flood.lock().unwrap_or_else(|e| e.into_inner());
        flood.complete(&self.blocked).to_vec()
    }
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
    swept: HashMap<SweepKey, Arc<CellMask>>,
    /// Travel distances from a robot cell in a state, settled on demand.
    travel: HashMap<(Key, usize), Arc<Mutex<Distances>>>,
    /// Inflated footprint of one part at one pose (its joint's and its ancestors' values):
    /// the cells it blocks beyond the inflated base map. Used only when `per_part` is set.
    footprints: HashMap<(usize, Vec<u16>), Arc<Vec<u32>>>,
    /// Build occupancies from cached per-part footprints (the search) instead of
    /// rasterising every part at every state (fresh checks).
    per_part: bool,
    /// The refiner's verdicts, per (state, joint, target): asked once per move.
    refinements: HashMap<(Key, usize, u16), Refinement>,
    /// Refiner calls that vetoed.
    pub vetoes: usize,
}

impl Caches {
    /// Caches for a search: occupancies are assembled from per-part footprints cached by
    /// pose (the same cells as rasterising the whole state: inflation distributes over
    /// unions).
    pub fn for_search() -> Self {
        Caches {
            per_part: true,
            ..Caches::default()
        }
    }
}

/// Entries kept per cache before it is cleared (bounds memory on long searches).
const CACHE_LIMIT: usize = 4096;
/// Occupancies kept (each holds two grid-sized arrays).
const OCCUPANCY_LIMIT: usize = 512;
/// Travel-distance tables kept (each holds about ten bytes per grid cell).
const TRAVEL_LIMIT: usize = 128;

fn bounded<K: std::hash::Hash + Eq, V>(m: &mut HashMap<K, V>) {
    bounded_to(m, CACHE_LIMIT);
}

fn bounded_to<K: std::hash::Hash + Eq, V>(m: &mut HashMap<K, V>, limit: usize) {
    if m.len() >= limit {
        m.clear();
    }
}

/// Offers the entries `rs` at base travel cost `travel` to the running minimum `best` of
/// `travel + aw·actuation`, ties to the lower cell, then to the entry offered first.
fn consider<'r>(
    travel: f64,
    aw: f64,
    rs: &[&'r RegionCell],
    best: &mut Option<(f64, &'r RegionCell)>,
) {
    for r in rs {
        let cost = travel + aw * r.actuation;
        let lower = best.is_none_or(|(c, b)| cost.total_cmp(&c).then(r.cell.cmp(&b.cell)).is_lt());
        if lower {
            *best = Some((cost, r));
        }
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
    /// Ancestors and the joint itself, per part: what the part's pose depends on.
    pose_context: Vec<Vec<JointId>>,
    /// The robot disc of `NavGrid::inflate` on the base grid.
    disc: Disc,
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
        let pose_context = model
            .parts()
            .iter()
            .map(|p| {
                let mut v = ancestors[p.id().index()].clone();
                v.push(p.joint());
                v
            })
            .collect();
        let disc = Disc::new(
            radius,
            base_blocked.resolution(),
            base_blocked.width(),
            base_blocked.height(),
        );
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
            pose_context,
            disc,
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

    /// The base map's grid inflated by the robot radius.
    pub fn base_grid(&self) -> &crate::scene::nav::NavGrid {
        &self.base_blocked
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
        BodyName::of(self.model, b)
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
        Ok(Occupancy::new(blocked, self.start_cell))
    }

    /// The cells part `part` blocks beyond the inflated base map at the state of the last
    /// forward kinematics: its footprint inflated by the robot radius.
    fn part_blocks(&self, data: &SceneData, part: PartId) -> Result<Vec<u32>, Error> {
        let fp = part_footprint(self.model, data, part)?;
        let cells = set_cells(fp.cells());
        let (w, h) = (self.base_blocked.width(), self.base_blocked.height());
        let base = self.base_blocked.cells();
        Ok(self
            .disc
            .inflate(w, h, &cells)
            .cells()
            .filter(|&c| !base[c])
            .map(|c| c as u32)
            .collect())
    }

    /// Occupancy of a lattice state from the per-part footprints cached by pose (equal to
    /// [`Checker::occupancy_of`] with every part).
    fn assembled_occupancy(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Occupancy, Error> {
        let mut blocked = Blocked::from_grid(&self.base_blocked);
        let mut posed = false;
        for p in self.model.parts() {
            if !include(p.id()) {
                continue;
            }
            let cells = self.cached_blocks(caches, data, key, p.id(), &mut posed)?;
            for &c in cells.iter() {
                blocked.cells[c as usize] = true;
            }
        }
        Ok(Occupancy::new(blocked, self.start_cell))
    }

    /// [`Checker::part_blocks`] of `part` at lattice state `key`, cached by the part's pose.
    /// `posed`: whether `data` already holds the forward kinematics of `key` (set when this
    /// call computes it).
    fn cached_blocks(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        part: PartId,
        posed: &mut bool,
    ) -> Result<Arc<Vec<u32>>, Error> {
        let k = part.index();
        let fkey = (k, Self::values_of(key, &self.pose_context[k]));
        if let Some(c) = caches.footprints.get(&fkey) {
            return Ok(c.clone());
        }
        if !*posed {
            forward_kinematics(self.model, data, &self.state_of(key))?;
            *posed = true;
        }
        let c = Arc::new(self.part_blocks(data, part)?);
        bounded_to(&mut caches.footprints, 4 * CACHE_LIMIT);
        caches.footprints.insert(fkey, c.clone());
        Ok(c)
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
        let o = Arc::new(if caches.per_part {
            self.assembled_occupancy(caches, data, key, &|_| true)?
        } else {
            self.occupancy_of(data, &self.state_of(key), true, &|_| true)?
        });
        bounded_to(&mut caches.occupancy, OCCUPANCY_LIMIT);
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
                        d >= m.reach_min
                            && d <= m.reach_max
                            && m.arm.is_none_or(|arm| {
                                arm.admits([c.x, c.y], &p.position, &p.normal, 0.0)
                            })
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
    ) -> Result<CellMask, Error> {
        let a = state.q[joint.index()];
        forward_kinematics(self.model, data, state)?;
        let lipschitz = motion_bound(self.model, data, joint)?.lipschitz();
        let res = self.base_blocked.resolution();
        let n = ((lipschitz * (b - a).abs() / res).ceil() as usize).clamp(1, 1000);
        let spacing = lipschitz * (b - a).abs() / n as f64;
        let (w, h) = (self.base_blocked.width(), self.base_blocked.height());
        let mut covered = vec![false; w * h];
        let mut s = state.clone();
        for k in 0..=n {
            s.q[joint.index()] = a + (b - a) * k as f64 / n as f64;
            forward_kinematics(self.model, data, &s)?;
            for p in self.model.parts()[joint.index()].subtree() {
                if include(p) {
                    for c in set_cells(part_footprint(self.model, data, p)?.cells()) {
                        covered[c as usize] = true;
                    }
                }
            }
        }
        let disc = Disc::new(self.radius + 0.5 * spacing, res, w, h);
        Ok(disc.inflate(w, h, &set_cells(&covered)))
    }

    /// Base-pose check of a move (check 2), with only parts `include` accepts.
    #[allow(clippy::too_many_arguments)]
    fn base_pose_ok(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<bool, Error> {
        Ok(self
            .base_pose_witness(caches, data, key, joint, to, include)?
            .is_some())
    }

    /// Occupancy of lattice state `key` with only the parts `include` accepts (not cached
    /// as a whole; per-part footprints are when `caches.per_part`).
    fn filtered_occupancy(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Occupancy, Error> {
        if caches.per_part {
            self.assembled_occupancy(caches, data, key, include)
        } else {
            self.occupancy_of(data, &self.state_of(key), false, include)
        }
    }

    /// As [`Checker::base_pose_ok`]; when it passes, also the start's free components before
    /// and after the move (the cells whose blocking could make it fail).
    fn base_pose_witness(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Option<Components>, Error> {
        let region = self.cached_region(caches, data, key, joint, to)?;
        if region.is_empty() {
            return Ok(None);
        }
        let before = self.filtered_occupancy(caches, data, key, include)?;
        let subtree = &self.model.parts()[joint.index()];
        let swept = if subtree.subtree().all(include) {
            self.cached_swept(caches, data, key, joint, to)?
        } else {
            let b = self.lattice.values(joint)[to as usize];
            Arc::new(self.swept_cells(data, &self.state_of(key), joint, b, include)?)
        };
        let mut after_key = key.to_vec();
        after_key[joint.index()] = to;
        let after = self.filtered_occupancy(caches, data, &after_key, include)?;
        let ok = region.iter().any(|r| {
            !before.blocked.cells[r.cell]
                && !swept.contains(r.cell)
                && before.reaches(r.cell)
                && after.reaches(r.cell)
        });
        Ok(ok.then_some((before.component(), after.component())))
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
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
        active: &[bool],
    ) -> Result<Vec<JointId>, Error> {
        let Some((comp_before, comp_after)) =
            self.base_pose_witness(caches, data, key, joint, to, &|p| active[p.index()])?
        else {
            return Ok(Vec::new());
        };
        let subtree = &self.model.parts()[joint.index()];
        // A footprint inflated by r touches the components iff the footprint touches the
        // components inflated by r (cell-to-square distances are symmetric on the grid);
        // the inflated footprint's cells beyond the inflated base map are enough, since the
        // components hold no cell of that map.
        let mut named = vec![false; self.model.nq()];
        let mut after_key = key.to_vec();
        after_key[joint.index()] = to;
        for k in [key, &after_key[..]] {
            let mut posed = false;
            for p in self.model.parts() {
                let i = p.id().index();
                if active[i] || named[i] {
                    continue;
                }
                if subtree.subtree_contains(p.id()) {
                    named[i] = true;
                    continue;
                }
                let cells = if caches.per_part {
                    self.cached_blocks(caches, data, k, p.id(), &mut posed)?
                } else {
                    if !posed {
                        forward_kinematics(self.model, data, &self.state_of(k))?;
                        posed = true;
                    }
                    Arc::new(self.part_blocks(data, p.id())?)
                };
                named[i] = cells
                    .iter()
                    .any(|&c| comp_before[c as usize] || comp_after[c as usize]);
            }
        }
        Ok((0..named.len())
            .filter(|&k| named[k])
            .map(JointId)
            .collect())
    }

    /// The manipulation region of moving `joint` to lattice value `to` in state `key`.
    fn cached_region(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<Arc<Vec<RegionCell>>, Error> {
        let ctx = Self::values_of(key, &self.ancestors[joint.index()]);
        let rkey = (joint.index(), key[joint.index()], to, ctx);
        if let Some(r) = caches.regions.get(&rkey) {
            return Ok(r.clone());
        }
        let b = self.lattice.values(joint)[to as usize];
        let r = Arc::new(self.region(data, &self.state_of(key), joint, b)?);
        bounded(&mut caches.regions);
        caches.regions.insert(rkey, r.clone());
        Ok(r)
    }

    /// The swept footprint of moving `joint` to lattice value `to` in state `key`.
    fn cached_swept(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<Arc<CellMask>, Error> {
        let skey = (
            joint.index(),
            key[joint.index()],
            to,
            Self::values_of(key, &self.shape_context[joint.index()]),
        );
        if let Some(s) = caches.swept.get(&skey) {
            return Ok(s.clone());
        }
        let b = self.lattice.values(joint)[to as usize];
        let s = Arc::new(self.swept_cells(data, &self.state_of(key), joint, b, &|_| true)?);
        bounded(&mut caches.swept);
        caches.swept.insert(skey, s.clone());
        Ok(s)
    }

    /// A lower bound on `actuation·(handle travel) + travel·(straight-line distance from the
    /// robot's cell to the base cell) + extra(base cell)` over the cells of the
    /// move's manipulation region that are free in state `key`; `INFINITY` if there are none
    /// (the move is then infeasible) and 0 for a part without handles. Every feasible
    /// choice of [`Checker::evaluate`] is such a cell, and its base travel (a grid path) is
    /// at least the straight-line distance, so with `extra` the heuristic of the state after
    /// the move this bounds the move's cost (without the fixed action cost) plus that
    /// heuristic from below. Cached inputs only: region and occupancy.
    #[allow(clippy::too_many_arguments)]
    pub fn move_bound(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        robot_cell: usize,
        joint: JointId,
        to: u16,
        extra: &dyn Fn(usize) -> f64,
    ) -> Result<f64, Error> {
        if self.model.parts()[joint.index()].handles().is_empty() {
            return Ok(0.0);
        }
        let region = self.cached_region(caches, data, key, joint, to)?;
        let before = self.cached_occupancy(caches, data, key)?;
        let [rx, ry] = self.cell_xy(robot_cell);
        let (tw, aw) = (self.settings.cost.travel, self.settings.cost.actuation);
        let mut best = f64::INFINITY;
        for r in region.iter() {
            if before.blocked.cells[r.cell] {
                continue;
            }
            let [x, y] = self.cell_xy(r.cell);
            let near = aw * r.actuation + tw * (x - rx).hypot(y - ry);
            // Exact shortcut only because `extra(..) >= 0`: a cell whose lower part `near`
            // is already no better cannot improve `best` (`move_bound_le` in RequeueKey.v).
            if near < best {
                best = best.min(near + extra(r.cell));
            }
        }
        Ok(best)
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
        let region = self.cached_region(caches, data, key, joint, to)?;
        if region.is_empty() {
            return Ok(Verdict::Infeasible {
                cause: Cause::NoBasePose,
                blockers: Blockers::Known(Vec::new()),
            });
        }
        let before = self.cached_occupancy(caches, data, key)?;
        let swept = self.cached_swept(caches, data, key, joint, to)?;
        let mut after_key = key.to_vec();
        after_key[joint.index()] = to;
        let after = self.cached_occupancy(caches, data, &after_key)?;
        let res = self.base_blocked.resolution();
        let clear: Vec<&RegionCell> = region
            .iter()
            .filter(|r| !before.blocked.cells[r.cell] && !swept.contains(r.cell))
            .collect();
        // The robot stands in the start's free component of this state (the start cell, or
        // the base cell of the move that led here, which had to be in it), so it can drive
        // to exactly the cells of that component.
        let reachable: Vec<&RegionCell> = clear
            .iter()
            .copied()
            .filter(|r| before.reaches(r.cell))
            .collect();
        let feasible: Vec<&RegionCell> = reachable
            .iter()
            .copied()
            .filter(|r| after.reaches(r.cell))
            .collect();
        if feasible.is_empty() {
            let cause = if clear.is_empty() && region.iter().all(|r| swept.contains(r.cell)) {
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
        }
        // The cheapest: least `travel·(path length) + actuation·(handle travel)`, then the
        // lowest cell index, then the first in region order. Path lengths are settled in
        // increasing order from the robot's cell only as far as that choice needs.
        let tkey = (key.to_vec(), robot_cell);
        let travel = match caches.travel.get(&tkey) {
            Some(t) => t.clone(),
            None => {
                let t = Arc::new(Mutex::new(Distances::new(&before.blocked, robot_cell)));
                bounded_to(&mut caches.travel, TRAVEL_LIMIT);
                caches.travel.insert(tkey, t.clone());
                t
            }
        };
        let mut travel = travel.lock().unwrap_or_else(|e| e.into_inner());
        let (tw, aw) = (self.settings.cost.travel, self.settings.cost.actuation);
        let mut best: Option<(f64, &RegionCell)> = None;
        if tw == 0.0 {
            consider(0.0, aw, &feasible, &mut best);
        } else {
            // Per cell, the region entries that can be chosen there.
            let mut at: HashMap<usize, Vec<&RegionCell>> = HashMap::new();
            for r in &feasible {
                at.entry(r.cell).or_default().push(r);
            }
            let least_actuation = feasible
                .iter()
                .map(|r| aw * r.actuation)
                .fold(f64::INFINITY, f64::min);
            // Cells settled by earlier questions first, then settle on.
            for (cell, rs) in &at {
                if let Some(d) = travel.settled(*cell) {
                    consider(tw * d * res, aw, rs, &mut best);
                }
            }
            while best.is_none_or(|(c, _)| tw * travel.frontier() * res + least_actuation <= c) {
                let Some((cell, d)) = travel.settle_next(&before.blocked) else {
                    break;
                };
                if let Some(rs) = at.get(&cell) {
                    consider(tw * d * res, aw, rs, &mut best);
                }
            }
        }
        let Some((_, best)) = best else {
            // Unreachable: every feasible cell is in the robot's component.
            return Ok(Verdict::Infeasible {
                cause: Cause::PathBlocked {
                    blockers: Vec::new(),
                },
                blockers: Blockers::Deferred,
            });
        };
        let best_travel = travel.to(&before.blocked, best.cell);
        drop(travel);
        let [x, y] = self.cell_xy(best.cell);
        let choice = Choice {
            handle: best.handle,
            cell: best.cell,
            base: [x, y, best.yaw],
            travel: best_travel * res,
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
        caches: &mut Caches,
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
            if self.base_pose_ok(caches, data, key, joint, to, &|q| q != p.id())? {
                out.push(p.name().to_string());
            }
        }
        Ok(out)
    }
}
