//! Calibration of the estimates' uncertainty: over seeds, the 95 % regions contain the truth
//! about 95 % of the time, and are not trivially large.
//!
//! Statistic: the squared Mahalanobis distance `d²` of the true axis (and pivot) from the
//! estimate under its covariance. For a calibrated 2-d Gaussian estimate `d² ~ χ²₂`: the 95 %
//! region is `d² ≤ 5.99` and the median of `d²` is `2 ln 2 ≈ 1.39`. The median pins the
//! region's size from both sides: regions `k` times too large in each direction make it
//! `1.39 / k²`, `k` times too small `1.39 k²`.

use super::*;

use kinscene::articulation::{CHI2_2DOF_95, Uncertainty};

/// `d²` of the axis and (revolute) the pivot of `e` against `truth`; `None` for an estimate
/// without uncertainty or of the wrong type.
fn mahalanobis(e: &Estimate, truth: &Truth) -> Option<(f64, Option<f64>, Uncertainty)> {
    let u = e.uncertainty?;
    match (&e.joint, truth) {
        (
            JointEstimate::Revolute { axis, pivot, .. },
            Truth::Revolute {
                axis: a, pivot: q, ..
            },
        ) => Some((
            u.axis_mahalanobis_squared(axis, a),
            u.pivot_mahalanobis_squared(pivot, axis, q, a),
            u,
        )),
        (JointEstimate::Prismatic { axis, .. }, Truth::Prismatic { axis: a, .. }) => {
            Some((u.axis_mahalanobis_squared(axis, a), None, u))
        }
        _ => None,
    }
}

