//! OMPL base and arm paths, re-checked by the independent dense check `first_invalid`.
//!
//! Soundness argument used throughout: OMPL checks every motion at states no further apart
//! than `settings.resolution` (in its distance, which bounds the xy / joint-space Euclidean
//! distance from above), so any state of a motion is within `resolution / 2` of a checked one.
//! Planning with `resolution / 2` of clearance (contact distance) therefore guarantees zero
//! clearance along the whole path, which the dense re-check (at a fifth of OMPL's spacing,
//! with no clearance) must confirm. A failure of the re-check would be a real defect.

use std::f64::consts::PI;
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use kinscene::Termination;
use kinscene::motion::paths::{
    CONTINUOUS_JOINT_WINDOW, PathError, PathFailure, PathOutcome, PathSettings, first_invalid,
    plan_arm, plan_arm_checked, plan_base,
};
use kinscene::scene::collision::{CollisionSettings, collisions_of};
use kinscene::scene::{
    BaseShape, Joint, JointId, Limits, PartId, PartSpec, SceneData, SceneModel, SceneModelBuilder,
    Shape, State, forward_kinematics,
};
use nalgebra::{Isometry3, Point3, Vector3};

/// Footprint radius of the base (m).
const RADIUS: f64 = 0.3;
/// Room: x ∈ [0, 6], y ∈ [0, 4] (bounds of the base centre).
const BOUNDS: ([f64; 2], [f64; 2]) = ([0.0, 0.0], [6.0, 4.0]);
/// OMPL's motion-check spacing for the base (m).
const BASE_RESOLUTION: f64 = 0.02;

/// A disc footprint of radius `RADIUS` as a vertical cylinder riding on two prismatic joints
/// (x, then y) added to a scene: the scene's own exact collision query decides validity.
struct Footprint {
    model: SceneModel,
    robot: PartId,
    joints: [JointId; 2],
    state: State,
    data: Mutex<SceneData>,
    settings: CollisionSettings,
}

impl Footprint {
    /// `clearance`: separation (m) required between the footprint and everything else.
    fn new(scene: SceneModel, clearance: f64) -> Footprint {
        let (lo, hi) = BOUNDS;
        let mut b: SceneModelBuilder = scene.to_builder();
        b.add_part(PartSpec::on_base(
            "footprint_x",
            Joint::prismatic(
                "footprint_x",
                Point3::origin(),
                Vector3::x(),
                Limits::new(lo[0], hi[0]),
            ),
        ));
        // Cylinder z ∈ [0.02, 2.0]: clear of a floor at z = 0, below the 2.4 m walls' tops.
        b.add_part(
            PartSpec::on_part(
                "footprint",
                "footprint_x",
                Joint::prismatic(
                    "footprint_y",
                    Point3::origin(),
                    Vector3::y(),
                    Limits::new(lo[1], hi[1]),
                ),
            )
            .with_collider(
                Shape::cylinder(RADIUS, 1.98),
                Isometry3::translation(0.0, 0.0, 1.01),
            ),
        );
        let model = b.build().unwrap();
        let joints = [
            model.joint_id("footprint_x").unwrap(),
            model.joint_id("footprint_y").unwrap(),
        ];
        Footprint {
            robot: model.part_id("footprint").unwrap(),
            state: model.zero_state(),
            data: Mutex::new(SceneData::new(&model)),
            settings: CollisionSettings {
                contact_distance: clearance,
                ..CollisionSettings::default()
            },
            joints,
            model,
        }
    }

    fn is_free(&self, x: f64, y: f64) -> bool {
        let mut state = self.state.clone();
        state.set_unchecked(self.joints[0], x);
        state.set_unchecked(self.joints[1], y);
        let mut data = self.data.lock().unwrap();
        forward_kinematics(&self.model, &mut data, &state).unwrap();
        collisions_of(&self.model, &data, &self.settings, self.robot)
            .unwrap()
            .is_empty()
    }
}

