//! The timing of a step's phases.

use super::refine::{ArmPaths, Placed, StepRefinement};
use nalgebra::DVector;

use crate::kinematics::robot::{BaseKind, Exempt, RobotConfig};
use crate::motion::timing::{
    BlendSettings, TimedPath, time_differential_drive, time_whole_body_differential,
};
use crate::planner::PlannerError;
use crate::planner::timed::{timed, value_at};
use crate::scene::collision::handle_front_shapes;
use crate::scene::{SceneData, forward_kinematics};

impl StepRefinement<'_, '_> {
    /// Times the base path and the arm's phases (a differential-drive base path exactly, with
    /// [`time_differential_drive`]): without stops at the corners where the
    /// blended trajectory passes the same checks as the path, sampled densely; else with a
    /// stop at the corner. Where the fingers may touch the grasped part (pre-grasp to
    /// post-grasp), a blended sample must also keep the gripper's contact shapes off the
    /// part's front (its shapes other than the handle's own): a corner cut there must not
    /// press the fingers into the door. Base, approach, manipulation (the arm, and the base of
    /// a whole-body manipulation), retreat.
    pub(super) fn time(
        &self,
        handle: &str,
        placed: &Placed,
        base_path: &[Vec<f64>],
        arm: &ArmPaths,
    ) -> Result<(TimedPath, TimedPath, Manipulation, TimedPath), PlannerError> {
        let ctx = self.ctx;
        let settings = ctx.settings;
        let base = placed.base;
        let grasp = Exempt::Grasp(&self.grasped);
        let b = ctx.robot.base();
        let blend = settings.blend.as_ref();
        let base_timed = match b.kind {
            BaseKind::Holonomic => timed(
                base_path,
                (&b.max_velocity, &b.max_acceleration),
                Some(2),
                blend,
                settings.base_check_resolution,
                &|_, _, p| {
                    let start = base_path.first().map_or(p, Vec::as_slice);
                    self.base_valid_from(start, &[p[0], p[1], p[2]])
                },
            )?,
            // Exact, never blended: a blended corner between a turn and a drive would move
            // the base sideways.
            BaseKind::DifferentialDrive => {
                time_differential_drive(base_path, &b.max_velocity, &b.max_acceleration)?
            }
        };
        let joints = ctx.robot.arm_joints();
        let vmax: Vec<f64> = joints.iter().map(|j| j.max_velocity).collect();
        let amax: Vec<f64> = joints.iter().map(|j| j.max_acceleration).collect();
        let limits = (vmax.as_slice(), amax.as_slice());
        let resolution = settings.arm_check_resolution;

        let handle = ctx.model.handle_id(handle)?;
        let front = handle_front_shapes(ctx.model, handle)?;
        let off_front = |b: [f64; 3], data: &SceneData, q: &[f64]| {
            let config = RobotConfig {
                base: b,
                arm: DVector::from_column_slice(q),
            };
            ctx.robot.link_poses(&config).is_ok_and(|poses| {
                ctx.collision
                    .contact_touches(&poses, ctx.model, data, handle.part(), &front)
                    .is_none()
            })
        };
        let stow = ctx.stow.as_slice();
        let free_before = self.free_arm(base, &self.data, stow, &arm.approach[arm.pregrasp]);
        let grasping_before = self.arm(base, &self.data, grasp);
        let approach = timed(
            &arm.approach,
            limits,
            None,
            blend,
            resolution,
            &|path, t, q| {
                if t < path.times[arm.pregrasp] {
                    free_before.valid(q)
                } else {
                    grasping_before.valid(q) && off_front(base, &self.data, q)
                }
            },
        )?;
        // The manipulation keeps the tool on the handle: its corners are cut by far less.
        let fine = blend.map(|b| BlendSettings {
            max_deviation: b.max_deviation.min(settings.manipulation_blend),
            ..*b
        });
        let manipulation = match placed.bases {
            None => (
                self.time_fixed_manipulation(placed, limits, fine.as_ref(), &off_front)?,
                None,
            ),
            Some(_) => self.time_whole_body(placed, limits, fine.as_ref(), &off_front)?,
        };
        let base = placed.end_base();
        let data_after = self.after()?;
        let grasping_after = self.arm(base, &data_after, grasp);
        let free_after = self.free_arm(base, &data_after, &arm.retreat[arm.postgrasp], stow);
        let retreat = timed(
            &arm.retreat,
            limits,
            None,
            blend,
            resolution,
            &|path, t, q| {
                if t <= path.times[arm.postgrasp] {
                    grasping_after.valid(q) && off_front(base, &data_after, q)
                } else {
                    free_after.valid(q)
                }
            },
        )?;
        Ok((base_timed, approach, manipulation, retreat))
    }

