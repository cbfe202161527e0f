//! Registration (step 3), model selection (step 4) and refinement (step 5) of the two-view
//! estimator: ICP of the part's points onto the post cloud under a rigid motion, then under a
//! rotation and a translation scored by BIC and the contact-path check, the chosen one refined.

use std::collections::HashSet;

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, Unit, UnitQuaternion, Vector3};

use super::TwoViewSettings;
use super::change::{Changes, median, voxel_subset};
use crate::articulation::cloud::centroid;
use crate::articulation::estimate::{Interaction, JointEstimate};
use crate::articulation::icp::{
    IcpSettings, MotionModel, NormalCache, Registration, icp, refine_translation, truncated_cost,
};
use crate::articulation::kdtree::KdTree;
use crate::articulation::screw::Screw;

/// ICP of the part's points onto the whole post cloud, with the contact pair weighted in.
pub(super) struct Fitter<'a> {
    /// The part points ICP registers: one per `icp_voxel` cube, evenly strided to at most
    /// `max_icp_points`.
    pub(super) sample: Vec<Point3<f64>>,
    post: &'a [Point3<f64>],
    post_tree: &'a KdTree,
    /// The contact pair `c_pre → c_post`.
    pub(super) contact: Option<(Point3<f64>, Point3<f64>)>,
    pub(super) settings: IcpSettings,
}

impl<'a> Fitter<'a> {
    /// The fitter of the part points `source`.
    pub(super) fn new(
        s: &TwoViewSettings,
        i: &Interaction<'_>,
        c: &'a Changes<'_>,
        source: &[Point3<f64>],
    ) -> Self {
        let tau = c.tau;
        // ICP runs on one point per `icp_voxel` cube, evenly strided to at most `max_icp_points`.
        let thinned = voxel_subset(source, s.icp_voxel);
        let stride = thinned.len().div_ceil(s.max_icp_points).max(1);
        let sample: Vec<Point3<f64>> = thinned.iter().step_by(stride).copied().collect();
        let settings = IcpSettings {
            stages: [
                (4.0 * s.max_correspondence_distance).max(0.1),
                (2.0 * s.max_correspondence_distance).max(2.0 * tau),
                s.max_correspondence_distance.max(tau),
            ],
            iterations: s.icp_iterations,
            trim_fraction: s.trim_fraction,
            extra_weight: s.contact_weight,
        };
        Fitter {
            sample,
            post: c.post,
            post_tree: &c.post_tree,
            contact: Some((i.contact_pre, i.contact_post)),
            settings,
        }
    }

    /// The sample registered under `model` from `init`.
    fn fit(&self, init: Isometry3<f64>, model: MotionModel) -> Option<Registration> {
        icp(
            &self.sample,
            self.post,
            self.post_tree,
            init,
            self.contact,
            model,
            &self.settings,
        )
    }
}

/// The initial guesses of the registration: the contact translation, and (when the new post
/// points at the contact are enough) the rotation taking the part's pre plane normal to the
/// post segment's normal combined with the contact translation.
pub(super) fn initial_guesses(
    s: &TwoViewSettings,
    i: &Interaction<'_>,
    post: &[Point3<f64>],
    source: &[Point3<f64>],
    part_post: &[usize],
) -> Vec<Isometry3<f64>> {
    let shift = i.contact_post - i.contact_pre;
    let mut inits = vec![Isometry3::translation(shift.x, shift.y, shift.z)];
    if part_post.len() >= s.min_part_points {
        let target: Vec<Point3<f64>> = part_post.iter().map(|&k| post[k]).collect();
        if let Some(r) = normal_rotation(source, &i.pre.origin, &target, &i.post.origin) {
            let t = i.contact_post.coords - r * i.contact_pre.coords;
            inits.push(Isometry3::from_parts(Translation3::from(t), r));
        }
    }
    inits
}

