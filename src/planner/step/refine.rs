//! Refining one step, phase by phase: the placement and the base path here, the arm's phases
//! in `arm.rs`, the timing in `timing.rs`.

use super::{
    Check, Failed, StepContext, StepMotion, StepTiming, describe, first_handle_name, grasped,
    grid_bounds, placement_causes, same_pose,
};
use crate::kinematics::robot::{Exempt, RobotConfig};
use crate::motion::paths::{PathOutcome, first_invalid, plan_base};
use crate::motion::placement::{PlacementProblem, place_and_plan};
use crate::planner::arm_check::ArmCheck;
use crate::planner::{PlannerError, StepFailure};
use crate::scene::{JointId, PartId, SceneData, State, forward_kinematics};
use crate::task::Step;

/// Refines `step` (index `index` of the plan) from `state` with the robot at `robot`. `Ok(Err)`
/// is a failed check (an outcome); `Err` bad input or a broken backend.
pub(in crate::planner) fn refine(
    ctx: &StepContext<'_>,
    index: usize,
    state: &State,
    joint: JointId,
    step: &Step,
    robot: &RobotConfig,
) -> Result<Result<StepMotion, Failed>, PlannerError> {
    let model = ctx.model;
    let handle_name = match &step.handle {
        Some(h) => h.clone(),
        None => first_handle_name(model, joint)?,
    };
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state)?;
    let r = StepRefinement {
        ctx,
        index,
        step,
        joint,
        state,
        data,
        grasped: grasped(model, joint),
        arm_margin: ctx
            .settings
            .margin
            .min(ctx.settings.placement.manipulation.margin),
    };
    let placed = match r.place(&handle_name, robot.base)? {
        Ok(p) => p,
        Err(f) => return Ok(Err(f)),
    };
    if ctx.termination.should_stop() {
        return Ok(Err(r.fail(Check::Stopped, "after base placement".into())));
    }
    let base = placed.base;
    let base_path = match r.base_path(robot.base, base)? {
        Ok(p) => p,
        Err(f) => return Ok(Err(f)),
    };
    let arm = match r.arm_paths(&placed)? {
        Ok(a) => a,
        Err(f) => return Ok(Err(f)),
    };
    let (base_timed, approach, manipulation, retreat) = r.time(&placed, &base_path, &arm)?;
    let timing = StepTiming {
        base: base_timed.duration,
        approach: approach.duration,
        manipulation: manipulation.duration,
        retreat: retreat.duration,
    };
    Ok(Ok(StepMotion {
        joint: step.joint.clone(),
        from: step.from,
        to: step.to,
        handle: handle_name,
        base,
        base_path: base_timed,
        approach,
        pregrasp: arm.pregrasp,
        manipulation,
        retreat,
        postgrasp: arm.postgrasp,
        timing,
    }))
}

/// One step being refined: its context, the scene at the step's start state and the parts the
/// gripper holds.
pub(super) struct StepRefinement<'c, 'a> {
    pub(super) ctx: &'c StepContext<'a>,
    pub(super) index: usize,
    pub(super) step: &'c Step,
    pub(super) joint: JointId,
    pub(super) state: &'c State,
    /// The scene at `state`.
    pub(super) data: SceneData,
    /// The grasped part and its descendants.
    pub(super) grasped: Vec<PartId>,
    /// The arm's margin: the arm phases end or start at the placement's configurations, which
    /// keep the placement's margin, so the arm keeps no more than that.
    pub(super) arm_margin: f64,
}

/// The placement of a step: the base pose and the arm's configurations (the straight approach
/// from the pre-grasp to the grasp, the handle trajectory, the straight retreat to the
/// post-grasp).
pub(super) struct Placed {
    pub(super) base: [f64; 3],
    pub(super) all: Vec<Vec<f64>>,
    /// Indices in `all` of the grasp and the release.
    pub(super) grasp_at: usize,
    pub(super) release_at: usize,
}

impl Placed {
    /// The handle trajectory's configurations.
    pub(super) fn waypoints(&self) -> &[Vec<f64>] {
        &self.all[self.grasp_at..=self.release_at]
    }
}

/// The arm's paths of a step: stowed to the grasp, and the release back to stowed.
pub(super) struct ArmPaths {
    pub(super) approach: Vec<Vec<f64>>,
    /// Index in `approach` of the pre-grasp configuration.
    pub(super) pregrasp: usize,
    pub(super) retreat: Vec<Vec<f64>>,
    /// Index in `retreat` of the post-grasp configuration.
    pub(super) postgrasp: usize,
}