/// The 95 % axis half-angle (rad) that the positions alone allow, from the true path
/// `positions` with isotropic noise `sigma` per axis, derived independently of the estimator:
/// a line's direction tilted by `δ` moves the position at `t` along it by `t δ`, so each
/// tangent coordinate has variance `σ² / Σ (tᵢ − t̄)²`; a circle's axis tilted by `δ` (in its
/// plane) lifts the position `q` (in-plane, about the centre) out of the plane by `δ · q`, and
/// the out-of-plane residuals involve only the tilt and the centre's height, so the tilt's
/// covariance is `σ² S⁻¹`, `S = Σ (qᵢ − q̄)(qᵢ − q̄)ᵀ`. The half-angle is `√(5.99 σ² / λ_min)`.
fn positions_only_half_angle(truth: &Truth, positions: &[Point3<f64>], sigma: f64) -> f64 {
    let lambda_min = match truth {
        Truth::Prismatic { axis, .. } => {
            let t: Vec<f64> = positions.iter().map(|p| axis.dot(&p.coords)).collect();
            let mean = t.iter().sum::<f64>() / t.len() as f64;
            t.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
        }
        Truth::Revolute { axis, .. } => {
            let e1 = axis.cross(&Vector3::x()).normalize();
            let e2 = axis.cross(&e1);
            let q: Vec<nalgebra::Vector2<f64>> = positions
                .iter()
                .map(|p| nalgebra::Vector2::new(e1.dot(&p.coords), e2.dot(&p.coords)))
                .collect();
            let mean = q.iter().sum::<nalgebra::Vector2<f64>>() / q.len() as f64;
            let s = q
                .iter()
                .map(|v| (v - mean) * (v - mean).transpose())
                .sum::<nalgebra::Matrix2<f64>>();
            s.symmetric_eigenvalues().min()
        }
    };
    (CHI2_2DOF_95 * sigma * sigma / lambda_min).sqrt()
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Coverage, median `d²` and the median 95 % size of a set of `d²` and sizes.
fn summary(d2: &[f64], sizes: &[f64]) -> (f64, f64, f64) {
    let inside = d2.iter().filter(|&&d| d <= CHI2_2DOF_95).count();
    (inside as f64 / d2.len() as f64, median(d2), median(sizes))
}

/// The proprioceptive estimator on the scenes' gripper paths (every 5th of the 200 poses:
/// 40, to keep the test fast), 3 % outlier poses, over 7 seeds per scene and depth σ cycling
/// through 2, 5 and 10 mm (position noise σ per axis, orientation noise σ / 5 mm degrees; the
/// estimator's settings assume 5 mm and 0.05 rad, so the noise must come from the data):
/// 42 revolute runs (3 doors), 42 prismatic (3 drawers / panels).
///
/// Asserted, per quantity (revolute axis, revolute pivot, prismatic axis):
/// - at most 2 of the 84 runs of the wrong type (each run of the right type carries an
///   uncertainty);
/// - coverage of the 95 % region in [0.8, 1.0]: with ~42 runs a calibrated region misses
///   Binomial(42, 0.05) times, ≥ 9 misses (< 0.8) has probability < 0.2 %;
/// - the median `d²` within [0.5, 3.5] around χ²₂'s 1.39 (its sampling sd over 42 runs is
///   ≈ 0.31): regions 1.7 × too large or 1.6 × too small in each direction fail it;
/// - axes: the median ratio of the 95 % half-angle to the positions-only one
///   ([`positions_only_half_angle`], from the true path and σ) at most 1.3: a line's
///   direction has no other information (ratio ≈ 1 up to the estimated σ and the outliers
///   left out), a circle's axis also has the orientations (ratio ≤ 1), so a region much
///   larger than what the data allow fails. The pivot's size is pinned by its median `d²`.
#[test]
fn proprioceptive_regions_are_calibrated() {
    let est = Proprioceptive::default();
    let (mut rev_axis, mut rev_pivot, mut pri_axis) = (Vec::new(), Vec::new(), Vec::new());
    let (mut half_angles, mut radii, mut pri_half_angles) = (Vec::new(), Vec::new(), Vec::new());
    let mut wrong = Vec::new();
    for (index, s) in scenarios().iter().enumerate() {
        for seed in 0..7u64 {
            let sigma = [0.002, 0.005, 0.010][(seed as usize + index) % 3];
            let (_, _, path) = proprioception(s, sigma, 0.03, 500 + seed, 1.0);
            let poses: Vec<_> = path.into_iter().step_by(5).collect();
            // The noise-free path of the same poses.
            let truth_path: Vec<Point3<f64>> = (0..200)
                .step_by(5)
                .map(|k| s.truth.motion(k as f64 / 199.0) * s.contact)
                .collect();
            let bound = positions_only_half_angle(&s.truth, &truth_path, sigma);
            let e = est.estimate_poses(&poses).expect("valid input");
            let ctx = format!("{} seed {seed} σ {sigma}: {e:?}", s.name);
            let Some((axis_d2, pivot_d2, u)) = mahalanobis(&e, &s.truth) else {
                eprintln!("wrong type or no uncertainty: {ctx}");
                wrong.push(e.uncertainty.map(|u| u.type_probability));
                continue;
            };
            if let Some(pivot_d2) = pivot_d2 {
                rev_axis.push(axis_d2);
                rev_pivot.push(pivot_d2);
                half_angles.push(u.axis_half_angle_95() / bound);
                radii.push(u.pivot_radius_95().expect("revolute"));
            } else {
                pri_axis.push(axis_d2);
                pri_half_angles.push(u.axis_half_angle_95() / bound);
            }
        }
    }
    eprintln!("wrong: {wrong:?}");
    // One sliding panel at σ = 10 mm is read as a turn (the known weakness of 40
    // noisy poses on a straight pull); more than 2 of 84 would be a regression.
    assert!(wrong.len() <= 2, "{wrong:?}");
    let checks = [
        ("revolute axis", summary(&rev_axis, &half_angles), 1.3),
        ("revolute pivot", summary(&rev_pivot, &radii), f64::INFINITY),
        ("prismatic axis", summary(&pri_axis, &pri_half_angles), 1.3),
    ];
    for (what, (coverage, median_d2, median_size), size_bound) in checks {
        let ctx = format!(
            "{what}: coverage {coverage:.3}, median d² {median_d2:.3}, median 95 % size \
             (axes: over the positions-only one) {median_size:.4}"
        );
        eprintln!("{ctx}");
        assert!((0.8..=1.0).contains(&coverage), "{ctx}");
        assert!((0.5..=3.5).contains(&median_d2), "{ctx}");
        assert!(median_size <= size_bound, "{ctx}");
    }
}

/// The two-view estimator's coverage over the scenes, 3 seeds each at σ = 5 mm (printed;
/// slow in debug): `cargo test --test lib two_view_coverage -- --ignored --nocapture`.
#[test]
#[ignore = "measurement; run with --ignored --nocapture"]
fn two_view_coverage() {
    let est = TwoView::default();
    for s in &scenarios() {
        for seed in 0..3u64 {
            let o = observe(s, 0.005, 0.05, 700 + seed, 1.0);
            let e = est.estimate(&o.interaction()).expect("valid input");
            let err = errors(s, &o, &e, 1.0);
            match mahalanobis(&e, &s.truth) {
                Some((axis, pivot, u)) => println!(
                    "{} seed {seed}: axis d² {axis:.2} (half-angle {:.2}°, error {:.2}°), \
                     pivot d² {:?} (radius {:?}, error {:?}), type p {:.3}",
                    s.name,
                    u.axis_half_angle_95().to_degrees(),
                    err.axis_deg,
                    pivot,
                    u.pivot_radius_95(),
                    err.pivot_m,
                    u.type_probability
                ),
                None => println!(
                    "{} seed {seed}: no uncertainty / wrong type: {:?}, type p {:?}\n  {}",
                    s.name,
                    e.joint,
                    e.uncertainty.map(|u| u.type_probability),
                    e.details
                ),
            }
        }
    }
}
