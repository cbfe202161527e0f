//! Which segments a step is executed in: the single placement first; when it does not cover
//! the step, segment ends from the longest reached prefix (the rule is in the module docs of
//! [`super`], "Segments").

use std::collections::BTreeSet;

use super::refine::{Placed, StepRefinement};
use super::whole_body::choose;
use super::{
    Check, Failed, FailedSegment, PlacementShortfall, SegmentMiss, SegmentTry, SplitMiss,
    StepContext, StepMotion, StepReason, first_handle_name,
};
use crate::kinematics::robot::RobotConfig;
use crate::motion::placement::{
    PlacementMethod, PlacementObjective, PlacementOutcome, placement_motion_turned,
    plan_manipulation_met,
};
use crate::planner::PlannerError;
use crate::scene::{HandleId, JointId, PartId, State};
use crate::task::Step;

/// Refines `step` (index `index` of the plan) from `state` with the robot at `robot`: the
/// motion of each of its segments, in order (one when a single base pose covers the step, or
/// when the base moves along with the arm, see `whole_body.rs`).
/// `Ok(Err)` is a failed check (an outcome); `Err` bad input or a broken backend.
pub(in crate::planner) fn refine(
    ctx: &StepContext<'_>,
    index: usize,
    state: &State,
    joint: JointId,
    step: &Step,
    robot: &RobotConfig,
) -> Result<Result<Vec<StepMotion>, Failed>, PlannerError> {
    let model = ctx.model;
    let handle_name = match &step.handle {
        Some(h) => h.clone(),
        None => first_handle_name(model, joint)?,
    };
    let mut run = Segments {
        ctx,
        index,
        step,
        joint,
        handle: model.handle_id(&handle_name)?,
        causes: BTreeSet::new(),
        first_whole: None,
        first_prefix: None,
    };
    let Some(settings) = &ctx.settings.whole_body else {
        return run.segmented(&handle_name, state, robot.base);
    };
    let whole_body = run.whole_body(settings, &handle_name, state, robot.base)?;
    let segmented = run.segmented(&handle_name, state, robot.base)?;
    Ok(choose(segmented, whole_body).map_err(|failed| *failed))
}

impl Segments<'_, '_> {
    /// The step in segments from `state` with the base at `base` (one segment when a single
    /// base pose covers it).
    fn segmented(
        &mut self,
        handle_name: &str,
        state: &State,
        base: [f64; 3],
    ) -> Result<Result<Vec<StepMotion>, Failed>, PlannerError> {
        let (ctx, step) = (self.ctx, self.step);
        let model = ctx.model;
        let mut motions: Vec<StepMotion> = Vec::new();
        let mut state = state.clone();
        let mut base = base;
        let mut from = step.from;
        loop {
            let i = motions.len();
            let (placed, end) = match self.next_segment(i, from, &state, base)? {
                Ok(next) => next,
                Err(f) => return Ok(Err(f)),
            };
            let segment = Step {
                from,
                to: end,
                ..step.clone()
            };
            let label = (i > 0 || end != step.to).then_some(FailedSegment {
                index: i,
                from,
                to: end,
            });
            let r =
                StepRefinement::new(ctx, self.index, step, &segment, label, self.joint, &state)?;
            if ctx.termination.should_stop() {
                return Ok(Err(r.fail(
                    Check::Stopped,
                    StepReason::Stopped {
                        when: "after base placement",
                    },
                )));
            }
            let motion = match r.execute(handle_name, &placed, base)? {
                Ok(m) => m,
                // Known causes: also the placements' (which chose this base pose).
                Err((f, causes)) => {
                    let causes = causes.map(|mut c| {
                        c.extend(self.causes.iter().copied());
                        c.sort_unstable();
                        c.dedup();
                        c
                    });
                    return Ok(Err((f, causes)));
                }
            };
            base = motion.end_base();
            motions.push(motion);
            if end == step.to {
                return Ok(Ok(motions));
            }
            state.set(model, self.joint, end)?;
            from = end;
        }
    }
}