impl<'c, 'a> StepRefinement<'c, 'a> {
    /// A failure without known causes: every joint may matter.
    pub(super) fn fail(&self, check: Check, reason: String) -> Failed {
        let failure = StepFailure {
            step: self.index,
            joint: self.step.joint.clone(),
            from: self.step.from,
            to: self.step.to,
            check,
            reason,
        };
        (failure, None)
    }

    /// The arm check at the scene `data`, with `exempt`.
    pub(super) fn arm<'d>(
        &'d self,
        base: [f64; 3],
        data: &'d SceneData,
        exempt: Exempt<'d>,
    ) -> ArmCheck<'d>
    where
        'c: 'd,
    {
        ArmCheck {
            ctx: self.ctx,
            base,
            data,
            exempt,
            margin: self.arm_margin,
        }
    }

    /// Placement: the base pose and the arm along the handle trajectory.
    fn place(
        &self,
        handle_name: &str,
        from: [f64; 3],
    ) -> Result<Result<Placed, Failed>, PlannerError> {
        let ctx = self.ctx;
        let handle = ctx.model.handle_id(handle_name)?;
        let placement = {
            let mut scratch = ctx.placement.lock().unwrap_or_else(|e| e.into_inner());
            place_and_plan(
                PlacementProblem {
                    robot: ctx.robot,
                    collision: ctx.collision,
                    ik: ctx.ik,
                    model: ctx.model,
                    state: self.state,
                },
                self.joint,
                handle,
                self.step.to,
                from,
                &ctx.settings.placement,
                &mut scratch,
                ctx.termination,
            )?
        };
        if !placement.is_complete() {
            let causes = placement_causes(&placement);
            let reason = placement.reason.clone().unwrap_or_else(|| {
                format!(
                    "{:.0} % of the waypoints reached",
                    100.0 * placement.reached_fraction
                )
            });
            let (failure, _) = self.fail(Check::Placement, reason);
            return Ok(Err((failure, causes)));
        }
        let trajectory = placement.motion.trajectory();
        Ok(Ok(Placed {
            base: placement.base,
            all: placement
                .arm
                .iter()
                .map(|q| q.as_slice().to_vec())
                .collect(),
            grasp_at: *trajectory.start(),
            release_at: *trajectory.end(),
        }))
    }

    /// Whether the robot at base pose `b` with the arm stowed is clear of the scene at the
    /// step's start state.
    pub(super) fn base_valid(&self, b: &[f64; 3]) -> bool {
        let ctx = self.ctx;
        let cfg = RobotConfig {
            base: *b,
            arm: ctx.stow.clone(),
        };
        match ctx.robot.link_poses(&cfg) {
            Ok(poses) => ctx
                .collision
                .scene_collision(
                    &poses,
                    ctx.model,
                    &self.data,
                    Exempt::Nothing,
                    ctx.settings.margin,
                )
                .is_none(),
            Err(_) => false,
        }
    }

    /// The base path from `from` to `to`, arm stowed, the whole robot against the scene at the
    /// step's start state, densely re-checked (yaw scaled by the footprint radius).
    fn base_path(
        &self,
        from: [f64; 3],
        to: [f64; 3],
    ) -> Result<Result<Vec<Vec<f64>>, Failed>, PlannerError> {
        let ctx = self.ctx;
        let settings = ctx.settings;
        let base_valid = |b: &[f64; 3]| self.base_valid(b);
        let base_path = if same_pose(&from, &to) {
            vec![from.to_vec(), to.to_vec()]
        } else {
            match plan_base(
                from,
                to,
                grid_bounds(ctx.model),
                &base_valid,
                &settings.paths,
                ctx.termination,
            )? {
                PathOutcome::Solved(p) => p,
                other => {
                    let check = if ctx.termination.should_stop() {
                        Check::Stopped
                    } else {
                        Check::BasePath
                    };
                    return Ok(Err(self.fail(check, describe(&other, "base"))));
                }
            }
        };
        let radius = ctx.robot.base().footprint_radius.max(1e-3);
        let scaled: Vec<Vec<f64>> = base_path
            .iter()
            .map(|p| vec![p[0], p[1], p[2] * radius])
            .collect();
        let base_valid_scaled = |p: &[f64]| self.base_valid(&[p[0], p[1], p[2] / radius]);
        if let Some((seg, at)) = first_invalid(
            &scaled,
            settings.base_check_resolution,
            false,
            &base_valid_scaled,
        ) {
            return Ok(Err(self.fail(
                Check::BasePath,
                format!(
                    "dense re-check: segment {seg} collides at ({:.3}, {:.3}, {:.3})",
                    at[0],
                    at[1],
                    at[2] / radius
                ),
            )));
        }
        Ok(Ok(base_path))
    }
}
