//! Whole-body manipulation of a step that no single base pose covers: the base moves along
//! with the arm during the manipulation ([`plan_whole_body`]), as the alternative to segments,
//! and the choice between the two by execution time (the rule is in the
//! [planner's docs](crate::planner#whole-body-manipulation)).

use std::collections::BTreeSet;

use super::refine::{Placed, StepRefinement};
use super::segment::{Segments, longest_prefix};
use super::{Check, Compared, Failed, StepMotion, StepReason, same_pose};
use crate::motion::placement::{
    JointMotion, PlacementOutcome, WholeBodyOutcome, WholeBodyPlan, WholeBodySettings,
    WholeBodyStart, plan_whole_body_from_starts,
};
use crate::planner::PlannerError;
use crate::scene::{PartId, State};

impl Placed {
    /// The configurations and base poses of the whole-body `plan` along `motion`; `Err` when
    /// the base moves during the straight approach or the straight retreat (the approach and
    /// the retreat run at one base pose each).
    pub(super) fn whole_body(plan: &WholeBodyPlan, motion: &JointMotion) -> Result<Placed, String> {
        let trajectory = motion.trajectory();
        let (grasp_at, release_at) = (*trajectory.start(), *trajectory.end());
        let bases = &plan.bases;
        if bases.len() != motion.len() || plan.arm.len() != motion.len() {
            return Err(format!(
                "the whole-body plan has {} waypoints, the motion {}",
                bases.len(),
                motion.len()
            ));
        }
        if bases[..=grasp_at].windows(2).any(|w| w[0] != w[1]) {
            return Err("the base moves during the straight approach".into());
        }
        if bases[release_at..].windows(2).any(|w| w[0] != w[1]) {
            return Err("the base moves during the straight retreat".into());
        }
        Ok(Placed {
            base: bases[0],
            all: plan.arm.iter().map(|q| q.as_slice().to_vec()).collect(),
            grasp_at,
            release_at,
            bases: Some(bases.clone()),
        })
    }
}

impl Segments<'_, '_> {
    /// The whole step executed with the base moving along with the arm, from `state` with the
    /// base at `base`, when the placement of the step (kept for the segments) does not cover
    /// it: `None` when it does, else the motion or why there is none. The whole-body plan
    /// starts, in order, at the base poses and first configurations of the
    /// [`WholeBodySettings::starts`] best samples of the longest-prefix placement (where the arm
    /// follows the handle furthest from one base pose; the best is kept for the segments too)
    /// and of the placement itself, those that reach the first waypoint, the first
    /// [`WholeBodySettings::starts`] of them, each with [`WholeBodySettings::arm_seeds`] arm
    /// seeds ([`plan_whole_body_from_starts`]); the first that tracks is kept.
    pub(super) fn whole_body(
        &mut self,
        settings: &WholeBodySettings,
        handle_name: &str,
        state: &State,
        base: [f64; 3],
    ) -> Result<Option<Result<StepMotion, WholeBodyMiss>>, PlannerError> {
        let ctx = self.ctx;
        let r = StepRefinement::new(
            ctx, self.index, self.step, self.step, None, self.joint, state,
        )?;
        let whole = r.placement(self.handle, base, &ctx.settings.placement)?;
        self.causes.extend(whole.obstacle_parts.iter().copied());
        if whole.is_complete() {
            self.first_whole = Some(whole);
            return Ok(None);
        }
        let prefix = longest_prefix(&r, self.handle, base, settings.starts)?;
        self.causes.extend(prefix.obstacle_parts.iter().copied());
        let starts = starts(&prefix, &whole, settings.starts);
        let mut why = Vec::new();
        if starts.is_empty() {
            why.push("whole-body: the arm reaches the first waypoint from no start".to_owned());
        }
        // What the attempts depend on beyond the placements' parts.
        let mut met = BTreeSet::new();
        let mut tracked = None;
        for start in &starts {
            match self.track(&r, &prefix.motion, start, settings, &mut met)? {
                Ok(placed) => {
                    tracked = Some(placed);
                    break;
                }
                Err(e) => why.push(e),
            }
            if ctx.termination.should_stop() {
                break;
            }
        }
        self.first_whole = Some(whole);
        self.first_prefix = Some(prefix);
        let mut causes = self.causes.clone();
        causes.extend(met);
        let Some(placed) = tracked else {
            return Ok(Some(Err(WholeBodyMiss {
                reason: why.join("; "),
                causes: Some(causes),
            })));
        };
        if !r.base_reachable(&placed.base) {
            return Ok(Some(Err(WholeBodyMiss {
                reason: "its first base pose is not clear for the stowed robot".into(),
                causes: None,
            })));
        }
        Ok(Some(match r.execute(handle_name, &placed, base)? {
            Ok(motion) => Ok(motion),
            Err((f, more)) => Err(WholeBodyMiss {
                reason: format!("{} failed: {}", f.check, f.reason),
                causes: more.map(|more| {
                    causes.extend(more);
                    causes
                }),
            }),
        }))
    }

