//! Which joints can influence a move's checks: conservative reach spheres, used to key the
//! memo of sweep checks by only the joints that matter.

use nalgebra::{Point3, Vector3};

use crate::scene::{JointId, JointKind, PartId, SceneModel};

/// A sphere; `radius < 0` marks "no geometry".
#[derive(Debug, Clone, Copy)]
struct Sphere {
    center: Point3<f64>,
    radius: f64,
}

impl Sphere {
    const EMPTY: Sphere = Sphere {
        center: Point3::new(0.0, 0.0, 0.0),
        radius: -1.0,
    };

    fn is_empty(&self) -> bool {
        self.radius < 0.0
    }

    /// The smallest sphere containing both.
    fn merge(self, o: Sphere) -> Sphere {
        if self.is_empty() {
            return o;
        }
        if o.is_empty() {
            return self;
        }
        let d = (o.center - self.center).norm();
        if d + o.radius <= self.radius {
            return self;
        }
        if d + self.radius <= o.radius {
            return o;
        }
        let radius = 0.5 * (d + self.radius + o.radius);
        let dir = (o.center - self.center) / d;
        Sphere {
            center: self.center + dir * (radius - self.radius),
            radius,
        }
    }
}

/// A sphere in a child part's frame → a sphere in the parent frame containing it for every
/// value of the child's joint within its limits.
fn sweep_through_joint(model: &SceneModel, child: PartId, s: Sphere) -> Sphere {
    if s.is_empty() {
        return s;
    }
    let j = &model.joints()[child.index()];
    let u: Vector3<f64> = j.axis;
    let local = match j.kind {
        // Rotation about the axis through the joint origin keeps the distance to the axis
        // and the axial coordinate: every image lies within (dist to axis + r) of the foot
        // of the perpendicular.
        JointKind::Revolute => {
            let along = u * u.dot(&s.center.coords);
            Sphere {
                center: Point3::from(along),
                radius: s.radius + (s.center.coords - along).norm(),
            }
        }
        JointKind::Prismatic => {
            let (lo, hi) = (j.limits.lower, j.limits.upper);
            Sphere {
                center: s.center + u * (0.5 * (lo + hi)),
                radius: s.radius + 0.5 * (hi - lo),
            }
        }
    };
    Sphere {
        center: j.parent_from_joint * local.center,
        radius: local.radius,
    }
}

/// For each joint `j`: the joints whose values can change the outcome of a sweep check of `j`
/// (its ancestors, its subtree, and every part whose reach sphere comes within `gap` of the
/// moving subtree's, with that part's ancestors), sorted.
pub(crate) fn sweep_contexts(model: &SceneModel, gap: f64) -> Vec<Vec<JointId>> {
    let parts = model.parts();
    // Each part's own geometry over all states, in the world frame.
    let own: Vec<Sphere> = parts
        .iter()
        .map(|p| {
            let mut s = p.colliders().iter().fold(Sphere::EMPTY, |acc, c| {
                let b = c.shape.bounding_sphere();
                acc.merge(Sphere {
                    center: c.part_from_shape * b.center,
                    radius: b.radius,
                })
            });
            let mut id = p.id();
            loop {
                s = sweep_through_joint(model, id, s);
                match parts[id.index()].parent() {
                    crate::scene::Parent::Part(q) => id = q,
                    crate::scene::Parent::Base => break,
                }
            }
            s
        })
        .collect();
    let ancestors = |p: PartId| {
        let mut out = Vec::new();
        let mut id = p;
        while let crate::scene::Parent::Part(q) = parts[id.index()].parent() {
            out.push(q.joint());
            id = q;
        }
        out
    };
    parts
        .iter()
        .map(|p| {
            let subtree: Vec<PartId> = p.subtree().collect();
            let mut ctx: Vec<JointId> = ancestors(p.id());
            ctx.extend(subtree.iter().map(|q| q.joint()));
            for x in parts {
                if p.subtree_contains(x.id()) || own[x.id().index()].is_empty() {
                    continue;
                }
                let sx = own[x.id().index()];
                let near = subtree.iter().any(|y| {
                    let sy = own[y.index()];
                    !sy.is_empty() && (sx.center - sy.center).norm() <= sx.radius + sy.radius + gap
                });
                if near {
                    ctx.push(x.id().joint());
                    ctx.extend(ancestors(x.id()));
                }
            }
            ctx.sort();
            ctx.dedup();
            ctx
        })
        .collect()
}

/// The joints on the path from the base to `part`'s joint, excluding it, sorted.
pub(crate) fn ancestor_joints(model: &SceneModel, part: PartId) -> Vec<JointId> {
    let mut out = Vec::new();
    let mut id = part;
    while let crate::scene::Parent::Part(q) = model.parts()[id.index()].parent() {
        out.push(q.joint());
        id = q;
    }
    out.sort();
    out
}
