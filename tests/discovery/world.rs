//! A small kinematic test world implementing `Perception` and `Hardware` from a ground-truth
//! `SceneModel`: ray-cast depth cameras with seeded Gaussian noise, a noisy handle detector,
//! a teleporting base, and compliant pulling that moves the true joint by the projection of the
//! commanded displacement onto the handle's motion. Test support, not the issue-7 simulator.

use kinscene::discovery::{
    Camera, HandleDetection, Hardware, HardwareFailure, LocalGoal, Perception, PointCloud,
    SensorFailure,
};
use kinscene::scene::{
    HandleId, JointKind, SceneData, SceneModel, Shape, State, forward_kinematics, joint_axis,
    world_from_handle,
};
use nalgebra::{
    Isometry2, Isometry3, Matrix3, Point2, Point3, Rotation3, Unit, UnitQuaternion, Vector3,
};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::query::Ray;
use parry3d_f64::shape::SharedShape;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Knobs of the test world.
#[derive(Debug, Clone)]
pub struct WorldSettings {
    /// Depth noise along each ray (m, standard deviation).
    pub depth_noise: f64,
    /// Handle detector position noise per axis (m, standard deviation).
    pub detection_noise: f64,
    /// Horizontal reach of the arm from the base centre (m).
    pub reach: f64,
    /// The arm cannot bring the gripper horizontally closer than this to the base centre (m):
    /// a pull step that would is refused with `SelfCollision`.
    pub min_reach: f64,
    /// The gripper closes on a handle within this distance of the commanded point (m).
    pub grasp_tolerance: f64,
    /// Head camera height (m).
    pub head_height: f64,
    /// Head camera rays: columns × rows.
    pub head_rays: (usize, usize),
    /// Robot radius for the navigation check (m).
    pub robot_radius: f64,
    /// Noise of the reported end-effector poses (grasp and pull steps): position σ per axis
    /// (m) and orientation σ per axis of a small rotation vector (rad). The true pose is
    /// unaffected. Default 0: exact poses.
    pub pose_noise: (f64, f64),
    /// The wrist turns the gripper at most this far (rad) from its orientation at the grasp:
    /// a pull step that would turn it further is refused with `JointLimit` (an arm joint at
    /// its limit; after a new grasp the wrist starts over). Default ∞.
    pub max_wrist_turn: f64,
}

impl Default for WorldSettings {
    fn default() -> Self {
        WorldSettings {
            depth_noise: 0.002,
            detection_noise: 0.005,
            reach: 1.0,
            min_reach: 0.25,
            grasp_tolerance: 0.04,
            head_height: 1.3,
            head_rays: (180, 150),
            robot_radius: 0.25,
            pose_noise: (0.0, 0.0),
            max_wrist_turn: f64::INFINITY,
        }
    }
}

/// What the gripper holds.
#[derive(Debug, Clone, Copy)]
enum Held {
    /// A handle of the model's part `part`, with the end effector's pose in the part frame.
    Part {
        handle: HandleId,
        part_from_ee: Isometry3<f64>,
    },
    /// A handle fixed to the base (no joint behind it).
    Fixed,
}

/// The test world.
pub struct World {
    /// Ground truth.
    pub model: SceneModel,
    /// Current true state.
    pub state: State,
    /// Knobs.
    pub settings: WorldSettings,
    /// Handles on the base map (position, outward normal): graspable, but nothing moves.
    pub fixed_handles: Vec<(Point3<f64>, Vector3<f64>)>,
    /// The next this-many grasps fail with `GraspLost` (fault injection).
    pub grasp_failures: usize,
    /// Obstacles the scene model (and so the base map) does not hold, e.g. a chair: discs
    /// (centre, radius, m) that navigation keeps the robot radius from.
    pub unmapped: Vec<(Point2<f64>, f64)>,
    /// Number of grasp calls so far.
    pub grasps: usize,
    base: Isometry2<f64>,
    ee: Isometry3<f64>,
    /// The gripper's orientation at the last grasp.
    grasped_as: UnitQuaternion<f64>,
    held: Option<Held>,
    time: f64,
    rng: ChaCha8Rng,
}

impl World {
    /// A world at the model's zero state with the robot at `base`.
    pub fn new(
        model: SceneModel,
        base: Isometry2<f64>,
        settings: WorldSettings,
        seed: u64,
    ) -> Self {
        let state = model.zero_state();
        let mut w = World {
            model,
            state,
            settings,
            fixed_handles: Vec::new(),
            grasp_failures: 0,
            unmapped: Vec::new(),
            grasps: 0,
            base,
            ee: Isometry3::identity(),
            grasped_as: UnitQuaternion::identity(),
            held: None,
            time: 0.0,
            rng: ChaCha8Rng::seed_from_u64(seed),
        };
        w.stow();
        w
    }

