//! The verdict of a whole move: check 1 (memoised sweep), check 2 (the cheapest base pose)
//! and check 3 (the refiner, asked once per move).

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::caches::{Caches, TRAVEL_LIMIT, bounded_to};
use super::region::RegionCell;
use super::{Blockers, Checker, Choice, Error, SweepVerdict, Verdict};
use crate::scene::nav::search::{Blocked, Distances};
use crate::scene::{JointId, SceneData};
use crate::task::plan::Cause;
use crate::task::refine::{MoveContext, Refinement, Refiner};

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

impl Checker<'_> {
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
        if let SweepVerdict::Blocked { cause, blockers } =
            self.cached_sweep(caches, data, key, joint, to)?
        {
            return Ok(Verdict::Infeasible {
                cause,
                blockers: Blockers::Known(blockers),
            });
        }
        // 2. Base pose.
        let choice = match self.base_pose(caches, data, key, robot_cell, joint, to)? {
            Verdict::Feasible(choice) => choice,
            infeasible => return Ok(infeasible),
        };
        // 3. Refinement.
        Ok(self.refinement(caches, key, robot_cell, joint, to, choice, refiner))
    }

    /// Check 2 of a move: the cheapest cell of its manipulation region that is free in state
    /// `key`, outside the swept footprint, and in the start's free component both before and
    /// after the move (infeasible with deferred blockers when there is none).
    fn base_pose(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        robot_cell: usize,
        joint: JointId,
        to: u16,
    ) -> Result<Verdict, Error> {
        let region = self.cached_region(caches, data, key, joint, to)?;
        if region.is_empty() {
            return Ok(Verdict::Infeasible {
                cause: Cause::NoBasePose { shortfall: None },
                blockers: Blockers::Known(Vec::new()),
            });
        }
        let before = self.cached_occupancy(caches, data, key)?;
        let swept = self.cached_swept(caches, data, key, joint, to)?;
        let mut after_key = key.to_vec();
        after_key[joint.index()] = to;
        let after = self.cached_occupancy(caches, data, &after_key)?;
        let clear: Vec<&RegionCell> = region
            .iter()
            .filter(|r| {
                !before.blocked.cells[r.cell]
                    && (r.segmented || !self.boundary.in_sweep(&swept, r.cell))
            })
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
            let cause = if clear.is_empty()
                && region
                    .iter()
                    .all(|r| self.boundary.in_sweep(&swept, r.cell))
            {
                Cause::NoBasePose { shortfall: None }
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
        Ok(
            match self.cheapest(caches, key, robot_cell, &before.blocked, &feasible) {
                Some(choice) => Verdict::Feasible(choice),
                // Unreachable: every feasible cell is in the robot's component.
                None => Verdict::Infeasible {
                    cause: Cause::PathBlocked {
                        blockers: Vec::new(),
                    },
                    blockers: Blockers::Deferred,
                },
            },
        )
    }

    /// The cheapest of the `feasible` region cells for the robot at `robot_cell` in state
    /// `key` (occupancy `blocked`): least `travel·(path length) + actuation·(handle travel)`,
    /// then the lowest cell index, then the first in region order; `None` if the robot reaches
    /// none. Path lengths are settled in increasing order from the robot's cell only as far as
    /// that choice needs (and kept in `caches.travel` for later questions).
    fn cheapest(
        &self,
        caches: &mut Caches,
        key: &[u16],
        robot_cell: usize,
        blocked: &Blocked,
        feasible: &[&RegionCell],
    ) -> Option<Choice> {
        let res = self.base_blocked.resolution();
        let tkey = (key.to_vec(), robot_cell);
        let travel = match caches.travel.get(&tkey) {
            Some(t) => t.clone(),
            None => {
                let t = Arc::new(Mutex::new(Distances::new(blocked, robot_cell)));
                bounded_to(&mut caches.travel, TRAVEL_LIMIT);
                caches.travel.insert(tkey, t.clone());
                t
            }
        };
        let mut travel = travel.lock().unwrap_or_else(|e| e.into_inner());
        let (tw, aw) = (self.settings.cost.travel, self.settings.cost.actuation);
        let mut best: Option<(f64, &RegionCell)> = None;
        if tw == 0.0 {
            consider(0.0, aw, feasible, &mut best);
        } else {
            // Per cell, the region entries that can be chosen there.
            let mut at: HashMap<usize, Vec<&RegionCell>> = HashMap::new();
            for r in feasible {
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
                let Some((cell, d)) = travel.settle_next(blocked) else {
                    break;
                };
                if let Some(rs) = at.get(&cell) {
                    consider(tw * d * res, aw, rs, &mut best);
                }
            }
        }
        let (_, best) = best?;
        let best_travel = travel.to(blocked, best.cell);
        let [x, y] = self.base_xy(best.cell);
        Some(Choice {
            handle: best.handle,
            cell: best.cell,
            base: [x, y, best.yaw],
            travel: best_travel * res,
            actuation: best.actuation,
        })
    }

    /// Check 3 of a move: the refiner's verdict on `choice`, asked once per (state, joint,
    /// target) and memoised; vetoes are counted in `caches.vetoes`.
    #[allow(clippy::too_many_arguments)]
    fn refinement(
        &self,
        caches: &mut Caches,
        key: &[u16],
        robot_cell: usize,
        joint: JointId,
        to: u16,
        choice: Choice,
        refiner: &dyn Refiner,
    ) -> Verdict {
        let state = self.state_of(key);
        let b = self.lattice.values(joint)[to as usize];
        let [rx, ry] = self.base_xy(robot_cell);
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
            Refinement::Accept => Verdict::Feasible(choice),
            Refinement::Veto { reason, blockers } => Verdict::Infeasible {
                cause: Cause::Vetoed { reason },
                blockers: match blockers {
                    Some(parts) => Blockers::Known(parts.iter().map(|p| p.joint()).collect()),
                    None => Blockers::Unknown,
                },
            },
        }
    }
}
