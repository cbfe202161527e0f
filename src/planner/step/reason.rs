//! Why a step could not be refined, as data: the phase, the bodies by URDF name, the values.
//!
//! [`StepReason`] is what [`StepFailure::reason`](super::StepFailure::reason) holds; its
//! `Display` is the one-line text the documents and the CLI print.

use std::fmt;

use crate::motion::paths::{DifferentialFailure, PathFailure};
use crate::motion::placement::{Obstacle, PlacementOutcome, WaypointFailure};

/// A path of a step: which motion a planner or a re-check worked on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepPath {
    /// The base drive to the placement's base pose, arm stowed.
    Base,
    /// The free arm path from the stowed to the pre-grasp configuration.
    ArmToPregrasp,
    /// The straight line in along the handle's inward normal to the grasp.
    StraightIn,
    /// The arm following the handle while the part moves.
    Manipulation,
    /// The straight line out along the handle's normal.
    StraightOut,
    /// The free arm path from the post-grasp back to the stowed configuration.
    ArmToStow,
}

impl fmt::Display for StepPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StepPath::Base => "base",
            StepPath::ArmToPregrasp => "arm approach",
            StepPath::StraightIn => "straight approach along the handle's normal",
            StepPath::Manipulation => "manipulation",
            StepPath::StraightOut => "straight retreat along the handle's normal",
            StepPath::ArmToStow => "arm retreat",
        })
    }
}

/// What the dense re-check found at a configuration.
#[derive(Debug, Clone, PartialEq)]
pub enum Contact {
    /// The robot touches something (links and bodies by URDF name), within `margin` (m).
    Touches {
        /// What is touched.
        obstacle: Obstacle,
        /// The clearance required (m).
        margin: f64,
    },
    /// The configuration has no pose (outside the model's domain).
    NoPose,
    /// The re-check rejected the configuration but naming what it touches found nothing.
    Unnamed,
}

impl fmt::Display for Contact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Contact::Touches { obstacle, margin } => {
                write!(f, "{obstacle} (margin {:.0} mm)", 1000.0 * margin)
            }
            Contact::NoPose => f.write_str("the configuration has no pose"),
            Contact::Unnamed => f.write_str("no collision found"),
        }
    }
}

/// How far a base placement got: waypoints reached, the first failure, and the placement's
/// own note (why its optimised result was rejected, when it was).
#[derive(Debug, Clone, PartialEq)]
pub struct PlacementShortfall {
    /// Waypoints reached from the chosen base pose.
    pub reached: usize,
    /// Waypoints of the motion placed.
    pub waypoints: usize,
    /// The first waypoint not reached and why.
    pub first: Option<(usize, WaypointFailure)>,
    /// The placement's reason in its own words, when it gave one.
    pub note: Option<String>,
}

impl PlacementShortfall {
    /// The shortfall of `placed`.
    pub(crate) fn of(placed: &PlacementOutcome) -> Self {
        let first = placed
            .failures
            .iter()
            .enumerate()
            .find_map(|(i, f)| f.clone().map(|f| (i, f)));
        PlacementShortfall {
            reached: placed.reached.iter().filter(|r| **r).count(),
            waypoints: placed.reached.len(),
            first,
            note: placed.reason.clone(),
        }
    }
}

impl fmt::Display for PlacementShortfall {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(note) = &self.note {
            return f.write_str(note);
        }
        write!(
            f,
            "{} of {} waypoints reached",
            self.reached, self.waypoints
        )?;
        if let Some((i, why)) = &self.first {
            write!(f, "; first at waypoint {i}: {why}")?;
        }
        Ok(())
    }
}

/// One segment end tried when a step was split, and why it was not covered.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentTry {
    /// The joint value the segment was to end at.
    pub end: f64,
    /// Why no base pose covers it.
    pub why: SegmentMiss,
}

/// Why a tried segment was not covered.
#[derive(Debug, Clone, PartialEq)]
pub enum SegmentMiss {
    /// Its placement reached every waypoint, but the stowed robot does not fit at the base pose.
    BaseNotClear,
    /// Its placement fell short.
    Placement(PlacementShortfall),
}

/// Why splitting a step into segments found none covered from one base pose.
#[derive(Debug, Clone, PartialEq)]
pub enum SplitMiss {
    /// From no base pose does the arm follow the motion past its first waypoint.
    NoPrefix {
        /// The most waypoints reached in a row from the pre-grasp.
        reached: usize,
        /// The waypoints of the motion (approach included).
        waypoints: usize,
    },
    /// The longest reached prefix ends at waypoint `prefix_end` of `intervals`, and none of
    /// the segment ends tried is covered from one base pose.
    Uncovered {
        /// The last waypoint of the longest reached prefix.
        prefix_end: usize,
        /// Waypoint intervals of the handle trajectory.
        intervals: usize,
        /// The segment ends tried, longest first.
        tried: Vec<SegmentTry>,
    },
    /// The planner's termination stopped the split.
    Stopped,
}