    /// The whole-body plan of `r`'s step along `motion` from `start` (its arm seeds as
    /// [`plan_whole_body_from_starts`] draws them), as a placement, or why there is none
    /// (every attempt's furthest waypoint and failure).
    fn track(
        &self,
        r: &StepRefinement<'_, '_>,
        motion: &JointMotion,
        start: &WholeBodyStart,
        settings: &WholeBodySettings,
        met: &mut BTreeSet<PartId>,
    ) -> Result<Result<Placed, String>, PlannerError> {
        let placement = &self.ctx.settings.placement;
        let attempts = plan_whole_body_from_starts(
            r.problem(),
            motion,
            std::slice::from_ref(start),
            placement.grasp,
            &placement.manipulation,
            settings,
            self.ctx.termination,
        )?;
        let mut why = Vec::new();
        for attempt in &attempts {
            met.extend(attempt.outcome.obstacles());
            if let WholeBodyOutcome::Tracked(plan) = &attempt.outcome {
                let b = attempt.base;
                return Ok(Placed::whole_body(plan, motion).map_err(|e| {
                    format!(
                        "from ({:.3}, {:.3}, {:.3}) arm seed {}: {e}",
                        b[0], b[1], b[2], attempt.arm_seed
                    )
                }));
            }
            why.push(attempt.summary());
        }
        if why.is_empty() {
            why.push("whole-body: stopped before any attempt".to_owned());
        }
        Ok(Err(why.join("; ")))
    }
}

/// The starts of a step's whole-body plan: the base poses and first configurations of the
/// longest-prefix placement's ranked samples, then of the placement `whole` (unless at one
/// of those poses), those that reach the first waypoint, at most `count`.
fn starts(
    prefix: &PlacementOutcome,
    whole: &PlacementOutcome,
    count: usize,
) -> Vec<WholeBodyStart> {
    let mut out: Vec<WholeBodyStart> = Vec::with_capacity(count);
    let ranked = prefix
        .ranked
        .iter()
        .filter(|p| p.reached_prefix() > 0)
        .map(|p| (p.base, &p.arm[0]));
    let whole = (whole.reached_prefix() > 0).then(|| (whole.base, &whole.arm[0]));
    for (base, seed) in ranked.chain(whole) {
        if out.len() < count && !out.iter().any(|s| same_pose(&s.base, &base)) {
            out.push(WholeBodyStart {
                base,
                seed: seed.clone(),
            });
        }
    }
    out
}

/// Why the whole-body alternative did not refine a step.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct WholeBodyMiss {
    /// The attempts' failures, or the one of the motion around the tracked plan.
    pub(super) reason: String,
    /// The parts whose values the miss depends on (the placements' and the attempts'
    /// obstacles); `None` when unknown (every joint may matter).
    pub(super) causes: Option<BTreeSet<PartId>>,
}

