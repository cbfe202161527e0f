//! Refining one segment of a step, phase by phase: the placement and the base path here, the
//! arm's phases in `arm.rs`, the timing in `timing.rs`; which segments, in `segment.rs`.

use std::collections::BTreeSet;

use nalgebra::DVector;

use super::certify::Stretch;
use super::{
    Check, Contact, Failed, FailedSegment, StepContext, StepMode, StepMotion, StepPath, StepReason,
    StepTiming, grasped, grid_bounds, path_or_reason, same_pose,
};
use crate::kinematics::robot::{BaseKind, Exempt, RobotConfig, SphereObstacles};
use crate::motion::paths::{differential_drive, first_invalid, plan_base};
use crate::motion::placement::{
    JointMotion, Obstacle, PlacementOutcome, PlacementProblem, PlacementSettings, place_and_plan,
    rest_self_margin,
};
use crate::motion::timing::TimedPath;
use crate::planner::arm_check::ArmCheck;
use crate::planner::{PlannerError, StepFailure};
use crate::scene::collision::Body;
use crate::scene::{HandleId, JointId, PartId, SceneData, State, forward_kinematics};
use crate::task::Step;

/// How many SE(2) base paths are planned for a differential-drive base before the base path
/// fails: each is turned into turn-and-drive pieces, which may collide where the SE(2) path
/// did not (the robot turns in place, and drives at its heading rather than the path's yaws).
pub(super) const DIFFERENTIAL_ATTEMPTS: u64 = 3;

/// One segment of a step being refined (the whole step when it is not segmented): its
/// context, the scene at the segment's start state and the parts the gripper holds.
pub(super) struct StepRefinement<'c, 'a> {
    pub(super) ctx: &'c StepContext<'a>,
    pub(super) index: usize,
    /// The task plan's step, which failures name.
    pub(super) task_step: &'c Step,
    /// The segment: the joint from its value in `state` to `step.to`.
    pub(super) step: &'c Step,
    /// Where in a segmented step this is (`None`: the step is refined as one segment).
    pub(super) segment: Option<FailedSegment>,
    pub(super) joint: JointId,
    pub(super) state: &'c State,
    /// The scene at `state`.
    pub(super) data: SceneData,
    /// The grasped part and its descendants.
    pub(super) grasped: Vec<PartId>,
    /// The arm's margin: the arm phases end or start at the placement's configurations, which
    /// keep the placement's margin, so the arm keeps no more than that.
    pub(super) arm_margin: f64,
    /// The clearance the robot's links keep from each other in the phases under the grasp
    /// rule (the straight approach and retreat, the manipulation): half the placement's
    /// ([`ManipulationSettings::self_margin`] capped by the stow's), which its
    /// configurations keep; the half allows for the finer re-check between them.
    ///
    /// [`ManipulationSettings::self_margin`]: crate::motion::placement::ManipulationSettings::self_margin
    pub(super) grasp_self_margin: f64,
}

/// The placement of a step: the base pose and the arm's configurations (the straight approach
/// from the pre-grasp to the grasp, the handle trajectory, the straight retreat to the
/// post-grasp).
pub(super) struct Placed {
    /// The base pose of the approach (for a whole-body manipulation, at its first waypoint).
    pub(super) base: [f64; 3],
    pub(super) all: Vec<Vec<f64>>,
    /// Indices in `all` of the grasp and the release.
    pub(super) grasp_at: usize,
    pub(super) release_at: usize,
    /// A whole-body manipulation: the base pose at each configuration of `all` (constant over
    /// the straight approach and the straight retreat). `None`: `base` throughout.
    pub(super) bases: Option<Vec<[f64; 3]>>,
}

impl Placed {
    /// The configurations `arm` at `base` along `motion` (every waypoint reached).
    pub(super) fn new(base: [f64; 3], arm: &[DVector<f64>], motion: &JointMotion) -> Placed {
        let trajectory = motion.trajectory();
        Placed {
            base,
            all: arm.iter().map(|q| q.as_slice().to_vec()).collect(),
            grasp_at: *trajectory.start(),
            release_at: *trajectory.end(),
            bases: None,
        }
    }

    /// The handle trajectory's configurations.
    pub(super) fn waypoints(&self) -> &[Vec<f64>] {
        &self.all[self.grasp_at..=self.release_at]
    }

    /// The base pose at each of [`Self::waypoints`].
    pub(super) fn waypoint_bases(&self) -> Vec<[f64; 3]> {
        match &self.bases {
            Some(b) => b[self.grasp_at..=self.release_at].to_vec(),
            None => vec![self.base; self.release_at + 1 - self.grasp_at],
        }
    }

