//! The table of vetoed moves the motion layer feeds back to the task search.

use crate::scene::{JointId, PartId, SceneModel, State};

/// A vetoed move and the states it is vetoed in: every state that agrees with the failed one on
/// the `fixed` joints (values compared bit for bit, as the task search produces them from its
/// lattice). A failure whose causes are known (parts the robot collided with, and the moved
/// part's ancestors, which place its axis) fixes only those joints, so the search does not
/// refine the same hopeless move again in states that differ elsewhere; an unattributed failure
/// fixes every joint.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct VetoRule {
    pub(super) joint: usize,
    pub(super) from: u64,
    pub(super) to: u64,
    pub(super) fixed: Vec<(usize, u64)>,
    /// The parts whose configuration may matter (`None`: unknown, every joint may).
    pub(super) blockers: Option<Vec<PartId>>,
    pub(super) reason: String,
}

impl VetoRule {
    pub(super) fn new(
        model: &SceneModel,
        state: &State,
        joint: JointId,
        to: f64,
        causes: Option<&[PartId]>,
        reason: String,
    ) -> Self {
        let values = state.as_slice();
        let from = values[joint.index()];
        let fixed: Vec<(usize, u64)> = match causes {
            None => values
                .iter()
                .enumerate()
                .map(|(i, v)| (i, v.to_bits()))
                .collect(),
            Some(parts) => {
                let mut joints: Vec<usize> = parts.iter().map(|p| p.joint().index()).collect();
                // The part's ancestors place its handle (the part itself is keyed by `from`).
                joints.extend(
                    model
                        .path_to_base(joint.part())
                        .skip(1)
                        .map(|p| p.joint().index()),
                );
                joints.sort_unstable();
                joints.dedup();
                joints
                    .into_iter()
                    .map(|j| (j, values[j].to_bits()))
                    .collect()
            }
        };
        VetoRule {
            joint: joint.index(),
            from: from.to_bits(),
            to: to.to_bits(),
            fixed,
            blockers: causes.map(<[PartId]>::to_vec),
            reason,
        }
    }

    pub(super) fn matches(&self, state: &State, joint: JointId, to: f64) -> bool {
        let values = state.as_slice();
        self.joint == joint.index()
            && self.to == to.to_bits()
            && values.get(self.joint).map(|v| v.to_bits()) == Some(self.from)
            && self
                .fixed
                .iter()
                .all(|(j, v)| values.get(*j).map(|x| x.to_bits()) == Some(*v))
    }
}