/// The step's motion from the segmented refinement `segmented` and the whole-body attempt
/// `whole_body` (`None`: not made): the one that refined, or with both the one with the
/// shorter execution time (the segments on a tie), the two times recorded on every entry.
/// When neither refined, the segmented failure, its reason joined with the whole-body one,
/// and the causes of both (unknown when either's are); a stopped refinement stays stopped.
pub(super) fn choose(
    segmented: Result<Vec<StepMotion>, Failed>,
    whole_body: Option<Result<StepMotion, WholeBodyMiss>>,
) -> Result<Vec<StepMotion>, Box<Failed>> {
    match (segmented, whole_body) {
        (segmented, None) => segmented.map_err(Box::new),
        (Ok(segments), Some(Err(_))) => Ok(segments),
        (Err(_), Some(Ok(motion))) => Ok(vec![motion]),
        (Ok(segments), Some(Ok(motion))) => {
            let compared = Compared {
                segments: segments.iter().map(|s| s.timing.total()).sum(),
                whole_body: motion.timing.total(),
            };
            let mut chosen = if compared.whole_body < compared.segments {
                vec![motion]
            } else {
                segments
            };
            for m in &mut chosen {
                m.compared = Some(compared);
            }
            Ok(chosen)
        }
        (Err(failed), Some(Err(_))) if failed.0.check == Check::Stopped => Err(Box::new(failed)),
        (Err((mut failure, causes)), Some(Err(miss))) => {
            failure.reason = StepReason::WholeBodyMissed {
                whole_body: miss.reason,
                fixed: Box::new(failure.reason),
            };
            let causes = causes.zip(miss.causes).map(|(mut parts, more)| {
                parts.extend(more);
                parts.sort_unstable();
                parts.dedup();
                parts
            });
            Err(Box::new((failure, causes)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::timing::time_parameterise;
    use crate::planner::{StepFailure, StepMode, StepTiming};

    /// A motion whose phases take `seconds` in all (its manipulation a 1-D path timed to
    /// last that long: `seconds²/4` rad at 1 rad/s², a triangle profile).
    fn motion(mode: StepMode, seconds: f64, from: f64, to: f64) -> StepMotion {
        let d = seconds * seconds / 4.0;
        let path = time_parameterise(&[vec![0.0], vec![d]], &[1e3], &[1.0], None).unwrap();
        assert!((path.duration - seconds).abs() < 1e-9);
        StepMotion {
            joint: "door_hinge".into(),
            from,
            to,
            handle: "door_handle".into(),
            base: [0.0; 3],
            base_path: path.clone(),
            approach: path.clone(),
            pregrasp: 0,
            manipulation: path.clone(),
            manipulation_base: None,
            retreat: path,
            postgrasp: 0,
            timing: StepTiming {
                manipulation: seconds,
                ..StepTiming::default()
            },
            mode,
            compared: None,
        }
    }

    fn failed() -> Failed {
        let failure = StepFailure {
            step: 0,
            joint: "door_hinge".into(),
            from: 0.0,
            to: 1.5,
            check: Check::Placement,
            reason: StepReason::Stopped { when: "placement" },
            segment: None,
        };
        (failure, Some(Vec::new()))
    }

    #[test]
    fn the_faster_alternative_is_kept_and_both_times_are_recorded() {
        // Two segments of 3 s and 4 s (7 s) against a whole-body motion of 6 s: whole-body.
        let segments = || {
            vec![
                motion(StepMode::Segment, 3.0, 0.0, 0.7),
                motion(StepMode::Segment, 4.0, 0.7, 1.5),
            ]
        };
        let chosen = choose(
            Ok(segments()),
            Some(Ok(motion(StepMode::WholeBody, 6.0, 0.0, 1.5))),
        )
        .unwrap();
        assert_eq!(chosen.len(), 1);
        assert_eq!(chosen[0].mode, StepMode::WholeBody);
        let compared = chosen[0].compared.unwrap();
        assert!((compared.segments - 7.0).abs() < 1e-9 && (compared.whole_body - 6.0).abs() < 1e-9);
        // A whole-body motion of 8 s loses to the 7 s of segments, recorded on both entries.
        let chosen = choose(
            Ok(segments()),
            Some(Ok(motion(StepMode::WholeBody, 8.0, 0.0, 1.5))),
        )
        .unwrap();
        assert_eq!(chosen.len(), 2);
        assert!(chosen.iter().all(|m| {
            m.mode == StepMode::Segment
                && m.compared
                    .is_some_and(|c| (c.whole_body - 8.0).abs() < 1e-9)
        }));
        // Only one refined: that one, nothing compared.
        let only = choose(
            Err(failed()),
            Some(Ok(motion(StepMode::WholeBody, 8.0, 0.0, 1.5))),
        );
        assert!(only.unwrap()[0].compared.is_none());
        let only = choose(Ok(segments()), Some(Err(miss("no", None)))).unwrap();
        assert!(only.len() == 2 && only[0].compared.is_none());
    }

    fn miss(reason: &str, causes: Option<&[usize]>) -> WholeBodyMiss {
        WholeBodyMiss {
            reason: reason.into(),
            causes: causes.map(|c| c.iter().map(|&i| PartId(i)).collect()),
        }
    }

    #[test]
    fn when_neither_refines_both_reasons_and_causes_are_kept() {
        let failed_at = |parts: &[usize]| {
            let (failure, _) = failed();
            (failure, Some(parts.iter().map(|&i| PartId(i)).collect()))
        };
        let (failure, causes) = *choose(
            Err(failed_at(&[3, 1])),
            Some(Err(miss("waypoint 9", Some(&[2, 3])))),
        )
        .unwrap_err();
        assert_eq!(failure.check, Check::Placement);
        assert_eq!(
            failure.reason.to_string(),
            "placement; with the base moving: waypoint 9"
        );
        // The union, sorted without repeats.
        let ids =
            |c: Option<Vec<PartId>>| c.map(|c| c.iter().map(|p| p.index()).collect::<Vec<_>>());
        assert_eq!(ids(causes), Some(vec![1, 2, 3]));
        // Unknown on either side: unknown.
        let (_, causes) = *choose(Err(failed_at(&[1])), Some(Err(miss("no", None)))).unwrap_err();
        assert!(causes.is_none());
        let (failure, _) = failed();
        let (_, causes) =
            *choose(Err((failure, None)), Some(Err(miss("no", Some(&[]))))).unwrap_err();
        assert!(causes.is_none());
        // Without a whole-body attempt, the segmented failure as it is.
        let (_, causes) = *choose(Err(failed()), None).unwrap_err();
        assert!(causes.is_some());
    }
}