    /// The manipulation at the fixed base pose `placed.base`: the arm's waypoints, blended by
    /// at most `fine` where the blended trajectory passes the dense check with the part where
    /// the arm's progress puts it.
    fn time_fixed_manipulation(
        &self,
        placed: &Placed,
        limits: (&[f64], &[f64]),
        fine: Option<&BlendSettings>,
        off_front: &OffFront<'_>,
    ) -> Result<TimedPath, PlannerError> {
        let model = self.ctx.model;
        let base = placed.base;
        let grasp = Exempt::Grasp(&self.grasped);
        let waypoints = placed.waypoints();
        let scratch = std::cell::RefCell::new((self.state.clone(), SceneData::new(model)));
        timed(
            waypoints,
            limits,
            None,
            fine,
            self.ctx.settings.arm_check_resolution,
            &|_, _, q| {
                let value = value_at(waypoints, q, self.step.from, self.step.to);
                let mut guard = scratch.borrow_mut();
                let (s, data) = &mut *guard;
                if s.set(model, self.joint, value).is_err()
                    || forward_kinematics(model, data, s).is_err()
                {
                    return false;
                }
                self.arm_exact(base, data, grasp).valid(q) && off_front(base, data, q)
            },
        )
    }

    /// A whole-body manipulation: base and arm timed together as one path
    /// `[x, y, yaw, q1, …, qn]` (yaw not wrapped: the whole-body steps turn by less than π),
    /// then cut into the arm's and the base's trajectories, in step. A holonomic base under
    /// its per-axis limits with the arm's, blended by at most `fine` where the blended
    /// trajectory passes the dense check (base, arm and part where the progress along the
    /// joint path puts them); a differential-drive base exactly, never blended (a blend would
    /// move it sideways), under its forward speed and yaw rate
    /// ([`time_whole_body_differential`]).
    fn time_whole_body(
        &self,
        placed: &Placed,
        (vmax, amax): (&[f64], &[f64]),
        fine: Option<&BlendSettings>,
        off_front: &OffFront<'_>,
    ) -> Result<Manipulation, PlannerError> {
        let ctx = self.ctx;
        let model = ctx.model;
        let b = ctx.robot.base();
        let grasp = Exempt::Grasp(&self.grasped);
        let path: Vec<Vec<f64>> = placed
            .waypoint_bases()
            .iter()
            .zip(placed.waypoints())
            .map(|(base, q)| base.iter().chain(q).copied().collect())
            .collect();
        let combined = match b.kind {
            BaseKind::Holonomic => {
                let v: Vec<f64> = b.max_velocity.iter().chain(vmax).copied().collect();
                let a: Vec<f64> = b.max_acceleration.iter().chain(amax).copied().collect();
                let scratch = std::cell::RefCell::new((self.state.clone(), SceneData::new(model)));
                timed(
                    &path,
                    (&v, &a),
                    None,
                    fine,
                    ctx.settings.arm_check_resolution,
                    &|_, _, p| {
                        let value = value_at(&path, p, self.step.from, self.step.to);
                        let mut guard = scratch.borrow_mut();
                        let (s, data) = &mut *guard;
                        if s.set(model, self.joint, value).is_err()
                            || forward_kinematics(model, data, s).is_err()
                        {
                            return false;
                        }
                        let b = [p[0], p[1], p[2]];
                        self.arm_exact(b, data, grasp).valid(&p[3..]) && off_front(b, data, &p[3..])
                    },
                )?
            }
            BaseKind::DifferentialDrive => time_whole_body_differential(
                &path,
                &b.max_velocity,
                &b.max_acceleration,
                vmax,
                amax,
            )?,
        };
        let dim = path[0].len();
        Ok((
            combined.coordinates(3..dim),
            Some(combined.coordinates(0..3)),
        ))
    }
}

/// Whether the gripper's contact shapes keep off the grasped part's front with the base at
/// the pose, the scene in the data and the arm at the configuration.
type OffFront<'a> = dyn Fn([f64; 3], &SceneData, &[f64]) -> bool + 'a;

/// The manipulation's timed paths: the arm's, and the base's of a whole-body manipulation.
pub(super) type Manipulation = (TimedPath, Option<TimedPath>);