impl fmt::Display for SplitMiss {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SplitMiss::NoPrefix { reached, waypoints } => write!(
                f,
                "from no base pose does the arm follow the motion past its first waypoint \
                 (the best reaches {reached} of {waypoints} waypoints in a row from the \
                 pre-grasp)"
            ),
            SplitMiss::Uncovered {
                prefix_end,
                intervals,
                tried,
            } => {
                write!(
                    f,
                    "the longest reached prefix ends at waypoint {prefix_end} of {intervals}, \
                     and no segment to "
                )?;
                for (k, t) in tried.iter().enumerate() {
                    if k > 0 {
                        f.write_str(", or to ")?;
                    }
                    match &t.why {
                        SegmentMiss::BaseNotClear => write!(
                            f,
                            "{:.4} (its base pose is not clear for the stowed robot)",
                            t.end
                        )?,
                        SegmentMiss::Placement(s) => write!(f, "{:.4} ({s})", t.end)?,
                    }
                }
                f.write_str(" is covered from one base pose")
            }
            SplitMiss::Stopped => f.write_str("stopped while choosing a segment"),
        }
    }
}

/// Why a step could not be refined: structured, with URDF names; `Display` renders one line.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq)]
pub enum StepReason {
    /// No base pose from which the arm reaches every waypoint of the step's handle motion.
    Placement(PlacementShortfall),
    /// A segmented step: `refined` segments took the joint to `up_to`, and no base pose covers
    /// the rest within `max_segments`.
    SegmentsExhausted {
        /// Segments refined.
        refined: usize,
        /// The joint's value where they ended.
        up_to: f64,
        /// The planner's [`max_segments`](crate::planner::PlannerSettings::max_segments).
        max_segments: usize,
        /// The placement of the rest.
        rest: PlacementShortfall,
    },
    /// No base pose covers the (rest of the) step, and no segment of it is covered either.
    NoSegment {
        /// The placement of the whole (rest of the) step.
        whole: PlacementShortfall,
        /// Why splitting it found no segment.
        split: SplitMiss,
    },
    /// The path planner returned no path.
    NoPath {
        /// Which path.
        path: StepPath,
        /// Why.
        failure: PathFailure,
    },
    /// The path's own start or goal configuration touches something, so no path can join
    /// them: what it touches.
    BlockedEnd {
        /// Which path.
        path: StepPath,
        /// The goal end (else the start).
        goal: bool,
        /// The configuration (a base pose x, y, yaw; or an arm configuration).
        at: Vec<f64>,
        /// What it touches.
        contact: Contact,
    },
    /// The path planner's budget ran out (or the planner was cancelled) before a path.
    PathStopped {
        /// Which path.
        path: StepPath,
        /// Cancelled rather than out of budget.
        cancelled: bool,
    },
    /// No SE(2) base path tried could be followed by turning in place and driving straight
    /// (a differential-drive base): why each failed.
    NoDifferentialPath {
        /// One failure per SE(2) path tried.
        failures: Vec<DifferentialFailure>,
    },
    /// The dense re-check of a returned path found a collision.
    Collision {
        /// Which path.
        path: StepPath,
        /// The segment of the path (between its configurations `segment` and `segment + 1`;
        /// for the manipulation, its waypoints).
        segment: usize,
        /// The configuration rejected (base: x, y, yaw; arm: joint values).
        at: Vec<f64>,
        /// The scene joint's value there (manipulation only).
        scene_joint: Option<f64>,
        /// What the robot touches there.
        contact: Contact,
    },
    /// Neither way of executing a step that no single base pose covers refined: the base
    /// moving along with the arm ([`PlannerSettings::whole_body`]) and the fixed-base
    /// manipulation (in segments, up to `max_segments`).
    ///
    /// [`PlannerSettings::whole_body`]: crate::planner::PlannerSettings::whole_body
    WholeBodyMissed {
        /// Why the whole-body execution failed, in one line.
        whole_body: String,
        /// Why the fixed-base execution failed.
        fixed: Box<StepReason>,
    },
    /// The planner's termination stopped the step.
    Stopped {
        /// Where: "before the step began", "after base placement", ….
        when: &'static str,
    },
}

