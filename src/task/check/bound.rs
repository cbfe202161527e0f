//! A lower bound on a move's cost from its manipulation region, for the search's priorities.

use super::caches::Caches;
use super::{Checker, Error};
use crate::scene::{JointId, SceneData};

impl Checker<'_> {
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
}
