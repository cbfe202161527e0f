//! Screw decomposition of a rigid motion (Chasles): rotation about a line plus translation along it.

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};

/// Below this rotation angle (rad) a motion is treated as a pure translation.
const PURE_TRANSLATION_ANGLE: f64 = 1e-9;

/// A rigid motion as a screw: rotate by `angle` about the line through `point` along `axis`,
/// then translate by `translation` along `axis`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Screw {
    /// Unit screw axis (map frame).
    pub axis: Unit<Vector3<f64>>,
    /// The point of the axis closest to the map origin, m (the origin for a pure translation).
    pub point: Point3<f64>,
    /// Rotation about `axis`, rad, in [0, π].
    pub angle: f64,
    /// Translation along `axis`, m.
    pub translation: f64,
}

impl Screw {
    /// Decomposes `motion` (a map-frame motion `p ↦ R p + t`).
    ///
    /// With rotation `θ` about `ω`, `d = ω·t` and `t⊥ = t − d ω`, the axis point is
    /// `(t⊥ + cot(θ/2) ω × t⊥) / 2`. A motion without rotation becomes a pure translation along
    /// `t / |t|` (the z axis for the identity).
    pub fn from_isometry(motion: &Isometry3<f64>) -> Self {
        let t = motion.translation.vector;
        match motion.rotation.axis_angle() {
            Some((axis, angle)) if angle > PURE_TRANSLATION_ANGLE => {
                let d = axis.dot(&t);
                let t_perp = t - axis.into_inner() * d;
                let p = (t_perp + axis.cross(&t_perp) / (angle / 2.0).tan()) / 2.0;
                // Shift to the point of the line closest to the origin.
                let p = p - axis.into_inner() * axis.dot(&p);
                Screw {
                    axis,
                    point: Point3::from(p),
                    angle,
                    translation: d,
                }
            }
            _ => {
                let (axis, n) = Unit::new_and_get(t);
                let axis = if n > 0.0 { axis } else { Vector3::z_axis() };
                Screw {
                    axis,
                    point: Point3::origin(),
                    angle: 0.0,
                    translation: n,
                }
            }
        }
    }

    /// The motion this screw describes.
    pub fn to_isometry(&self) -> Isometry3<f64> {
        let rotation = UnitQuaternion::from_axis_angle(&self.axis, self.angle);
        let about_point = Translation3::from(self.point.coords)
            * rotation
            * Translation3::from(-self.point.coords);
        Translation3::from(self.axis.into_inner() * self.translation) * about_point
    }

    /// The point of the axis line closest to `q`.
    pub fn closest_axis_point(&self, q: &Point3<f64>) -> Point3<f64> {
        self.point + self.axis.into_inner() * self.axis.dot(&(q - self.point))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motion built from a known screw decomposes back into it.
    #[test]
    fn round_trip() {
        let axis = Unit::new_normalize(Vector3::new(0.2, -0.5, 1.0));
        let point = Point3::new(0.3, 1.2, -0.4);
        let point = point - axis.into_inner() * axis.dot(&point.coords);
        let s = Screw {
            axis,
            point,
            angle: 0.7,
            translation: 0.05,
        };
        let back = Screw::from_isometry(&s.to_isometry());
        assert!((back.axis.into_inner() - axis.into_inner()).norm() < 1e-12);
        assert!((back.point - point).norm() < 1e-12);
        assert!((back.angle - 0.7).abs() < 1e-12);
        assert!((back.translation - 0.05).abs() < 1e-12);
    }
}