/// A 6 m × 4 m room split by a wall x ∈ [2.9, 3.1]; `gap` leaves y ∈ [1.6, 2.4] open (0.8 m,
/// wide enough for the 0.6 m footprint plus clearance).
fn corridor(gap: bool) -> SceneModel {
    let mut b = SceneModelBuilder::new();
    let wall = |name: &str, y0: f64, y1: f64| {
        BaseShape::new(
            name,
            Shape::box_size(Vector3::new(0.2, y1 - y0, 2.4)),
            Isometry3::translation(3.0, 0.5 * (y0 + y1), 1.2),
        )
    };
    if gap {
        b.add_base_shape(wall("wall_south", -1.0, 1.6));
        b.add_base_shape(wall("wall_north", 2.4, 5.0));
    } else {
        b.add_base_shape(wall("wall", -1.0, 5.0));
    }
    b.build().unwrap()
}

fn base_settings(seed: u64, budget: Duration) -> PathSettings {
    PathSettings {
        budget,
        resolution: BASE_RESOLUTION,
        seed: Some(seed),
        ..PathSettings::default()
    }
}

fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

#[test]
fn base_path_through_the_gap_passes_the_dense_recheck() {
    let planning = Footprint::new(corridor(true), BASE_RESOLUTION / 2.0);
    let exact = Footprint::new(corridor(true), 0.0);
    let valid = |q: &[f64; 3]| planning.is_free(q[0], q[1]);
    let recheck = |q: &[f64]| exact.is_free(q[0], q[1]);
    let (start, goal) = ([1.0, 0.8, 0.0], [5.0, 1.0, 3.0]);
    // Not trivial: the straight motion crosses the wall.
    assert!(first_invalid(&[start.to_vec(), goal.to_vec()], 0.01, true, &recheck).is_some());

    let settings = base_settings(11, Duration::from_secs(10));
    let outcome = plan_base(start, goal, BOUNDS, &valid, &settings, &Termination::none()).unwrap();
    let PathOutcome::Solved(path) = outcome else {
        panic!("{outcome:?}")
    };
    assert_eq!(path[0], start.to_vec());
    let last = path.last().unwrap();
    // OMPL's goal tolerance is 1e-6 in its SE(2) distance.
    assert!(
        (last[0] - goal[0]).hypot(last[1] - goal[1]) <= 1e-6,
        "{last:?}"
    );
    assert!(wrap(last[2] - goal[2]).abs() <= 2e-6, "{last:?}");
    // Yaw is unwrapped: consecutive yaws differ by at most π.
    assert!(path.windows(2).all(|w| (w[1][2] - w[0][2]).abs() <= PI));
    // Every state within the xy bounds.
    assert!(
        path.iter()
            .all(|q| (0.0..=6.0).contains(&q[0]) && (0.0..=4.0).contains(&q[1]))
    );
    assert_eq!(
        first_invalid(&path, BASE_RESOLUTION / 5.0, true, &recheck),
        None
    );
    // It went through the gap: where it crosses x = 3, y leaves the disc clear of both wall
    // ends (the gap is y ∈ [1.6, 2.4]).
    let crossing = path
        .windows(2)
        .find(|w| (w[0][0] - 3.0) * (w[1][0] - 3.0) <= 0.0)
        .expect("the path crosses x = 3");
    let t = (3.0 - crossing[0][0]) / (crossing[1][0] - crossing[0][0]);
    let y = crossing[0][1] + t * (crossing[1][1] - crossing[0][1]);
    assert!(
        (1.6 + RADIUS..=2.4 - RADIUS).contains(&y),
        "y = {y} at x = 3"
    );
}

#[test]
fn same_seed_same_base_path() {
    let planning = Footprint::new(corridor(true), BASE_RESOLUTION / 2.0);
    let valid = |q: &[f64; 3]| planning.is_free(q[0], q[1]);
    let settings = base_settings(5, Duration::from_secs(10));
    let run = || {
        plan_base(
            [1.0, 0.8, 0.0],
            [5.0, 1.0, 1.0],
            BOUNDS,
            &valid,
            &settings,
            &Termination::none(),
        )
    };
    let first = run().unwrap();
    assert!(first.is_solved(), "{first:?}");
    assert_eq!(first, run().unwrap());
}

