//! The feasibility predicate of a move (one joint, one lattice value to another, all other
//! joints fixed), shared by the search and by [`Feasibility`](super::Feasibility).
//!
//! A move of joint `j` from `a` to `b` in state Θ (robot in the start's free component) is
//! feasible iff
//! 1. **sweep**: [`check_joint_motion`](crate::scene::collision::check_joint_motion)
//!    certifies the moving subtree free of every other checked body over the closed interval
//!    `[a, b]` (which includes the end state, check 3);
//! 2. **base pose**: some grid cell `c` is in the manipulation region of one of the part's
//!    handles ([`ManipulationSettings`](super::ManipulationSettings)), is free in the
//!    inflated occupancy of Θ, lies in the start's free component of Θ (so the robot can
//!    drive there from wherever it is), is outside the inflated footprint swept by the moving
//!    subtree, and lies in the start's free component of the state after the move (the robot
//!    is not trapped);
//! 3. the refiner accepts it.
//!
//! Inflation is by the robot radius. With
//! [`TaskSettings::boundary_clearance`](super::TaskSettings::boundary_clearance), the cells
//! the inflated base map blocks only by rasterisation are decided in exact geometry, and a
//! freed cell's base pose is its witness point rather than its centre (see `boundary.rs`;
//! travel is still measured between cell centres). The swept footprint is the union of the subtree's
//! footprints at samples spaced so that no point moves more than one cell between them,
//! inflated by the radius plus half that spacing (so it covers the continuous sweep).
//!
//! This file holds the [`Checker`] of one problem (its derived tables and the robot's start
//! cell) and the verdict types; each check and cache has its own file below.

mod blockers;
mod bound;
mod boundary;
mod caches;
mod occupancy;
mod region;
mod shortfall;
mod sweep;
mod swept;
mod verdict;

pub(crate) use caches::Caches;

use super::Error;
use super::goal::Problem;
use super::lattice::Lattice;
use super::plan::Cause;
use super::reach::{ancestor_joints, sweep_contexts};
use super::settings::TaskSettings;
use crate::scene::nav::search::{Blocked, Disc, Flood};
use crate::scene::nav::{NavGrid, occupancy};
use crate::scene::{HandleId, JointId, SceneData, SceneModel, State, forward_kinematics};

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
    /// The cells of the start's free component in the inflated base map (the parts left
    /// out): where a segmented move may put the robot between its runs.
    base_component: Vec<bool>,
    /// The cells of the inflated base map freed by the exact decision at its boundary
    /// ([`TaskSettings::boundary_clearance`]), with their witness poses.
    boundary: boundary::Boundary,
}

impl<'a> Checker<'a> {
    pub fn new(
        model: &'a SceneModel,
        problem: &Problem,
        settings: &'a TaskSettings,
        lattice: &'a Lattice,
    ) -> Result<Self, Error> {
        let radius = problem.robot.radius;
        let mut base_blocked = model.base_grid().inflate(radius)?;
        let boundary = match settings.boundary_clearance {
            Some(clearance) => boundary::Boundary::free(
                model.base_grid(),
                &mut base_blocked,
                &crate::scene::nav::base_shadows(model),
                radius,
                clearance,
            ),
            None => boundary::Boundary::default(),
        };
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
            base_component: Vec::new(),
            boundary,
        };
        checker.start_cell = checker.locate_start(problem)?;
        let free = Blocked::from_grid(&checker.base_blocked);
        checker.base_component = Flood::new(&free, checker.start_cell)
            .complete(&free)
            .to_vec();
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

    /// The base position the robot takes in a cell: the witness of a cell freed at the
    /// grid's boundary, else the centre. Travel is measured between centres
    /// ([`Checker::cell_xy`]).
    pub fn base_xy(&self, cell: usize) -> [f64; 2] {
        match self.boundary.point(cell) {
            Some(p) => [p.x, p.y],
            None => self.cell_xy(cell),
        }
    }

    /// Number of cells freed by the exact decision at the grid's boundary.
    pub fn boundary_cells(&self) -> usize {
        self.boundary.len()
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
}