/// Step 3: the rigid registration of the lower truncated cost from `inits`; `Err` when there
/// is none or it moves no part point of `source` by `min_motion`.
pub(super) fn register(
    s: &TwoViewSettings,
    fitter: &Fitter<'_>,
    source: &[Point3<f64>],
    inits: &[Isometry3<f64>],
) -> Result<Registration, String> {
    let Some(rigid) = inits
        .iter()
        .filter_map(|init| fitter.fit(*init, MotionModel::Rigid))
        .min_by(|a, b| a.cost.total_cmp(&b.cost))
    else {
        return Err("registration found no correspondences".into());
    };
    let moved = source
        .iter()
        .map(|p| (rigid.motion * p - p).norm())
        .fold(0.0, f64::max);
    if moved < s.min_motion {
        return Err(format!(
            "too little motion: the part moves at most {moved:.4} m (need {} m)",
            s.min_motion
        ));
    }
    Ok(rigid)
}

/// The joint model chosen in step 4, with what chose it.
pub(super) struct Selection {
    /// Whether the rotation won.
    pub(super) revolute: bool,
    /// The chosen model's registration.
    pub(super) chosen: Registration,
    /// BIC of the rotation and of the translation (∞ if not registered).
    pub(super) bic_r: f64,
    pub(super) bic_p: f64,
    /// Path residuals (m) of the rotation and of the translation (NaN without enough poses).
    pub(super) path_r: f64,
    pub(super) path_p: f64,
    /// Whether the contact-path check overruled BIC.
    pub(super) forced: bool,
    /// The model-selection margin: the BIC difference, or 10 when the path decided.
    pub(super) margin: f64,
    /// The occupied τ-voxels that count as evidence.
    pub(super) n_eff: f64,
}

/// Step 4: the rotation and the translation fitted from the rigid motion `rigid` (the
/// translation also from the contact translation `shift`), each scored by BIC on all part
/// points `source`; the lower BIC wins unless the contact-path check decides. `Err` when
/// neither could be registered.
pub(super) fn select(
    s: &TwoViewSettings,
    i: &Interaction<'_>,
    c: &Changes<'_>,
    fitter: &Fitter<'_>,
    source: &[Point3<f64>],
    rigid: &Registration,
    shift: Isometry3<f64>,
) -> Result<Selection, String> {
    let tau = c.tau;
    // Residuals of neighbouring points are correlated (sampling pattern, surface noise), so the
    // evidence counts occupied τ-voxels rather than points.
    let voxels: HashSet<[i64; 3]> = source
        .iter()
        .map(|p| p.coords.map(|c| (c / tau).floor() as i64).into())
        .collect();
    let n_eff = voxels.len().max(1) as f64;
    let bic = |cost: f64, k: f64| n_eff * cost.max(1e-12).ln() + k * n_eff.ln();
    let rotation = fitter.fit(rigid.motion, MotionModel::Rotation);
    // The translation also starts from the contact's shift: a rigid fit that turned the part
    // (a drawer's front mapped onto its own top, say) can leave the translation from its
    // motion without correspondences.
    let translation = [rigid.motion, shift]
        .into_iter()
        .filter_map(|init| fitter.fit(init, MotionModel::Translation))
        .min_by(|a, b| a.cost.total_cmp(&b.cost));
    // Both models are scored on all part points, not the ICP subset.
    let full_cost = |r: &Registration| {
        truncated_cost(source, &c.post_tree, &r.motion, fitter.settings.stages[2])
    };
    let bic_r = rotation
        .as_ref()
        .map_or(f64::INFINITY, |r| bic(full_cost(r), 5.0));
    let bic_p = translation
        .as_ref()
        .map_or(f64::INFINITY, |r| bic(full_cost(r), 3.0));
    let (path_r, path_p, path_poses) = path_check(s, i, &rotation, &translation);
    let (fits_r, fits_p) = (path_r <= s.path_tolerance, path_p <= s.path_tolerance);
    let forced = path_poses && fits_r != fits_p;
    let revolute = match (&rotation, &translation) {
        (Some(_), Some(_)) if forced => fits_r,
        (Some(_), Some(_)) => bic_r < bic_p,
        (Some(_), None) => true,
        (None, Some(_)) => false,
        (None, None) => return Err("neither joint model could be registered".into()),
    };
    // The path check overrules BIC only when they disagree.
    let forced = forced && revolute != (bic_r < bic_p);
    // The score's model-selection margin: the BIC difference, or 10 when the path decided.
    let margin = if forced { 10.0 } else { (bic_p - bic_r).abs() };
    let chosen = if revolute { rotation } else { translation }
        .expect("the chosen model was registered (checked in the match above)");
    Ok(Selection {
        revolute,
        chosen,
        bic_r,
        bic_p,
        path_r,
        path_p,
        forced,
        margin,
        n_eff,
    })
}

