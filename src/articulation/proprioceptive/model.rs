//! The two joint models, a line and a circle, their residuals, and the hypotheses through a
//! minimal set of poses.

use nalgebra::{Isometry3, Point3, Unit, UnitQuaternion, Vector3};

use super::OrientationModel;

/// A joint hypothesis fitted to the end-effector poses.
#[derive(Debug, Clone, Copy)]
pub(super) enum Model {
    /// A line through `point` along `dir`; `grasp` is the constant end-effector orientation.
    Line {
        point: Point3<f64>,
        dir: Unit<Vector3<f64>>,
        grasp: UnitQuaternion<f64>,
    },
    /// A circle about the axis `normal` through `center`; the end effector's orientation is
    /// `Rot(normal, φ) · grasp`, `φ` the position's angle on the circle.
    Circle {
        center: Point3<f64>,
        normal: Unit<Vector3<f64>>,
        radius: f64,
        grasp: UnitQuaternion<f64>,
    },
}

/// Fixed in-plane basis `(e1, e2)` of a unit normal.
pub(super) fn basis(n: &Unit<Vector3<f64>>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = n.cross(&helper).normalize();
    (e1, n.cross(&e1))
}

impl Model {
    /// Number of free parameters (orientation offset included when used).
    pub(super) fn parameters(&self, orientation: OrientationModel) -> f64 {
        let extra = orientation.parameters();
        match self {
            Model::Line { .. } => 4.0 + extra,
            Model::Circle { .. } => 6.0 + extra,
        }
    }

    /// The angle of `p` on the circle (0 for a line).
    pub(super) fn phase(&self, p: &Point3<f64>) -> f64 {
        match self {
            Model::Line { .. } => 0.0,
            Model::Circle { center, normal, .. } => {
                let (e1, e2) = basis(normal);
                let w = p - center;
                w.dot(&e2).atan2(w.dot(&e1))
            }
        }
    }

    /// The orientation the model predicts for an end effector at `p`.
    fn orientation(&self, p: &Point3<f64>) -> UnitQuaternion<f64> {
        match self {
            Model::Line { grasp, .. } => *grasp,
            Model::Circle { normal, grasp, .. } => {
                UnitQuaternion::from_axis_angle(normal, self.phase(p)) * grasp
            }
        }
    }

    /// Position residual (m, 2-d: perpendicular to the line / off the circle) and orientation
    /// residual (rad) under `orientation`.
    pub(super) fn residual(
        &self,
        pose: &Isometry3<f64>,
        orientation: OrientationModel,
    ) -> (f64, f64) {
        let p = Point3::from(pose.translation.vector);
        let r = match self {
            Model::Line { point, dir, .. } => {
                let w = p - point;
                (w - dir.into_inner() * dir.dot(&w)).norm()
            }
            Model::Circle {
                center,
                normal,
                radius,
                ..
            } => {
                let w = p - center;
                let h = normal.dot(&w);
                let rho = (w - normal.into_inner() * h).norm();
                ((rho - radius).powi(2) + h * h).sqrt()
            }
        };
        (r, orientation.angle(&self.orientation(&p), &pose.rotation))
    }
}

pub(super) fn position(pose: &Isometry3<f64>) -> Point3<f64> {
    Point3::from(pose.translation.vector)
}

/// The line through two poses' positions.
pub(super) fn line_through(poses: &[Isometry3<f64>], idx: &[usize]) -> Option<Model> {
    let (a, b) = (position(&poses[idx[0]]), position(&poses[idx[1]]));
    let dir = Unit::try_new(b - a, 1e-9)?;
    Some(Model::Line {
        point: a,
        dir,
        grasp: poses[idx[0]].rotation,
    })
}

/// The circle through three poses' positions (`None` if they are nearly collinear).
pub(super) fn circle_through(poses: &[Isometry3<f64>], idx: &[usize]) -> Option<Model> {
    let [a, b, c] = [0, 1, 2].map(|k| position(&poses[idx[k]]));
    let (u, v) = (b - a, c - a);
    let w = u.cross(&v);
    let w2 = w.norm_squared();
    if w2 < 1e-12 * u.norm_squared() * v.norm_squared() || w2 == 0.0 {
        return None;
    }
    let center = a + (v.cross(&w) * u.norm_squared() + w.cross(&u) * v.norm_squared()) / (2.0 * w2);
    let normal = Unit::new_normalize(w);
    let radius = (a - center).norm();
    let mut model = Model::Circle {
        center,
        normal,
        radius,
        grasp: UnitQuaternion::identity(),
    };
    let grasp = UnitQuaternion::from_axis_angle(&normal, -model.phase(&a)) * poses[idx[0]].rotation;
    if let Model::Circle { grasp: g, .. } = &mut model {
        *g = grasp;
    }
    Some(model)
}
