//! Rigid motions about a joint's world axis (Rodrigues, the paper's Eq. (3)).

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

use crate::scene::JointAxis;
use crate::scene::JointKind;

impl JointAxis {
    /// The paper's Eq. (3): `R(φ) = I + sin φ [u]× + (1 − cos φ) [u]×²`, the rotation by
    /// `phi` rad about the unit direction `u`.
    pub fn rodrigues(&self, phi: f64) -> Matrix3<f64> {
        let k = self.direction.cross_matrix();
        Matrix3::identity() + k * phi.sin() + k * k * (1.0 - phi.cos())
    }

    /// The world-frame rigid motion applied to every point of the moving subtree when the
    /// joint value changes by `delta`: `x ↦ R(delta)(x − q) + q` (revolute) or
    /// `x ↦ x + delta·u` (prismatic).
    pub fn displacement(&self, delta: f64) -> Isometry3<f64> {
        match self.kind {
            JointKind::Revolute => {
                let rotation = UnitQuaternion::from_axis_angle(&self.direction, delta);
                let q = self.pivot.coords;
                // x ↦ R(x − q) + q = R x + (q − R q).
                Isometry3::from_parts(Translation3::from(q - rotation * q), rotation)
            }
            JointKind::Prismatic => Isometry3::from_parts(
                Translation3::from(self.direction.into_inner() * delta),
                UnitQuaternion::identity(),
            ),
        }
    }

    /// Eq. (4)/(5) for one point: where `p` goes when the joint value changes by `delta`.
    pub fn move_point(&self, p: &Point3<f64>, delta: f64) -> Point3<f64> {
        match self.kind {
            JointKind::Revolute => self.pivot + self.rodrigues(delta) * (p - self.pivot),
            JointKind::Prismatic => p + self.direction.into_inner() * delta,
        }
    }

    /// Eq. (3) applied to a direction (prismatic motions leave directions unchanged).
    pub fn move_vector(&self, v: &Vector3<f64>, delta: f64) -> Vector3<f64> {
        match self.kind {
            JointKind::Revolute => self.rodrigues(delta) * v,
            JointKind::Prismatic => *v,
        }
    }

    /// Distance (m) from a point to the axis line.
    pub fn distance_to_axis(&self, p: &Point3<f64>) -> f64 {
        (p - self.pivot).cross(&self.direction).norm()
    }
}
