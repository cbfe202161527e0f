//! Where the part attaches: the registered part the handle lies on (nested), else the base,
//! and the part's joint frame on it.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};

use super::JointLine;
use crate::discovery::settings::DiscoverySettings;
use crate::discovery::shapes::PlacedShape;
use crate::scene::{
    Joint, JointKind, Limits, PartSpec, SceneData, SceneModel, State, forward_kinematics,
};

/// The part of handle `index` on its parent (the registered part the handle at `c` lies on at
/// `state`, else the base), its joint at `line`'s origin with axes aligned with the map frame
/// at discovery time; with the joint frame in the map frame.
pub(super) fn attach(
    index: usize,
    line: &JointLine,
    c: Point3<f64>,
    model: &SceneModel,
    state: &State,
    s: &DiscoverySettings,
) -> Result<(PartSpec, Isometry3<f64>), String> {
    let JointLine {
        kind,
        axis,
        origin,
        upper,
        ..
    } = *line;
    // Parent: the registered part the handle lies on, else the base.
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state).map_err(|e| e.to_string())?;
    let parent = nest_parent(model, &data, &c, s.nest_margin);
    let world_from_parent = parent
        .map(|k| data.world_from_parts()[k])
        .unwrap_or_else(Isometry3::identity);
    // The joint frame: at the origin, axes aligned with the map frame at discovery time.
    let world_from_joint = Isometry3::from_parts(
        Translation3::from(origin.coords),
        UnitQuaternion::identity(),
    );
    let parent_from_joint = world_from_parent.inverse() * world_from_joint;
    let name = format!("part{index}");
    let joint_name = match kind {
        JointKind::Revolute => format!("{name}_hinge"),
        JointKind::Prismatic => format!("{name}_slide"),
    };
    let joint = Joint::new(
        joint_name,
        kind,
        parent_from_joint,
        axis,
        Limits::new(0.0, upper),
    );
    let spec = match parent {
        Some(k) => PartSpec::on_part(name.clone(), model.parts()[k].name(), joint),
        None => PartSpec::on_base(name.clone(), joint),
    };
    Ok((spec, world_from_joint))
}

/// The nesting rule: the registered part (index) with a collider within `margin` of `p` at the
/// current state, the nearest one; ties go to the deeper part.
fn nest_parent(
    model: &SceneModel,
    data: &SceneData,
    p: &Point3<f64>,
    margin: f64,
) -> Option<usize> {
    let mut best: Option<(f64, usize, usize)> = None;
    for part in model.parts() {
        let k = part.id().index();
        let world_from_part = data.world_from_parts()[k];
        for collider in part.colliders() {
            let Some(shape) = PlacedShape::new(
                &collider.shape,
                &(world_from_part * collider.part_from_shape),
            ) else {
                continue;
            };
            let d = shape.distance(p);
            if d > margin {
                continue;
            }
            let better = match best {
                None => true,
                Some((bd, depth, _)) => d < bd - 1e-9 || (d <= bd + 1e-9 && part.depth() > depth),
            };
            if better {
                best = Some((d, part.depth(), k));
            }
        }
    }
    best.map(|(_, _, k)| k)
}
