//! Check 1 of a move: the certified sweep of the moving subtree, its memo key and the
//! blocked verdict with the bodies in contact.

use super::caches::Caches;
use super::{Checker, Error, SweepKey, SweepVerdict};
use crate::scene::collision::{Body, Contact, SweepStatus, check_joint_motion};
use crate::scene::{JointId, SceneData};
use crate::task::plan::{BodyName, Cause};

impl Checker<'_> {
    /// The joints whose values can change the sweep check of `joint` (its ancestors, its
    /// subtree and the parts whose reach spheres come near, with their ancestors; sorted).
    pub fn sweep_context(&self, joint: JointId) -> &[JointId] {
        &self.contexts[joint.index()]
    }

    /// The memo key of the sweep of `joint` from its value in `key` to value index `to`.
    pub fn sweep_key(&self, key: &[u16], joint: JointId, to: u16) -> SweepKey {
        (
            joint.index(),
            key[joint.index()],
            to,
            Self::values_of(key, &self.contexts[joint.index()]),
        )
    }

    /// Runs the sweep check (no memo; callable from any thread).
    pub fn sweep(
        &self,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<SweepVerdict, Error> {
        let state = self.state_of(key);
        let a = state.q[joint.index()];
        let b = self.lattice.values(joint)[to as usize];
        let out = check_joint_motion(self.model, data, &state, joint, a, b, &self.settings.sweep)?;
        let (contacts, value, conclusive) = match out.status {
            SweepStatus::Free => return Ok(SweepVerdict::Free),
            SweepStatus::Collision { value, contacts } => (contacts, value, true),
            SweepStatus::Inconclusive { value, nearest, .. } => (nearest, value, false),
        };
        let mut blockers = Vec::new();
        for c in &contacts {
            for body in [c.a, c.b] {
                if let Body::Part(p) = body {
                    blockers.push(p.joint());
                }
            }
        }
        let (moving, other) = contacts
            .first()
            .map(|c: &Contact| (self.body_name(c.a), self.body_name(c.b)))
            .unwrap_or_else(|| {
                let n = BodyName::Part(self.model.parts()[joint.index()].name().into());
                (n.clone(), n)
            });
        let cause = if conclusive {
            Cause::Collision {
                moving,
                other,
                value,
            }
        } else {
            Cause::Inconclusive {
                moving,
                other,
                value,
            }
        };
        Ok(SweepVerdict::Blocked { cause, blockers })
    }

    pub fn body_name(&self, b: Body) -> BodyName {
        BodyName::of(self.model, b)
    }

    /// [`Checker::sweep`] of moving `joint` to lattice value `to` in state `key`, memoised in
    /// `caches.sweeps`.
    pub(super) fn cached_sweep(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        joint: JointId,
        to: u16,
    ) -> Result<SweepVerdict, Error> {
        let sk = self.sweep_key(key, joint, to);
        Ok(match caches.sweeps.get(&sk) {
            Some(v) => v.clone(),
            None => {
                let v = self.sweep(data, key, joint, to)?;
                caches.sweeps.insert(sk, v.clone());
                v
            }
        })
    }
}
