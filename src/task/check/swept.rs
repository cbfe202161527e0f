//! The swept footprint of a move: the cells the moving subtree covers during the motion,
//! inflated so that they cover the continuous sweep, cached per move and context.

use std::sync::Arc;

use super::caches::{Caches, bounded};
use super::{Checker, Error};
use crate::scene::motion::motion_bound;
use crate::scene::nav::part_footprint;
use crate::scene::nav::search::{CellMask, Disc, set_cells};
use crate::scene::{JointId, PartId, SceneData, State, forward_kinematics};

impl Checker<'_> {
    /// The swept footprint of moving `joint` to lattice value `to` in state `key`.
    pub(super) fn cached_swept(
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

    /// Cells covered by the moving subtree (only parts `include` accepts) during the motion,
    /// inflated by the robot radius plus half the sample spacing.
    pub(super) fn swept_cells(
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
}