    fn data(&self) -> SceneData {
        let mut data = SceneData::new(&self.model);
        forward_kinematics(&self.model, &mut data, &self.state).expect("valid true state");
        data
    }

    /// Every collision shape placed in the world at the current state.
    fn placed(&self) -> Vec<(SharedShape, Pose, Point3<f64>, f64)> {
        let data = self.data();
        let mut out = Vec::new();
        for s in &self.model.base().shapes {
            out.extend(place(&s.shape, &s.world_from_shape));
        }
        for part in self.model.parts() {
            let world_from_part = data.world_from_part(part.id()).expect("part pose");
            for c in part.colliders() {
                out.extend(place(&c.shape, &(world_from_part * c.part_from_shape)));
            }
        }
        out
    }

    /// True handles in the world: (position, outward normal, what it is).
    fn handles(&self) -> Vec<(Point3<f64>, Vector3<f64>, Held)> {
        let data = self.data();
        let mut out: Vec<_> = self
            .model
            .handles()
            .map(|(id, _)| {
                let h = world_from_handle(&self.model, &data, id).expect("handle pose");
                let held = Held::Part {
                    handle: id,
                    part_from_ee: Isometry3::identity(),
                };
                (h.position, h.normal.into_inner(), held)
            })
            .collect();
        out.extend(
            self.fixed_handles
                .iter()
                .map(|(p, n)| (*p, *n, Held::Fixed)),
        );
        out
    }

    fn gaussian(&mut self) -> f64 {
        // Box–Muller.
        let u1: f64 = self.rng.random::<f64>().max(1e-300);
        let u2: f64 = self.rng.random::<f64>();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    /// `pose` as the arm reports it: with `pose_noise` (no random draw when it is zero, so
    /// that noise-free worlds keep their sequences).
    fn reported(&mut self, pose: Isometry3<f64>) -> Isometry3<f64> {
        let (sp, so) = self.settings.pose_noise;
        if sp == 0.0 && so == 0.0 {
            return pose;
        }
        let dp = Vector3::new(self.gaussian(), self.gaussian(), self.gaussian()) * sp;
        let dr = Vector3::new(self.gaussian(), self.gaussian(), self.gaussian()) * so;
        Isometry3::from_parts(
            (pose.translation.vector + dp).into(),
            UnitQuaternion::from_scaled_axis(dr) * pose.rotation,
        )
    }

    /// Ray-casts a grid of rays from `origin`; each direction from `dirs`.
    fn render(&mut self, origin: Point3<f64>, dirs: &[Vector3<f64>]) -> PointCloud {
        const MAX_RANGE: f64 = 4.0;
        let shapes = self.placed();
        let mut points = Vec::with_capacity(dirs.len());
        for d in dirs {
            let ray = Ray::new(vec(&origin.coords), vec(d));
            let mut best = MAX_RANGE;
            for (shape, pose, center, radius) in &shapes {
                // Bounding-sphere prefilter.
                let oc = center - origin;
                let along = oc.dot(d);
                if (oc - d * along).norm() > *radius || along + radius < 0.0 {
                    continue;
                }
                if let Some(t) = shape.cast_ray(pose, &ray, best, true) {
                    best = best.min(t);
                }
            }
            if best < MAX_RANGE {
                let t = best + self.settings.depth_noise * self.gaussian();
                points.push(origin + d * t);
            }
        }
        self.time += 0.1;
        PointCloud::new(points, origin, self.time)
    }

    fn head(&self) -> (Point3<f64>, Vec<Vector3<f64>>) {
        let t = self.base.translation.vector;
        let yaw = self.base.rotation.angle();
        let origin = Point3::new(t.x, t.y, self.settings.head_height);
        let (cols, rows) = self.settings.head_rays;
        let mut dirs = Vec::with_capacity(cols * rows);
        for r in 0..rows {
            // Elevation from -65° to +10°, azimuth ±45°: about 0.5° per ray.
            let el = (-65.0 + 75.0 * r as f64 / (rows - 1) as f64).to_radians();
            for c in 0..cols {
                let az = yaw + (-45.0 + 90.0 * c as f64 / (cols - 1) as f64).to_radians();
                dirs.push(Vector3::new(
                    el.cos() * az.cos(),
                    el.cos() * az.sin(),
                    el.sin(),
                ));
            }
        }
        (origin, dirs)
    }

    fn wrist(&self) -> (Point3<f64>, Vec<Vector3<f64>>) {
        // The camera sits 12 cm behind the gripper, looking along the approach (ee z).
        let origin = self.ee * Point3::new(0.0, 0.0, -0.12);
        let n = 24;
        let mut dirs = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                let a = (-40.0 + 80.0 * i as f64 / (n - 1) as f64).to_radians();
                let b = (-40.0 + 80.0 * j as f64 / (n - 1) as f64).to_radians();
                let local = Vector3::new(a.tan(), b.tan(), 1.0).normalize();
                dirs.push(self.ee.rotation * local);
            }
        }
        (origin, dirs)
    }

    fn stow(&mut self) {
        let t = self.base.translation.vector;
        let yaw = self.base.rotation.angle();
        let forward = Vector3::new(yaw.cos(), yaw.sin(), 0.0);
        let p = Point3::new(t.x, t.y, 0.9) + forward * 0.2;
        self.ee = Isometry3::from_parts(p.coords.into(), gripper_rotation(&forward));
    }

    fn free(&self, pose: &Isometry2<f64>) -> bool {
        let at = Point2::from(pose.translation.vector);
        if self
            .unmapped
            .iter()
            .any(|(c, r)| (at - c).norm() < r + self.settings.robot_radius)
        {
            return false;
        }
        let grid = self
            .model
            .base_grid()
            .inflate(self.settings.robot_radius)
            .expect("inflate");
        match grid.cell_of(Point2::from(pose.translation.vector)) {
            Some((i, j)) => !grid.is_occupied(i, j),
            None => true,
        }
    }

    fn horizontal_distance(&self, p: &Point3<f64>) -> f64 {
        (Point2::new(p.x, p.y) - Point2::from(self.base.translation.vector)).norm()
    }
}

