//! Which joints a failed base-pose check depends on: the check relaxed to some parts, its
//! witness (the start's free components) and the parts named in reports.

use std::sync::Arc;

use super::caches::Caches;
use super::{Checker, Error};
use crate::scene::nav::part_footprint;
use crate::scene::{JointId, PartId, SceneData, forward_kinematics};

/// The start's free components before and after a move.
type Components = (Vec<bool>, Vec<bool>);

impl Checker<'_> {
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
                && !self.boundary.in_sweep(&swept, r.cell)
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
    /// check (before or after), or comes within two cells of a freed boundary cell in it
    /// (which it blocks then). A part whose inflated footprint misses those components cannot
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
                // A footprint cell also blocks the freed boundary cells near it.
                let in_comp = |c: usize| comp_before[c] || comp_after[c];
                named[i] = cells.iter().any(|&c| {
                    in_comp(c as usize) || self.boundary.blocks_any(c as usize, &in_comp)
                });
            }
        }
        Ok((0..named.len())
            .filter(|&k| named[k])
            .map(JointId)
            .collect())
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
