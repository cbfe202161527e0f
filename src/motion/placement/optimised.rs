//! The optimised base placement: base pose and all arm configurations as one CasADi/IPOPT
//! problem, initialised from the best sample, accepted only after an independent check.

use std::time::{Duration, Instant};

use kinscene_casadi::{Expr, Nlp, NlpSettings, NlpSolver};
use nalgebra::{DVector, Isometry3, Point2, Vector2, Vector3};

use super::grasp::GraspRotation;
use super::manipulation::Prepared;
use super::plan::{ManipulationPlan, WaypointFailure};
use super::sampled::wrap;
use super::symbolic::world_from_tool;
use super::{ManipulationSettings, OptimisationSettings, PlacementError};
use crate::kinematics::robot::{ArmJoint, RobotModel};
use crate::scene::collision::geometry::WorldBox;

/// Everything the compiled NLP depends on; a cached solver is reused only for an equal key.
#[derive(Debug, Clone, PartialEq)]
struct NlpKey {
    joints: Vec<ArmJoint>,
    base_from_arm_root: Isometry3<f64>,
    last_from_tool: Isometry3<f64>,
    waypoints: usize,
    rotation: GraspRotation,
    half_planes: usize,
    trust_region: [f64; 2],
    max_joint_jump: f64,
    nlp: NlpSettings,
}

/// A compiled placement NLP.
#[derive(Debug)]
struct Compiled {
    key: NlpKey,
    solver: NlpSolver,
}

/// Caller-owned scratch for [`place_and_plan`](super::place_and_plan): the compiled
/// placement NLP, rebuilt only when the robot, `K`, the grasp rotation mode or a setting it
/// depends on changes (the waypoints, the sample and the obstacles are parameters).
///
/// `Send`, not `Sync` (CasADi solvers are used from one thread at a time).
#[derive(Debug, Default)]
pub struct PlacementData {
    compiled: Option<Compiled>,
    builds: usize,
}

impl PlacementData {
    /// Empty scratch: the first optimised placement compiles the NLP.
    pub fn new() -> PlacementData {
        PlacementData::default()
    }

    /// How many times an NLP was compiled into this scratch.
    pub fn builds(&self) -> usize {
        self.builds
    }
}

/// Parameters per waypoint: grasp point (3), then the target frame's x, y, z axes (9).
const WAYPOINT_PARAMS: usize = 12;

/// Builds the NLP for `key` (see the module docs of [`super`] for the problem).
fn build(robot: &RobotModel, key: &NlpKey) -> Result<NlpSolver, PlacementError> {
    let dof = robot.dof();
    let n = key.waypoints;
    let mut nlp = Nlp::new();
    let inf = f64::INFINITY;
    let base = [
        nlp.variable("base_x", -inf, inf)?,
        nlp.variable("base_y", -inf, inf)?,
        nlp.variable("base_yaw", -inf, inf)?,
    ];
    let (lower, upper) = robot.arm_bounds();
    let q: Vec<Vec<Expr>> = (0..n)
        .map(|k| nlp.variables(&format!("q{k}"), lower.as_slice(), upper.as_slice()))
        .collect::<Result<_, _>>()?;
    let sample_base = nlp.parameters("sample_base", 3);
    let sample_q: Vec<Vec<Expr>> = (0..n)
        .map(|k| nlp.parameters(&format!("sample_q{k}"), dof))
        .collect();
    let waypoint: Vec<Vec<Expr>> = (0..n)
        .map(|k| nlp.parameters(&format!("waypoint{k}"), WAYPOINT_PARAMS))
        .collect();
    let planes: Vec<Vec<Expr>> = (0..key.half_planes)
        .map(|i| nlp.parameters(&format!("half_plane{i}"), 3))
        .collect();
    let pull_weight = nlp.parameter("pull_weight");

    // Trust region around the sample.
    let dx = &base[0] - &sample_base[0];
    let dy = &base[1] - &sample_base[1];
    let dyaw = &base[2] - &sample_base[2];
    nlp.constrain(
        dx.sq() + dy.sq(),
        f64::NEG_INFINITY,
        key.trust_region[0].powi(2),
    )?;
    nlp.constrain(dyaw.clone(), -key.trust_region[1], key.trust_region[1])?;
    // Footprint clearance: n · b >= s per half-plane slot.
    for p in &planes {
        nlp.constrain(&p[0] * &base[0] + &p[1] * &base[1] - &p[2], 0.0, inf)?;
    }
    for k in 0..n {
        let w = &waypoint[k];
        let tool = world_from_tool(robot, &base, &q[k]);
        for (t, p) in tool.translation.iter().zip(w) {
            nlp.constrain_eq(t - p, 0.0)?;
        }
        let axis =
            |c: usize| -> Vector3<Expr> { Vector3::from_fn(|i, _| tool.rotation[(i, c)].clone()) };
        let target =
            |a: usize| -> Vector3<Expr> { Vector3::from_fn(|i, _| w[3 + 3 * a + i].clone()) };
        let (tx, tz) = (axis(0), axis(2));
        // Tool +z orthogonal to the target's x and y, on the side of its z.
        nlp.constrain_eq(tz.dot(&target(0)), 0.0)?;
        nlp.constrain_eq(tz.dot(&target(1)), 0.0)?;
        nlp.constrain(tz.dot(&target(2)), 0.0, inf)?;
        if key.rotation == GraspRotation::Fixed {
            nlp.constrain_eq(tx.dot(&target(1)), 0.0)?;
            nlp.constrain(tx.dot(&target(0)), 0.0, inf)?;
        }
    }
    let mut smoothness = Expr::constant(0.0);
    for pair in q.windows(2) {
        for (a, b) in pair[1].iter().zip(&pair[0]) {
            let d = a - b;
            nlp.constrain(d.clone(), -key.max_joint_jump, key.max_joint_jump)?;
            smoothness += d.sq();
        }
    }
    let mut pull = dx.sq() + dy.sq() + dyaw.sq();
    for (qk, sk) in q.iter().zip(&sample_q) {
        for (a, b) in qk.iter().zip(sk) {
            pull += (a - b).sq();
        }
    }
    nlp.minimize(smoothness + pull_weight * pull)?;
    Ok(nlp.build(&key.nlp)?)
}

