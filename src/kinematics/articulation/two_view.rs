//! The two-view estimator: segment the moving part, register it rigidly, decompose the motion.

use std::collections::HashSet;

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, Unit, UnitQuaternion, Vector3};

use super::cloud::centroid;
use super::error::ArticulationError;
use super::estimate::{ArticulationEstimator, Estimate, Interaction, JointEstimate};
use super::icp::{
    IcpSettings, MotionModel, NormalCache, Registration, icp, refine_translation, truncated_cost,
};
use super::kdtree::KdTree;
use super::screw::Screw;
use super::visibility::RangeImage;
use crate::InvalidSetting;

/// Settings of [`TwoView`]. Lengths in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoViewSettings {
    /// Smallest distance at which a pre point with no post point nearer counts as changed.
    pub change_distance: f64,
    /// The change threshold is at least this multiple of the median pre → post nearest-neighbour
    /// distance (a noise scale measured on the mostly static scene).
    pub noise_multiplier: f64,
    /// Connectivity radius of the region growing.
    pub neighbor_radius: f64,
    /// Changed points within this distance of a contact seed their region.
    pub seed_radius: f64,
    /// Fewer segmented points than this gives [`Unknown`](super::JointEstimate::Unknown).
    pub min_part_points: usize,
    /// A fitted motion that moves no part point farther than this gives `Unknown`.
    pub min_motion: f64,
    /// ICP iterations per stage.
    pub icp_iterations: usize,
    /// Fraction of correspondences ICP keeps each step (the closest ones), in (0, 1].
    pub trim_fraction: f64,
    /// Largest correspondence distance of the final ICP stage.
    pub max_correspondence_distance: f64,
    /// Angular bin (rad) of the post cloud's range image used to tell occluded from vacated
    /// space; about twice the sensor's angular resolution.
    pub visibility_bin: f64,
    /// ICP registers one part point per cube of this side (m; 0 keeps every point), then an
    /// evenly strided subset of at most `max_icp_points` of those.
    pub icp_voxel: f64,
    /// ICP registers an evenly strided subset of at most this many part points.
    pub max_icp_points: usize,
    /// Weight of the contact pair `c_pre → c_post` relative to all point pairs, in [0, 1).
    pub contact_weight: f64,
    /// Contact-path check of model selection: a joint model whose predicted end-effector path
    /// misses the recorded positions by more than this median distance (m) is rejected when
    /// the other model's path does not (see [`TwoView`]).
    pub path_tolerance: f64,
    /// The contact-path check needs at least this many end-effector poses.
    pub min_path_poses: usize,
}

impl Default for TwoViewSettings {
    fn default() -> Self {
        TwoViewSettings {
            change_distance: 0.015,
            noise_multiplier: 4.0,
            neighbor_radius: 0.025,
            seed_radius: 0.06,
            min_part_points: 50,
            min_motion: 0.015,
            icp_iterations: 30,
            trim_fraction: 0.8,
            max_correspondence_distance: 0.03,
            visibility_bin: 0.01,
            icp_voxel: 0.012,
            max_icp_points: 4000,
            contact_weight: 0.05,
            path_tolerance: 0.02,
            min_path_poses: 5,
        }
    }
}