/// The segments of one step being chosen, and the parts the placements so far depended on.
pub(super) struct Segments<'c, 'a> {
    pub(super) ctx: &'c StepContext<'a>,
    pub(super) index: usize,
    pub(super) step: &'c Step,
    pub(super) joint: JointId,
    pub(super) handle: HandleId,
    /// The scene parts that got in the way of any placement of this step: with them (and the
    /// moved part's ancestors) at the same values, every placement, and so every segment end
    /// and base pose, is the same.
    pub(super) causes: BTreeSet<PartId>,
    /// The placement of the whole step from the robot's pose, when the whole-body attempt
    /// made it already (the first segment's placement then).
    pub(super) first_whole: Option<PlacementOutcome>,
    /// The longest-prefix placement of the whole step, when the whole-body attempt made it
    /// already (the first split's then).
    pub(super) first_prefix: Option<PlacementOutcome>,
}

impl Segments<'_, '_> {
    /// Segment `i`, which starts at `from` in `state` with the base at `base`: its placement
    /// and its end, or why there is none (with the parts it depends on).
    fn next_segment(
        &mut self,
        i: usize,
        from: f64,
        state: &State,
        base: [f64; 3],
    ) -> Result<Result<(Placed, f64), Failed>, PlannerError> {
        let ctx = self.ctx;
        let max = ctx.settings.max_segments;
        let rest = Step {
            from,
            ..self.step.clone()
        };
        let label = (max > 1 || i > 0).then_some(FailedSegment {
            index: i,
            from,
            to: self.step.to,
        });
        let r = StepRefinement::new(ctx, self.index, self.step, &rest, label, self.joint, state)?;
        let whole = match self.first_whole.take().filter(|_| i == 0) {
            Some(whole) => whole,
            None => r.placement(self.handle, base, &ctx.settings.placement)?,
        };
        self.causes.extend(whole.obstacle_parts.iter().copied());
        if whole.is_complete() {
            return Ok(Ok((
                Placed::new(whole.base, &whole.arm, &whole.motion),
                self.step.to,
            )));
        }
        let why = PlacementShortfall::of(&whole);
        if i + 1 >= max {
            let reason = if i == 0 {
                StepReason::Placement(why)
            } else {
                StepReason::SegmentsExhausted {
                    refined: i,
                    up_to: from,
                    max_segments: max,
                    rest: why,
                }
            };
            return Ok(Err(self.placement_failure(&r, reason)));
        }
        if ctx.termination.should_stop() {
            return Ok(Err(r.fail(
                Check::Stopped,
                StepReason::Stopped {
                    when: "after base placement",
                },
            )));
        }
        match self.split(&r, base)? {
            Ok(next) => Ok(Ok(next)),
            Err(_) if ctx.termination.should_stop() => Ok(Err(r.fail(
                Check::Stopped,
                StepReason::Stopped {
                    when: "while choosing where to regrasp",
                },
            ))),
            Err(split) => {
                let reason = StepReason::NoSegment { whole: why, split };
                Ok(Err(self.placement_failure(&r, reason)))
            }
        }
    }

    /// A placement failure of `r` that depends on the parts in `causes`.
    fn placement_failure(&self, r: &StepRefinement<'_, '_>, reason: StepReason) -> Failed {
        let (failure, _) = r.fail(Check::Placement, reason);
        (failure, Some(self.causes.iter().copied().collect()))
    }