/// The contact-path check: the path residuals of the rotation and of the translation (∞ for a
/// model not registered), and whether there are enough end-effector poses (`min_path_poses`)
/// for the check; NaN residuals when there are not.
fn path_check(
    s: &TwoViewSettings,
    i: &Interaction<'_>,
    rotation: &Option<Registration>,
    translation: &Option<Registration>,
) -> (f64, f64, bool) {
    // Each model predicts where the end effector went.
    let path: Vec<Point3<f64>> = i
        .ee_poses
        .iter()
        .map(|(_, p)| Point3::from(p.translation.vector))
        .collect();
    let path_fit = |r: &Option<Registration>, model| {
        r.as_ref()
            .map(|r| path_residual(&r.motion, model, &path))
            .unwrap_or(f64::INFINITY)
    };
    if path.len() >= s.min_path_poses {
        (
            path_fit(rotation, MotionModel::Rotation),
            path_fit(translation, MotionModel::Translation),
            true,
        )
    } else {
        (f64::NAN, f64::NAN, false)
    }
}

/// Step 5: the chosen model registered again on the ICP points its motion explains (a post
/// neighbour within τ; the static surfaces hidden in the post view, which no motion explains,
/// drop out): a rotation by the same ICP at the final limit, a translation by point-to-plane
/// ICP. Unchanged with fewer than `min_part_points` such points.
pub(super) fn refine(
    s: &TwoViewSettings,
    c: &Changes<'_>,
    fitter: &Fitter<'_>,
    chosen: Registration,
    revolute: bool,
) -> Registration {
    let tau = c.tau;
    let explained: Vec<Point3<f64>> = fitter
        .sample
        .iter()
        .filter(|p| c.to_post(&(chosen.motion * *p)) <= tau)
        .copied()
        .collect();
    if explained.len() < s.min_part_points {
        chosen
    } else if revolute {
        let fine = IcpSettings {
            stages: [tau; 3],
            ..fitter.settings
        };
        icp(
            &explained,
            c.post,
            &c.post_tree,
            chosen.motion,
            fitter.contact,
            MotionModel::Rotation,
            &fine,
        )
        .unwrap_or(chosen)
    } else {
        let normals = NormalCache::new(c.post, &c.post_tree, s.neighbor_radius * 1.2);
        let t = refine_translation(
            &explained,
            c.post,
            &c.post_tree,
            &normals,
            chosen.motion.translation.vector,
            fitter.contact,
            tau,
            s,
        );
        Registration {
            motion: Isometry3::translation(t.x, t.y, t.z),
            cost: chosen.cost,
        }
    }
}

/// The joint of the chosen `motion`: the screw's axis through the point nearest the contact
/// `contact_pre` and its angle, or the translation's direction and length.
pub(super) fn joint_of(
    motion: &Isometry3<f64>,
    revolute: bool,
    contact_pre: &Point3<f64>,
) -> JointEstimate {
    let screw = Screw::from_isometry(motion);
    if revolute {
        JointEstimate::Revolute {
            axis: screw.axis,
            pivot: screw.closest_axis_point(contact_pre),
            angle: screw.angle,
        }
    } else {
        let (axis, distance) = Unit::new_and_get(motion.translation.vector);
        JointEstimate::Prismatic { axis, distance }
    }
}

