//! The three backends in one process, on a miniature of the paper's manipulation step.
//!
//! A planar mobile base carries a two-link arm (Pinocchio model). A handle stands behind a wall.
//! 1. CasADi/IPOPT chooses the base pose and arm angles that put the tool on the handle while
//!    keeping the base clear of it and close to where it starts (a whole-body base placement,
//!    written with nalgebra matrices of symbolic expressions).
//! 2. Pinocchio recomputes the tool pose at that solution: an independent check of the NLP.
//! 3. OMPL plans the base path in SE(2) from the start to the chosen pose around the wall, with
//!    the validity check written in Rust.
//!
//! Run: `bash setup.sh && cargo run --release --example backends`

use std::time::Duration;

use kinscene::kinematics::pinocchio::{self as pin, JointIndex, JointKind, JointLimits};
use kinscene::motion::casadi::{Expr, Nlp, NlpSettings};
use kinscene::motion::ompl::{self, PlanSettings, Problem, StateSpace, Termination};
use nalgebra::{DVector, Isometry3, Matrix3, Vector3};

/// Arm link lengths (m) and the height of the arm above the base (m).
const L1: f64 = 0.5;
const L2: f64 = 0.4;
const ARM_HEIGHT: f64 = 0.8;
/// The handle to reach (world, m), and how far the base must stay from it (m).
const HANDLE: [f64; 2] = [2.0, 1.0];
const BASE_CLEARANCE: f64 = 0.6;
/// The robot base is a disc of this radius (m); the wall is the box x ∈ [0.9, 1.1], y ≤ 1.6.
const ROBOT_RADIUS: f64 = 0.3;
const WALL: ([f64; 2], [f64; 2]) = ([0.9, 1.1], [-2.0, 1.6]);

