//! Keep pulling until confident (`discover`, step 6): a small door pulled only 4 cm at
//! first is pulled further until the estimate's 95 % regions are within the settings'
//! limits, and then matches the ground truth; an ordinary door whose first estimate is
//! already confident is not pulled again.
//!
//! The end-effector poses carry 2 mm / 1° noise (the scenarios), so the
//! proprioceptive estimator's regions are those of a real fit, not of exact poses.

use kinscene::articulation::{Proprioceptive, axis_angle_error, axis_position_error};
use kinscene::discovery::{Discovery, DiscoverySettings, PullEnd};
use kinscene::scene::{JointKind, SceneModel};
use nalgebra::{Point3, Vector3};

use super::algorithm::run_with;
use super::scenes::{DOOR_AXIS, DOOR_PIVOT, door_cabinet, small_door_cabinet};
use super::world::World;

/// 2 mm position and 1° orientation noise on every reported end-effector pose.
fn noisy_poses(w: &mut World) {
    w.settings.pose_noise = (0.002, 1f64.to_radians());
}

fn discover_door(truth: SceneModel, seed: u64, settings: &DiscoverySettings) -> (World, Discovery) {
    run_with(
        truth,
        &Proprioceptive::default(),
        seed,
        noisy_poses,
        settings,
    )
}

/// The registered joint's axis error (degrees) and axis-line distance (m) from the door's
/// true hinge.
fn hinge_errors(d: &Discovery) -> (f64, f64) {
    let joint = &d.model.joints()[0];
    assert_eq!(joint.kind, JointKind::Revolute, "{:#?}", d.log[0]);
    let axis = joint.parent_from_joint.rotation * joint.axis;
    let origin = Point3::from(joint.parent_from_joint.translation.vector);
    (
        axis_angle_error(&axis, &Vector3::from(DOOR_AXIS)),
        axis_position_error(
            &origin,
            &axis,
            &Point3::from(DOOR_PIVOT),
            &Vector3::from(DOOR_AXIS),
        ),
    )
}

/// The 0.25 m door (handle on a 0.197 m arc) with a first pull of 4 cm (about 12°): alone,
/// the proprioceptive estimate of that arc is not confident (measured: `Unknown`, too few
/// inlier poses); with the loop the robot grasps again at the last contact and pulls on
/// (`extra_pull`, 15 cm) until the regions are within the limits (2° / 2 cm), and the
/// registered hinge is then within 3.5° and 3 cm of the truth. Tolerance: the 4° bound of
/// the limits this test was written for, less what the stitching of two noisy grasps adds
/// outside the fit's covariance (two 1° orientation errors at the regrasp, ~1.4°; measured
/// at those limits 1.2°, 3.0°, 2.5° for seeds 1–3, at the default 2° / 2 cm 0.82°, 1.48°,
/// 1.70° after 2 further pulls each) — 3.5° allows that without allowing the 5–17° of a
/// two-view estimate of the short pull.
#[test]
fn a_short_pull_of_a_small_door_is_continued_until_confident() {
    let short = DiscoverySettings {
        axis_snap: 0.0,
        target_pull: 0.04,
        ..DiscoverySettings::default()
    };
    let once = DiscoverySettings {
        max_extra_pulls: 0,
        ..short.clone()
    };
    for seed in 1..=3 {
        // Without the loop: the first pull's estimate has doubts.
        let (_, d0) = discover_door(small_door_cabinet(), seed, &once);
        let p0 = d0.log[0].pulling.as_ref().expect("the estimator ran");
        assert_eq!(p0.extra_pulls, 0);
        assert!(!p0.doubts.is_empty(), "seed {seed}: {:#?}", d0.log[0]);
        // With it: more pull, a confident and correct estimate.
        let (world, d) = discover_door(small_door_cabinet(), seed, &short);
        let log = &d.log[0];
        assert!(log.succeeded(), "seed {seed}: {log:#?}");
        let pulling = log.pulling.as_ref().expect("the estimator ran");
        assert_eq!(pulling.end, PullEnd::Confident, "seed {seed}: {log:#?}");
        assert!(pulling.extra_pulls >= 1 && pulling.doubts.is_empty());
        assert_eq!(log.attempts.len(), 1 + pulling.extra_pulls);
        // Pulled on: the contact is more than 15 cm from the first grasp (the first pull
        // stopped at 4 cm), the true door more than 0.5 rad open (4 cm is 0.2 rad).
        assert!(
            log.pull_distance > 0.15,
            "seed {seed}: {}",
            log.pull_distance
        );
        assert!(world.state.as_slice()[0] > 0.5);
        // The uncertainty it stopped at, as logged, is within the limits.
        let e = log.estimate.as_ref().unwrap();
        assert!(e.axis_half_angle_95.unwrap() <= short.confident_axis_95);
        assert!(e.pivot_radius_95.unwrap() <= short.confident_pivot_95);
        assert!(e.type_probability.unwrap() >= short.confident_type_probability);
        let (deg, metres) = hinge_errors(&d);
        eprintln!(
            "seed {seed}: {} further pulls, {deg:.2}°, {metres:.4} m",
            pulling.extra_pulls
        );
        assert!(deg <= 3.5, "seed {seed}: axis error {deg}°");
        assert!(metres <= 0.03, "seed {seed}: pivot error {metres} m");
        // The model's opening is the door's (within 0.05 rad).
        let opened = d.state.as_slice()[0];
        assert!(
            (opened - world.state.as_slice()[0]).abs() < 0.05,
            "{opened}"
        );
    }
}

