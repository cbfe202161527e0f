//! The manipulation region of a move: the base cells from which the robot can hold one of the
//! part's handles along the whole motion (reach, height, front), cached per move and context.

use std::sync::Arc;

use super::caches::{Caches, bounded};
use super::{Checker, Error};
use crate::scene::motion::grasp_trajectory;
use crate::scene::{HandleId, JointId, JointKind, SceneData, State, joint_axis};

/// A cell of a move's manipulation region, with the handle it serves and the handle travel.
#[derive(Debug, Clone, Copy)]
pub(super) struct RegionCell {
    pub(super) cell: usize,
    pub(super) handle: HandleId,
    pub(super) actuation: f64,
    pub(super) yaw: f64,
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
}
