//! The manipulation region of a move: the base cells from which the robot can hold one of the
//! part's handles along the whole motion (reach, height, front), cached per move and context.

use std::sync::Arc;

use super::caches::{Caches, bounded};
use super::{Checker, Error};
use crate::scene::motion::grasp_trajectory;
use crate::scene::{HandleId, HandlePose, JointId, JointKind, SceneData, State, joint_axis};

/// A cell of a move's manipulation region, with the handle it serves and the handle travel.
#[derive(Debug, Clone, Copy)]
pub(super) struct RegionCell {
    pub(super) cell: usize,
    pub(super) handle: HandleId,
    pub(super) actuation: f64,
    pub(super) yaw: f64,
    /// The cell covers only a prefix of the motion, and the rest is covered by at most
    /// `segments − 1` more runs from free cells ([`ManipulationSettings::segments`]); it is
    /// exempt from the swept-footprint rule (the robot leaves it before the part is done).
    ///
    /// [`ManipulationSettings::segments`]: crate::task::ManipulationSettings::segments
    pub(super) segmented: bool,
}

impl Checker<'_> {
    /// The manipulation region of moving `joint` to lattice value `to` in state `key`.
    pub(super) fn cached_region(
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
            self.cells_of(&traj, handle, actuation, &mut out);
        }
        Ok(out)
    }

    /// The region cells of one handle's grasp trajectory `traj` (in the height band): the cells
    /// covering it whole and, with segmented moves, those covering a prefix whose rest the
    /// runs cover (see [`ManipulationSettings::segments`]).
    ///
    /// [`ManipulationSettings::segments`]: crate::task::ManipulationSettings::segments
    fn cells_of(
        &self,
        traj: &[HandlePose],
        handle: HandleId,
        actuation: f64,
        out: &mut Vec<RegionCell>,
    ) {
        let m = &self.settings.manipulation;
        let grid = &self.base_blocked;
        let (w, h, res) = (grid.width(), grid.height(), grid.resolution());
        let p0 = traj[0].position;
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for p in traj {
            x0 = x0.min(p.position.x - m.reach_max);
            y0 = y0.min(p.position.y - m.reach_max);
            x1 = x1.max(p.position.x + m.reach_max);
            y1 = y1.max(p.position.y + m.reach_max);
        }
        let o = grid.origin();
        let idx = |v: f64, o: f64, n: usize| {
            (((v - o) / res).floor().max(0.0) as usize).min(n.saturating_sub(1))
        };
        let covers = |c: nalgebra::Point2<f64>, p: &HandlePose| {
            let d = (c.x - p.position.x).hypot(c.y - p.position.y);
            d >= m.reach_min
                && d <= m.reach_max
                && m.arm
                    .is_none_or(|arm| arm.admits([c.x, c.y], &p.position, &p.normal, 0.0))
        };
        let front = |c: nalgebra::Point2<f64>, p: &HandlePose| {
            (c.x - p.position.x) * p.normal.x + (c.y - p.position.y) * p.normal.y >= 0.0
        };
        let last = traj.len() - 1;
        // Segmented moves: per free cell, the run of waypoints it covers from each waypoint
        // it covers on the front side; `ext[s]` the longest over the cells.
        let mut ext: Vec<usize> = (0..=last).collect();
        let mut prefixes: Vec<(usize, usize)> = Vec::new();
        for j in idx(y0, o.y, h)..=idx(y1, o.y, h) {
            for i in idx(x0, o.x, w)..=idx(x1, o.x, w) {
                if grid.is_occupied(i, j) {
                    continue;
                }
                let cell = j * w + i;
                let [cx, cy] = self.base_xy(cell);
                let c = nalgebra::Point2::new(cx, cy);
                let cover: Vec<bool> = traj.iter().map(|p| covers(c, p)).collect();
                if cover.iter().all(|k| *k) && front(c, &traj[0]) {
                    out.push(RegionCell {
                        cell,
                        handle,
                        actuation,
                        yaw: (p0.y - c.y).atan2(p0.x - c.x),
                        segmented: false,
                    });
                    continue;
                }
                if m.segments < 2 {
                    continue;
                }
                let mut run_end = vec![0usize; last + 1];
                for k in (0..=last).rev() {
                    run_end[k] = if k < last && cover[k] && cover[k + 1] {
                        run_end[k + 1]
                    } else {
                        k
                    };
                }
                if !self.base_component[cell] {
                    continue;
                }
                // Runs stand on cells of the rasterised base map only (the rule the validator
                // re-checks); a cell freed at the grid's boundary can still start the move.
                let grid_free = self.boundary.point(cell).is_none();
                for s in 0..last {
                    if grid_free && cover[s] && front(c, &traj[s]) {
                        ext[s] = ext[s].max(run_end[s]);
                    }
                }
                if cover[0] && front(c, &traj[0]) && run_end[0] > 0 {
                    prefixes.push((cell, run_end[0]));
                }
            }
        }
        if !prefixes.is_empty() {
            let need = runs_needed(&ext);
            for (cell, end) in prefixes {
                let rest = (1..=end).map(|t| need[t]).min().unwrap_or(usize::MAX);
                if rest < m.segments {
                    let [cx, cy] = self.base_xy(cell);
                    let c = nalgebra::Point2::new(cx, cy);
                    out.push(RegionCell {
                        cell,
                        handle,
                        actuation,
                        yaw: (p0.y - c.y).atan2(p0.x - c.x),
                        segmented: true,
                    });
                }
            }
        }
    }
}

/// `need[s]`: the fewest runs that cover waypoints `s..=last` when a run from `s` can reach
/// at most waypoint `ext[s]` (consecutive runs share their boundary waypoint, where the robot
/// lets go and grasps again); 0 at `last`, `usize::MAX` when no cover exists.
fn runs_needed(ext: &[usize]) -> Vec<usize> {
    let last = ext.len() - 1;
    let mut need = vec![usize::MAX; ext.len()];
    need[last] = 0;
    for s in (0..last).rev() {
        need[s] = (s + 1..=ext[s])
            .map(|t| need[t])
            .min()
            .unwrap_or(usize::MAX)
            .saturating_add(1);
    }
    need
}

#[cfg(test)]
mod tests {
    use super::runs_needed;

    #[test]
    fn runs_cover_the_waypoints_greedily_and_gaps_are_never_covered() {
        // 0..=4: a run from 0 reaches 2, from 2 reaches 4: two runs; from 1 reaches 3, then
        // 3 reaches 4: two runs.
        assert_eq!(runs_needed(&[2, 3, 4, 4, 4]), vec![2, 2, 1, 1, 0]);
        // Nothing leaves waypoint 1: waypoints 0 and 1 have no cover.
        assert_eq!(runs_needed(&[1, 1, 2])[0], usize::MAX);
        assert_eq!(runs_needed(&[0]), vec![0]);
    }
}
