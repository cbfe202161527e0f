//! The joint models of the fused fit: their parameters, motion and residuals.
//!
//! A state is one joint hypothesis with the nuisance parameters of the gripper's path. The
//! parameters are offsets around the state (re-centred after every step), so that the
//! covariance of the offsets is the covariance in the tangent planes [`Uncertainty`] uses.
//!
//! [`Uncertainty`]: crate::articulation::Uncertainty

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};

use crate::articulation::uncertainty::tangent_basis;

/// The joint type of a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Revolute,
    Prismatic,
}

/// A joint hypothesis with the path's nuisance parameters.
///
/// - Revolute: rotation by `travel` (rad) about the line through `pivot` (kept level with the
///   contact) along `axis`; the path lies on the circle of radius `path[0]` at height `path[1]`
///   above the pivot.
/// - Prismatic: translation by `travel` (m) along `axis`; the path is the line whose
///   coordinates in `tangent_basis(axis)` are `path`.
///
/// The approach axis is constant, `approach`, in the frame that moves with the gripper's
/// position: (radial, tangential, axis) about a revolute axis, `(e1, e2, axis)` for a
/// prismatic one.
///
/// Parameter offsets: `[tilt e1, tilt e2, pivot e1, pivot e2, travel, path 0..2, approach
/// b1, b2]` (revolute, 9) or `[tilt e1, tilt e2, travel, path 0..2, approach b1, b2]`
/// (prismatic, 7), `e1, e2 = tangent_basis(axis)`, `b1, b2 = tangent_basis(approach)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct State {
    pub(super) kind: Kind,
    pub(super) axis: Unit<Vector3<f64>>,
    pub(super) pivot: Point3<f64>,
    pub(super) travel: f64,
    pub(super) path: [f64; 2],
    pub(super) approach: Unit<Vector3<f64>>,
}

/// One pose of the path: the gripper's position and approach axis.
#[derive(Debug, Clone, Copy)]
pub(super) struct PathPose {
    pub(super) position: Point3<f64>,
    pub(super) approach: Vector3<f64>,
}

impl State {
    /// The number of free parameters.
    pub(super) fn parameters(&self) -> usize {
        match self.kind {
            Kind::Revolute => 9,
            Kind::Prismatic => 7,
        }
    }

    /// The state at parameter offsets `d`; a revolute pivot is moved back level with
    /// `contact` (the path height follows it).
    pub(super) fn perturbed(&self, d: &[f64], contact: &Point3<f64>) -> State {
        let [e1, e2] = tangent_basis(&self.axis);
        let axis = Unit::new_normalize(
            self.axis.into_inner() + e1.into_inner() * d[0] + e2.into_inner() * d[1],
        );
        let tilt_approach = |a: f64, b: f64| {
            let [b1, b2] = tangent_basis(&self.approach);
            Unit::new_normalize(
                self.approach.into_inner() + b1.into_inner() * a + b2.into_inner() * b,
            )
        };
        match self.kind {
            Kind::Revolute => {
                let moved = self.pivot + e1.into_inner() * d[2] + e2.into_inner() * d[3];
                let pivot = moved + axis.into_inner() * axis.dot(&(contact - moved));
                let path = [
                    self.path[0] + d[5],
                    self.path[1] + d[6] - axis.dot(&(pivot - moved)),
                ];
                State {
                    axis,
                    pivot,
                    travel: self.travel + d[4],
                    path,
                    approach: tilt_approach(d[7], d[8]),
                    ..*self
                }
            }
            Kind::Prismatic => State {
                axis,
                travel: self.travel + d[2],
                path: [self.path[0] + d[3], self.path[1] + d[4]],
                approach: tilt_approach(d[5], d[6]),
                ..*self
            },
        }
    }

    /// The part's motion pre → post.
    pub(super) fn motion(&self) -> Isometry3<f64> {
        match self.kind {
            Kind::Revolute => {
                let r = UnitQuaternion::from_axis_angle(&self.axis, self.travel);
                Translation3::from(self.pivot.coords) * r * Translation3::from(-self.pivot.coords)
            }
            Kind::Prismatic => {
                let t = self.axis.into_inner() * self.travel;
                Isometry3::translation(t.x, t.y, t.z)
            }
        }
    }

    /// The path's 4 normalised residuals of `pose`: the position's offset from the circle or
    /// line (2, over `sigma_p`), the approach axis's deviation from `approach` (2, over
    /// `sigma_o`).
    pub(super) fn pose_residuals(&self, pose: &PathPose, sigma_p: f64, sigma_o: f64) -> [f64; 4] {
        let (position, local) = self.local(pose);
        let [b1, b2] = tangent_basis(&self.approach);
        [
            (position[0] - self.path[0]) / sigma_p,
            (position[1] - self.path[1]) / sigma_p,
            b1.dot(&local) / sigma_o,
            b2.dot(&local) / sigma_o,
        ]
    }

