//! Both estimators against the ground truth of the synthetic scenes.

use super::*;

/// The renderer puts noise-free points on the surfaces it reports, and only on faces that face
/// the camera (a partial view).
#[test]
fn renderer_gives_partial_exact_views() {
    let s = &scenarios()[0];
    let o = observe(s, 0.0, 0.0, 1, 1.0);
    let mut boxes = s.statics.clone();
    boxes.extend(s.part.iter().copied());
    assert!(o.pre.points.len() > 10_000, "{}", o.pre.points.len());
    for p in &o.pre.points {
        // Each point lies on the boundary of some box (distance to the nearest box surface ≈ 0).
        let on_surface = boxes.iter().any(|b| {
            let l = b.world_from_box.inverse() * p;
            let inside = (0..3).all(|k| l[k].abs() <= b.half_extents[k] + 1e-9);
            inside && (0..3).any(|k| (l[k].abs() - b.half_extents[k]).abs() < 1e-9)
        });
        assert!(on_surface, "{p}");
    }
    // The cabinet's back panel is hidden behind the closed door before the interaction.
    let back = &s.statics[4];
    let behind = o.pre.points.iter().filter(|p| {
        let l = back.world_from_box.inverse() * *p;
        (0..3).all(|k| l[k].abs() <= back.half_extents[k] + 1e-9)
    });
    assert_eq!(behind.count(), 0);
}

/// Targets of the issue at σ = 5 mm, 5 % outliers, partial views: the right joint type,
/// ≤ 2° axis error for both types, ≤ 2 cm pivot (axis line) error for revolute joints, for both
/// estimators on every scenario. Travel (angle or distance) within 3° / 2 cm: the proprioceptive
/// travel comes from the first and last inlier poses, σ√2 ≈ 7 mm (≈ 0.9° at a 0.45 m radius)
/// per estimate, so these are 3σ bounds. The two-view segmentation is ≥ 80 % precise (its points
/// are on the part; the documented leak is the floor the opened door hides from the post view,
/// 10–15 % for the doors) and overlaps the part with IoU ≥ 0.7 except where the geometry cannot tell (the sliding panel's face slides along itself; the nested drawer's front stays
/// within τ of its housing), which the module documents.
#[test]
fn estimators_meet_targets_at_5mm() {
    for s in &scenarios() {
        let o = observe(s, 0.005, 0.05, 7, 1.0);
        for est in estimators() {
            let e = est.estimate(&o.interaction()).expect("valid input");
            let err = errors(s, &o, &e, 1.0);
            let ctx = format!("{} / {}: {err:?}\n{}", s.name, est.name(), e.details);
            assert!(err.kind_ok, "wrong type: {ctx}");
            assert!(err.axis_deg <= 2.0, "axis: {ctx}");
            if let Some(p) = err.pivot_m {
                assert!(p <= 0.02, "pivot: {ctx}");
            }
            let travel_tol = if matches!(s.truth, Truth::Revolute { .. }) {
                3.0
            } else {
                0.02
            };
            assert!(err.travel <= travel_tol, "travel: {ctx}");
            if let Some((iou, precision)) = err.iou.zip(err.precision) {
                assert!(precision >= 0.8, "segmentation precision: {ctx}");
                let ambiguous = matches!(s.name, "sliding panel" | "drawer on opened door");
                assert!(ambiguous || iou >= 0.7, "segmentation IoU: {ctx}");
            }
            assert!((0.0..=1.0).contains(&e.score), "{ctx}");
        }
    }
}

/// The two-view estimator returns the moving part's points in the pre pose.
#[test]
fn two_view_part_points_are_the_segmented_pre_points() {
    let s = &scenarios()[3];
    let o = observe(s, 0.002, 0.0, 3, 1.0);
    let e = TwoView::default().estimate(&o.interaction()).unwrap();
    assert_eq!(e.part_points.len(), e.moving.len());
    for (k, p) in e.moving.iter().zip(&e.part_points) {
        assert_eq!(o.pre.points[*k], *p);
    }
    // The returned segmentation contains (almost) no static points: ≥ 95 % of it is the part.
    let on_part = e
        .moving
        .iter()
        .filter(|&&k| o.pre_labels[k] == Some(PART))
        .count();
    assert!(
        on_part as f64 >= 0.95 * e.moving.len() as f64,
        "{on_part}/{}",
        e.moving.len()
    );
}

/// The NaN score: two-view on the sliding panel (a correctly classified translation
/// whose rotation fit can fail, BIC ∞) at σ = 5 and 10 mm, two seeds each. Every score and
/// type probability is finite and in [0, 1], and a known joint carries a finite uncertainty.
#[test]
fn sliding_door_scores_are_finite() {
    let s = scenarios()
        .into_iter()
        .find(|s| s.name == "sliding panel")
        .expect("the sliding panel scene");
    for (sigma, seed) in [(0.005, 31), (0.005, 32), (0.010, 33), (0.010, 34)] {
        let o = observe(&s, sigma, 0.05, seed, 1.0);
        let e = TwoView::default().estimate(&o.interaction()).unwrap();
        let ctx = format!("σ {sigma} seed {seed}: {e:?}");
        assert!(
            e.score.is_finite() && (0.0..=1.0).contains(&e.score),
            "{ctx}"
        );
        if e.joint.kind() != JointKindEstimate::Unknown {
            let u = e.uncertainty.expect(&ctx);
            assert!((0.0..=1.0).contains(&u.type_probability), "{ctx}");
            assert!(u.axis_half_angle_95().is_finite(), "{ctx}");
        }
    }
}
