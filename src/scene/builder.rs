//! Building and validating a [`SceneModel`].

use std::collections::BTreeSet;

use serde::{Deserialize, Serialize};

use super::base::{BaseMap, BaseShape};
use super::collision::geometry::{CollisionGeometry, CompiledShape};
use super::ids::{BaseShapeId, HandleId, JointId, Parent, PartId};
use super::model::SceneModel;
use super::nav::{NavGridSettings, footprint};
use super::part::{Handle, Part, PartSpec};
use super::tree;
use super::validate::{check_finite, check_isometry, renormalized, unit_direction};
use super::{ElementKind, Error};

/// A scene description: plain data, validated into a [`SceneModel`] by
/// [`build`](SceneModelBuilder::build). Parts may be added in any order; they refer to their
/// parent by name.
///
/// # Example
/// ```
/// use kinscene::scene::{Joint, Limits, PartSpec, SceneModelBuilder, Shape};
/// use nalgebra::{Isometry3, Point3, Vector3};
///
/// let mut builder = SceneModelBuilder::new();
/// builder.add_part(
///     PartSpec::on_base(
///         "door",
///         Joint::revolute("hinge", Point3::new(1.0, 0.0, 0.0), Vector3::z(), Limits::new(0.0, 1.6)),
///     )
///     .with_collider(
///         Shape::box_size(Vector3::new(0.5, 0.02, 0.7)),
///         Isometry3::translation(0.25, 0.0, 0.35),
///     ),
/// );
/// let model = builder.build()?;
/// assert_eq!(model.nq(), 1);
/// # Ok::<(), kinscene::scene::Error>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SceneModelBuilder {
    /// The static base map.
    pub base: BaseMap,
    /// The articulated parts, in any order.
    pub parts: Vec<PartSpec>,
}

impl SceneModelBuilder {
    /// An empty scene.
    pub fn new() -> Self {
        SceneModelBuilder::default()
    }

    /// Adds a static shape to the base map.
    pub fn add_base_shape(&mut self, shape: BaseShape) -> &mut Self {
        self.base.shapes.push(shape);
        self
    }

    /// Sets the navigation-grid settings.
    pub fn nav_settings(&mut self, settings: NavGridSettings) -> &mut Self {
        self.base.nav = settings;
        self
    }

    /// Adds a part.
    pub fn add_part(&mut self, part: PartSpec) -> &mut Self {
        self.parts.push(part);
        self
    }

