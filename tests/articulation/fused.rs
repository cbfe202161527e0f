//! The fused estimator on the hard classes (`hard.rs`): at least as good as the better single
//! source, the right type, nothing NaN; the 95 % regions' coverage reported; one source alone
//! reduces it to that source's estimator; settings are validated.

use super::hard::{hard_cases, observe};
use super::*;

use kinscene::articulation::{Fused, FusedSettings};

/// Over 3 seeds at σ = 5 mm on `case`: the fused estimate has the right type every time, a
/// finite score and uncertainty, a mean axis error at most the better single source's (mean
/// over the same seeds) plus 0.2°, and mean axis and pivot errors at most the two-view's.
/// Returns the fused estimates' mean signed travel error (rad or m) and how many of the 3
/// 95 % regions contain the truth.
/// Measured (not asserted, it does not hold): the fused mean pivot error is up to 1 cm above
/// the proprioceptive one on the small door opened 10°, where the clouds still pull the
/// angle low (≈ 0.8°).
fn fused_on(case_index: usize) -> (f64, usize) {
    let case = &hard_cases()[case_index];
    let seeds = [1u64, 2, 3];
    let estimators: [Box<dyn ArticulationEstimator>; 3] = [
        Box::new(TwoView::default()),
        Box::new(Proprioceptive::default()),
        Box::new(Fused::default()),
    ];
    let mut sums = [[0.0f64; 2]; 3];
    let mut covered = 0;
    let mut travel = 0.0;
    for &seed in &seeds {
        let o = observe(case, 0.005, seed);
        for (k, est) in estimators.iter().enumerate() {
            let e = est.estimate(&o.interaction()).expect("valid input");
            let r = case.truth.errors(&e);
            let (kind_ok, axis, pivot, inside) =
                (r.kind_ok, r.axis_deg, r.pivot_m.unwrap_or(0.0), r.covered);
            let ctx = format!(
                "{} seed {seed} {}: {axis:.2}° {pivot:.4} m\n{}",
                case.name,
                est.name(),
                e.details
            );
            eprintln!("{ctx}");
            // A wrong type counts as a 90° / 1 m error for the single sources.
            sums[k][0] += if kind_ok { axis } else { 90.0 };
            sums[k][1] += if kind_ok { pivot } else { 1.0 };
            if k == 2 {
                assert!(kind_ok, "wrong type: {ctx}");
                assert!(
                    e.score.is_finite() && (0.0..=1.0).contains(&e.score),
                    "{ctx}"
                );
                let u = e
                    .uncertainty
                    .expect("a fused estimate carries its uncertainty");
                assert!(u.axis_half_angle_95().is_finite(), "{ctx}");
                assert!(u.type_probability.is_finite(), "{ctx}");
                covered += usize::from(inside);
                travel += match (&e.joint, case.truth) {
                    (JointEstimate::Revolute { angle, .. }, Truth::Revolute { angle: a, .. }) => {
                        angle - a
                    }
                    (
                        JointEstimate::Prismatic { distance, .. },
                        Truth::Prismatic { distance: d, .. },
                    ) => distance - d,
                    _ => f64::NAN,
                };
            }
        }
    }
    let n = seeds.len() as f64;
    let mean = |k: usize, m: usize| sums[k][m] / n;
    eprintln!(
        "{}: mean axis two-view {:.2}° proprioceptive {:.2}° fused {:.2}°; pivot {:.4} / {:.4} / {:.4} m; fused 95 % coverage {covered}/3",
        case.name,
        mean(0, 0),
        mean(1, 0),
        mean(2, 0),
        mean(0, 1),
        mean(1, 1),
        mean(2, 1)
    );
    assert!(
        mean(2, 0) <= mean(0, 0).min(mean(1, 0)) + 0.2,
        "{}: axis",
        case.name
    );
    assert!(
        mean(2, 0) <= mean(0, 0),
        "{}: axis against two-view",
        case.name
    );
    assert!(
        mean(2, 1) <= mean(0, 1),
        "{}: pivot against two-view",
        case.name
    );
    (travel / n, covered)
}

#[test]
fn fused_small_door() {
    fused_on(0);
}

/// The sagging door (15°): besides [`fused_on`]'s checks, the swept angle is not pulled low
/// (mean signed error over the 3 seeds within ±0.6°, against 15°; it was −1.2° when the
/// clouds' evidence was the change-detected part alone), and the 95 % regions contain the
/// truth in at least 2 of the 3 seeds (0 of 3 before the sandwich covariance).
#[test]
fn fused_sagging_door() {
    let (travel, covered) = fused_on(1);
    assert!(travel.to_degrees().abs() <= 0.6, "{}°", travel.to_degrees());
    assert!(covered >= 2, "{covered}/3");
}

/// The drawer (12 cm): besides [`fused_on`]'s checks, the pulled distance within ±5 mm
/// on average and every 95 % region containing the truth.
#[test]
fn fused_rotated_drawer() {
    let (travel, covered) = fused_on(2);
    assert!(travel.abs() <= 0.005, "{travel} m");
    assert_eq!(covered, 3);
}

/// With no poses the fused estimate is the two-view one; with empty clouds it is the
/// proprioceptive one.
#[test]
fn one_source_reduces_to_that_source() {
    let case = &hard_cases()[0];
    let o = observe(case, 0.002, 5);
    let no_poses = Interaction {
        ee_poses: &[],
        ..o.interaction()
    };
    let fused = Fused::default().estimate(&no_poses).unwrap();
    let two_view = TwoView::default().estimate(&no_poses).unwrap();
    assert_eq!(fused.joint, two_view.joint);
    assert_eq!(fused.uncertainty, two_view.uncertainty);
    let poses_only = proprio_only(&o.ee_poses);
    let fused = Fused::default().estimate(&poses_only).unwrap();
    let proprioceptive = Proprioceptive::default().estimate(&poses_only).unwrap();
    assert_eq!(fused.joint, proprioceptive.joint);
    assert_eq!(fused.uncertainty, proprioceptive.uncertainty);
}

/// Bad settings are typed errors naming the field, checked before any work.
#[test]
fn fused_settings_are_validated() {
    assert!(FusedSettings::default().validate().is_ok());
    let bad = |settings: FusedSettings| {
        let e = Fused { settings }.estimate(&proprio_only(&[])).unwrap_err();
        let ArticulationError::InvalidSetting(s) = e else {
            panic!("{e:?}")
        };
        s.to_string()
    };
    let msg = bad(FusedSettings {
        plane_radius: f64::NAN,
        ..Default::default()
    });
    assert!(msg.contains("plane_radius"), "{msg}");
    let msg = bad(FusedSettings {
        lm_iterations: 0,
        ..Default::default()
    });
    assert!(msg.contains("lm_iterations"), "{msg}");
    let mut settings = FusedSettings::default();
    settings.two_view.trim_fraction = 0.0;
    assert!(bad(settings).contains("trim_fraction"));
}