    /// The pose in the frame moving with the gripper's position: the position's two
    /// coordinates the path fixes (distance from the axis and height, or the coordinates
    /// across the line) and the approach axis's components.
    fn local(&self, pose: &PathPose) -> ([f64; 2], Vector3<f64>) {
        let (x, z) = (&pose.position, &pose.approach);
        match self.kind {
            Kind::Revolute => {
                let (radial, tangential, rho, h) = self.ring(x);
                let local = Vector3::new(z.dot(&radial), z.dot(&tangential), self.axis.dot(z));
                ([rho, h], local)
            }
            Kind::Prismatic => {
                let [e1, e2] = tangent_basis(&self.axis);
                let local = Vector3::new(e1.dot(z), e2.dot(z), self.axis.dot(z));
                ([e1.dot(&x.coords), e2.dot(&x.coords)], local)
            }
        }
    }

    /// A position's radial and tangential directions about the axis, its distance from the
    /// axis and height above the pivot.
    fn ring(&self, x: &Point3<f64>) -> (Vector3<f64>, Vector3<f64>, f64, f64) {
        let v = x - self.pivot;
        let h = self.axis.dot(&v);
        let w = v - self.axis.into_inner() * h;
        let rho = w.norm();
        let radial = if rho > 0.0 { w / rho } else { Vector3::zeros() };
        (radial, self.axis.cross(&radial), rho, h)
    }

    /// The travel the path shows from the mean of the `head` poses to that of the `tail`
    /// ones: the signed angle about the axis between their mean radial directions, or the
    /// distance along the axis between their mean positions.
    pub(super) fn path_travel(&self, head: &[PathPose], tail: &[PathPose]) -> f64 {
        let mean = |ps: &[PathPose]| {
            ps.iter().map(|p| p.position.coords).sum::<Vector3<f64>>() / ps.len().max(1) as f64
        };
        let (a, b) = (Point3::from(mean(head)), Point3::from(mean(tail)));
        match self.kind {
            Kind::Revolute => {
                let (ua, _, _, _) = self.ring(&a);
                let (ub, _, _, _) = self.ring(&b);
                self.axis.dot(&ua.cross(&ub)).atan2(ua.dot(&ub))
            }
            Kind::Prismatic => self.axis.dot(&(b - a)),
        }
    }

    /// The path parameters and approach that fit `poses` best for this joint (their means),
    /// in place.
    pub(super) fn fit_path(&mut self, poses: &[PathPose]) {
        let n = poses.len().max(1) as f64;
        let (mut path, mut approach) = (Vector3::zeros(), Vector3::zeros());
        for p in poses {
            let (position, local) = self.local(p);
            path += Vector3::new(position[0], position[1], 0.0);
            approach += local;
        }
        self.path = [path.x / n, path.y / n];
        if let Some(a) = Unit::try_new(approach, 1e-12) {
            self.approach = a;
        }
    }

    /// What turns a position error into a travel error: the path's circle radius (m per
    /// rad), 1 for a prismatic joint (whose travel is a length).
    pub(super) fn travel_scale(&self) -> f64 {
        match self.kind {
            Kind::Revolute => self.path[0].abs(),
            Kind::Prismatic => 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Poses turning with a door about z through (0, 0, 0): zero residuals at the true state,
    /// and the path's travel is the turned angle.
    #[test]
    fn a_true_revolute_state_explains_its_path() {
        let contact = Point3::new(0.4, 0.0, 0.5);
        let poses: Vec<PathPose> = (0..10)
            .map(|k| {
                let r = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.03 * k as f64);
                PathPose {
                    position: r * contact,
                    approach: r * Vector3::y(),
                }
            })
            .collect();
        let mut s = State {
            kind: Kind::Revolute,
            axis: Vector3::z_axis(),
            pivot: Point3::new(0.0, 0.0, 0.5),
            travel: 0.27,
            path: [0.0; 2],
            approach: Vector3::z_axis(),
        };
        s.fit_path(&poses);
        assert!((s.path[0] - 0.4).abs() < 1e-12 && s.path[1].abs() < 1e-12);
        for p in &poses {
            assert!(
                s.pose_residuals(p, 0.001, 0.01)
                    .iter()
                    .all(|r| r.abs() < 1e-9)
            );
        }
        assert!((s.path_travel(&poses[..1], &poses[9..]) - 0.27).abs() < 1e-12);
        // The motion maps the first pose's position onto the last's.
        assert!((s.motion() * poses[0].position - poses[9].position).norm() < 1e-12);
        // A pivot offset along the axis is moved back level with the contact.
        let p = s.perturbed(&[0.0; 9], &(contact + Vector3::z() * 0.2));
        assert!((p.pivot.z - 0.7).abs() < 1e-12 && (p.path[1] + 0.2).abs() < 1e-12);
    }
}