/// The half-plane parameters `(nx, ny, s)` for the `slots` obstacle boxes nearest to the
/// sampled base centre (see the module docs of [`super`]); unused slots are `(0, 0, -1)`.
fn half_planes(
    prepared: &Prepared<'_>,
    base: [f64; 3],
    settings: &OptimisationSettings,
) -> Vec<f64> {
    let robot = prepared.problem.robot;
    let model = prepared.problem.model;
    // The base link's height and horizontal radius from its colliders' bounding spheres.
    let (height, radius) = robot
        .links()
        .first()
        .map(|l| {
            l.colliders.iter().fold((0.0_f64, 0.0_f64), |(h, r), c| {
                let s = c.bounding_sphere();
                (
                    h.max(s.center.z + s.radius),
                    r.max(s.center.x.hypot(s.center.y) + s.radius),
                )
            })
        })
        .unwrap_or((0.0, 0.0));
    let mut boxes: Vec<WorldBox> = model
        .geometry
        .base
        .iter()
        .map(|s| s.world_box(&Isometry3::identity()))
        .collect();
    for (p, shapes) in model.geometry.parts.iter().enumerate() {
        let moving = prepared.moving.iter().any(|m| m.index() == p);
        let states = if moving { prepared.scene.len() } else { 1 };
        for data in &prepared.scene[..states] {
            let pose = data.world_from_parts()[p];
            boxes.extend(shapes.iter().map(|s| s.world_box(&pose)));
        }
    }
    let centre = Point2::new(base[0], base[1]);
    let mut planes: Vec<(f64, [f64; 3])> = boxes
        .iter()
        .filter(|b| b.max.z > 1e-3 && b.min.z < height)
        .filter_map(|b| {
            let closest = Point2::new(
                centre.x.clamp(b.min.x, b.max.x),
                centre.y.clamp(b.min.y, b.max.y),
            );
            let d = (centre - closest).norm();
            if d <= 1e-9 || d > settings.obstacle_radius {
                return None;
            }
            let normal: Vector2<f64> = (centre - closest) / d;
            let required = (radius + settings.clearance).min(d);
            Some((
                d,
                [normal.x, normal.y, normal.dot(&closest.coords) + required],
            ))
        })
        .collect();
    planes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::with_capacity(3 * settings.max_half_planes);
    for i in 0..settings.max_half_planes {
        out.extend(planes.get(i).map_or([0.0, 0.0, -1.0], |p| p.1));
    }
    out
}

/// What the optimiser did.
#[derive(Debug, Clone)]
pub(crate) struct Optimised {
    /// The verified plan, or `None` with the reason it was rejected.
    pub plan: Result<ManipulationPlan, String>,
    /// IPOPT's status of the last solve.
    pub status: String,
    /// IPOPT iterations over all solves.
    pub iterations: usize,
    /// Time to compile the NLP (zero when cached).
    pub build_time: Duration,
    /// Time of the IPOPT solves.
    pub solve_time: Duration,
}