impl TwoViewSettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`ArticulationError::InvalidSetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ArticulationError> {
        let positive = [
            ("change_distance", self.change_distance),
            ("noise_multiplier", self.noise_multiplier),
            ("neighbor_radius", self.neighbor_radius),
            ("seed_radius", self.seed_radius),
            ("min_motion", self.min_motion),
            (
                "max_correspondence_distance",
                self.max_correspondence_distance,
            ),
            ("path_tolerance", self.path_tolerance),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(InvalidSetting::new(name, value, "finite and > 0").into());
            }
        }
        if !(self.icp_voxel.is_finite() && self.icp_voxel >= 0.0) {
            return Err(InvalidSetting::new("icp_voxel", self.icp_voxel, "finite and ≥ 0").into());
        }
        if !(self.trim_fraction > 0.0 && self.trim_fraction <= 1.0) {
            return Err(
                InvalidSetting::new("trim_fraction", self.trim_fraction, "in (0, 1]").into(),
            );
        }
        if !(self.contact_weight >= 0.0 && self.contact_weight < 1.0) {
            return Err(
                InvalidSetting::new("contact_weight", self.contact_weight, "in [0, 1)").into(),
            );
        }
        for (name, value) in [
            ("min_part_points", self.min_part_points),
            ("icp_iterations", self.icp_iterations),
            ("max_icp_points", self.max_icp_points),
            ("min_path_poses", self.min_path_poses),
        ] {
            if value == 0 {
                return Err(InvalidSetting::new(name, 0.0, "≥ 1").into());
            }
        }
        Ok(())
    }
}

/// The two-view estimator (see the module docs of [`super`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TwoView {
    /// Its settings.
    pub settings: TwoViewSettings,
}

impl ArticulationEstimator for TwoView {
    fn name(&self) -> &str {
        "two-view"
    }

    /// # Errors
    /// Bad input ([`Interaction::validate`]) or bad settings ([`TwoViewSettings::validate`]).
    fn estimate(&self, interaction: &Interaction<'_>) -> Result<Estimate, ArticulationError> {
        interaction.validate()?;
        self.settings.validate()?;
        Ok(estimate(&self.settings, interaction))
    }
}

/// The rule, step by step:
///
/// 1. **Change detection.** A pre point is *changed* when no post point lies within
///    `τ = max(change_distance, noise_multiplier · median pre→post nearest-neighbour distance)`;
///    symmetrically a post point is *new*.
/// 2. **Segmentation seed.** Region growing (connectivity `neighbor_radius`) over changed pre
///    points from those within `seed_radius` of `c_pre` (or the changed point nearest to it);
///    likewise new post points from `c_post`.
/// 3. **Registration.** Trimmed ICP of the segmented pre points (one per `icp_voxel` cube) to
///    the whole post cloud, with the contact pair `c_pre → c_post` weighted in, from two initial
///    guesses: the contact translation, and the rotation taking the segment's pre plane normal
///    to the post segment's normal combined with the contact translation. The lower truncated
///    cost wins.
/// 4. **Model selection.** From the rigid motion, ICP fits the two joint models (pure rotation
///    about a line, 5 parameters; pure translation, 3 parameters, also from the contact's
///    shift, the lower cost kept); each gets
///    `BIC = n ln(RSS/N) + k ln n` from the mean truncated squared residual `RSS/N` of the `N`
///    part points, where `n` counts the `τ`-voxels the part occupies (neighbouring residuals are
///    correlated, so `N` would overstate the evidence); the lower BIC wins, unless the
///    **contact-path check** decides: with at least `min_path_poses` end-effector poses, each
///    model predicts the gripper's path (a circle about the fitted axis, or a line along the
///    fitted translation, through the path's start); a model whose median distance from the
///    recorded positions exceeds `path_tolerance` is rejected when the other model's is within
///    it. Why: static surfaces that the moved part hides in the post view (the carcass face
///    below a drawer pulled towards the camera) are segmented with the part, and a large
///    rotation can map them onto other surfaces (a drawer front onto its own top) better than
///    the true translation explains the part; the path a pulled drawer's handle took is
///    straight, which no such rotation predicts.
/// 5. **Refinement.** The chosen model is registered again on the ICP points its motion
///    explains (a post neighbour within `τ`): rotation by the same ICP at the final limit;
///    translation by point-to-plane ICP (normals of the post cloud, a small point-to-point term
///    for the directions no surface constrains), whose residuals measure depth noise rather
///    than the two views' different sampling.
/// 6. **Final segmentation.** Grown from the seed over the pre points that the fitted motion
///    explains (a post neighbour within `τ` after the motion) better than the static hypothesis
///    by a margin `τ/4`, or as well up to that margin while moving less than `2τ` (points near a
///    hinge, which both explain), and over the points that neither explains although the post
///    sensor saw through the place they were (in a range image around the post origin, no post
///    point in front of it by more than `τ` and one behind it by more than `τ`): they left.
///    A point the post sensor did not see around at all (outside its field of view or range)
///    is not evidence of motion and is left out. Known limits: static surfaces that the
///    motion maps onto themselves and that the moved part hides in the post view (the floor
///    just in front of a door turning about a vertical axis) are taken as moving; part surfaces
///    sliding along themselves, and thin strips of the part within `τ` of a static surface, are
///    left out.
fn estimate(s: &TwoViewSettings, i: &Interaction<'_>) -> Estimate {
    let (pre, post) = (&i.pre.points, &i.post.points);
    if pre.len() < s.min_part_points || post.len() < s.min_part_points {
        return Estimate::unknown(format!(
            "too few points: {} pre, {} post (need {})",
            pre.len(),
            post.len(),
            s.min_part_points
        ));
    }
    let pre_tree = KdTree::new(pre);
    let post_tree = KdTree::new(post);
    // Nearest-neighbour distances are only compared with τ-sized thresholds, so the searches
    // stop at `far` (a point with no neighbour nearer is reported at `far`): searches that find
    // nothing are what costs time. `far` is at least 2τ (recomputed for very sparse clouds).
    let distances = |far: f64| {
        let nn = |tree: &KdTree, p: &Point3<f64>| tree.nearest(p, far).map_or(far, |(_, d)| d);
        let d_pre: Vec<f64> = pre.iter().map(|p| nn(&post_tree, p)).collect();
        let d_post: Vec<f64> = post.iter().map(|p| nn(&pre_tree, p)).collect();
        let tau = s.change_distance.max(s.noise_multiplier * median(&d_pre));
        (d_pre, d_post, tau)
    };
    let mut far = 10.0 * s.change_distance;
    let (mut d_pre, mut d_post, mut tau) = distances(far);
    if 2.0 * tau > far {
        far = 4.0 * tau;
        (d_pre, d_post, tau) = distances(far);
    }
    let nn = |tree: &KdTree, p: &Point3<f64>| tree.nearest(p, far).map_or(far, |(_, d)| d);
    let changed: Vec<bool> = d_pre.iter().map(|&d| d > tau).collect();
    let new: Vec<bool> = d_post.iter().map(|&d| d > tau).collect();

    let seeds_pre = seeds(pre, &pre_tree, &changed, &i.contact_pre, s.seed_radius);
    let part = grow(&pre_tree, pre, &changed, &seeds_pre, s.neighbor_radius);
    if part.len() < s.min_part_points {
        return Estimate::unknown(format!(
            "too little motion: {} changed points connected to the contact (need {}, τ = {tau:.4} m)",
            part.len(),
            s.min_part_points
        ));
    }
    let seeds_post = seeds(post, &post_tree, &new, &i.contact_post, s.seed_radius);
    let part_post = grow(&post_tree, post, &new, &seeds_post, s.neighbor_radius);
    let source: Vec<Point3<f64>> = part.iter().map(|&k| pre[k]).collect();
    // ICP runs on one point per `icp_voxel` cube, evenly strided to at most `max_icp_points`.
    let thinned = voxel_subset(&source, s.icp_voxel);
    let stride = thinned.len().div_ceil(s.max_icp_points).max(1);
    let sample: Vec<Point3<f64>> = thinned.iter().step_by(stride).copied().collect();

    let icp_settings = IcpSettings {
        stages: [
            (4.0 * s.max_correspondence_distance).max(0.1),
            (2.0 * s.max_correspondence_distance).max(2.0 * tau),
            s.max_correspondence_distance.max(tau),
        ],
        iterations: s.icp_iterations,
        trim_fraction: s.trim_fraction,
        extra_weight: s.contact_weight,
    };
    let contact = Some((i.contact_pre, i.contact_post));
    let shift = i.contact_post - i.contact_pre;
    let mut inits = vec![Isometry3::translation(shift.x, shift.y, shift.z)];
    if part_post.len() >= s.min_part_points {
        let target: Vec<Point3<f64>> = part_post.iter().map(|&k| post[k]).collect();
        if let Some(r) = normal_rotation(&source, &i.pre.origin, &target, &i.post.origin) {
            let t = i.contact_post.coords - r * i.contact_pre.coords;
            inits.push(Isometry3::from_parts(Translation3::from(t), r));
        }
    }
    let fit = |init: Isometry3<f64>, model| {
        icp(
            &sample,
            post,
            &post_tree,
            init,
            contact,
            model,
            &icp_settings,
        )
    };
    let Some(rigid) = inits
        .iter()
        .filter_map(|init| fit(*init, MotionModel::Rigid))
        .min_by(|a, b| a.cost.total_cmp(&b.cost))
    else {
        return Estimate::unknown("registration found no correspondences");
    };
    let moved = source
        .iter()
        .map(|p| (rigid.motion * p - p).norm())
        .fold(0.0, f64::max);
    if moved < s.min_motion {
        return Estimate::unknown(format!(
            "too little motion: the part moves at most {moved:.4} m (need {} m)",
            s.min_motion
        ));
    }

    // Residuals of neighbouring points are correlated (sampling pattern, surface noise), so the
    // evidence counts occupied τ-voxels rather than points.
    let voxels: HashSet<[i64; 3]> = source
        .iter()
        .map(|p| p.coords.map(|c| (c / tau).floor() as i64).into())
        .collect();
    let n_eff = voxels.len().max(1) as f64;
    let bic = |cost: f64, k: f64| n_eff * cost.max(1e-12).ln() + k * n_eff.ln();
    let rotation = fit(rigid.motion, MotionModel::Rotation);
    // The translation also starts from the contact's shift: a rigid fit that turned the part
    // (a drawer's front mapped onto its own top, say) can leave the translation from its
    // motion without correspondences.
    let translation = [rigid.motion, inits[0]]
        .into_iter()
        .filter_map(|init| fit(init, MotionModel::Translation))
        .min_by(|a, b| a.cost.total_cmp(&b.cost));
    // Both models are scored on all part points, not the ICP subset.
    let full_cost =
        |r: &Registration| truncated_cost(&source, &post_tree, &r.motion, icp_settings.stages[2]);
    let bic_r = rotation
        .as_ref()
        .map_or(f64::INFINITY, |r| bic(full_cost(r), 5.0));
    let bic_p = translation
        .as_ref()
        .map_or(f64::INFINITY, |r| bic(full_cost(r), 3.0));
    // The contact-path check: each model predicts where the end effector went.
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
    let (path_r, path_p) = if path.len() >= s.min_path_poses {
        (
            path_fit(&rotation, MotionModel::Rotation),
            path_fit(&translation, MotionModel::Translation),
        )
    } else {
        (f64::NAN, f64::NAN)
    };
    let (fits_r, fits_p) = (path_r <= s.path_tolerance, path_p <= s.path_tolerance);
    let forced = path.len() >= s.min_path_poses && fits_r != fits_p;
    let revolute = match (&rotation, &translation) {
        (Some(_), Some(_)) if forced => fits_r,
        (Some(_), Some(_)) => bic_r < bic_p,
        (Some(_), None) => true,
        (None, Some(_)) => false,
        (None, None) => return Estimate::unknown("neither joint model could be registered"),
    };
    // The path check overrules BIC only when they disagree.
    let forced = forced && revolute != (bic_r < bic_p);
    // The score's model-selection margin: the BIC difference, or 10 when the path decided.
    let margin = if forced { 10.0 } else { (bic_p - bic_r).abs() };
    let chosen = if revolute { rotation } else { translation }
        .expect("the chosen model was registered (checked in the match above)");
    // Refinement: the chosen model registered again on the part points its motion explains
    // (the static surfaces hidden in the post view, which no motion explains, drop out).
    let explained: Vec<Point3<f64>> = sample
        .iter()
        .filter(|p| nn(&post_tree, &(chosen.motion * *p)) <= tau)
        .copied()
        .collect();
    let chosen = if explained.len() < s.min_part_points {
        chosen
    } else if revolute {
        let fine = IcpSettings {
            stages: [tau; 3],
            ..icp_settings
        };
        icp(
            &explained,
            post,
            &post_tree,
            chosen.motion,
            contact,
            MotionModel::Rotation,
            &fine,
        )
        .unwrap_or(chosen)
    } else {
        let normals = NormalCache::new(post, &post_tree, s.neighbor_radius * 1.2);
        let t = refine_translation(
            &explained,
            post,
            &post_tree,
            &normals,
            chosen.motion.translation.vector,
            contact,
            tau,
            s,
        );
        Registration {
            motion: Isometry3::translation(t.x, t.y, t.z),
            cost: chosen.cost,
        }
    };
    let screw = Screw::from_isometry(&chosen.motion);
    let joint = if revolute {
        JointEstimate::Revolute {
            axis: screw.axis,
            pivot: screw.closest_axis_point(&i.contact_pre),
            angle: screw.angle,
        }
    } else {
        let (axis, distance) = Unit::new_and_get(chosen.motion.translation.vector);
        JointEstimate::Prismatic { axis, distance }
    };

    let residual = |p: &Point3<f64>| nn(&post_tree, p);
    let post_view = RangeImage::new(post, i.post.origin, s.visibility_bin);
    let eligible: Vec<bool> = pre
        .iter()
        .zip(&d_pre)
        .map(|(p, &d_static)| {
            let q = chosen.motion * p;
            let d_part = residual(&q);
            let margin = tau / 4.0;
            let hinge = (q - p).norm() < 2.0 * tau;
            let vacated = d_part > tau && d_static > tau && post_view.seen_through(p, tau);
            (d_part <= tau
                && (d_part + margin < d_static || (hinge && d_part <= d_static + margin)))
                || vacated
        })
        .collect();
    let moving = grow(&pre_tree, pre, &eligible, &seeds_pre, s.neighbor_radius);
    let n = source.len() as f64;
    let inliers = source
        .iter()
        .filter(|p| residual(&(chosen.motion * *p)) <= tau)
        .count() as f64
        / n;
    let score = score_of(inliers, margin);
    let details = format!(
        "two-view: tau {tau:.4} m, {} seed points, {} post points, rigid cost {:.3e}, \
         BIC revolute {bic_r:.1} prismatic {bic_p:.1}, path residual revolute {path_r:.4} m \
         prismatic {path_p:.4} m{}, screw angle {:.2} deg, axial {:.4} m, \
         inliers {:.3}, n_eff {n_eff}",
        part.len(),
        part_post.len(),
        rigid.cost,
        if forced { " (path decided)" } else { "" },
        Screw::from_isometry(&rigid.motion).angle.to_degrees(),
        Screw::from_isometry(&rigid.motion).translation,
        inliers,
    );
    Estimate {
        joint,
        part_points: moving.iter().map(|&k| pre[k]).collect(),
        moving,
        score,
        details,
    }
}

/// The first of `points` in each cube of side `voxel` (all points for `voxel` = 0), in order.
fn voxel_subset(points: &[Point3<f64>], voxel: f64) -> Vec<Point3<f64>> {
    if voxel <= 0.0 {
        return points.to_vec();
    }
    let mut seen: HashSet<[i64; 3]> = HashSet::with_capacity(points.len());
    points
        .iter()
        .filter(|p| seen.insert(p.coords.map(|c| (c / voxel).floor() as i64).into()))
        .copied()
        .collect()
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

/// Indices of `mask`ed points within `radius` of `contact`, or the masked point nearest to it.
fn seeds(
    points: &[Point3<f64>],
    tree: &KdTree,
    mask: &[bool],
    contact: &Point3<f64>,
    radius: f64,
) -> Vec<usize> {
    let mut out = Vec::new();
    tree.for_each_within(contact, radius, |k, _| {
        if mask[k] {
            out.push(k);
        }
    });
    if out.is_empty() {
        let nearest = (0..points.len())
            .filter(|&k| mask[k])
            .map(|k| (k, (points[k] - contact).norm()))
            .filter(|&(_, d)| d <= 3.0 * radius)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        out.extend(nearest.map(|(k, _)| k));
    }
    out
}

/// Breadth-first region growing over `mask`ed points from `seeds` (sorted result).
fn grow(
    tree: &KdTree,
    points: &[Point3<f64>],
    mask: &[bool],
    seeds: &[usize],
    radius: f64,
) -> Vec<usize> {
    let mut seen = vec![false; points.len()];
    let mut queue: Vec<usize> = Vec::new();
    for &k in seeds {
        if mask[k] && !seen[k] {
            seen[k] = true;
            queue.push(k);
        }
    }
    let mut head = 0;
    while head < queue.len() {
        let k = queue[head];
        head += 1;
        tree.for_each_within(&points[k], radius, |j, _| {
            if mask[j] && !seen[j] {
                seen[j] = true;
                queue.push(j);
            }
        });
    }
    queue.sort_unstable();
    queue
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

fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The estimate's score: the inlier fraction times the model-selection confidence
/// `margin / (margin + 10)`. An infinite margin (only one model could be registered) is a
/// certain selection (the quotient itself would be ∞/∞ = NaN).
fn score_of(inliers: f64, margin: f64) -> f64 {
    let selection = if margin.is_finite() {
        margin / (margin + 10.0)
    } else {
        1.0
    };
    (inliers * selection).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed rotation fit (BIC ∞) makes the margin infinite: the score is then the inlier
    /// fraction, finite, not ∞/∞ = NaN.
    #[test]
    fn an_infinite_margin_scores_the_inliers() {
        assert_eq!(score_of(0.8, f64::INFINITY), 0.8);
        // 10 / (10 + 10) = half the inliers.
        assert!((score_of(0.8, 10.0) - 0.4).abs() < 1e-12);
    }

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
