//! Collision elements on import: primitives and meshes, attached to the base or a part.

use nalgebra::Vector3;
use urdf_rs::{Geometry, Link};

use super::import::{Importer, Owner, Visit, compose};
use super::numbers::isometry_from_origin;
use crate::scene::validate::check_finite;
use crate::scene::{BaseShape, Collider, Error, MeshSource, Shape};

impl Importer<'_> {
    /// Converts the link's collision elements and attaches them to its owner.
    pub(super) fn add_collisions(&mut self, link: &Link, visit: &Visit) -> Result<(), Error> {
        for (k, collision) in link.collision.iter().enumerate() {
            let what = format!("URDF link {:?} collision {k}", link.name);
            let origin = &collision.origin;
            check_finite(origin.xyz.iter().chain(origin.rpy.iter()).copied(), || {
                format!("{what} origin")
            })?;
            let pose = compose(
                visit.owner_from_link.as_ref(),
                isometry_from_origin(&origin.xyz, &origin.rpy),
            );
            let shapes = self.shapes(&link.name, &collision.geometry, &what)?;
            let name = match collision.name.as_deref() {
                Some(name) if !name.is_empty() => name.to_string(),
                _ => format!("{}#{k}", link.name),
            };
            let several = shapes.len() > 1;
            for (i, shape) in shapes.into_iter().enumerate() {
                match visit.owner {
                    Owner::Base => self.builder.base.shapes.push(BaseShape::new(
                        if several {
                            format!("{name}/{i}")
                        } else {
                            name.clone()
                        },
                        shape,
                        pose,
                    )),
                    Owner::Part(p) => self.builder.parts[p]
                        .colliders
                        .push(Collider::new(shape, pose)),
                }
            }
        }
        Ok(())
    }

    /// The shapes of one `<geometry>`: one for a primitive, one per sub-mesh for a mesh.
    /// Each is validated here so that errors name the URDF element.
    fn shapes(&mut self, link: &str, geometry: &Geometry, what: &str) -> Result<Vec<Shape>, Error> {
        let shapes = match geometry {
            Geometry::Box { size } => vec![Shape::box_size(Vector3::from(**size))],
            Geometry::Cylinder { radius, length } => vec![Shape::Cylinder {
                radius: *radius,
                length: *length,
            }],
            Geometry::Capsule { radius, length } => vec![Shape::Capsule {
                radius: *radius,
                length: *length,
            }],
            Geometry::Sphere { radius } => vec![Shape::Sphere { radius: *radius }],
            Geometry::Mesh { filename, scale } => {
                let scale = scale.map_or(Vector3::repeat(1.0), |s| Vector3::from(*s));
                check_finite(scale.iter().copied(), || {
                    format!("{what} mesh {filename:?} scale")
                })?;
                let meshes = self.meshes.load(link, filename, &scale)?;
                if meshes.is_empty() {
                    return Err(Error::DegenerateMesh {
                        what: format!("{what} mesh {filename:?}"),
                        reason: "the file has no vertices".into(),
                    });
                }
                meshes
                    .into_iter()
                    .map(|vertices| Shape::ConvexMesh {
                        vertices,
                        source: Some(MeshSource {
                            uri: filename.clone(),
                            scale,
                        }),
                    })
                    .collect()
            }
        };
        let several = shapes.len() > 1;
        for (i, shape) in shapes.iter().enumerate() {
            let what = match shape {
                Shape::ConvexMesh {
                    source: Some(s), ..
                } if several => format!("{what} mesh {:?} sub-mesh {i}", s.uri),
                Shape::ConvexMesh {
                    source: Some(s), ..
                } => format!("{what} mesh {:?}", s.uri),
                _ => what.to_string(),
            };
            shape.validate(&what)?;
        }
        Ok(shapes)
    }
}