impl fmt::Display for StepReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StepReason::Placement(s) => write!(f, "{s}"),
            StepReason::SegmentsExhausted {
                refined,
                up_to,
                max_segments,
                rest,
            } => write!(
                f,
                "{refined} segment(s) refined up to {up_to:.4}, and no base pose covers the \
                 rest within max_segments = {max_segments}: {rest}"
            ),
            StepReason::NoSegment { whole, split } => write!(f, "{whole}; segmenting: {split}"),
            StepReason::NoPath { path, failure } => write!(f, "no {path} path: {failure}"),
            StepReason::BlockedEnd {
                path,
                goal,
                at,
                contact,
            } => {
                let end = if *goal { "goal" } else { "start" };
                write!(f, "no {path} path: its {end}")?;
                if *path == StepPath::Base && at.len() == 3 {
                    write!(f, " ({:.3}, {:.3}, {:.3})", at[0], at[1], at[2])?;
                }
                write!(f, " touches: {contact}")
            }
            StepReason::PathStopped {
                path,
                cancelled: false,
            } => write!(f, "no {path} path within the budget"),
            StepReason::PathStopped {
                path,
                cancelled: true,
            } => write!(f, "{path} path: cancelled"),
            StepReason::NoDifferentialPath { failures } => {
                f.write_str("differential drive: ")?;
                for (k, why) in failures.iter().enumerate() {
                    if k > 0 {
                        f.write_str("; ")?;
                    }
                    write!(f, "SE(2) path {}: {why}", k + 1)?;
                }
                Ok(())
            }
            StepReason::Collision {
                path,
                segment,
                at,
                scene_joint,
                contact,
            } => {
                write!(f, "dense re-check: segment {segment} of the {path}")?;
                if *path == StepPath::Base && at.len() == 3 {
                    write!(f, " at ({:.3}, {:.3}, {:.3})", at[0], at[1], at[2])?;
                }
                if let Some(v) = scene_joint {
                    write!(f, " (scene joint at {v:.4})")?;
                }
                write!(f, ": {contact}")
            }
            StepReason::WholeBodyMissed { whole_body, fixed } => {
                write!(f, "{fixed}; with the base moving: {whole_body}")
            }
            StepReason::Stopped { when } => f.write_str(when),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::BaseShapeId;
    use crate::scene::collision::{Body, BodyName};

    /// The texts are the one-line reasons the documents carried before the reasons were data;
    /// written out by hand here from the formats.
    #[test]
    fn reasons_render_to_one_line_with_urdf_names() {
        let touch = Contact::Touches {
            obstacle: Obstacle::Scene {
                link: 5,
                body: Body::Base(BaseShapeId(3)),
                link_name: "wrist".into(),
                body_name: BodyName::Base("counter".into()),
            },
            margin: 0.02,
        };
        let base = StepReason::Collision {
            path: StepPath::Base,
            segment: 4,
            at: vec![1.0, -2.5, 0.125],
            scene_joint: None,
            contact: touch.clone(),
        };
        assert_eq!(
            base.to_string(),
            format!("dense re-check: segment 4 of the base at (1.000, -2.500, 0.125): {touch}")
        );
        assert!(touch.to_string().contains("\"wrist\"") && touch.to_string().contains("20 mm"));
        // A path whose own end touches something names it, with the base pose.
        let blocked = StepReason::BlockedEnd {
            path: StepPath::Base,
            goal: false,
            at: vec![1.0, -2.5, 0.125],
            contact: touch.clone(),
        };
        assert_eq!(
            blocked.to_string(),
            format!("no base path: its start (1.000, -2.500, 0.125) touches: {touch}")
        );
        let manip = StepReason::Collision {
            path: StepPath::Manipulation,
            segment: 2,
            at: vec![0.0; 7],
            scene_joint: Some(0.5),
            contact: Contact::Unnamed,
        };
        assert_eq!(
            manip.to_string(),
            "dense re-check: segment 2 of the manipulation (scene joint at 0.5000): no collision found"
        );
        let short = PlacementShortfall {
            reached: 3,
            waypoints: 11,
            first: Some((
                3,
                WaypointFailure::OutOfReach {
                    distance: 1.5,
                    reach: 1.25,
                },
            )),
            note: None,
        };
        let exhausted = StepReason::SegmentsExhausted {
            refined: 2,
            up_to: 0.75,
            max_segments: 3,
            rest: short.clone(),
        };
        assert_eq!(
            exhausted.to_string(),
            "2 segment(s) refined up to 0.7500, and no base pose covers the rest within \
             max_segments = 3: 3 of 11 waypoints reached; first at waypoint 3: out of reach \
             (1.500 m from the first arm joint, reach 1.250 m)"
        );
        let split = StepReason::NoSegment {
            whole: short,
            split: SplitMiss::Uncovered {
                prefix_end: 4,
                intervals: 10,
                tried: vec![
                    SegmentTry {
                        end: 0.4,
                        why: SegmentMiss::BaseNotClear,
                    },
                    SegmentTry {
                        end: 0.2,
                        why: SegmentMiss::BaseNotClear,
                    },
                ],
            },
        };
        let text = split.to_string();
        assert!(
            text.ends_with(
                "segmenting: the longest reached prefix ends at waypoint 4 of 10, and no \
                 segment to 0.4000 (its base pose is not clear for the stowed robot), or to \
                 0.2000 (its base pose is not clear for the stowed robot) is covered from one \
                 base pose"
            ),
            "{text}"
        );
    }
}
