//! The uncertainty an estimate carries: Gaussian covariances of the axis direction and the
//! pivot in their 2-d tangent planes, and the probability of the joint type, with the 95 %
//! regions they imply.

use nalgebra::{Matrix2, Point3, Unit, Vector2, Vector3};

use super::estimate::{Estimate, JointEstimate};

/// The 95 % quantile of the χ² distribution with 2 degrees of freedom, `−2 ln 0.05`: a 2-d
/// Gaussian puts 95 % of its mass inside the ellipse of squared Mahalanobis radius this.
pub const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// A 2-d Gaussian in a plane of map space: a covariance in the orthonormal `basis`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneCovariance {
    /// Two orthonormal directions spanning the plane (map frame).
    pub basis: [Unit<Vector3<f64>>; 2],
    /// Covariance of the coordinates along `basis` (rad² for an axis direction, m² for a
    /// pivot).
    pub covariance: Matrix2<f64>,
}

impl PlaneCovariance {
    /// The coordinates of `v` (map frame) along [`basis`](Self::basis).
    pub fn coordinates(&self, v: &Vector3<f64>) -> Vector2<f64> {
        Vector2::new(self.basis[0].dot(v), self.basis[1].dot(v))
    }

    /// `vᵀ Σ⁻¹ v` of the in-plane part of `v`: ∞ when the covariance is singular (then no
    /// offset but zero is inside any region), NaN never (a non-finite input gives ∞).
    pub fn mahalanobis_squared(&self, v: &Vector3<f64>) -> f64 {
        let x = self.coordinates(v);
        match self.covariance.try_inverse() {
            Some(inv) => {
                let d = (x.transpose() * inv * x)[0];
                if d.is_finite() && d >= 0.0 {
                    d
                } else {
                    f64::INFINITY
                }
            }
            None => f64::INFINITY,
        }
    }

    /// The largest semi-axis of the region `xᵀ Σ⁻¹ x ≤ chi2`: `√(chi2 · λ_max)`.
    pub fn radius(&self, chi2: f64) -> f64 {
        let l = self.covariance.symmetric_eigenvalues();
        (chi2 * l.x.max(l.y).max(0.0)).sqrt()
    }
}

/// The uncertainty of a known joint estimate (see [`Estimate::uncertainty`]).
///
/// Regions are Gaussian (first-order, from the fit's curvature; each estimator's docs say how
/// its covariance is derived). The 95 % region of a 2-d quantity is the ellipse of squared
/// Mahalanobis radius [`CHI2_2DOF_95`].
///
/// [`Estimate::uncertainty`]: super::Estimate::uncertainty
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Uncertainty {
    /// Probability of the reported joint type against the other one (BIC's approximation of
    /// the posterior with equal priors, `1 / (1 + exp(−ΔBIC / 2))`). Below ½ when a check
    /// other than the model evidence chose the type (the two-view contact-path check): the
    /// evidence then disagrees, which the caller should treat as ambiguous.
    pub type_probability: f64,
    /// The axis direction's covariance in its tangent plane (rad²): the offset of a direction
    /// `a` from the estimated axis `â` is the rotation vector taking `â` to `a` (its length
    /// the angle between them).
    pub axis: PlaneCovariance,
    /// Revolute joints: the covariance (m²) of where the axis line crosses the plane normal
    /// to the estimated axis through the estimated pivot (the point of the axis level with
    /// the contact). `None` for a prismatic joint.
    pub pivot: Option<PlaneCovariance>,
}

impl Uncertainty {
    /// The 95 % confidence half-angle of the axis direction (rad): the largest angular
    /// semi-axis of its 95 % ellipse.
    pub fn axis_half_angle_95(&self) -> f64 {
        self.axis.radius(CHI2_2DOF_95)
    }

    /// The 95 % pivot radius (m): the largest semi-axis of the pivot's 95 % ellipse; `None`
    /// for a prismatic joint.
    pub fn pivot_radius_95(&self) -> Option<f64> {
        self.pivot.map(|p| p.radius(CHI2_2DOF_95))
    }

    /// The squared Mahalanobis distance of the direction `axis` from the `estimated` one
    /// (either sign of `axis`; the nearer is taken): at most [`CHI2_2DOF_95`] inside the 95 %
    /// region.
    pub fn axis_mahalanobis_squared(
        &self,
        estimated: &Unit<Vector3<f64>>,
        axis: &Unit<Vector3<f64>>,
    ) -> f64 {
        let a = if axis.dot(estimated) < 0.0 {
            -axis.into_inner()
        } else {
            axis.into_inner()
        };
        let cross = estimated.cross(&a);
        let sin = cross.norm();
        let angle = sin.atan2(estimated.dot(&a));
        // The rotation vector from the estimate to `a` (perpendicular to both).
        let offset = if sin > 0.0 {
            cross * (angle / sin)
        } else {
            Vector3::zeros()
        };
        // Tangent coordinates: the direction moves by `offset × â`.
        self.axis.mahalanobis_squared(&offset.cross(estimated))
    }

