//! The starts of the joint fit: the two single-source estimates, the rigid registration's
//! screw, and closed-form fits to the path (an algebraic circle about each candidate axis,
//! the path's principal direction).

use nalgebra::{Isometry3, Matrix3, Point3, Unit, Vector2, Vector3};

use super::model::{Kind, PathPose, State};
use crate::articulation::estimate::{Estimate, JointEstimate};
use crate::articulation::proprioceptive::kasa_circle;
use crate::articulation::screw::Screw;
use crate::articulation::uncertainty::tangent_basis;

/// What the starts are built from.
pub(super) struct Sources<'a> {
    pub(super) two_view: &'a Estimate,
    pub(super) proprioceptive: &'a Estimate,
    pub(super) rigid: Isometry3<f64>,
    pub(super) poses: &'a [PathPose],
    pub(super) contact_pre: Point3<f64>,
    pub(super) contact_post: Point3<f64>,
}

/// The revolute starts: the estimates' and the rigid screw's axes with their pivots and
/// angles, and for each of those axes and the axis the approach turned about, the algebraic
/// circle through the path's positions (its centre as the pivot, the angle the path swept).
pub(super) fn revolute(src: &Sources<'_>) -> Vec<State> {
    let mut lines: Vec<(Unit<Vector3<f64>>, Point3<f64>, f64)> = Vec::new();
    for e in [src.two_view, src.proprioceptive] {
        if let JointEstimate::Revolute { axis, pivot, angle } = e.joint {
            lines.push((axis, pivot, angle));
        }
    }
    let screw = Screw::from_isometry(&src.rigid);
    if screw.angle > 0.5f64.to_radians() {
        lines.push((screw.axis, screw.point, screw.angle));
    }
    let mut axes: Vec<Unit<Vector3<f64>>> = lines.iter().map(|l| l.0).collect();
    axes.extend(approach_turn(src.poses));
    let mut out: Vec<State> = lines
        .iter()
        .map(|&(axis, pivot, angle)| state(Kind::Revolute, axis, pivot, angle, src))
        .collect();
    for axis in axes {
        if let Some(center) = algebraic_circle(src.poses, &axis) {
            let mut s = state(Kind::Revolute, axis, center, 0.0, src);
            let n = src.poses.len();
            s.travel = s.path_travel(&src.poses[..1], &src.poses[n - 1..]);
            out.push(s);
        }
    }
    out
}

/// The prismatic starts: the estimates' directions, the contact's displacement and the
/// path's principal direction, each with the travel the contacts show along it (the
/// estimate's own where it has one).
pub(super) fn prismatic(src: &Sources<'_>) -> Vec<State> {
    let shift = src.contact_post - src.contact_pre;
    let mut out = Vec::new();
    for e in [src.two_view, src.proprioceptive] {
        if let JointEstimate::Prismatic { axis, distance } = e.joint {
            out.push(state(Kind::Prismatic, axis, src.contact_pre, distance, src));
        }
    }
    let mut dirs: Vec<Unit<Vector3<f64>>> = Unit::try_new(shift, 1e-9).into_iter().collect();
    dirs.extend(principal_direction(src.poses));
    for d in dirs {
        let d = if d.dot(&shift) < 0.0 { -d } else { d };
        out.push(state(
            Kind::Prismatic,
            d,
            src.contact_pre,
            d.dot(&shift),
            src,
        ));
    }
    out
}

/// A state with its pivot level with the contact and the path parameters fitted.
fn state(
    kind: Kind,
    axis: Unit<Vector3<f64>>,
    point: Point3<f64>,
    travel: f64,
    src: &Sources<'_>,
) -> State {
    let c = src.contact_pre;
    let mut s = State {
        kind,
        axis,
        pivot: point + axis.into_inner() * axis.dot(&(c - point)),
        travel,
        path: [0.0; 2],
        approach: Vector3::z_axis(),
    };
    s.fit_path(src.poses);
    s
}

/// The axis the approach direction turned about from the first to the last pose (the
/// cross product of their mean approach axes over the first and last tenth), if it turned
/// by more than 1°.
fn approach_turn(poses: &[PathPose]) -> Option<Unit<Vector3<f64>>> {
    let m = poses.len().div_ceil(10).max(1);
    let mean = |ps: &[PathPose]| ps.iter().map(|p| p.approach).sum::<Vector3<f64>>();
    let (a, b) = (mean(&poses[..m]), mean(&poses[poses.len() - m..]));
    let c = a.cross(&b);
    (c.norm() > 1f64.to_radians().sin() * a.norm() * b.norm()).then(|| Unit::new_normalize(c))
}

/// The algebraic (Kåsa) circle through the positions projected on the plane normal to
/// `axis`: its centre (in the plane of the positions' mean height), `None` when degenerate.
fn algebraic_circle(poses: &[PathPose], axis: &Unit<Vector3<f64>>) -> Option<Point3<f64>> {
    let [e1, e2] = tangent_basis(axis);
    let q: Vec<Vector2<f64>> = poses
        .iter()
        .map(|p| Vector2::new(e1.dot(&p.position.coords), e2.dot(&p.position.coords)))
        .collect();
    let (centre, _) = kasa_circle(&q)?;
    let height = poses
        .iter()
        .map(|p| axis.dot(&p.position.coords))
        .sum::<f64>()
        / poses.len() as f64;
    let c = e1.into_inner() * centre.x + e2.into_inner() * centre.y + axis.into_inner() * height;
    c.iter().all(|v| v.is_finite()).then_some(Point3::from(c))
}

/// The principal direction of the positions, oriented from the first to the last.
fn principal_direction(poses: &[PathPose]) -> Option<Unit<Vector3<f64>>> {
    let n = poses.len() as f64;
    let mean = poses
        .iter()
        .map(|p| p.position.coords)
        .sum::<Vector3<f64>>()
        / n;
    let scatter: Matrix3<f64> = poses
        .iter()
        .map(|p| (p.position.coords - mean) * (p.position.coords - mean).transpose())
        .sum();
    let eig = scatter.symmetric_eigen();
    let (i, _) = eig.eigenvalues.argmax();
    let d = Unit::try_new(eig.eigenvectors.column(i).into_owned(), 1e-12)?;
    let span = poses.last()?.position - poses.first()?.position;
    Some(if d.dot(&span) < 0.0 { -d } else { d })
}