/// The ordinary door (0.59 m), pulled the default 30 cm, with limits of 4° / 4 cm (the
/// paper's 2° / 2 cm mean targets; the defaults are twice as tight): the first estimate is
/// already confident (measured: 95 % half-angle 3.4–3.6°, pivot radius 3.2–3.4 cm), so the
/// robot grasps once and the discovery is exactly what it is without the loop.
#[test]
fn a_confident_door_is_not_pulled_further() {
    let with = DiscoverySettings {
        axis_snap: 0.0,
        confident_axis_95: 4f64.to_radians(),
        confident_pivot_95: 0.04,
        ..DiscoverySettings::default()
    };
    let without = DiscoverySettings {
        max_extra_pulls: 0,
        ..with.clone()
    };
    for seed in 1..=3 {
        let (world, d) = discover_door(door_cabinet(), seed, &with);
        let log = &d.log[0];
        assert!(log.succeeded(), "seed {seed}: {log:#?}");
        let pulling = log.pulling.as_ref().unwrap();
        assert_eq!(pulling.end, PullEnd::Confident, "seed {seed}: {log:#?}");
        assert_eq!(pulling.extra_pulls, 0);
        assert_eq!(log.attempts.len(), 1);
        assert_eq!(world.grasps, 1);
        let (_, d0) = discover_door(door_cabinet(), seed, &without);
        assert_eq!(d, d0, "seed {seed}");
        let (deg, metres) = hinge_errors(&d);
        assert!(
            deg <= 3.0 && metres <= 0.03,
            "seed {seed}: {deg}°, {metres} m"
        );
    }
}

/// The same door at the default limits (2° / 2 cm): the first estimate is not confident
/// (above), so the robot grasps again and pulls on until it is: 1–2 further pulls
/// (measured for seeds 1–3: 1, 2, 1; half-angles 1.9°, 1.4°, 1.7°; errors 0.98°, 0.55°,
/// 0.30° and 0.5, 1.1, 1.2 cm), and the hinge is then within the limits of the truth.
#[test]
fn at_the_default_limits_the_door_is_pulled_on_until_confident() {
    let settings = DiscoverySettings {
        axis_snap: 0.0,
        ..DiscoverySettings::default()
    };
    for seed in 1..=3 {
        let (_, d) = discover_door(door_cabinet(), seed, &settings);
        let log = &d.log[0];
        assert!(log.succeeded(), "seed {seed}: {log:#?}");
        let pulling = log.pulling.as_ref().expect("the estimator ran");
        assert_eq!(pulling.end, PullEnd::Confident, "seed {seed}: {log:#?}");
        assert!(pulling.extra_pulls >= 1, "seed {seed}: {log:#?}");
        let e = log.estimate.as_ref().unwrap();
        assert!(e.axis_half_angle_95.unwrap() <= settings.confident_axis_95);
        assert!(e.pivot_radius_95.unwrap() <= settings.confident_pivot_95);
        let (deg, metres) = hinge_errors(&d);
        assert!(
            deg <= 2.0 && metres <= 0.02,
            "seed {seed}: {deg}°, {metres} m"
        );
    }
}