    /// The first segment of the rest `r` (which no single base pose covers): the base pose
    /// with the longest reached prefix and the candidate ends it gives, each evaluated there
    /// and else placed anew; `Err` says why none is covered.
    fn split(
        &mut self,
        r: &StepRefinement<'_, '_>,
        base: [f64; 3],
    ) -> Result<Result<(Placed, f64), SplitMiss>, PlannerError> {
        let ctx = self.ctx;
        let settings = &ctx.settings.placement;
        let first = r.step.from == self.step.from;
        let prefix = match self.first_prefix.take().filter(|_| first) {
            Some(prefix) => prefix,
            None => longest_prefix(r, self.handle, base, 1)?,
        };
        self.causes.extend(prefix.obstacle_parts.iter().copied());
        let motion = &prefix.motion;
        let approach = motion.approach;
        let steps = motion.trajectory().count() - 1;
        let reached = prefix.reached_prefix();
        // The last reached waypoint of the handle trajectory (0 is the grasp), short of the
        // last: a segment must move the part, and must leave some of the motion to the next.
        let last = reached
            .checked_sub(approach + 1)
            .map(|e| e.min(steps.saturating_sub(1)))
            .filter(|e| *e >= 1);
        let Some(last) = last else {
            return Ok(Err(SplitMiss::NoPrefix {
                reached,
                waypoints: motion.len(),
            }));
        };
        let mut tried = Vec::new();
        for e in candidate_ends(last) {
            let end = motion.values[approach + e];
            let segment = Step {
                from: r.step.from,
                to: end,
                ..self.step.clone()
            };
            let s = StepRefinement::new(
                ctx, self.index, self.step, &segment, None, self.joint, r.state,
            )?;
            // The prefix's grasp (turned about a bar or not) carries its segment.
            let seg_motion = placement_motion_turned(
                s.problem(),
                self.joint,
                self.handle,
                end,
                settings,
                motion.grasp_angle,
            )?;
            let (at_prefix, met) = plan_manipulation_met(
                s.problem(),
                &seg_motion,
                prefix.base,
                &ctx.robot.neutral(),
                settings.grasp,
                &settings.manipulation,
            )?;
            self.causes.extend(met);
            // A base pose the base path cannot end at (the stowed arm in the way, which the
            // placement does not check) would only fail the segment later.
            if at_prefix.is_complete() && s.base_reachable(&at_prefix.base) {
                return Ok(Ok((
                    Placed::new(at_prefix.base, &at_prefix.arm, &seg_motion),
                    end,
                )));
            }
            if ctx.termination.should_stop() {
                return Ok(Err(SplitMiss::Stopped));
            }
            let placed = s.placement(self.handle, base, settings)?;
            self.causes.extend(placed.obstacle_parts.iter().copied());
            if placed.is_complete() && s.base_reachable(&placed.base) {
                return Ok(Ok((
                    Placed::new(placed.base, &placed.arm, &placed.motion),
                    end,
                )));
            }
            let why = if placed.is_complete() {
                SegmentMiss::BaseNotClear
            } else {
                SegmentMiss::Placement(PlacementShortfall::of(&placed))
            };
            tried.push(SegmentTry { end, why });
        }
        Ok(Err(SplitMiss::Uncovered {
            prefix_end: last,
            intervals: steps,
            tried,
        }))
    }
}

/// The placement of `r`'s segment with the objective
/// [`LongestPrefix`](PlacementObjective::LongestPrefix) (sampled), the robot's base at `base`:
/// the base pose from which the arm follows the motion furthest without letting go, with the
/// `keep` best samples in [`PlacementOutcome::ranked`].
pub(super) fn longest_prefix(
    r: &StepRefinement<'_, '_>,
    handle: HandleId,
    base: [f64; 3],
    keep: usize,
) -> Result<PlacementOutcome, PlannerError> {
    let mut settings = r.ctx.settings.placement.clone();
    settings.method = PlacementMethod::Sampled;
    settings.sampling.objective = PlacementObjective::LongestPrefix;
    settings.sampling.keep = keep.max(1);
    r.placement(handle, base, &settings)
}

/// The candidate ends of a segment whose longest reached prefix ends at handle-trajectory
/// waypoint `last` (>= 1), longest first: `last`; `last − 1` (the end itself may be reachable
/// but not let go of, the straight retreat from it failing); `⌊last / 2⌋` (a segment well
/// inside what that base pose reached). Only waypoints past the first, without repeats.
fn candidate_ends(last: usize) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::with_capacity(3);
    for e in [last, last - 1, last / 2] {
        if e >= 1 && !out.contains(&e) {
            out.push(e);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::candidate_ends;

    #[test]
    fn candidate_ends_are_the_prefix_end_the_one_before_and_its_half() {
        assert_eq!(candidate_ends(1), [1]);
        assert_eq!(candidate_ends(2), [2, 1]);
        assert_eq!(candidate_ends(3), [3, 2, 1]);
        assert_eq!(candidate_ends(4), [4, 3, 2]);
        assert_eq!(candidate_ends(9), [9, 8, 4]);
    }
}