/// The median distance of the recorded end-effector positions `path` from the path the joint
/// model `motion` predicts for them, through the path's start (the coordinate-wise median of
/// its first 5 % of positions, 1 to 5 of them): for [`MotionModel::Rotation`] the circle about the screw axis
/// (distance in the (radius, height) half-plane around the axis), for
/// [`MotionModel::Translation`] the line along the translation. A gripper holding the part moves
/// rigidly with it, so every point of the gripper follows such a path whatever the grasp offset.
fn path_residual(motion: &Isometry3<f64>, model: MotionModel, path: &[Point3<f64>]) -> f64 {
    if path.is_empty() {
        return f64::INFINITY;
    }
    let head = &path[..path.len().div_ceil(20).clamp(1, 5)];
    let start = Point3::from(Vector3::from_fn(|k, _| {
        median(&head.iter().map(|p| p[k]).collect::<Vec<_>>())
    }));
    let distances: Vec<f64> = match model {
        MotionModel::Rotation => {
            let screw = Screw::from_isometry(motion);
            let ring = |p: &Point3<f64>| {
                let v = p - screw.point;
                let h = screw.axis.dot(&v);
                ((v - screw.axis.into_inner() * h).norm(), h)
            };
            let (r0, h0) = ring(&start);
            path.iter()
                .map(|p| {
                    let (r, h) = ring(p);
                    (r - r0).hypot(h - h0)
                })
                .collect()
        }
        MotionModel::Translation | MotionModel::Rigid => {
            let dir = motion
                .translation
                .vector
                .try_normalize(1e-12)
                .unwrap_or_else(Vector3::zeros);
            path.iter()
                .map(|p| {
                    let d = p - start;
                    (d - dir * dir.dot(&d)).norm()
                })
                .collect()
        }
    };
    median(&distances)
}

/// The smallest rotation taking the plane normal of `a` (oriented toward `origin_a`) to that of
/// `b` (oriented toward `origin_b`); `None` if either normal is ill-defined.
fn normal_rotation(
    a: &[Point3<f64>],
    origin_a: &Point3<f64>,
    b: &[Point3<f64>],
    origin_b: &Point3<f64>,
) -> Option<UnitQuaternion<f64>> {
    let na = plane_normal(a, origin_a)?;
    let nb = plane_normal(b, origin_b)?;
    UnitQuaternion::rotation_between(&na, &nb)
}

/// The least-squares plane normal of `points` (smallest principal axis), toward `origin`.
fn plane_normal(points: &[Point3<f64>], origin: &Point3<f64>) -> Option<Vector3<f64>> {
    let c = centroid(points);
    let mut cov = Matrix3::zeros();
    for p in points {
        let d = p - c;
        cov += d * d.transpose();
    }
    let eig = cov.symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|&x, &y| eig.eigenvalues[x].total_cmp(&eig.eigenvalues[y]));
    // A plane needs a clearly smallest spread.
    if eig.eigenvalues[order[0]] > 0.25 * eig.eigenvalues[order[1]] {
        return None;
    }
    let n = eig.eigenvectors.column(order[0]).into_owned();
    Some(if n.dot(&(origin - c)) < 0.0 { -n } else { n })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight path fits the translation model and misses a 90° rotation that maps its ends
    /// onto each other; an arc fits its own rotation and misses the chord's translation.
    #[test]
    fn path_residual_tells_lines_from_arcs() {
        // Straight 0.3 m along -y.
        let line: Vec<Point3<f64>> = (0..16)
            .map(|k| Point3::new(0.3, -0.05 - 0.02 * k as f64, 0.6))
            .collect();
        let translation = Isometry3::translation(0.0, -0.3, 0.0);
        assert!(path_residual(&translation, MotionModel::Translation, &line) < 1e-12);
        // The 90° rotation about the vertical line through the chord's apex (0.15 m from the
        // chord's middle) maps the start onto the end.
        let screw = Screw {
            axis: Vector3::z_axis(),
            point: Point3::new(0.45, -0.2, 0.0),
            angle: std::f64::consts::FRAC_PI_2,
            translation: 0.0,
        };
        let rotation = screw.to_isometry();
        assert!((rotation * line[0] - line[15]).norm() < 1e-9);
        // Radius 0.212 m, the chord's middle 0.15 m from the axis: the median point of the path
        // is ≈ 0.045 m off the circle.
        let miss = path_residual(&rotation, MotionModel::Rotation, &line);
        assert!(miss > 0.03, "{miss}");
        // The arc itself.
        let arc: Vec<Point3<f64>> = (0..16)
            .map(|k| {
                let partial = Screw {
                    angle: screw.angle * k as f64 / 15.0,
                    ..screw
                };
                partial.to_isometry() * line[0]
            })
            .collect();
        assert!(path_residual(&rotation, MotionModel::Rotation, &arc) < 1e-9);
        let chord = Isometry3::translation(0.0, -0.3, 0.0);
        assert!(path_residual(&chord, MotionModel::Translation, &arc) > 0.03);
    }
}