/// The same door with a wrist that turns the gripper at most 0.35 rad (20°) from its grasp
/// orientation (the test world's `max_wrist_turn`: a pull step past it is refused with
/// `JointLimit`, the arm at a joint limit, as the kitchen's Gen3 stops pulling a corner
/// door). The first pull stops at about 0.17 m of the 0.30 m target, an arc whose estimate
/// has doubts (measured for seeds 1–3: 1.5–4.2°, 0.3–2.2 cm off). With
/// `reposition_at_arm_limit` off, pulling ends there (`PullEnd::JointLimit`). With it (the
/// default), the further pulls start from a base pose placed in front of the last contact,
/// where the wrist starts over: 2 further pulls each (measured), the door 0.93 rad open, the
/// estimate confident and within the limits (2° / 2 cm) of the true hinge (measured: 1.47°,
/// 1.27°, 0.83° and 0.44, 0.04, 0.82 cm).
#[test]
fn at_the_arm_s_limit_the_door_is_pulled_on_from_a_new_base_pose() {
    let settings = DiscoverySettings {
        axis_snap: 0.0,
        ..DiscoverySettings::default()
    };
    let stop_at_limit = DiscoverySettings {
        reposition_at_arm_limit: false,
        ..settings.clone()
    };
    let wrist = |w: &mut World| {
        noisy_poses(w);
        w.settings.max_wrist_turn = 0.35;
    };
    for seed in 1..=3 {
        let run = |s: &DiscoverySettings| {
            run_with(door_cabinet(), &Proprioceptive::default(), seed, wrist, s)
        };
        let (_, d0) = run(&stop_at_limit);
        let log0 = &d0.log[0];
        let p0 = log0.pulling.as_ref().expect("the estimator ran");
        assert_eq!(p0.end, PullEnd::JointLimit, "seed {seed}: {log0:#?}");
        assert!(!p0.doubts.is_empty() && p0.extra_pulls == 0);
        assert!(log0.pull_distance < 0.2, "{}", log0.pull_distance);

        let (world, d) = run(&settings);
        let log = &d.log[0];
        assert!(log.succeeded(), "seed {seed}: {log:#?}");
        let pulling = log.pulling.as_ref().expect("the estimator ran");
        assert_eq!(pulling.end, PullEnd::Confident, "seed {seed}: {log:#?}");
        assert!(pulling.extra_pulls >= 1 && pulling.doubts.is_empty());
        // Every further pull started from another base pose than the first attempt's.
        let first = log.attempts[0].world_from_base.translation.vector;
        assert!(
            log.attempts[1..]
                .iter()
                .all(|a| (a.world_from_base.translation.vector - first).norm() > 0.05),
            "seed {seed}: {log:#?}"
        );
        assert!(
            log.notes
                .iter()
                .any(|n| n.contains("the arm reached a limit"))
        );
        assert!(
            log.pull_distance > 0.4,
            "seed {seed}: {}",
            log.pull_distance
        );
        assert!(world.state.as_slice()[0] > 0.8);
        let (deg, metres) = hinge_errors(&d);
        eprintln!(
            "seed {seed}: {} further pulls, {deg:.2}°, {metres:.4} m",
            pulling.extra_pulls
        );
        assert!(
            deg <= 2.0 && metres <= 0.02,
            "seed {seed}: {deg}°, {metres} m"
        );
    }
}
