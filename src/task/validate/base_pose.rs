//! The base-pose rule of a replayed step: the recorded pose, or brute force over the grid.

use nalgebra::Point2;

use super::replay::Replay;
use crate::scene::motion::grasp_trajectory;
use crate::scene::nav::NavGrid;
use crate::scene::{HandleId, JointId, Part, State};
use crate::task::Error;
use crate::task::plan::Step;

impl Replay<'_> {
    /// The base-pose rule of the step (recorded pose, or brute force over the grid).
    pub(super) fn base_pose(
        &mut self,
        state: &State,
        joint: JointId,
        b: f64,
        s: &Step,
    ) -> Result<Option<String>, Error> {
        let model = self.model;
        let part = &model.parts()[joint.index()];
        let handles = match step_handles(part, s) {
            Ok(handles) => handles,
            Err(why) => return Ok(Some(why)),
        };
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
        let runs = if m.segments > 1 {
            Some(self.run_covers(&trajectories)?)
        } else {
            None
        };
        // Segmented moves (see `ManipulationSettings`): a cell covering a prefix of a
        // trajectory from its front, the rest covered by at most `segments − 1` runs.
        let segmented = |x: f64, y: f64| {
            runs.as_ref()
                .is_some_and(|runs| prefix_then_runs(&m, &trajectories, runs, [x, y]))
        };
        let before = self.free_at(state)?;
        let mut after_state = state.clone();
        after_state.q[joint.index()] = b;
        let after = self.free_at(&after_state)?;
        let swept = self.swept(state, joint, b)?;
        let grid = model.base_grid();
        let whole = |c: usize| {
            let p = grid.cell_center(c % grid.width(), c / grid.width());
            in_region(p.x, p.y)
        };
        let conditions = |c: usize| {
            [
                !before.cells.blocked[c],
                before.connected[c],
                // A segmented move's first base position is left before the part is done.
                !swept.blocked[c] || !whole(c),
                !after.cells.blocked[c] && after.connected[c],
            ]
        };
        let in_region = |x: f64, y: f64| in_region(x, y) || segmented(x, y);
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
            let mut ok = conditions(j * grid.width() + i);
            // A pose the grid blocks or cuts off may still be free in exact geometry near
            // the grid's boundary (see `exact`).
            if let Some(clearance) = self.settings.boundary_clearance {
                if !(ok[0] && ok[1]) && self.exact_base(state, &before, [x, y], clearance)? {
                    (ok[0], ok[1]) = (true, true);
                }
                if !ok[3] && self.exact_base(&after_state, &after, [x, y], clearance)? {
                    ok[3] = true;
                }
            }
            if let Some(k) = ok.iter().position(|c| !c) {
                return Ok(Some(format!("base pose ({x}, {y}) {}", WHAT[k])));
            }
            return Ok(None);
        }
        // No recorded pose: some cell must satisfy every condition.
        let Some(counts) = first_cell(grid, &in_region, &conditions) else {
            return Ok(None);
        };
        Ok(Some(format!(
            "no base pose for joint {:?} from {a} to {b}: {} cells in the manipulation \
             region, {} of them free, {} reachable, {} outside the sweep, 0 connected after \
             the move",
            s.joint, counts[0], counts[1], counts[2], counts[3]
        )))
    }
}

/// Whether base position `c` covers a prefix of one of the `trajectories` from its front
/// (at least two waypoints) and `runs` cover the rest within `m.segments − 1` runs.
fn prefix_then_runs(
    m: &crate::task::ManipulationSettings,
    trajectories: &[Vec<crate::scene::HandlePose>],
    runs: &[RunCovers],
    [x, y]: [f64; 2],
) -> bool {
    trajectories.iter().zip(runs).any(|(traj, run)| {
        let (p0, n0) = (traj[0].position, traj[0].normal);
        if (x - p0.x) * n0.x + (y - p0.y) * n0.y < 0.0 {
            return false;
        }
        let prefix = traj
            .iter()
            .take_while(|p| {
                let d = (x - p.position.x).hypot(y - p.position.y);
                d >= m.reach_min
                    && d <= m.reach_max
                    && m.arm
                        .is_none_or(|arm| arm.admits([x, y], &p.position, &p.normal, 0.0))
            })
            .count();
        prefix >= 2 && run.covered_after(prefix - 1, m.segments - 1)
    })
}

