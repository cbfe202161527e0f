//! The timing of a step's phases.

use super::refine::{ArmPaths, Placed, StepRefinement};
use crate::kinematics::robot::{BaseKind, Exempt};
use crate::motion::timing::{BlendSettings, TimedPath, time_differential_drive};
use crate::planner::PlannerError;
use crate::planner::timed::{timed, value_at};
use crate::scene::{SceneData, forward_kinematics};

impl StepRefinement<'_, '_> {
    /// Times the base path and the arm's phases (a differential-drive base path exactly, with
    /// [`time_differential_drive`]): without stops at the corners where the
    /// blended trajectory passes the same checks as the path, sampled densely; else with stops,
    /// exactly on the checked path. Base, approach, manipulation, retreat.
    pub(super) fn time(
        &self,
        placed: &Placed,
        base_path: &[Vec<f64>],
        arm: &ArmPaths,
    ) -> Result<(TimedPath, TimedPath, TimedPath, TimedPath), PlannerError> {
        let ctx = self.ctx;
        let settings = ctx.settings;
        let model = ctx.model;
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
                &|_, _, p| self.base_valid(&[p[0], p[1], p[2]]),
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

        let free_before = self.arm(base, &self.data, Exempt::Nothing);
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
                    grasping_before.valid(q)
                }
            },
        )?;
        // The manipulation keeps the tool on the handle: its corners are cut by far less.
        let fine = blend.map(|b| BlendSettings {
            max_deviation: b.max_deviation.min(settings.manipulation_blend),
            ..*b
        });
        let waypoints = placed.waypoints();
        let scratch = std::cell::RefCell::new((self.state.clone(), SceneData::new(model)));
        let manipulation = timed(
            waypoints,
            limits,
            None,
            fine.as_ref(),
            resolution,
            &|_, _, q| {
                let value = value_at(waypoints, q, self.step.from, self.step.to);
                let mut guard = scratch.borrow_mut();
                let (s, data) = &mut *guard;
                if s.set(model, self.joint, value).is_err()
                    || forward_kinematics(model, data, s).is_err()
                {
                    return false;
                }
                self.arm_exact(base, data, grasp).valid(q)
            },
        )?;
        let data_after = self.after()?;
        let grasping_after = self.arm(base, &data_after, grasp);
        let free_after = self.arm(base, &data_after, Exempt::Nothing);
        let retreat = timed(
            &arm.retreat,
            limits,
            None,
            blend,
            resolution,
            &|path, t, q| {
                if t <= path.times[arm.postgrasp] {
                    grasping_after.valid(q)
                } else {
                    free_after.valid(q)
                }
            },
        )?;
        Ok((base_timed, approach, manipulation, retreat))
    }
}