/// Optimises from `sample` with each of the pull weights in turn, until a result passes the
/// verification (and, if the sample reached every waypoint, is no less smooth than it).
pub(crate) fn optimise(
    prepared: &Prepared<'_>,
    sample: &ManipulationPlan,
    manipulation: &ManipulationSettings,
    settings: &OptimisationSettings,
    data: &mut PlacementData,
) -> Result<Optimised, PlacementError> {
    let robot = prepared.problem.robot;
    let dof = robot.dof();
    let n = prepared.motion.len();
    let key = NlpKey {
        joints: robot.arm_joints().to_vec(),
        base_from_arm_root: *robot.base_from_arm_root(),
        last_from_tool: *robot.last_from_tool(),
        waypoints: n,
        rotation: prepared.rotation,
        half_planes: settings.max_half_planes,
        trust_region: settings.trust_region,
        max_joint_jump: manipulation.max_joint_jump,
        nlp: settings.nlp.clone(),
    };
    let start = Instant::now();
    if data.compiled.as_ref().is_none_or(|c| c.key != key) {
        data.compiled = None;
        let solver = build(robot, &key)?;
        data.compiled = Some(Compiled { key, solver });
        data.builds += 1;
    }
    let build_time = start.elapsed();
    let solver = &data.compiled.as_ref().expect("compiled above").solver;

    // Initial guess and parameters: the sample (arm clamped into the limits), the grasp frames,
    // the half-planes.
    let (lower, upper) = (&prepared.lower, &prepared.upper);
    let mut x0 = Vec::with_capacity(3 + dof * n);
    x0.extend(sample.base);
    for q in &sample.arm {
        x0.extend(
            q.iter()
                .zip(lower.iter().zip(upper.iter()))
                .map(|(v, (lo, hi))| v.clamp(*lo, *hi)),
        );
    }
    let mut params = x0.clone();
    for g in &prepared.motion.grasps {
        params.extend(g.position.coords.iter());
        let r = g.world_from_tool.rotation.to_rotation_matrix().into_inner();
        for c in 0..3 {
            params.extend(r.column(c).iter());
        }
    }
    params.extend(half_planes(prepared, sample.base, settings));
    params.push(0.0);
    let mut result = Optimised {
        plan: Err("no pull weight given".to_owned()),
        status: String::new(),
        iterations: 0,
        build_time,
        solve_time: Duration::ZERO,
    };
    let mut rejections = Vec::new();
    for &weight in &settings.pull_weights {
        *params.last_mut().expect("pushed above") = weight;
        let solution = solver.solve(&x0, &params)?;
        result.status = format!("{:?}", solution.status);
        result.iterations += solution.iterations;
        result.solve_time += solution.solve_time;
        let x = &solution.x;
        if !x.iter().all(|v| v.is_finite()) {
            rejections.push(format!("pull {weight:e}: IPOPT returned non-finite values"));
            continue;
        }
        let base = [x[0], x[1], wrap(x[2])];
        let arm: Vec<DVector<f64>> = (0..n)
            .map(|k| DVector::from_column_slice(&x[3 + k * dof..3 + (k + 1) * dof]))
            .collect();
        let plan = verify(prepared, base, arm, manipulation)?;
        let rejection = match plan.reason() {
            Some(reason) => reason,
            None if sample.is_complete() && plan.smoothness() > sample.smoothness() => format!(
                "smoothness {:.4} exceeds the sample's {:.4}",
                plan.smoothness(),
                sample.smoothness()
            ),
            None => {
                result.plan = Ok(plan);
                return Ok(result);
            }
        };
        rejections.push(format!(
            "pull {weight:e}, IPOPT {}: {rejection}",
            result.status
        ));
    }
    result.plan = Err(rejections.join("; "));
    Ok(result)
}

/// The independent check of an optimised plan: every waypoint within the tolerances under
/// Pinocchio's forward kinematics (not the expressions IPOPT saw), within the joint limits, no
/// joint jump, and collision-free at the waypoints and along the segments (as for samples).
fn verify(
    prepared: &Prepared<'_>,
    base: [f64; 3],
    arm: Vec<DVector<f64>>,
    settings: &ManipulationSettings,
) -> Result<ManipulationPlan, PlacementError> {
    let robot = prepared.problem.robot;
    let model = robot.pinocchio();
    let mut pin = kinscene_pinocchio::Data::new(model)?;
    let world_from_base = RobotModel::world_from_base(base);
    let mut scratch = crate::scene::SceneData::new(prepared.problem.model);
    let mut failures = Vec::with_capacity(arm.len());
    for (k, q) in arm.iter().enumerate() {
        kinscene_pinocchio::forward_kinematics(model, &mut pin, q)?;
        let base_from_tool = kinscene_pinocchio::frame_placement(model, &pin, robot.tool_frame())?;
        let (position_error, rotation_error) =
            prepared.tool_errors(&(world_from_base * base_from_tool), k, settings);
        let failure = if position_error > settings.position_tolerance
            || rotation_error > settings.rotation_tolerance
        {
            Some(WaypointFailure::OutOfTolerance {
                position_error,
                rotation_error,
            })
        } else {
            let prev = k.checked_sub(1).map(|p| &arm[p]);
            prepared.check_waypoint(base, q, k, prev, settings, &mut scratch)?
        };
        failures.push(failure);
    }
    Ok(ManipulationPlan {
        base,
        reached: failures.iter().map(Option::is_none).collect(),
        failures,
        arm,
    })
}