fn main() -> Result<(), kinscene::Error> {
    // --- Pinocchio: planar base + two revolute joints about z, tool frame at the arm tip.
    let mut b = pin::ModelBuilder::new();
    let base = b.add_joint(
        "base",
        JointIndex::UNIVERSE,
        Isometry3::identity(),
        JointKind::Planar,
        JointLimits::NONE,
    )?;
    let shoulder = b.add_joint(
        "shoulder",
        base,
        Isometry3::translation(0.0, 0.0, ARM_HEIGHT),
        JointKind::Revolute { axis: Vector3::z() },
        JointLimits::position(-2.5, 2.5),
    )?;
    let elbow = b.add_joint(
        "elbow",
        shoulder,
        Isometry3::translation(L1, 0.0, 0.0),
        JointKind::Revolute { axis: Vector3::z() },
        JointLimits::position(-2.5, 2.5),
    )?;
    let tool = b.add_frame("tool", elbow, Isometry3::translation(L2, 0.0, 0.0))?;
    let model = b.build()?;
    println!(
        "Pinocchio {}: model with nq = {}, nv = {}",
        pin::pinocchio_version()?,
        model.nq(),
        model.nv()
    );

    // --- CasADi: base placement as one NLP over (x, y, yaw, q1, q2).
    let mut nlp = Nlp::new();
    // The base stays right of the wall with its radius and 5 cm to spare.
    let wall_clear = WALL.0[1] + ROBOT_RADIUS + 0.05;
    let x = nlp.variable("x", wall_clear, 4.0)?;
    let y = nlp.variable("y", -2.0, 3.0)?;
    let yaw = nlp.variable("yaw", -std::f64::consts::PI, std::f64::consts::PI)?;
    let q1 = nlp.variable("q1", -2.5, 2.5)?;
    let q2 = nlp.variable("q2", -2.5, 2.5)?;
    let world_from_tool = se2(&x, &y, &yaw)
        * se2(&Expr::constant(0.0), &Expr::constant(0.0), &q1)
        * se2(&Expr::constant(L1), &Expr::constant(0.0), &q2)
        * se2(
            &Expr::constant(L2),
            &Expr::constant(0.0),
            &Expr::constant(0.0),
        );
    nlp.constrain_eq(&world_from_tool[(0, 2)] - HANDLE[0], 0.0)?;
    nlp.constrain_eq(&world_from_tool[(1, 2)] - HANDLE[1], 0.0)?;
    let (dx, dy) = (&x - HANDLE[0], &y - HANDLE[1]);
    nlp.constrain(dx.sq() + dy.sq(), BASE_CLEARANCE.powi(2), f64::INFINITY)?;
    // Drive as little as possible; keep the arm near its middle.
    nlp.minimize(x.sq() + y.sq() + 0.1 * (q1.sq() + q2.sq()))?;
    let solver = nlp.build(&NlpSettings::default())?;
    let sol = solver.solve(&[1.6, 0.5, 0.0, 0.3, 0.3], &[])?;
    println!(
        "IPOPT: {:?} in {} iterations ({:.1} ms): base = ({:.3}, {:.3}, {:.3} rad), arm = ({:.3}, {:.3}) rad",
        sol.status,
        sol.iterations,
        sol.solve_time.as_secs_f64() * 1e3,
        sol.x[0],
        sol.x[1],
        sol.x[2],
        sol.x[3],
        sol.x[4]
    );
    if !sol.status.is_success() {
        println!("no base placement found; stopping");
        return Ok(());
    }

    // --- Pinocchio checks the NLP's answer independently.
    let [bx, by, byaw, a1, a2] = [sol.x[0], sol.x[1], sol.x[2], sol.x[3], sol.x[4]];
    let q = DVector::from_vec(vec![bx, by, byaw.cos(), byaw.sin(), a1, a2]);
    let mut data = pin::Data::new(&model)?;
    pin::forward_kinematics(&model, &mut data, &q)?;
    let reached = pin::frame_placement(&model, &data, tool)?
        .translation
        .vector;
    let miss = ((reached.x - HANDLE[0]).powi(2) + (reached.y - HANDLE[1]).powi(2)).sqrt();
    println!(
        "Pinocchio FK at the solution: tool at ({:.4}, {:.4}, {:.3}); miss {:.2e} m",
        reached.x, reached.y, reached.z, miss
    );

    // --- OMPL: the base path around the wall.
    let problem = Problem::new(
        StateSpace::Se2 {
            x: [-1.0, 4.0],
            y: [-2.0, 3.0],
        },
        vec![0.0, 0.0, 0.0],
        vec![bx, by, byaw],
    );
    let base_is_clear = |s: &[f64]| distance_to_wall(s[0], s[1]) > ROBOT_RADIUS;
    let outcome = ompl::plan(
        &problem,
        &base_is_clear,
        &PlanSettings::default(),
        Termination::after(Duration::from_secs(2)),
    )?;
    let length: f64 = outcome
        .path
        .windows(2)
        .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
        .sum();
    println!(
        "OMPL RRTConnect: {:?} in {:.2} ms, {} waypoints, {:.2} m of base travel",
        outcome.status,
        outcome.planning_time.as_secs_f64() * 1e3,
        outcome.path.len(),
        length
    );
    for s in &outcome.path {
        println!("  base ({:6.3}, {:6.3}, {:6.3})", s[0], s[1], s[2]);
    }
    Ok(())
}

/// A planar rigid transform as a 3×3 homogeneous matrix of expressions.
fn se2(x: &Expr, y: &Expr, angle: &Expr) -> Matrix3<Expr> {
    let (c, s) = (angle.cos(), angle.sin());
    let (zero, one) = (Expr::constant(0.0), Expr::constant(1.0));
    Matrix3::new(
        c.clone(),
        -&s,
        x.clone(),
        s,
        c,
        y.clone(),
        zero.clone(),
        zero,
        one,
    )
}

/// Distance (m) from a point to the wall box (0 inside it).
fn distance_to_wall(x: f64, y: f64) -> f64 {
    let dx = (WALL.0[0] - x).max(x - WALL.0[1]).max(0.0);
    let dy = (WALL.1[0] - y).max(y - WALL.1[1]).max(0.0);
    (dx * dx + dy * dy).sqrt()
}