/// A gripper orientation whose z axis is `approach`, x as close to world up as possible.
fn gripper_rotation(approach: &Vector3<f64>) -> UnitQuaternion<f64> {
    let z = approach.normalize();
    let up = if z.z.abs() < 0.9 {
        Vector3::z()
    } else {
        Vector3::x()
    };
    let x = (up - z * up.dot(&z)).normalize();
    let y = z.cross(&x);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(Matrix3::from_columns(
        &[x, y, z],
    )))
}

fn vec(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn pose(iso: &Isometry3<f64>) -> Pose {
    let q = iso.rotation.quaternion();
    Pose::from_parts(
        vec(&iso.translation.vector),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

/// A shape as a parry shape at `world_from_shape`, with its bounding sphere.
fn place(
    shape: &Shape,
    world_from_shape: &Isometry3<f64>,
) -> Option<(SharedShape, Pose, Point3<f64>, f64)> {
    let (s, shape_from_parry) = kinscene::scene::collision::parry_shape(shape).ok()?;
    let sphere = shape.bounding_sphere();
    Some((
        s,
        pose(&(world_from_shape * shape_from_parry)),
        world_from_shape * sphere.center,
        sphere.radius,
    ))
}

impl Perception for World {
    fn observe(&mut self, camera: Camera) -> Result<PointCloud, SensorFailure> {
        let (origin, dirs) = match camera {
            Camera::Head => self.head(),
            Camera::Wrist => self.wrist(),
        };
        Ok(self.render(origin, &dirs))
    }

    fn detect_handles(&mut self) -> Result<Vec<HandleDetection>, SensorFailure> {
        let (origin, _) = self.head();
        let yaw = self.base.rotation.angle();
        let shapes = self.placed();
        let mut out = Vec::new();
        for (p, _, _) in self.handles() {
            let d = p - origin;
            let dist = d.norm();
            let bearing = (d.y.atan2(d.x) - yaw + std::f64::consts::PI)
                .rem_euclid(2.0 * std::f64::consts::PI)
                - std::f64::consts::PI;
            if dist > 2.5 || bearing.abs() > 50f64.to_radians() {
                continue;
            }
            // Line of sight: nothing more than 5 cm in front of the handle.
            let ray = Ray::new(vec(&origin.coords), vec(&(d / dist)));
            let occluded = shapes
                .iter()
                .any(|(s, pose, _, _)| s.cast_ray(pose, &ray, dist - 0.05, true).is_some());
            if occluded {
                continue;
            }
            let sigma = self.settings.detection_noise;
            let noise = Vector3::new(self.gaussian(), self.gaussian(), self.gaussian()) * sigma;
            out.push(HandleDetection {
                position: p + noise,
                half_extents: Vector3::new(0.02, 0.02, 0.06),
                confidence: 0.9,
                stamp: self.time,
            });
        }
        Ok(out)
    }
}

impl Hardware for World {
    fn navigate_to(&mut self, world_from_base: &Isometry2<f64>) -> Result<(), HardwareFailure> {
        if self.held.is_some() {
            return Err(HardwareFailure::Other {
                reason: "navigating while holding a handle".into(),
            });
        }
        if !self.free(world_from_base) {
            return Err(HardwareFailure::NavigationFailed {
                reason: "goal in collision".into(),
            });
        }
        self.base = *world_from_base;
        self.stow();
        self.time += 5.0;
        Ok(())
    }

    fn navigate_local(&mut self, goal: &LocalGoal) -> Result<(), HardwareFailure> {
        self.navigate_to(&goal.world_from_base)
    }

    fn grasp(
        &mut self,
        point: &Point3<f64>,
        approach: &Unit<Vector3<f64>>,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        self.grasps += 1;
        self.time += 2.0;
        if self.horizontal_distance(point) > self.settings.reach {
            return Err(HardwareFailure::Unreachable);
        }
        if self.grasp_failures > 0 {
            self.grasp_failures -= 1;
            return Err(HardwareFailure::GraspLost);
        }
        let nearest = self
            .handles()
            .into_iter()
            .map(|(p, _, held)| ((p - point).norm(), p, held))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((dist, p, held)) = nearest else {
            return Err(HardwareFailure::GraspLost);
        };
        if dist > self.settings.grasp_tolerance {
            return Err(HardwareFailure::GraspLost);
        }
        let ee = Isometry3::from_parts(p.coords.into(), gripper_rotation(approach));
        self.ee = ee;
        self.grasped_as = ee.rotation;
        self.held = Some(match held {
            Held::Part { handle, .. } => {
                let data = self.data();
                let world_from_part = data.world_from_part(handle.part()).expect("part");
                Held::Part {
                    handle,
                    part_from_ee: world_from_part.inverse() * ee,
                }
            }
            Held::Fixed => Held::Fixed,
        });
        Ok(self.reported(ee))
    }

    fn pull_step(
        &mut self,
        direction: &Unit<Vector3<f64>>,
        step: f64,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        self.time += 0.5;
        let Some(held) = self.held else {
            return Err(HardwareFailure::GraspLost);
        };
        let Held::Part {
            handle,
            part_from_ee,
        } = held
        else {
            // Pulling on something fixed: the admittance controller does not move.
            return Ok(self.ee);
        };
        let data = self.data();
        let joint = handle.part().joint();
        let axis = joint_axis(&self.model, &data, joint).expect("axis");
        let here = self.ee.translation.vector;
        // The handle's velocity per unit joint value.
        let v = match axis.kind {
            JointKind::Revolute => axis.direction.cross(&(here - axis.pivot.coords)),
            JointKind::Prismatic => axis.direction.into_inner(),
        };
        let dq = (direction.into_inner() * step).dot(&v) / v.norm_squared();
        let limits = self.model.joints()[joint.index()].limits;
        let q = self.state.as_slice()[joint.index()];
        let target = limits.clamp(q + dq);
        if (target - q).abs() < 1e-9 && dq.abs() > 1e-9 {
            return Err(HardwareFailure::JointLimit);
        }
        let mut next = self.state.clone();
        next.set_unchecked(joint, target);
        let old = std::mem::replace(&mut self.state, next);
        let world_from_part = *self.data().world_from_part(handle.part()).expect("part");
        let ee = world_from_part * part_from_ee;
        let reach = self.horizontal_distance(&Point3::from(ee.translation.vector));
        if reach > self.settings.reach
            || ee.rotation.angle_to(&self.grasped_as) > self.settings.max_wrist_turn
        {
            self.state = old;
            return Err(HardwareFailure::JointLimit);
        }
        if reach < self.settings.min_reach {
            self.state = old;
            return Err(HardwareFailure::SelfCollision);
        }
        self.ee = ee;
        Ok(self.reported(ee))
    }

    fn retract(&mut self) -> Result<(), HardwareFailure> {
        self.held = None;
        self.stow();
        self.time += 2.0;
        Ok(())
    }

    fn ee_pose(&self) -> Isometry3<f64> {
        self.ee
    }

    fn base_pose(&self) -> Isometry2<f64> {
        self.base
    }

    fn time(&self) -> f64 {
        self.time
    }
}