    /// The squared Mahalanobis distance of the line through `point` along `axis` from the
    /// estimated pivot, where the line crosses the plane through `estimated_pivot` normal to
    /// `estimated_axis`; ∞ for a line parallel to that plane, `None` for a prismatic joint.
    pub fn pivot_mahalanobis_squared(
        &self,
        estimated_pivot: &Point3<f64>,
        estimated_axis: &Unit<Vector3<f64>>,
        point: &Point3<f64>,
        axis: &Unit<Vector3<f64>>,
    ) -> Option<f64> {
        let pivot = self.pivot?;
        let along = estimated_axis.dot(axis);
        if along.abs() < 1e-9 {
            return Some(f64::INFINITY);
        }
        let t = estimated_axis.dot(&(estimated_pivot - point)) / along;
        let crossing = point + axis.into_inner() * t;
        Some(pivot.mahalanobis_squared(&(crossing - estimated_pivot)))
    }
}

/// How `u`, the uncertainty of `joint`, relates to another estimate of the same joint in
/// [`consistent_with`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Other {
    /// From part of the same data (the fused estimator's path alone): the less precise
    /// estimate, whose covariance bounds that of the difference.
    Nested,
    /// From other data (the path against the clouds): the difference has the sum of the two
    /// covariances.
    Independent,
}

/// `u`, the uncertainty of `joint`, widened where `other` (an estimate of the same joint from
/// the gripper's path alone) disagrees: the two differ by the squared Mahalanobis distance
/// `D` in the region of the difference (`other`'s own for [`Other::Nested`], the sum of the
/// two, `u`'s expressed in `other`'s tangent bases, for [`Other::Independent`]); without a
/// bias, `D` is of the order of its 2 degrees of freedom. A larger `D` is a disagreement
/// `u` does not know about (a bias the clouds' residuals cannot show: which points a
/// segmentation kept, a surface's sampling, a part of the front out of view), so the block
/// is scaled by `D / 2` (Birge's ratio). Unchanged when `other` has another joint type or
/// no uncertainty.
pub(crate) fn consistent_with(
    mut u: Uncertainty,
    joint: &JointEstimate,
    other: &Estimate,
    relation: Other,
) -> Uncertainty {
    let Some(mut p) = other.uncertainty else {
        return u;
    };
    if relation == Other::Independent {
        let add = |to: &mut PlaneCovariance, from: &PlaneCovariance| {
            let m = Matrix2::from_fn(|i, j| to.basis[i].dot(&from.basis[j]));
            to.covariance += m * from.covariance * m.transpose();
        };
        add(&mut p.axis, &u.axis);
        if let (Some(to), Some(from)) = (p.pivot.as_mut(), u.pivot.as_ref()) {
            add(to, from);
        }
    }
    let widen = |block: &mut PlaneCovariance, d: f64| {
        if d.is_finite() && d > 2.0 {
            block.covariance *= d / 2.0;
        }
    };
    match (joint, &other.joint) {
        (
            JointEstimate::Revolute { axis, pivot, .. },
            JointEstimate::Revolute {
                axis: a, pivot: q, ..
            },
        ) => {
            widen(&mut u.axis, p.axis_mahalanobis_squared(a, axis));
            if let (Some(block), Some(d)) = (
                u.pivot.as_mut(),
                p.pivot_mahalanobis_squared(q, a, pivot, axis),
            ) {
                widen(block, d);
            }
        }
        (JointEstimate::Prismatic { axis, .. }, JointEstimate::Prismatic { axis: a, .. }) => {
            widen(&mut u.axis, p.axis_mahalanobis_squared(a, axis));
        }
        _ => {}
    }
    u
}

/// BIC's approximation of the posterior probability of the model with `bic` against the one
/// with `other` (equal priors): `1 / (1 + exp((bic − other) / 2))`, finite for every input
/// (∞ against a finite BIC is 0, both ∞ or NaN is ½).
pub(crate) fn bic_probability(bic: f64, other: f64) -> f64 {
    let d = (bic - other) / 2.0;
    if d.is_nan() {
        return 0.5;
    }
    1.0 / (1.0 + d.exp())
}

