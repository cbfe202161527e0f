//! The arm's phases of a step: the straight approach and retreat along the handle's normal,
//! the free paths to and from the stowed configuration, and the manipulation's re-check.

use super::StepReason;
use super::refine::{ArmPaths, Placed, StepRefinement};
use super::shortcut::{Timer, random_time_shortcuts, time_shortcuts};
use super::{Check, Failed, StepPath, check_manipulation, path_or_reason};
use crate::kinematics::robot::{ArmCheck as FastArmCheck, EdgeScene, Exempt};
use crate::motion::paths::{first_invalid, plan_arm, plan_arm_checked};
use crate::planner::PlannerError;
use crate::planner::arm_check::ArmCheck;
use crate::planner::timed::timed;
use crate::scene::{SceneData, forward_kinematics};

impl StepRefinement<'_, '_> {
    /// A straight part (approach or retreat), densely re-checked under the grasp rule.
    fn straight(
        &self,
        path: &[Vec<f64>],
        arm: &ArmCheck<'_>,
        check: Check,
        which: StepPath,
    ) -> Option<Failed> {
        first_invalid(path, self.ctx.settings.arm_check_resolution, false, &|q| {
            arm.valid(q)
        })
        .map(|(segment, at)| {
            let contact = arm.describe(&at);
            self.fail(
                check,
                StepReason::Collision {
                    path: which,
                    segment,
                    at,
                    scene_joint: None,
                    contact,
                },
            )
        })
    }

    /// One free arm phase: OMPL, the dense re-check, then the time shortcuts
    /// ([`PlannerSettings::arm_time_shortcuts`](crate::planner::PlannerSettings)) and the
    /// random ones (`arm_random_shortcuts`), each checked by the same dense rule.
    fn arm_phase(
        &self,
        from: &[f64],
        to: &[f64],
        arm: &ArmCheck<'_>,
        check: Check,
        which: StepPath,
    ) -> Result<Result<Vec<Vec<f64>>, Failed>, PlannerError> {
        let ctx = self.ctx;
        let (lower, upper) = ctx.robot.arm_bounds();
        let scene = EdgeScene {
            model: ctx.model,
            data: arm.data,
            exempt: arm.exempt,
            margin: arm.margin,
        };
        // With the sphere model, the search checks states and whole motions with the
        // kinematics layer's fast exact check (the exact answer at every state, every motion
        // certified continuously unless the settings ask for the discrete check, one call per
        // motion); the dense re-check below stays with this step's own check.
        let fast = match ctx.spheres {
            Some(spheres) => Some(
                FastArmCheck::new(ctx.robot, ctx.collision, spheres, scene, arm.base)?
                    .with_self_margin(arm.self_margin)
                    .with_continuous(ctx.settings.continuous_arm_motions),
            ),
            None => None,
        };
        let outcome = match &fast {
            Some(check) => plan_arm_checked(
                from,
                to,
                lower.as_slice(),
                upper.as_slice(),
                check,
                &ctx.settings.paths,
                ctx.termination,
            )?,
            None => plan_arm(
                from,
                to,
                lower.as_slice(),
                upper.as_slice(),
                &|q: &[f64]| arm.valid(q),
                &ctx.settings.paths,
                ctx.termination,
            )?,
        };
        let path = match path_or_reason(outcome, which, (from, to), &|q| arm.describe(q)) {
            Ok(p) => p,
            Err(reason) => {
                let check = if ctx.termination.should_stop() {
                    Check::Stopped
                } else {
                    check
                };
                return Ok(Err(self.fail(check, *reason)));
            }
        };
        let resolution = ctx.settings.arm_check_resolution;
        if let Some((segment, at)) = first_invalid(&path, resolution, false, &|q| arm.valid(q)) {
            let contact = arm.describe(&at);
            return Ok(Err(self.fail(
                check,
                StepReason::Collision {
                    path: which,
                    segment,
                    at,
                    scene_joint: None,
                    contact,
                },
            )));
        }
        let joints = ctx.robot.arm_joints();
        let vmax: Vec<f64> = joints.iter().map(|j| j.max_velocity).collect();
        let amax: Vec<f64> = joints.iter().map(|j| j.max_acceleration).collect();
        let timer = Timer {
            vmax: &vmax,
            amax: &amax,
            blend: ctx.settings.blend.as_ref(),
        };
        // Shortcuts pull the path tight, against the robot itself too: the phase's check
        // keeps a clearance from it (`free_arm`), so that a leg cannot graze a link between
        // its checked states.
        let valid = |q: &[f64]| arm.valid(q);
        let greedy = time_shortcuts(
            path.clone(),
            &timer,
            ctx.settings.arm_time_shortcuts,
            resolution,
            &valid,
        );
        // One stream per phase, reproducible from the paths' seed.
        let seed = ctx.settings.paths.seed.unwrap_or(0) ^ (which as u64).wrapping_mul(0x9e37_79b9);
        let random = random_time_shortcuts(
            greedy.clone(),
            &timer,
            ctx.settings.arm_random_shortcuts,
            seed,
            resolution,
            &valid,
        );
        // The shortcuts' timer assumes every corner blended; the step's timing stops where a
        // blend fails its check, and a path pulled tight has more such corners. Of the path
        // and its shortcut versions, the one quickest as the step times it (the same blends,
        // checks and stops) is kept; the first on a tie.
        let duration = |p: &[Vec<f64>]| -> Result<f64, PlannerError> {
            Ok(timed(
                p,
                (&vmax, &amax),
                None,
                ctx.settings.blend.as_ref(),
                resolution,
                &|_, _, q| arm.valid(q),
            )?
            .duration)
        };
        let mut best = (duration(&path)?, path);
        for candidate in [greedy, random] {
            if candidate != best.1 {
                let d = duration(&candidate)?;
                if d < best.0 {
                    best = (d, candidate);
                }
            }
        }
        Ok(Ok(best.1))
    }