    /// The base pose of the retreat: the last waypoint's.
    pub(super) fn end_base(&self) -> [f64; 3] {
        self.bases
            .as_ref()
            .and_then(|b| b.last().copied())
            .unwrap_or(self.base)
    }
}

/// How far (m) a base path may stay within the arm paths' margin of the scene after its
/// start: the robot leaves where the previous step left it, which kept that margin.
pub(super) const LEAVE: f64 = 0.3;

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
    /// The segment `step` of `task_step` (index `index` in the plan) from `state`, where the
    /// joint is at `step.from`.
    pub(super) fn new(
        ctx: &'c StepContext<'a>,
        index: usize,
        task_step: &'c Step,
        step: &'c Step,
        segment: Option<FailedSegment>,
        joint: JointId,
        state: &'c State,
    ) -> Result<Self, PlannerError> {
        let model = ctx.model;
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, state)?;
        let placement_self_margin = rest_self_margin(
            &PlacementProblem {
                robot: ctx.robot,
                collision: ctx.collision,
                ik: ctx.ik,
                model,
                state,
            },
            ctx.settings.placement.manipulation.self_margin,
            ctx.settings.placement.stow.as_ref().unwrap_or(ctx.stow),
        )?;
        Ok(StepRefinement {
            grasp_self_margin: 0.5 * placement_self_margin,
            ctx,
            index,
            task_step,
            step,
            segment,
            joint,
            state,
            data,
            grasped: grasped(model, joint),
            arm_margin: ctx
                .settings
                .margin
                .min(ctx.settings.placement.manipulation.margin),
        })
    }

    /// `failed` (an arm phase's failure at the base poses of `placed`) with the parts in the
    /// robot's reach there as its causes ([`Self::near_parts`]), added to any it has: no
    /// configuration of the robot at those base poses comes near another part, so the phase
    /// fails the same way whatever the other joints do (a farther part that comes nearer
    /// only adds an obstacle).
    fn near_causes(&self, failed: Failed, placed: &Placed) -> Result<Failed, PlannerError> {
        let (failure, causes) = failed;
        let bases: Vec<[f64; 3]> = match &placed.bases {
            Some(bases) => bases.clone(),
            None => vec![placed.base],
        };
        let mut near = self.near_parts(&bases)?;
        near.extend(causes.unwrap_or_default());
        Ok((failure, Some(near.into_iter().collect())))
    }

    /// The scene parts in the robot's reach from any of `bases`, at the step's start or end
    /// state: those with a shape whose bounding box comes within the robot's horizontal
    /// extent (the largest [`SpeedBound::link_radius`](crate::kinematics::robot::SpeedBound),
    /// over every arm configuration) plus the planner's margin of a base position.
    pub(super) fn near_parts(&self, bases: &[[f64; 3]]) -> Result<BTreeSet<PartId>, PlannerError> {
        let ctx = self.ctx;
        let reach = (0..ctx.robot.links().len())
            .map(|l| ctx.speeds.link_radius(l))
            .fold(0.0, f64::max)
            + ctx.settings.margin;
        let after = self.after()?;
        let mut near = BTreeSet::new();
        for data in [&self.data, &after] {
            for (p, shapes) in ctx.model.geometry.parts.iter().enumerate() {
                let Some(pose) = data.world_from_part(PartId(p)) else {
                    continue;
                };
                let reached = shapes.iter().any(|s| {
                    let b = s.enclosing_world_box(pose);
                    bases.iter().any(|c| {
                        let dx = (b.min.x - c[0]).max(c[0] - b.max.x).max(0.0);
                        let dy = (b.min.y - c[1]).max(c[1] - b.max.y).max(0.0);
                        dx.hypot(dy) <= reach
                    })
                });
                if reached {
                    near.insert(PartId(p));
                }
            }
        }
        Ok(near)
    }

    /// A failure without known causes: every joint may matter.
    pub(super) fn fail(&self, check: Check, reason: StepReason) -> Failed {
        let failure = StepFailure {
            step: self.index,
            joint: self.task_step.joint.clone(),
            from: self.task_step.from,
            to: self.task_step.to,
            check,
            reason,
            segment: self.segment,
        };
        (failure, None)
    }

    /// The placement problem at the segment's start state.
    pub(super) fn problem(&self) -> PlacementProblem<'c> {
        let ctx = self.ctx;
        PlacementProblem {
            robot: ctx.robot,
            collision: ctx.collision,
            ik: ctx.ik,
            model: ctx.model,
            state: self.state,
        }
    }

    /// [`place_and_plan`] for the segment with `settings`, the robot's base at `from`.
    pub(super) fn placement(
        &self,
        handle: HandleId,
        from: [f64; 3],
        settings: &PlacementSettings,
    ) -> Result<PlacementOutcome, PlannerError> {
        let ctx = self.ctx;
        let mut scratch = ctx.placement.lock().unwrap_or_else(|e| e.into_inner());
        Ok(place_and_plan(
            self.problem(),
            self.joint,
            handle,
            self.step.to,
            from,
            settings,
            &mut scratch,
            ctx.termination,
        )?)
    }

    /// The segment's phases from the placement `placed`, the robot's base at `from`: the base
    /// path, the arm's paths, their timing.
    pub(super) fn execute(
        &self,
        handle: &str,
        placed: &Placed,
        from: [f64; 3],
    ) -> Result<Result<StepMotion, Failed>, PlannerError> {
        let base = placed.base;
        // The arm's failures depend only on the parts in its reach at the placement's base
        // poses; the base path's on the whole map (unknown causes).
        let near = |f: Failed| self.near_causes(f, placed);
        let base_path = match self.base_path(from, base)? {
            Ok(p) => p,
            Err(f) => return Ok(Err(f)),
        };
        let arm = match self.arm_paths(placed)? {
            Ok(a) => a,
            Err(f) => return Ok(Err(near(f)?)),
        };
        let (base_timed, approach, (manipulation, manipulation_base), retreat) =
            self.time(handle, placed, &base_path, &arm)?;
        if let Some(f) = self.certify_base(&base_timed) {
            return Ok(Err(f));
        }
        if let Some(f) = self.certify_arm(placed, &arm, &approach, &retreat)? {
            return Ok(Err(near(f)?));
        }
        if let Some(f) =
            self.certify_manipulation(placed, &manipulation, manipulation_base.as_ref())?
        {
            return Ok(Err(near(f)?));
        }
        let timing = StepTiming {
            base: base_timed.duration,
            approach: approach.duration,
            manipulation: manipulation.duration,
            retreat: retreat.duration,
        };
        Ok(Ok(StepMotion {
            joint: self.step.joint.clone(),
            from: self.step.from,
            to: self.step.to,
            handle: handle.to_owned(),
            base,
            base_path: base_timed,
            approach,
            pregrasp: arm.pregrasp,
            manipulation,
            manipulation_base,
            retreat,
            postgrasp: arm.postgrasp,
            timing,
            mode: if placed.bases.is_some() {
                StepMode::WholeBody
            } else if self.segment.is_some() {
                StepMode::Segment
            } else {
                StepMode::FixedBase
            },
            compared: None,
        }))
    }

    /// The timed approach and retreat certified free between their checked configurations
    /// (`certify.rs`): the approach free up to the pre-grasp and under the grasp rule from it,
    /// at the placement's base pose in the step's start state; the retreat under the grasp
    /// rule up to the post-grasp and free after it, at the manipulation's last base pose in the
    /// state after the step.
    fn certify_arm(
        &self,
        placed: &Placed,
        arm: &ArmPaths,
        approach: &TimedPath,
        retreat: &TimedPath,
    ) -> Result<Option<Failed>, PlannerError> {
        let grasp = Exempt::Grasp(&self.grasped);
        let pregrasp = approach.times[arm.pregrasp];
        let stretches = [
            Stretch {
                which: StepPath::ArmToPregrasp,
                from: 0.0,
                to: pregrasp,
                data: &self.data,
                exempt: Exempt::Nothing,
            },
            Stretch {
                which: StepPath::StraightIn,
                from: pregrasp,
                to: approach.duration,
                data: &self.data,
                exempt: grasp,
            },
        ];
        if let Some(f) = self.certify(approach, placed.base, &stretches, Check::Approach) {
            return Ok(Some(f));
        }
        let after = self.after()?;
        let postgrasp = retreat.times[arm.postgrasp];
        let stretches = [
            Stretch {
                which: StepPath::StraightOut,
                from: 0.0,
                to: postgrasp,
                data: &after,
                exempt: grasp,
            },
            Stretch {
                which: StepPath::ArmToStow,
                from: postgrasp,
                to: retreat.duration,
                data: &after,
                exempt: Exempt::Nothing,
            },
        ];
        Ok(self.certify(retreat, placed.end_base(), &stretches, Check::Retreat))
    }

    /// The arm check at the scene `data`, with `exempt`, with the sphere fast path when the
    /// planner has one (its obstacles built here, once per call: use it for many states of
    /// one scene state, [`Self::arm_exact`] for one).
    pub(super) fn arm<'d>(
        &'d self,
        base: [f64; 3],
        data: &'d SceneData,
        exempt: Exempt<'d>,
    ) -> ArmCheck<'d>
    where
        'c: 'd,
    {
        let obstacles = self
            .ctx
            .spheres
            .map(|_| SphereObstacles::new(self.ctx.model, data, exempt, self.arm_margin));
        ArmCheck {
            obstacles,
            ..self.arm_exact(base, data, exempt)
        }
    }

    /// The arm check at the scene `data`, with `exempt`, exact only (parry for every state);
    /// the links keep [`Self::grasp_self_margin`] from each other.
    pub(super) fn arm_exact<'d>(
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
            self_margin: self.grasp_self_margin,
            obstacles: None,
        }
    }

    /// The check of a free arm phase from `from` to `to` at `base` in the scene `data`
    /// (nothing exempt): as [`arm`](Self::arm), and the robot's links keep a clearance from
    /// each other, the arm margin but at most half the least one the phase's ends have (so
    /// that a stow or pre-grasp with two links close together stays valid). A path with no
    /// self-clearance can graze the robot between its checked states, and a real arm tracks
    /// its path with some error.
    pub(super) fn free_arm<'d>(
        &'d self,
        base: [f64; 3],
        data: &'d SceneData,
        from: &[f64],
        to: &[f64],
    ) -> ArmCheck<'d>
    where
        'c: 'd,
    {
        let ctx = self.ctx;
        let clearance = |q: &[f64]| {
            ctx.robot
                .link_poses(&RobotConfig {
                    base,
                    arm: DVector::from_column_slice(q),
                })
                .map_or(0.0, |poses| {
                    ctx.collision.self_clearance(&poses, 2.0 * self.arm_margin)
                })
        };
        let ends = clearance(from).min(clearance(to));
        ArmCheck {
            self_margin: self.arm_margin.min(0.5 * ends).max(0.0),
            ..self.arm(base, data, Exempt::Nothing)
        }
    }

    /// Whether a base path can end at `b`: inside the navigation grid's extent (the base
    /// path's bounds) and [`base_valid`](Self::base_valid).
    pub(super) fn base_reachable(&self, b: &[f64; 3]) -> bool {
        let (lo, hi) = grid_bounds(self.ctx.model);
        (lo[0]..=hi[0]).contains(&b[0]) && (lo[1]..=hi[1]).contains(&b[1]) && self.base_valid(b)
    }

    /// Whether the robot at base pose `b` with the arm stowed is clear of the scene at the
    /// step's start state.
    pub(super) fn base_valid(&self, b: &[f64; 3]) -> bool {
        matches!(self.base_hit(b, self.ctx.settings.margin), Ok(None))
    }

    /// [`Self::base_valid`] along a base path that starts at `start`: within [`LEAVE`] of the
    /// start the stowed robot keeps the arm paths' (smaller) margin, the one the step it
    /// stands after kept there (a drawer pulled towards the robot ends close to it); farther
    /// out the base paths' margin.
    pub(super) fn base_valid_from(&self, start: &[f64], b: &[f64; 3]) -> bool {
        let leaving = (b[0] - start[0]).hypot(b[1] - start[1]) <= LEAVE;
        let margin = if leaving {
            self.arm_margin
        } else {
            self.ctx.settings.margin
        };
        matches!(self.base_hit(b, margin), Ok(None))
    }

    /// What the stowed robot at base pose `b` touches within `margin` in the step's start
    /// state, `(link, collider, body)` (`Err`: the pose has no link poses).
    fn base_hit(&self, b: &[f64; 3], margin: f64) -> Result<Option<(usize, usize, Body)>, ()> {
        let ctx = self.ctx;
        let cfg = RobotConfig {
            base: *b,
            arm: ctx.stow.clone(),
        };
        let poses = ctx.robot.link_poses(&cfg).map_err(|_| ())?;
        Ok(ctx
            .collision
            .scene_contact(&poses, ctx.model, &self.data, Exempt::Nothing, margin))
    }

    /// [`Self::base_hit`] as a named contact.
    pub(super) fn base_contact(&self, b: &[f64; 3]) -> Contact {
        match self.base_hit(b, self.ctx.settings.margin) {
            Ok(Some((link, collider, body))) => Contact::Touches {
                obstacle: Obstacle::scene_named(
                    self.ctx.robot,
                    self.ctx.model,
                    (link, body),
                    Some(collider),
                ),
                margin: self.ctx.settings.margin,
            },
            Ok(None) => Contact::Unnamed,
            Err(()) => Contact::NoPose,
        }
    }

    /// The base path from `from` to `to`, arm stowed, the whole robot against the scene at the
    /// step's start state, densely re-checked (yaw scaled by the footprint radius). For a
    /// differential-drive base the SE(2) path is turned into turn-in-place and drive-straight
    /// pieces ([`differential_drive`], each piece checked densely); when no such pieces follow
    /// it, another SE(2) path is planned (seed + 1, ...), up to [`DIFFERENTIAL_ATTEMPTS`] in all.
    fn base_path(
        &self,
        from: [f64; 3],
        to: [f64; 3],
    ) -> Result<Result<Vec<Vec<f64>>, Failed>, PlannerError> {
        let differential = match self.ctx.robot.base().kind {
            BaseKind::Holonomic => false,
            BaseKind::DifferentialDrive => true,
        };
        let attempts = if differential {
            DIFFERENTIAL_ATTEMPTS
        } else {
            1
        };
        let mut failures = Vec::new();
        for attempt in 0..attempts {
            let planned = match self.se2_path(from, to, attempt)? {
                Ok(p) => p,
                Err(f) => return Ok(Err(f)),
            };
            let path = if differential {
                let valid = |a: &[f64], b: &[f64]| {
                    self.base_collision(&from, &[a.to_vec(), b.to_vec()])
                        .is_none()
                };
                match differential_drive(&planned, &valid) {
                    Ok(p) => p,
                    Err(why) => {
                        failures.push(why);
                        if self.ctx.termination.should_stop() {
                            break;
                        }
                        continue;
                    }
                }
            } else {
                planned
            };
            if let Some((segment, at)) = self.base_collision(&from, &path) {
                let contact = self.base_contact(&[at[0], at[1], at[2]]);
                return Ok(Err(self.fail(
                    Check::BasePath,
                    StepReason::Collision {
                        path: StepPath::Base,
                        segment,
                        at,
                        scene_joint: None,
                        contact,
                    },
                )));
            }
            return Ok(Ok(path));
        }
        let check = if self.ctx.termination.should_stop() {
            Check::Stopped
        } else {
            Check::BasePath
        };
        Ok(Err(
            self.fail(check, StepReason::NoDifferentialPath { failures })
        ))
    }

    /// An SE(2) base path from `from` to `to` (OMPL, the path settings' seed plus `attempt`).
    fn se2_path(
        &self,
        from: [f64; 3],
        to: [f64; 3],
        attempt: u64,
    ) -> Result<Result<Vec<Vec<f64>>, Failed>, PlannerError> {
        let ctx = self.ctx;
        if same_pose(&from, &to) {
            return Ok(Ok(vec![from.to_vec(), to.to_vec()]));
        }
        let mut settings = ctx.settings.paths.clone();
        settings.seed = settings.seed.map(|s| s.wrapping_add(attempt));
        let base_valid = |b: &[f64; 3]| self.base_valid_from(&from, b);
        let outcome = plan_base(
            from,
            to,
            grid_bounds(ctx.model),
            &base_valid,
            &settings,
            ctx.termination,
        )?;
        let contact = |b: &[f64]| match b {
            &[x, y, yaw] => self.base_contact(&[x, y, yaw]),
            _ => Contact::NoPose,
        };
        Ok(
            path_or_reason(outcome, StepPath::Base, (&from, &to), &contact).map_err(|reason| {
                let check = if ctx.termination.should_stop() {
                    Check::Stopped
                } else {
                    Check::BasePath
                };
                self.fail(check, *reason)
            }),
        )
    }

    /// The first base pose along `path` (straight segments, yaw not wrapped; part of a base
    /// path from `start`) where the robot with the arm stowed is not
    /// [`base_valid_from`](Self::base_valid_from) `start`, sampled at the planner's base
    /// resolution with the yaw scaled by the footprint radius: the segment and the pose.
    pub(super) fn base_collision(
        &self,
        start: &[f64],
        path: &[Vec<f64>],
    ) -> Option<(usize, Vec<f64>)> {
        let radius = self.ctx.robot.base().footprint_radius.max(1e-3);
        let scaled: Vec<Vec<f64>> = path
            .iter()
            .map(|p| vec![p[0], p[1], p[2] * radius])
            .collect();
        let valid = |p: &[f64]| self.base_valid_from(start, &[p[0], p[1], p[2] / radius]);
        first_invalid(
            &scaled,
            self.ctx.settings.base_check_resolution,
            false,
            &valid,
        )
        .map(|(seg, at)| (seg, vec![at[0], at[1], at[2] / radius]))
    }
}
