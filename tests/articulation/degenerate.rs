//! Degenerate input (no motion, too little, a pure twist) and bad input.

use super::*;

#[test]
fn degenerate_input_gives_unknown() {
    let s = &scenarios()[0];
    // No motion at all.
    let still = observe(s, 0.005, 0.05, 2, 0.0);
    for est in estimators() {
        let e = est.estimate(&still.interaction()).unwrap();
        assert!(
            matches!(e.joint, JointEstimate::Unknown { .. }),
            "{}: {e:?}",
            est.name()
        );
    }
    // Too little motion: the door moves 0.5° (the handle 4 mm, below both noise-level thresholds).
    let nudge = observe(s, 0.005, 0.0, 2, 0.5 / 40.0);
    for est in estimators() {
        let e = est.estimate(&nudge.interaction()).unwrap();
        assert!(
            matches!(e.joint, JointEstimate::Unknown { .. }),
            "{}: {e:?}",
            est.name()
        );
    }
    // Too few points and too few poses.
    let few = PointCloud::new(still.pre.points[..20].to_vec(), still.pre.origin, 0.0);
    let i = Interaction {
        pre: &few,
        post: &few,
        ee_poses: &still.ee_poses[..3],
        ..still.interaction()
    };
    for est in estimators() {
        let e = est.estimate(&i).unwrap();
        assert!(
            matches!(e.joint, JointEstimate::Unknown { .. }),
            "{}: {e:?}",
            est.name()
        );
    }
    // Collinear end-effector positions while the orientation turns by 60°: neither a line (the
    // orientation changes) nor a circle (no curvature) explains it, when the turn moves what
    // the orientation model trusts. A turn about the tool's z axis (the approach) is a wrist
    // roll to the approach-axis model: a straight slide with a rolling wrist.
    let twist = |about: Vector3<f64>| -> Vec<(f64, Isometry3<f64>)> {
        (0..20)
            .map(|k| {
                let f = k as f64 / 19.0;
                let p = Isometry3::new(
                    Vector3::new(0.3 * f, 0.0, 0.8),
                    about * (FRAC_PI_2 * 2.0 / 3.0) * f,
                );
                (f, p)
            })
            .collect()
    };
    for (orientation, about, slide) in [
        (OrientationModel::Rigid, Vector3::z(), false),
        (OrientationModel::Rigid, Vector3::y(), false),
        (OrientationModel::ApproachAxis, Vector3::y(), false),
        (OrientationModel::ApproachAxis, Vector3::z(), true),
    ] {
        let e = proprio(orientation).estimate_poses(&twist(about)).unwrap();
        if slide {
            let JointEstimate::Prismatic { axis, .. } = e.joint else {
                panic!("{orientation:?}: {e:?}")
            };
            assert!(axis_angle_error(&axis, &Vector3::x_axis()) < 0.1, "{e:?}");
        } else {
            assert!(
                matches!(e.joint, JointEstimate::Unknown { .. }),
                "{orientation:?} about {about:?}: {e:?}"
            );
        }
    }
}

#[test]
fn bad_input_is_an_error() {
    let s = &scenarios()[3];
    let o = observe(s, 0.002, 0.0, 4, 1.0);
    let mut nan = o.pre.clone();
    nan.points[17].y = f64::NAN;
    let i = Interaction {
        pre: &nan,
        ..o.interaction()
    };
    for est in estimators() {
        let err = est.estimate(&i).unwrap_err();
        assert_eq!(
            err,
            ArticulationError::NonFinite {
                input: InputKind::PreCloud,
                what: "point",
                index: 17
            }
        );
    }
    let mut colored = o.post.clone();
    colored.colors = Some(vec![[0.5; 3]; colored.points.len() - 1]);
    let i = Interaction {
        post: &colored,
        ..o.interaction()
    };
    let err = TwoView::default().estimate(&i).unwrap_err();
    assert!(
        matches!(
            err,
            ArticulationError::ColorCountMismatch {
                input: InputKind::PostCloud,
                ..
            }
        ),
        "{err}"
    );
    let mut poses = o.ee_poses.clone();
    poses[5].0 = poses[4].0;
    let i = Interaction {
        ee_poses: &poses,
        ..o.interaction()
    };
    let err = Proprioceptive::default().estimate(&i).unwrap_err();
    assert!(
        matches!(err, ArticulationError::TimeNotIncreasing { index: 5, .. }),
        "{err}"
    );
    let i = Interaction {
        contact_post: Point3::new(f64::INFINITY, 0.0, 0.0),
        ..o.interaction()
    };
    assert!(matches!(
        TwoView::default().estimate(&i),
        Err(ArticulationError::NonFinite {
            input: InputKind::ContactPost,
            ..
        })
    ));
    let bad = TwoView {
        settings: TwoViewSettings {
            trim_fraction: 0.0,
            ..Default::default()
        },
    };
    assert!(matches!(
        bad.estimate(&o.interaction()),
        Err(ArticulationError::InvalidSetting(s)) if s.field == "trim_fraction"
    ));
}
