//! The one place where nalgebra types become parry's glam types.
//!
//! parry3d ≥ 0.26 does its math in glam; the crate's public API is nalgebra. Nothing outside
//! `scene::collision` sees a parry or glam type.

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::math::{Pose, Rotation, Vector};

/// A nalgebra vector as a parry vector.
pub(crate) fn vector(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// A nalgebra point as a parry vector (parry uses vectors for points).
pub(crate) fn point(p: &Point3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// A parry vector as a nalgebra vector.
pub(crate) fn from_vector(v: &Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// A nalgebra isometry as a parry pose.
pub(crate) fn pose(iso: &Isometry3<f64>) -> Pose {
    let q = iso.rotation.quaternion();
    Pose::from_parts(
        vector(&iso.translation.vector),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}
