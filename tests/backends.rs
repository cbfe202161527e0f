//! The three C++ backends in one process.
//!
//! OMPL links Debian's boost 1.74 and Pinocchio the wheel's boost 1.90; both are loaded here at
//! once (asserted from `/proc/self/maps`), and Pinocchio is even called from inside OMPL's
//! planning loop through the Rust validity callback. Each shim is loaded with RTLD_DEEPBIND, so
//! neither library's boost calls bind to the other's copy; this test is the guard that all three
//! keep producing correct numbers together.

#![cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]

use std::sync::Mutex;
use std::time::Duration;

use kinscene::kinematics::pinocchio::{self as pin, JointIndex, JointKind, JointLimits};
use kinscene::motion::casadi::{Expr, Nlp, NlpSettings};
use kinscene::motion::ompl::{self, PlanSettings, PlanStatus, Problem, StateSpace, Termination};
use nalgebra::{DVector, Isometry3, Point2, Vector3};

/// Link lengths (m) of a planar 3R arm whose joints all turn about z.
const LINKS: [f64; 3] = [0.4, 0.3, 0.2];
/// A disc obstacle in the arm's plane: centre and radius (m). Link 1 (0.4 m) passes under it;
/// links 2 and 3 must fold to get by, so the straight joint-space line is blocked.
const OBSTACLE: ([f64; 2], f64) = ([0.55, 0.15], 0.06);
/// Where the tool must end up (m).
const TARGET: [f64; 2] = [-0.35, 0.45];
/// OMPL checks motions every `RESOLUTION · extent` in joint space, extent = 2π·√3 for [-π, π]³.
const RESOLUTION: f64 = 0.002;

struct Arm {
    model: pin::Model,
    joints: [JointIndex; 3],
    tool: pin::FrameIndex,
}

fn arm() -> Arm {
    let mut b = pin::ModelBuilder::new();
    let mut parent = JointIndex::UNIVERSE;
    let mut offset = 0.0;
    let mut joints = [JointIndex::UNIVERSE; 3];
    for (i, len) in LINKS.iter().enumerate() {
        parent = b
            .add_joint(
                &format!("j{i}"),
                parent,
                Isometry3::translation(offset, 0.0, 0.0),
                JointKind::Revolute { axis: Vector3::z() },
                JointLimits::position(-std::f64::consts::PI, std::f64::consts::PI),
            )
            .unwrap();
        joints[i] = parent;
        offset = *len;
    }
    let tool = b
        .add_frame("tool", parent, Isometry3::translation(offset, 0.0, 0.0))
        .unwrap();
    Arm {
        model: b.build().unwrap(),
        joints,
        tool,
    }
}

/// The arm's link segments at q, from Pinocchio's joint placements and tool frame.
fn segments(arm: &Arm, data: &mut pin::Data, q: &[f64]) -> Vec<(Point2<f64>, Point2<f64>)> {
    pin::forward_kinematics(&arm.model, data, &DVector::from_row_slice(q)).unwrap();
    let mut points: Vec<Point2<f64>> = arm
        .joints
        .iter()
        .map(|&j| pin::joint_placement(&arm.model, data, j).unwrap())
        .map(|p| Point2::new(p.translation.x, p.translation.y))
        .collect();
    let tool = pin::frame_placement(&arm.model, data, arm.tool).unwrap();
    points.push(Point2::new(tool.translation.x, tool.translation.y));
    points.windows(2).map(|w| (w[0], w[1])).collect()
}

fn point_segment_distance(p: Point2<f64>, a: Point2<f64>, b: Point2<f64>) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// Smallest distance from the obstacle's centre to the arm, minus the obstacle's radius.
fn clearance(arm: &Arm, data: &mut pin::Data, q: &[f64]) -> f64 {
    let centre = Point2::from(OBSTACLE.0);
    segments(arm, data, q)
        .into_iter()
        .map(|(a, b)| point_segment_distance(centre, a, b))
        .fold(f64::INFINITY, f64::min)
        - OBSTACLE.1
}

/// The smallest clearance along the straight joint-space motion a → b, sampled 1e-3 rad apart.
fn min_clearance(arm: &Arm, data: &mut pin::Data, a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    let n = (d / 1e-3).ceil().max(1.0) as usize;
    (0..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let s: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect();
            clearance(arm, data, &s)
        })
        .fold(f64::INFINITY, f64::min)
}

