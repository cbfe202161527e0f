//! The final-move sets `C_j` of the module docs: the base cells from which a move can bring a
//! goal joint into its target.

use super::{Heuristic, MAX_POSE_COMBINATIONS, SLACK};
use crate::scene::{JointId, SceneData, SceneModel, State, forward_kinematics};
use crate::task::Error;
use crate::task::check::Checker;
use crate::task::reach::ancestor_joints;

impl Heuristic<'_> {
    /// `C_j` of one goal joint (see the module docs); `None` beyond [`MAX_POSE_COMBINATIONS`]
    /// ancestor value combinations, or if the joint meets its target at every value.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn final_move_set(
        &self,
        model: &SceneModel,
        checker: &Checker<'_>,
        data: &mut SceneData,
        joint: JointId,
        reachable: &[bool],
        least_span: &mut f64,
    ) -> Result<Option<Vec<usize>>, Error> {
        let Some(target) = self.problem.goal.target(joint) else {
            return Ok(None);
        };
        let values = self.lattice.values(joint);
        let inside: Vec<f64> = values
            .iter()
            .copied()
            .filter(|v| target.contains(*v))
            .collect();
        if inside.len() == values.len() {
            // Every value meets the target: the joint is never unmet.
            return Ok(None);
        }
        let part = &model.parts()[joint.index()];
        let ancestors = ancestor_joints(model, part.id());
        let Some(combinations) = ancestors
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(self.lattice.values(*a).len()))
            .filter(|n| *n <= MAX_POSE_COMBINATIONS)
        else {
            return Ok(None);
        };
        let m = &self.settings.manipulation;
        let grid = checker.base_grid();
        let (w, h, res) = (self.width, self.height, self.resolution);
        let o = grid.origin();
        let index = |v: f64, o: f64, n: usize| {
            (((v - o) / res).floor().max(0.0) as usize).min(n.saturating_sub(1))
        };
        let mut member = vec![false; w * h];
        // Whether a cell serves a position inside the target: the last run of a segmented
        // move holds one, so without such a cell no move meets the target either way.
        let mut any_final = false;
        let mut state: State = self.problem.start.clone();
        for mut k in 0..combinations {
            for a in &ancestors {
                let values = self.lattice.values(*a);
                state.q[a.index()] = values[k % values.len()];
                k /= values.len();
            }
            // With segmented moves the move's base cell covers the grasp point's first
            // position (the part at any lattice value), not necessarily its last.
            let segmented = m.segments > 1;
            for v in values {
                let in_target = target.contains(*v);
                if !(in_target || segmented) {
                    continue;
                }
                state.q[joint.index()] = *v;
                forward_kinematics(model, data, &state)?;
                let world_from_part = data.world_from_parts()[part.id().index()];
                for handle in part.handles() {
                    let p = world_from_part * handle.position;
                    let n = world_from_part * handle.normal;
                    if p.z < m.height_min - SLACK || p.z > m.height_max + SLACK {
                        continue;
                    }
                    let r = m.reach_max + SLACK;
                    for j in index(p.y - r, o.y, h)..=index(p.y + r, o.y, h) {
                        for i in index(p.x - r, o.x, w)..=index(p.x + r, o.x, w) {
                            let cell = j * w + i;
                            let [cx, cy] = checker.base_xy(cell);
                            let c = nalgebra::Point2::new(cx, cy);
                            let d = (c.x - p.x).hypot(c.y - p.y);
                            if d >= m.reach_min - SLACK && d <= r && reachable[cell] {
                                match &m.arm {
                                    Some(arm) => {
                                        let span = arm.span([c.x, c.y], &p, &n);
                                        if in_target {
                                            *least_span = least_span.min(span);
                                        }
                                        if span <= arm.radius + SLACK {
                                            member[cell] = true;
                                            any_final |= in_target;
                                        }
                                    }
                                    None => {
                                        member[cell] = true;
                                        any_final |= in_target;
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        if !any_final {
            return Ok(Some(Vec::new()));
        }
        Ok(Some((0..w * h).filter(|&c| member[c]).collect()))
    }
}