    /// The scene after the step.
    pub(super) fn after(&self) -> Result<SceneData, PlannerError> {
        let model = self.ctx.model;
        let mut after = self.state.clone();
        after.set(model, self.joint, self.step.to)?;
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, &after)?;
        Ok(data)
    }

    /// The arm's phases: stowed → pre-grasp (nothing exempt) → straight in to the grasp (the
    /// grasp rule), at the placement's base pose; the manipulation re-checked with the part
    /// (and, whole-body, the base) moving along with the arm; then in the new state straight
    /// out to the post-grasp (the grasp rule) and free to stowed, at the manipulation's last
    /// base pose.
    pub(super) fn arm_paths(
        &self,
        placed: &Placed,
    ) -> Result<Result<ArmPaths, Failed>, PlannerError> {
        let ctx = self.ctx;
        let base = placed.base;
        let stow = ctx.stow.as_slice();
        let grasp = Exempt::Grasp(&self.grasped);

        let inward = &placed.all[..=placed.grasp_at];
        if let Some(f) = self.straight(
            inward,
            &self.arm(base, &self.data, grasp),
            Check::Approach,
            StepPath::StraightIn,
        ) {
            return Ok(Err(f));
        }
        let free_before = self.free_arm(base, &self.data, stow, &inward[0]);
        let free_path = match self.arm_phase(
            stow,
            &inward[0],
            &free_before,
            Check::Approach,
            StepPath::ArmToPregrasp,
        )? {
            Ok(p) => p,
            Err(f) => return Ok(Err(f)),
        };
        let pregrasp = free_path.len() - 1;
        let approach = free_path
            .into_iter()
            .chain(inward.iter().skip(1).cloned())
            .collect();

        let hit = |d: &SceneData, b: [f64; 3], q: &[f64]| self.arm_exact(b, d, grasp).hit(q);
        let (state, joint, step) = (self.state, self.joint, self.step);
        let bases = placed.waypoint_bases();
        let along = (placed.waypoints(), bases.as_slice());
        if let Some(reason) = check_manipulation(ctx, state, joint, step, along, &hit)? {
            return Ok(Err(self.fail(Check::Manipulation, reason)));
        }

        // A whole-body manipulation lets go where its last waypoint put the base.
        let base = placed.end_base();
        let data_after = self.after()?;
        let outward = &placed.all[placed.release_at..];
        if let Some(f) = self.straight(
            outward,
            &self.arm(base, &data_after, grasp),
            Check::Retreat,
            StepPath::StraightOut,
        ) {
            return Ok(Err(f));
        }
        let postgrasp = outward.len() - 1;
        let free_path = match self.arm_phase(
            &outward[postgrasp],
            stow,
            &self.free_arm(base, &data_after, &outward[postgrasp], stow),
            Check::Retreat,
            StepPath::ArmToStow,
        )? {
            Ok(p) => p,
            Err(f) => return Ok(Err(f)),
        };
        let retreat = outward
            .iter()
            .cloned()
            .chain(free_path.into_iter().skip(1))
            .collect();
        Ok(Ok(ArmPaths {
            approach,
            pregrasp,
            retreat,
            postgrasp,
        }))
    }
}
