//! Why a move has no base pose, in numbers: the limit of the manipulation region
//! ([`ManipulationSettings`](crate::task::ManipulationSettings)) that no free cell of the base
//! map satisfies, for the handle that comes nearest.
//!
//! Computed only for a report (a search that ends without a plan), so it scans the whole grid.

use nalgebra::Point2;

use super::caches::Caches;
use super::{Checker, Error};
use crate::scene::motion::grasp_trajectory;
use crate::scene::{HandleId, HandlePose, JointId, SceneData};
use crate::task::plan::{Cause, ReachLimit, ReachShortfall};

impl Checker<'_> {
    /// Whether no move of `joint` into its target (the lattice values `inside` accepts) has a
    /// base pose whatever the other parts do: every move from a value outside to one inside,
    /// at every combination of values of the joints the move's region and swept footprint
    /// depend on (its ancestors and its subtree), ends in [`Checker::no_base_pose`]. Such a
    /// target is unreachable: the joint must move into it at some point, in some state. Gives
    /// up (`None`) beyond `limit` checks. On a proof, returns the direct move from `start`
    /// into the target, with its cause.
    pub(crate) fn target_without_base_pose(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        start: &[u16],
        joint: JointId,
        inside: &dyn Fn(f64) -> bool,
        limit: usize,
    ) -> Result<Option<(u16, Cause)>, Error> {
        let values = self.lattice.values(joint);
        if inside(values[start[joint.index()] as usize]) {
            return Ok(None);
        }
        let (into, outside): (Vec<u16>, Vec<u16>) =
            (0..values.len() as u16).partition(|&v| inside(values[v as usize]));
        let mut context: Vec<JointId> = self.shape_context[joint.index()].clone();
        context.retain(|&j| j != joint);
        let sizes: Vec<usize> = context
            .iter()
            .map(|&j| self.lattice.values(j).len())
            .collect();
        let combinations = sizes.iter().try_fold(1usize, |n, &k| n.checked_mul(k));
        let moves = into.len() * outside.len();
        if into.is_empty() || combinations.is_none_or(|c| c.saturating_mul(moves) > limit) {
            return Ok(None);
        }
        let mut key = start.to_vec();
        for mut c in 0..combinations.unwrap_or(0) {
            for (j, &n) in context.iter().zip(&sizes) {
                key[j.index()] = (c % n) as u16;
                c /= n;
            }
            for &a in &outside {
                key[joint.index()] = a;
                for &b in &into {
                    if self.no_base_pose(caches, data, &key, joint, b)?.is_none() {
                        return Ok(None);
                    }
                }
            }
        }
        let a = start[joint.index()];
        let b = *into
            .iter()
            .min_by(|x, y| {
                let d = |v: u16| (values[v as usize] - values[a as usize]).abs();
                d(**x).total_cmp(&d(**y))
            })
            .unwrap_or(&into[0]);
        Ok(self
            .no_base_pose(caches, data, start, joint, b)?
            .map(|cause| (b, cause)))
    }

    /// `Cause::NoBasePose` with its shortfall when moving `joint` to lattice value `to` in
    /// state `key` has no base pose whatever the other parts do (check 2's first case: the
    /// manipulation region is empty, or each of its cells that is not segmented lies in the
    /// swept footprint and none is segmented); `None` otherwise. For a report of moves the
    /// search pruned by their bound without checking them.
    pub(crate) fn no_base_pose(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<Option<Cause>, Error> {
        if self.model.parts()[joint.index()].handles().is_empty() {
            return Ok(None);
        }
        let region = self.cached_region(caches, data, key, joint, to)?;
        let swept = self.cached_swept(caches, data, key, joint, to)?;
        if region
            .iter()
            .any(|r| r.segmented || !self.boundary.in_sweep(&swept, r.cell))
        {
            return Ok(None);
        }
        let shortfall = self.reach_shortfall(caches, data, key, joint, to)?;
        Ok(Some(Cause::NoBasePose {
            shortfall: shortfall.map(Box::new),
        }))
    }

    /// The shortfall of moving `joint` to lattice value `to` in state `key`: for each of the
    /// part's handles the first limit its grasp trajectory breaks, and of those the one of the
    /// handle that gets furthest along its trajectory. When a cell of the base map would hold
    /// a handle throughout but every such cell lies in the part's swept footprint, the limits
    /// are those of the cells outside it (and `swept` says so). `None` when the part has no
    /// handle.
    pub(crate) fn reach_shortfall(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<Option<ReachShortfall>, Error> {
        let part = &self.model.parts()[joint.index()];
        let state = self.state_of(key);
        let (a, b) = (
            state.q[joint.index()],
            self.lattice.values(joint)[to as usize],
        );
        let steps = self.settings.manipulation.steps;
        let free = self.free_cells(&|_| true);
        let swept = self.cached_swept(caches, data, key, joint, to)?;
        let unswept = self.free_cells(&|cell| !swept.contains(cell));
        let mut best: Option<(usize, ReachShortfall)> = None;
        for (index, h) in part.handles().iter().enumerate() {
            let handle = HandleId {
                part: part.id(),
                index,
            };
            let traj = grasp_trajectory(self.model, data, &state, handle, joint, a, b, steps)?;
            let (mut progress, mut limit) = self.first_limit(&traj, &free);
            let whole = matches!(limit, ReachLimit::Split { held, .. } if held == traj.len());
            if whole {
                (progress, limit) = self.first_limit(&traj, &unswept);
            }
            if best.as_ref().is_none_or(|(p, _)| progress > *p) {
                let shortfall = ReachShortfall {
                    handle: h.name.clone(),
                    waypoints: traj.len(),
                    swept: whole,
                    limit,
                };
                best = Some((progress, shortfall));
            }
        }
        Ok(best.map(|(_, s)| s))
    }

    /// The first limit `traj` breaks from the base cells `free`, with how far along it the
    /// handle gets (waypoints held from one cell, for ranking handles).
    fn first_limit(&self, traj: &[HandlePose], free: &[Point2<f64>]) -> (usize, ReachLimit) {
        let m = &self.settings.manipulation;
        let band = [m.height_min, m.height_max];
        if let Some((k, p)) = traj
            .iter()
            .enumerate()
            .find(|(_, p)| !(band[0]..=band[1]).contains(&p.position.z))
        {
            return (
                0,
                ReachLimit::Height {
                    waypoint: k,
                    z: p.position.z,
                    band,
                },
            );
        }
        let elevation = traj[0].normal.z.clamp(-1.0, 1.0).asin().abs();
        if elevation > m.max_normal_elevation {
            return (
                0,
                ReachLimit::Elevation {
                    elevation,
                    max: m.max_normal_elevation,
                },
            );
        }
        for (k, p) in traj.iter().enumerate() {
            let holding: Vec<&Point2<f64>> = free
                .iter()
                .filter(|c| self.holds(c, p) && (k > 0 || front(c, p)))
                .collect();
            if holding.is_empty() {
                return (k, self.unreachable(free, k, p));
            }
        }
        // Every waypoint is held from some cell, none from one cell throughout: the longest
        // prefix one cell in front of the start holds.
        let held = free
            .iter()
            .filter(|c| front(c, &traj[0]))
            .map(|c| traj.iter().take_while(|p| self.holds(c, p)).count())
            .max()
            .unwrap_or(0);
        (
            held,
            ReachLimit::Split {
                held,
                segments: m.segments,
            },
        )
    }

    /// The limit at waypoint `k` (grasp pose `p`), which no free cell holds.
    fn unreachable(&self, free: &[Point2<f64>], k: usize, p: &HandlePose) -> ReachLimit {
        let m = &self.settings.manipulation;
        let dist = |c: &Point2<f64>| (c.x - p.position.x).hypot(c.y - p.position.y);
        let nearest = free.iter().map(dist).fold(f64::INFINITY, f64::min);
        let in_annulus = free
            .iter()
            .filter(|c| (m.reach_min..=m.reach_max).contains(&dist(c)));
        let least_span = m.arm.as_ref().and_then(|arm| {
            let s = in_annulus
                .map(|c| arm.span([c.x, c.y], &p.position, &p.normal))
                .fold(f64::INFINITY, f64::min);
            s.is_finite().then_some((s, arm.radius))
        });
        ReachLimit::Unreachable {
            waypoint: k,
            position: [p.position.x, p.position.y, p.position.z],
            reach: [m.reach_min, m.reach_max],
            nearest_free: nearest.is_finite().then_some(nearest),
            arm_span: least_span,
        }
    }

    /// Whether a base at `c` holds grasp pose `p` (annulus and arm reach).
    fn holds(&self, c: &Point2<f64>, p: &HandlePose) -> bool {
        let m = &self.settings.manipulation;
        let d = (c.x - p.position.x).hypot(c.y - p.position.y);
        (m.reach_min..=m.reach_max).contains(&d)
            && m.arm
                .is_none_or(|arm| arm.admits([c.x, c.y], &p.position, &p.normal, 0.0))
    }

    /// The centres of the free cells of the inflated base map that `keep` accepts (by index).
    fn free_cells(&self, keep: &dyn Fn(usize) -> bool) -> Vec<Point2<f64>> {
        let g = &self.base_blocked;
        let w = g.width();
        (0..g.height())
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .filter(|&(i, j)| !g.is_occupied(i, j) && keep(j * w + i))
            .map(|(i, j)| g.cell_center(i, j))
            .collect()
    }
}

/// Whether `c` lies on the outward side of grasp pose `p`.
fn front(c: &Point2<f64>, p: &HandlePose) -> bool {
    (c.x - p.position.x) * p.normal.x + (c.y - p.position.y) * p.normal.y >= 0.0
}