#[test]
fn walled_off_goal_is_an_outcome_within_the_budget() {
    let planning = Footprint::new(corridor(false), BASE_RESOLUTION / 2.0);
    let valid = |q: &[f64; 3]| planning.is_free(q[0], q[1]);
    let budget = Duration::from_millis(500);
    let settings = base_settings(3, budget);
    let t0 = Instant::now();
    let outcome = plan_base(
        [1.0, 0.8, 0.0],
        [5.0, 1.0, 0.0],
        BOUNDS,
        &valid,
        &settings,
        &Termination::none(),
    );
    let elapsed = t0.elapsed();
    // RRTConnect searches until its budget runs out; OMPL then reports an approximate
    // solution, which is a timeout (not a proof that no path exists).
    assert!(
        matches!(outcome, Ok(PathOutcome::Timeout(()))),
        "{outcome:?}"
    );
    // The budget covers planning and simplification; allow 0.5 s for set-up and the shim load.
    assert!(elapsed < budget + Duration::from_millis(500), "{elapsed:?}");
}

#[test]
fn an_iteration_budget_ends_the_walled_off_search_the_same_way_every_time() {
    // The walled-off goal of the test above, with the wall clock far beyond what 2000
    // iterations need (60 s) and an iteration budget: the search ends on the count, an
    // infeasible outcome naming the budget, the same twice, in well under the wall clock.
    let settings = PathSettings {
        max_iterations: Some(2000),
        ..base_settings(3, Duration::from_secs(60))
    };
    // From (1.0, 0.8) across the corridor, with or without the wall's gap.
    let run = |gap: bool, goal: [f64; 3]| {
        let planning = Footprint::new(corridor(gap), BASE_RESOLUTION / 2.0);
        let valid = |q: &[f64; 3]| planning.is_free(q[0], q[1]);
        plan_base(
            [1.0, 0.8, 0.0],
            goal,
            BOUNDS,
            &valid,
            &settings,
            &Termination::none(),
        )
        .unwrap()
    };
    let t0 = Instant::now();
    let first = run(false, [5.0, 1.0, 0.0]);
    assert!(t0.elapsed() < Duration::from_secs(30), "{:?}", t0.elapsed());
    assert_eq!(
        first,
        PathOutcome::Infeasible(PathFailure::IterationBudget { iterations: 2000 })
    );
    let reason = PathFailure::IterationBudget { iterations: 2000 }.to_string();
    assert!(
        reason.contains("iteration budget (2000 iterations)"),
        "{reason}"
    );
    assert_eq!(first, run(false, [5.0, 1.0, 0.0]));
    // The corridor with its gap is solved within the same budget, the same path twice.
    let solved = run(true, [5.0, 1.0, 1.0]);
    assert!(solved.is_solved(), "{solved:?}");
    assert_eq!(solved, run(true, [5.0, 1.0, 1.0]));
    let zero = PathSettings {
        max_iterations: Some(0),
        ..PathSettings::default()
    };
    assert!(zero.validate().is_err());
}

#[test]
fn cancel_flag_set_before_planning_cancels() {
    let planning = Footprint::new(corridor(false), 0.0);
    let valid = |q: &[f64; 3]| planning.is_free(q[0], q[1]);
    let flag = AtomicBool::new(true);
    let settings = base_settings(3, Duration::from_secs(10));
    let t0 = Instant::now();
    let outcome = plan_base(
        [1.0, 0.8, 0.0],
        [5.0, 1.0, 0.0],
        BOUNDS,
        &valid,
        &settings,
        &Termination::none().with_cancel(&flag),
    )
    .unwrap();
    assert_eq!(outcome, PathOutcome::Cancelled(()));
    assert!(t0.elapsed() < Duration::from_secs(2));
}

#[test]
fn invalid_start_and_goal_are_outcomes() {
    let planning = Footprint::new(corridor(true), 0.0);
    let valid = |q: &[f64; 3]| planning.is_free(q[0], q[1]);
    let settings = base_settings(1, Duration::from_secs(1));
    // Centre 0.1 m from the wall's face: the 0.3 m disc overlaps it.
    let inside = [2.8, 0.8, 0.0];
    let free = [1.0, 0.8, 0.0];
    assert!(!valid(&inside) && valid(&free));
    let outcome = plan_base(
        inside,
        free,
        BOUNDS,
        &valid,
        &settings,
        &Termination::none(),
    )
    .unwrap();
    assert_eq!(outcome, PathOutcome::Infeasible(PathFailure::InvalidStart));
    let outcome = plan_base(
        free,
        inside,
        BOUNDS,
        &valid,
        &settings,
        &Termination::none(),
    )
    .unwrap();
    assert_eq!(outcome, PathOutcome::Infeasible(PathFailure::InvalidGoal));
    // A goal outside the bounds is an outcome too (the start is an error, below).
    let outcome = plan_base(
        free,
        [7.0, 1.0, 0.0],
        BOUNDS,
        &valid,
        &settings,
        &Termination::none(),
    )
    .unwrap();
    assert_eq!(outcome, PathOutcome::Infeasible(PathFailure::InvalidGoal));
}