fn boost_versions_loaded() -> (bool, bool) {
    let maps = std::fs::read_to_string("/proc/self/maps").unwrap();
    (
        maps.contains("libboost_") && maps.contains(".so.1.74.0"),
        maps.contains("libboost_") && maps.contains(".so.1.90.0"),
    )
}

#[test]
fn all_three_in_one_process() {
    let arm = arm();

    // 1. CasADi/IPOPT: inverse kinematics of the tool onto TARGET, closest to q = 0.
    let mut nlp = Nlp::new();
    let q: Vec<Expr> = (0..3)
        .map(|i| nlp.variable(&format!("q{i}"), -3.0, 3.0).unwrap())
        .collect();
    let (mut angle, mut x, mut y) = (
        Expr::constant(0.0),
        Expr::constant(0.0),
        Expr::constant(0.0),
    );
    for (qi, len) in q.iter().zip(LINKS) {
        angle += qi;
        x += len * angle.cos();
        y += len * angle.sin();
    }
    nlp.constrain_eq(x - TARGET[0], 0.0).unwrap();
    nlp.constrain_eq(y - TARGET[1], 0.0).unwrap();
    nlp.minimize(q.iter().map(Expr::sq).sum::<Expr>()).unwrap();
    let sol = nlp
        .build(&NlpSettings::default())
        .unwrap()
        .solve(&[1.0, 0.5, 0.5], &[])
        .unwrap();
    assert!(sol.status.is_success(), "IPOPT: {:?}", sol.status);
    let goal = sol.x.clone();

    // 2. Pinocchio, an independent kinematics implementation, confirms the IK answer
    //    (IPOPT's constraint tolerance is 1e-8 on the residual; 1e-6 m leaves margin).
    let mut data = pin::Data::new(&arm.model).unwrap();
    let tip = segments(&arm, &mut data, &goal)[2].1;
    assert!((tip - Point2::from(TARGET)).norm() < 1e-6, "tool at {tip}");

    // 3. OMPL plans from q = 0 (arm stretched along x, beside the obstacle) to the IK answer;
    //    the validity callback runs Pinocchio FK inside OMPL's loop.
    //    Between two checked states q moves at most step = RESOLUTION·2π√3 (Euclidean), and any
    //    arm point at most step·√(0.9² + 0.5² + 0.2²) (its distances to the three joints), so a
    //    point of an intermediate state is within half of that of a checked one. Requiring that
    //    much clearance makes the dense re-check below sound.
    let step = RESOLUTION * 2.0 * std::f64::consts::PI * 3f64.sqrt();
    let margin = 0.5 * step * (0.9f64.powi(2) + 0.5f64.powi(2) + 0.2f64.powi(2)).sqrt();
    let shared = Mutex::new(pin::Data::new(&arm.model).unwrap());
    let checker = |s: &[f64]| clearance(&arm, &mut shared.lock().unwrap(), s) > margin;
    let pi = std::f64::consts::PI;
    let problem = Problem::new(
        StateSpace::RealVector {
            lower: vec![-pi; 3],
            upper: vec![pi; 3],
        },
        vec![0.0; 3],
        goal.clone(),
    );
    let settings = PlanSettings {
        resolution_fraction: RESOLUTION,
        ..PlanSettings::default()
    };
    let outcome = ompl::plan(
        &problem,
        &checker,
        &settings,
        Termination::after(Duration::from_secs(5)),
    )
    .unwrap();
    assert_eq!(outcome.status, PlanStatus::ExactSolution);
    assert_eq!(outcome.path.first().unwrap(), &vec![0.0; 3]);
    let last = outcome.path.last().unwrap();
    let goal_error: f64 = last.iter().zip(&goal).map(|(a, b)| (a - b).powi(2)).sum();
    assert!(goal_error.sqrt() <= problem.goal_tolerance);

    // The problem is not trivial: the straight joint-space motion hits the obstacle.
    assert!(min_clearance(&arm, &mut data, &[0.0; 3], &goal) <= 0.0);
    // Dense re-check of every motion, 1e-3 rad apart, with zero margin: an independent
    // confirmation that the arm never touches the obstacle along the returned path.
    for w in outcome.path.windows(2) {
        assert!(min_clearance(&arm, &mut data, &w[0], &w[1]) > 0.0, "{w:?}");
    }

    // Both boost versions really are in this process (otherwise the test proves nothing).
    assert_eq!(boost_versions_loaded(), (true, true));
}