/// Which waypoints of one grasp trajectory runs of the segmented rule can cover: per
/// waypoint `t`, the waypoints a run from `t` reaches, over every free cell of the inflated
/// base map connected to the start.
pub(super) struct RunCovers {
    /// `reach[t]`: the last waypoint some cell covers from `t` on (from its front at `t`);
    /// `t` itself when none.
    reach: Vec<usize>,
}

impl RunCovers {
    /// Whether waypoints from some `t` in `1..=from` to the last are covered by at most
    /// `runs` runs (breadth-first over the waypoints reached).
    pub(super) fn covered_after(&self, from: usize, runs: usize) -> bool {
        let last = self.reach.len() - 1;
        let mut at: Vec<bool> = (0..=last).map(|t| t >= 1 && t <= from).collect();
        if at[last] {
            return true;
        }
        for _ in 0..runs {
            let mut next = at.clone();
            for (t, _) in at.iter().enumerate().filter(|(_, a)| **a) {
                next[t..=self.reach[t]].fill(true);
            }
            if next[last] {
                return true;
            }
            at = next;
        }
        false
    }
}

impl Replay<'_> {
    /// The [`RunCovers`] of each trajectory, by brute force over the whole grid.
    fn run_covers(
        &self,
        trajectories: &[Vec<crate::scene::HandlePose>],
    ) -> Result<Vec<RunCovers>, Error> {
        let m = self.settings.manipulation;
        let grid = self.model.base_grid();
        let cells = super::cells::Cells::of(&grid.inflate(self.radius)?);
        let connected = cells.reachable_from(self.start);
        let mut out = Vec::with_capacity(trajectories.len());
        for traj in trajectories {
            let mut reach: Vec<usize> = (0..traj.len()).collect();
            for c in (0..connected.len()).filter(|c| connected[*c]) {
                let q = grid.cell_center(c % grid.width(), c / grid.width());
                let covered: Vec<bool> = traj
                    .iter()
                    .map(|p| {
                        let d = (q.x - p.position.x).hypot(q.y - p.position.y);
                        d >= m.reach_min
                            && d <= m.reach_max
                            && m.arm.is_none_or(|arm| {
                                arm.admits([q.x, q.y], &p.position, &p.normal, 0.0)
                            })
                    })
                    .collect();
                for (t, p) in traj.iter().enumerate() {
                    let facing = (q.x - p.position.x) * p.normal.x
                        + (q.y - p.position.y) * p.normal.y
                        >= 0.0;
                    if covered[t] && facing {
                        let end = t + covered[t..].iter().take_while(|k| **k).count() - 1;
                        reach[t] = reach[t].max(end);
                    }
                }
            }
            out.push(RunCovers { reach });
        }
        Ok(out)
    }
}

/// The handles a step may grasp: the one it names, or every handle of the part; `Err` with the
/// reason when it names another part's handle or the part has none.
fn step_handles(part: &Part, s: &Step) -> Result<Vec<HandleId>, String> {
    let handles: Vec<HandleId> = match &s.handle {
        Some(name) => match part.handles().iter().position(|h| &h.name == name) {
            Some(index) => vec![HandleId {
                part: part.id(),
                index,
            }],
            None => {
                return Err(format!(
                    "handle {name:?} is not a handle of part {:?}",
                    part.name()
                ));
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
        return Err(format!("part {:?} has no handle", part.name()));
    }
    Ok(handles)
}

/// Brute force over the grid: `None` if some cell in the region passes all four
/// `conditions`, else how many region cells passed the first k conditions, k = 0..4.
fn first_cell(
    grid: &NavGrid,
    in_region: &dyn Fn(f64, f64) -> bool,
    conditions: &dyn Fn(usize) -> [bool; 4],
) -> Option<[usize; 4]> {
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
                return None;
            }
            for c in counts.iter_mut().take(passed + 1) {
                *c += 1;
            }
        }
    }
    Some(counts)
}