#[test]
fn bad_base_input_gives_typed_errors() {
    let valid = |_: &[f64; 3]| true;
    let ok = PathSettings::default();
    let plan = |start: [f64; 3], bounds, settings: &PathSettings| {
        plan_base(
            start,
            [1.0, 1.0, 0.0],
            bounds,
            &valid,
            settings,
            &Termination::none(),
        )
    };
    assert!(matches!(
        plan([f64::NAN, 0.5, 0.0], BOUNDS, &ok),
        Err(PathError::NonFinite {
            what: "start",
            index: 0,
            ..
        })
    ));
    assert!(matches!(
        plan([0.5, 0.5, 0.0], ([0.0, 5.0], [6.0, 4.0]), &ok),
        Err(PathError::InvalidBounds { axis: 1, .. })
    ));
    assert!(matches!(
        plan([0.5, 0.5, 0.0], ([0.0, 0.0], [f64::INFINITY, 4.0]), &ok),
        Err(PathError::NonFinite {
            what: "xy bounds",
            index: 2,
            ..
        })
    ));
    assert!(matches!(
        plan([-0.5, 0.5, 0.0], BOUNDS, &ok),
        Err(PathError::StartOutOfBounds { axis: 0, .. })
    ));
    let zero_budget = PathSettings {
        budget: Duration::ZERO,
        ..PathSettings::default()
    };
    assert!(matches!(
        plan([0.5, 0.5, 0.0], BOUNDS, &zero_budget),
        Err(PathError::InvalidSetting(s)) if s.field == "budget"
    ));
    for resolution in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-300] {
        let bad = PathSettings {
            resolution,
            ..PathSettings::default()
        };
        assert!(
            matches!(
                plan([0.5, 0.5, 0.0], BOUNDS, &bad),
                Err(PathError::InvalidSetting(s)) if s.field == "resolution"
            ),
            "{resolution}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Arm: a 4-D joint space with a forbidden region stated directly in q.

/// OMPL's motion-check spacing in joint space (rad).
const ARM_RESOLUTION: f64 = 0.01;

/// Forbidden set F: the slab |q0| ≤ 0.2 except the window 1.0 < q1 < 1.6, i.e. the union of
/// the boxes {|q0| ≤ 0.2, q1 ≤ 1.0} and {|q0| ≤ 0.2, q1 ≥ 1.6} (q2, q3 free). The distance
/// from q to each box is the Euclidean norm of the per-axis excesses; a state is valid when it
/// is further than `clearance` from both.
fn arm_valid(q: &[f64], clearance: f64) -> bool {
    let slab = (q[0].abs() - 0.2).max(0.0);
    let below = slab.hypot((q[1] - 1.0).max(0.0));
    let above = slab.hypot((1.6 - q[1]).max(0.0));
    below > clearance && above > clearance
}

#[test]
fn arm_path_through_the_window_passes_the_dense_recheck() {
    let start = [-1.0, 0.0, 0.5, 0.0];
    // The last joint is continuous: the goal value is kept as given (beyond π).
    let goal = [1.0, 0.2, -0.5, 4.0];
    let lower = [-PI, -PI, -PI, f64::NEG_INFINITY];
    let upper = [PI, PI, PI, f64::INFINITY];
    let planning = |q: &[f64]| arm_valid(q, ARM_RESOLUTION / 2.0);
    let exact = |q: &[f64]| arm_valid(q, 0.0);
    assert!(first_invalid(&[start.to_vec(), goal.to_vec()], 0.01, false, &exact).is_some());

    let settings = PathSettings {
        resolution: ARM_RESOLUTION,
        budget: Duration::from_secs(10),
        seed: Some(21),
        ..PathSettings::default()
    };
    let outcome = plan_arm(
        &start,
        &goal,
        &lower,
        &upper,
        &planning,
        &settings,
        &Termination::none(),
    )
    .unwrap();
    let PathOutcome::Solved(path) = outcome else {
        panic!("{outcome:?}")
    };
    assert_eq!(path[0], start.to_vec());
    let last = path.last().unwrap();
    let goal_error = last
        .iter()
        .zip(&goal)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(goal_error <= 1e-6, "{last:?}");
    // Finite joints stay within their limits; the continuous one within its window.
    let window = (0.0 - CONTINUOUS_JOINT_WINDOW, 4.0 + CONTINUOUS_JOINT_WINDOW);
    for q in &path {
        assert!(q[..3].iter().all(|v| v.abs() <= PI), "{q:?}");
        assert!(q[3] >= window.0 && q[3] <= window.1, "{q:?}");
    }
    assert_eq!(
        first_invalid(&path, ARM_RESOLUTION / 5.0, false, &exact),
        None
    );
    // It went through the window: where q0 crosses 0, q1 is inside (1.0, 1.6).
    let crossing = path
        .windows(2)
        .find(|w| w[0][0] * w[1][0] <= 0.0)
        .expect("q0 changes sign");
    let t = crossing[0][0] / (crossing[0][0] - crossing[1][0]);
    let q1 = crossing[0][1] + t * (crossing[1][1] - crossing[0][1]);
    assert!(q1 > 1.0 && q1 < 1.6, "q1 = {q1} at q0 = 0");
}

#[test]
fn arm_blocked_goal_and_bad_input() {
    let settings = PathSettings {
        budget: Duration::from_millis(300),
        seed: Some(2),
        ..PathSettings::default()
    };
    // Closing the window (a full slab) walls the goal off.
    let slab = |q: &[f64]| q[0].abs() > 0.2;
    let (lower, upper) = ([-PI; 3], [PI; 3]);
    let outcome = plan_arm(
        &[-1.0, 0.0, 0.0],
        &[1.0, 0.0, 0.0],
        &lower,
        &upper,
        &slab,
        &settings,
        &Termination::none(),
    )
    .unwrap();
    assert!(
        matches!(
            outcome,
            PathOutcome::Timeout(())
                | PathOutcome::Infeasible(
                    PathFailure::Planner { .. } | PathFailure::Approximate { .. }
                )
        ),
        "{outcome:?}"
    );
    // Invalid start.
    let outcome = plan_arm(
        &[0.0, 0.0, 0.0],
        &[1.0, 0.0, 0.0],
        &lower,
        &upper,
        &slab,
        &settings,
        &Termination::none(),
    )
    .unwrap();
    assert_eq!(outcome, PathOutcome::Infeasible(PathFailure::InvalidStart));

    let any = |_: &[f64]| true;
    let arm = |start: &[f64], goal: &[f64], lower: &[f64], upper: &[f64]| {
        plan_arm(
            start,
            goal,
            lower,
            upper,
            &any,
            &settings,
            &Termination::none(),
        )
    };
    assert!(matches!(
        arm(&[], &[], &[], &[]),
        Err(PathError::ZeroDimension)
    ));
    assert!(matches!(
        arm(&[0.0; 3], &[0.0; 2], &lower, &upper),
        Err(PathError::DimensionMismatch {
            what: "goal",
            expected: 3,
            got: 2
        })
    ));
    assert!(matches!(
        arm(&[0.0; 3], &[0.0; 3], &lower, &upper[..2]),
        Err(PathError::DimensionMismatch {
            what: "upper bounds",
            ..
        })
    ));
    assert!(matches!(
        arm(&[0.0; 3], &[0.0, f64::NAN, 0.0], &lower, &upper),
        Err(PathError::NonFinite {
            what: "goal",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        arm(&[0.0; 3], &[0.0; 3], &[-1.0, f64::NAN, -1.0], &upper),
        Err(PathError::NonFinite {
            what: "lower bounds",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        arm(&[0.0; 3], &[0.0; 3], &[-1.0, 2.0, -1.0], &[1.0; 3]),
        Err(PathError::InvalidBounds { axis: 1, .. })
    ));
    assert!(matches!(
        arm(
            &[0.0; 3],
            &[0.0; 3],
            &[f64::INFINITY; 3],
            &[f64::INFINITY; 3]
        ),
        Err(PathError::InvalidBounds { axis: 0, .. })
    ));
    assert!(matches!(
        arm(&[0.0, 0.0, 3.5], &[0.0; 3], &lower, &upper),
        Err(PathError::StartOutOfBounds { axis: 2, .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// first_invalid on hand-built paths.

/// Invalid inside the closed box x ∈ [0.95, 1.05], y ∈ [0.42, 0.48].
fn outside_box(q: &[f64]) -> bool {
    !((0.95..=1.05).contains(&q[0]) && (0.42..=0.48).contains(&q[1]))
}

#[test]
fn first_invalid_finds_the_point_between_valid_waypoints() {
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    assert!(path.iter().all(|q| outside_box(q)));
    // Segment 1 runs up x = 1 and enters the box at y = 0.42. With spacing 0.01 (100 steps)
    // the samples are y = j/100, and j = 42 is the first inside.
    let (segment, q) = first_invalid(&path, 0.01, false, &outside_box).unwrap();
    assert_eq!(segment, 1);
    assert_eq!(q, vec![1.0, 0.42]);
    // Spacing 0.2 (5 or 6 steps: y = 0.4, 0.6 or y = 1/3, 1/2) jumps over the 0.06 m box.
    assert_eq!(first_invalid(&path, 0.2, false, &outside_box), None);
    // An invalid waypoint is reported as the end of the segment leading to it.
    let path = vec![vec![0.0, 0.45], vec![1.0, 0.45], vec![2.0, 0.45]];
    let (segment, q) = first_invalid(&path, 10.0, false, &outside_box).unwrap();
    assert_eq!((segment, q), (0, vec![1.0, 0.45]));
}

#[test]
fn first_invalid_wraps_yaw_the_short_way() {
    // Invalid while |yaw| < 1: turning from 3.0 to -3.0 the short way (through π, 0.28 rad)
    // never gets there; the long way (through 0, 6 rad) does.
    let valid = |q: &[f64]| q[2].abs() >= 1.0;
    let path = vec![vec![0.0, 0.0, 3.0], vec![0.0, 0.0, -3.0]];
    assert_eq!(first_invalid(&path, 0.01, true, &valid), None);
    let (segment, q) = first_invalid(&path, 0.01, false, &valid).unwrap();
    assert_eq!(segment, 0);
    assert!(q[2] < 1.0 && q[2] > 0.98, "{q:?}");
}

#[test]
fn first_invalid_fails_closed() {
    let any = |_: &[f64]| true;
    let path = vec![vec![0.0, 0.0], vec![1.0, 0.0]];
    assert_eq!(first_invalid(&[], 0.1, false, &any), None);
    for resolution in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            first_invalid(&path, resolution, false, &any),
            Some((0, vec![0.0, 0.0]))
        );
    }
    let nan = vec![vec![0.0, 0.0], vec![f64::NAN, 0.0]];
    assert!(matches!(
        first_invalid(&nan, 0.1, false, &any),
        Some((0, _))
    ));
    let ragged = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0]];
    assert_eq!(
        first_invalid(&ragged, 0.1, false, &any),
        Some((1, vec![1.0]))
    );
    // wrap_yaw needs [x, y, yaw].
    assert_eq!(
        first_invalid(&path, 0.1, true, &any),
        Some((0, vec![0.0, 0.0]))
    );
}

#[test]
fn the_callers_termination_bounds_a_path_and_a_spent_one_stops_it_at_once() {
    // The corridor of the other base tests, with a generous per-path budget: the caller's
    // condition decides. A deadline already passed is a timeout before OMPL is called.
    let planning = Footprint::new(corridor(false), 0.0);
    let valid = |q: &[f64; 3]| planning.is_free(q[0], q[1]);
    let settings = base_settings(3, Duration::from_secs(10));
    let spent = Termination::after(Duration::ZERO);
    let t0 = Instant::now();
    let outcome = plan_base(
        [1.0, 0.8, 0.0],
        [5.0, 1.0, 0.0],
        BOUNDS,
        &valid,
        &settings,
        &spent,
    )
    .unwrap();
    assert_eq!(outcome, PathOutcome::Timeout(()));
    assert!(
        t0.elapsed() < Duration::from_millis(100),
        "{:?}",
        t0.elapsed()
    );
    // A walled-off goal under a 0.3 s caller deadline (the path budget is 10 s): stopped by
    // the caller's deadline, plus set-up.
    let walled = Footprint::new(corridor(false), BASE_RESOLUTION / 2.0);
    let valid = |q: &[f64; 3]| walled.is_free(q[0], q[1]);
    let t0 = Instant::now();
    let outcome = plan_base(
        [1.0, 0.8, 0.0],
        [5.0, 1.0, 0.0],
        BOUNDS,
        &valid,
        &settings,
        &Termination::after(Duration::from_millis(300)),
    )
    .unwrap();
    assert!(
        matches!(
            outcome,
            PathOutcome::Timeout(())
                | PathOutcome::Infeasible(
                    PathFailure::Planner { .. } | PathFailure::Approximate { .. }
                )
        ),
        "{outcome:?}"
    );
    assert!(
        t0.elapsed() < Duration::from_millis(800),
        "{:?}",
        t0.elapsed()
    );
}

/// [`plan_arm_checked`]: the Gen3 at the origin reaches from one side of a post to the other
/// (the straight motion hits it); the path is re-checked by the dense check (a fifth of the
/// planner's spacing) with the exact parry check at no clearance. Soundness as in the module
/// docs: between checked states (at most 0.01 apart in joint space) no point of the arm moves
/// more than 0.01·√7·1.2 m / 2 < 0.02 m from its nearest checked position (every lever arm of
/// the Gen3 is under 1.2 m), so planning with 0.02 m of clearance keeps the whole path clear
/// of the scene. The planner's checker and the re-check share only `link_poses`.
#[test]
fn arm_path_with_the_arm_check_passes_the_exact_recheck() {
    use kinscene::kinematics::robot::{
        ArmCheck, EdgeScene, Exempt, RobotCollision, RobotConfig, RobotModel, RobotSpheres,
        SphereSettings,
    };
    use nalgebra::DVector;

    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(BaseShape::new(
        "post",
        Shape::cylinder(0.05, 2.0),
        Isometry3::translation(0.55, 0.0, 1.0),
    ));
    let model = b.build().unwrap();
    let mut data = SceneData::new(&model);
    forward_kinematics(&model, &mut data, &State::from_slice(&model, &[]).unwrap()).unwrap();
    let scene = EdgeScene {
        model: &model,
        data: &data,
        exempt: Exempt::Nothing,
        margin: 0.02,
    };
    let check = ArmCheck::new(&robot, &collision, &spheres, scene, [0.0; 3]).unwrap();
    let exact = |q: &[f64]| {
        let Ok(poses) = robot.link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: DVector::from_column_slice(q),
        }) else {
            return false;
        };
        collision.self_collision(&poses).is_none()
            && collision
                .scene_collision(&poses, &model, &data, Exempt::Nothing, 0.0)
                .is_none()
    };
    let mut start = robot.neutral();
    let mut goal = robot.neutral();
    start[0] = -1.2;
    goal[0] = 1.2;
    for q in [&mut start, &mut goal] {
        q[1] = 0.9;
        q[3] = 0.6;
    }
    let (start, goal) = (start.as_slice().to_vec(), goal.as_slice().to_vec());
    assert!(exact(&start) && exact(&goal));
    assert!(first_invalid(&[start.clone(), goal.clone()], 0.002, false, &exact).is_some());
    let (lower, upper) = robot.arm_bounds();
    let settings = PathSettings {
        seed: Some(5),
        budget: Duration::from_secs(10),
        ..PathSettings::default()
    };
    let outcome = plan_arm_checked(
        &start,
        &goal,
        lower.as_slice(),
        upper.as_slice(),
        &check,
        &settings,
        &Termination::none(),
    )
    .unwrap();
    let PathOutcome::Solved(path) = outcome else {
        panic!("{outcome:?}")
    };
    assert_eq!(path[0], start);
    assert_eq!(
        first_invalid(&path, settings.resolution / 5.0, false, &exact),
        None
    );
}