    /// Validates the description and builds the model.
    ///
    /// Checks, in this order: names are non-empty and unique per kind (parts, joints, handles,
    /// base shapes); every parent exists; the parent relation has no cycle; every number is
    /// finite; axes and handle normals have norm ≥ [`MIN_AXIS_NORM`](super::MIN_AXIS_NORM)
    /// (then they are normalised); rotations are unit quaternions within 1e-6 (then
    /// renormalised); `lower <= upper`; shape dimensions are > 0 and meshes span a volume;
    /// navigation settings are valid. Parts are renumbered in depth-first pre-order.
    ///
    /// # Errors
    /// The first violation found, as the matching [`Error`] variant naming the element.
    pub fn build(&self) -> Result<SceneModel, Error> {
        check_names(self)?;
        let tree = tree::resolve(&self.parts)?;
        let mut parts = Vec::with_capacity(self.parts.len());
        let mut joints = Vec::with_capacity(self.parts.len());
        let mut geometry = CollisionGeometry::default();
        for (pos, &k) in tree.order.iter().enumerate() {
            let spec = &self.parts[k];
            joints.push(spec.joint.validated()?);
            let mut compiled = Vec::with_capacity(spec.colliders.len());
            for (c, collider) in spec.colliders.iter().enumerate() {
                let what = format!("part {:?} collider {c}", spec.name);
                collider.validate(&what)?;
                let pose = renormalized(&collider.part_from_shape);
                compiled.push(CompiledShape::new(&collider.shape, &pose, &what)?);
            }
            geometry.parts.push(compiled);
            let handles = spec
                .handles
                .iter()
                .map(validated_handle)
                .collect::<Result<Vec<_>, _>>()?;
            parts.push(Part {
                name: spec.name.clone(),
                id: PartId(pos),
                parent: tree.parent[pos].map_or(Parent::Base, |p| Parent::Part(PartId(p))),
                colliders: spec
                    .colliders
                    .iter()
                    .map(|c| {
                        super::Collider::new(c.shape.clone(), renormalized(&c.part_from_shape))
                    })
                    .collect(),
                handles,
                children: Vec::new(),
                subtree_end: tree.subtree_end[pos],
                depth: tree.depth[pos],
            });
        }
        for pos in 0..parts.len() {
            if let Parent::Part(p) = parts[pos].parent {
                parts[p.0].children.push(PartId(pos));
            }
        }
        let mut base = self.base.clone();
        for shape in &mut base.shapes {
            let what = format!("base shape {:?}", shape.name);
            shape.shape.validate(&what)?;
            check_isometry(&shape.world_from_shape, &what)?;
            shape.world_from_shape = renormalized(&shape.world_from_shape);
            geometry.base.push(CompiledShape::new(
                &shape.shape,
                &shape.world_from_shape,
                &what,
            )?);
        }
        base.nav.validate()?;
        let base_grid = footprint::base_grid(&base)?;
        let names = |kind| name_index(self, kind, &tree.order);
        Ok(SceneModel {
            part_names: names(ElementKind::Part)
                .map(|(n, k)| (n, PartId(k)))
                .collect(),
            joint_names: names(ElementKind::Joint)
                .map(|(n, k)| (n, JointId(k)))
                .collect(),
            handle_names: parts
                .iter()
                .flat_map(|p: &Part| {
                    p.handles
                        .iter()
                        .enumerate()
                        .map(|(index, h)| (h.name.clone(), HandleId { part: p.id, index }))
                })
                .collect(),
            base_names: base
                .shapes
                .iter()
                .enumerate()
                .map(|(k, s)| (s.name.clone(), BaseShapeId(k)))
                .collect(),
            parts,
            joints,
            base,
            geometry,
            base_grid,
        })
    }
}

/// (name, position) pairs of parts or joints, positions in pre-order.
fn name_index<'a>(
    b: &'a SceneModelBuilder,
    kind: ElementKind,
    order: &'a [usize],
) -> impl Iterator<Item = (String, usize)> + 'a {
    order.iter().enumerate().map(move |(pos, &k)| {
        let spec = &b.parts[k];
        let name = if kind == ElementKind::Part {
            &spec.name
        } else {
            &spec.joint.name
        };
        (name.clone(), pos)
    })
}

fn validated_handle(h: &Handle) -> Result<Handle, Error> {
    let what = || format!("handle {:?}", h.name);
    check_finite(h.position.coords.iter().copied(), what)?;
    let normal = unit_direction(&h.normal, what, || Error::ZeroNormal {
        handle: h.name.clone(),
    })?;
    Ok(Handle {
        normal: normal.into_inner(),
        ..h.clone()
    })
}

/// Rejects empty and repeated names, per kind.
fn check_names(b: &SceneModelBuilder) -> Result<(), Error> {
    let lists: [(ElementKind, Vec<&str>); 4] = [
        (
            ElementKind::Part,
            b.parts.iter().map(|p| p.name.as_str()).collect(),
        ),
        (
            ElementKind::Joint,
            b.parts.iter().map(|p| p.joint.name.as_str()).collect(),
        ),
        (
            ElementKind::Handle,
            b.parts
                .iter()
                .flat_map(|p| p.handles.iter().map(|h| h.name.as_str()))
                .collect(),
        ),
        (
            ElementKind::BaseShape,
            b.base.shapes.iter().map(|s| s.name.as_str()).collect(),
        ),
    ];
    for (kind, names) in lists {
        let mut seen = BTreeSet::new();
        for name in names {
            if name.is_empty() {
                return Err(Error::EmptyName { kind });
            }
            if !seen.insert(name) {
                return Err(Error::DuplicateName {
                    kind,
                    name: name.to_string(),
                });
            }
        }
    }
    Ok(())
}