/// An orthonormal basis `(e1, e2)` of the plane normal to `n`.
pub(crate) fn tangent_basis(n: &Unit<Vector3<f64>>) -> [Unit<Vector3<f64>>; 2] {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = Unit::new_normalize(n.cross(&helper));
    [e1, Unit::new_normalize(n.cross(&e1))]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal covariance: the half-angle is the larger σ times √χ², and an offset along
    /// the basis has Mahalanobis distance (x/σ)².
    #[test]
    fn regions_of_a_diagonal_covariance() {
        let axis = Vector3::z_axis();
        let basis = tangent_basis(&axis);
        let u = Uncertainty {
            type_probability: 0.9,
            axis: PlaneCovariance {
                basis,
                covariance: Matrix2::new(0.01f64.powi(2), 0.0, 0.0, 0.02f64.powi(2)),
            },
            pivot: Some(PlaneCovariance {
                basis,
                covariance: Matrix2::new(1e-4, 0.0, 0.0, 1e-4),
            }),
        };
        assert!((u.axis_half_angle_95() - 0.02 * CHI2_2DOF_95.sqrt()).abs() < 1e-12);
        assert!((u.pivot_radius_95().unwrap() - 0.01 * CHI2_2DOF_95.sqrt()).abs() < 1e-12);
        // Tilting the axis by 0.01 rad towards basis[0] is 1 σ along the first coordinate.
        let tilted = Unit::new_normalize(axis.into_inner() + basis[0].into_inner() * 0.01f64.tan());
        let d = u.axis_mahalanobis_squared(&axis, &tilted);
        assert!((d - 1.0).abs() < 1e-9, "{d}");
        // The opposite sign is the same line.
        assert!((u.axis_mahalanobis_squared(&axis, &-tilted) - d).abs() < 1e-12);
        // A parallel line 2 cm away along basis[1] is 2 σ: squared distance 4.
        let p = Point3::new(0.3, 0.1, 0.0);
        let q = p + basis[1].into_inner() * 0.02 + Vector3::z() * 5.0;
        let d = u.pivot_mahalanobis_squared(&p, &axis, &q, &axis).unwrap();
        assert!((d - 4.0).abs() < 1e-9, "{d}");
    }

    /// Two vertical hinges 3 cm apart, each with pivot covariance 1 cm² per axis and axis
    /// covariance 1e-4 rad²: independent, the difference has 2 cm² per axis, so `D = 0.03² /
    /// 2e-4 = 4.5` and the pivot block is scaled by 2.25; nested (the other's region alone),
    /// `D = 9`, scaled by 4.5; the axes agree (`D = 0`), so the axis block is unchanged; an
    /// other estimate of another type changes nothing.
    #[test]
    fn disagreement_widens_by_birges_ratio() {
        let axis = Vector3::z_axis();
        let basis = tangent_basis(&axis);
        let block = |v: f64| PlaneCovariance {
            basis,
            covariance: Matrix2::identity() * v,
        };
        let u = Uncertainty {
            type_probability: 0.99,
            axis: block(1e-4),
            pivot: Some(block(1e-4)),
        };
        let joint = JointEstimate::Revolute {
            axis,
            pivot: Point3::origin(),
            angle: 0.5,
        };
        let other = Estimate {
            joint: JointEstimate::Revolute {
                axis,
                pivot: Point3::new(0.03, 0.0, 0.2),
                angle: 0.5,
            },
            uncertainty: Some(u),
            ..Estimate::unknown("")
        };
        let scale = |w: Uncertainty| w.pivot.unwrap().covariance[(0, 0)] / 1e-4;
        let wide = consistent_with(u, &joint, &other, Other::Independent);
        assert!((scale(wide) - 2.25).abs() < 1e-9, "{}", scale(wide));
        assert_eq!(wide.axis, u.axis);
        let nested = consistent_with(u, &joint, &other, Other::Nested);
        assert!((scale(nested) - 4.5).abs() < 1e-9, "{}", scale(nested));
        let slide = Estimate {
            joint: JointEstimate::Prismatic {
                axis,
                distance: 0.1,
            },
            ..other
        };
        assert_eq!(consistent_with(u, &joint, &slide, Other::Independent), u);
    }

    /// The BIC probability is ½ at a tie, finite at the extremes.
    #[test]
    fn bic_probability_is_finite() {
        assert_eq!(bic_probability(3.0, 3.0), 0.5);
        assert!(bic_probability(0.0, 10.0) > 0.99);
        assert_eq!(bic_probability(f64::INFINITY, 1.0), 0.0);
        assert_eq!(bic_probability(1.0, f64::INFINITY), 1.0);
        assert_eq!(bic_probability(f64::INFINITY, f64::INFINITY), 0.5);
    }
}
