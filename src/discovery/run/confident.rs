//! Keep pulling until confident (beyond the paper's Algorithm 1): the post-interaction
//! observation and PredArticulation, and while the estimate's uncertainty exceeds the
//! settings' limits, a further pull from the last contact, a new observation and a new
//! estimate. The rules are documented on [`discover`](crate::discovery::discover), step 6.

use nalgebra::{Isometry2, Point3, Vector2};

use crate::articulation::{Estimate, JointEstimate};
use crate::discovery::explore::{AttemptInput, attempt, checked_cloud};
use crate::discovery::interface::{HardwareFailure, LocalGoal, PointCloud};
use crate::discovery::log::{
    AttemptEnd, Doubt, EstimateLog, HandleLog, PullEnd, PullingLog, Stage,
};
use crate::discovery::placement::{FreeSpace, horizontal, plan_base};
use crate::discovery::settings::DiscoverySettings;

use super::pull::skipped;
use super::{Pulled, Run, Stop, fail};

impl Run<'_> {
    /// Steps 5 and 6 of [`discover`](crate::discovery::discover): step back from the handle
    /// at `p` (approach direction `dir`), observe, estimate; while the estimate has
    /// [`doubts`], the part is not at a limit and fewer than `max_extra_pulls` further pulls
    /// were made, pull further ([`Run::pull_further`]) and repeat. The loop's end is logged in
    /// `entry.pulling`. Returns the last estimate (unchecked) and its post-interaction
    /// observation.
    pub(super) fn estimate_until_confident(
        &mut self,
        entry: &mut HandleLog,
        index: usize,
        p: &Point3<f64>,
        dir: &Vector2<f64>,
        pulled: &mut Pulled,
        free: &FreeSpace,
    ) -> Result<(Estimate, PointCloud), Stop> {
        let s = self.s;
        // Why pulling must stop once the estimate is in (a failure of a further pull).
        let mut pending: Option<PullEnd> = None;
        // The last pull ended at the arm's limit (`JointLimit`): it cannot go on from that
        // base pose. A further pull starts from a new one, or pulling stops.
        let mut at_arm_limit = entry.attempts.last().is_some_and(|a| at_limit(&a.end));
        let mut extra_pulls = 0;
        // The most confident estimate so far: (round, estimate, doubts, shortfall).
        let mut best: Option<(usize, Estimate, Vec<Doubt>, f64)> = None;
        // The round of the last estimate.
        let mut last;
        loop {
            self.step_back(entry, p, dir, pulled.contact_post, free);
            let o_post = self.observe(
                Stage::Estimation,
                "post-interaction observation",
                "post-interaction",
            )?;
            let estimate = self.estimate(entry, index, pulled, &o_post)?;
            let doubts = doubts(&estimate, s);
            let short = shortfall(&estimate, s);
            last = extra_pulls;
            if best.as_ref().is_none_or(|b| short < b.3) {
                best = Some((extra_pulls, estimate, doubts.clone(), short));
            }
            let end = if doubts.is_empty() {
                Some(PullEnd::Confident)
            } else if pending.is_some() {
                pending.take()
            } else if extra_pulls >= s.max_extra_pulls {
                Some(out_of_pulls(at_arm_limit))
            } else {
                None
            };
            // Where the next pull starts: the last pull's base pose, or after the arm's limit
            // a new one in front of the last contact (none: pulling stops at the limit).
            let from = match end {
                Some(_) => None,
                None if at_arm_limit => self.past_arm_limit(entry, pulled, free),
                None => Some(pulled.base),
            };
            let Some(from) = from else {
                let end = end.unwrap_or(PullEnd::JointLimit);
                let kept = self.kept(entry, pulled, best, last, end, extra_pulls);
                return Ok((kept, o_post));
            };
            extra_pulls += 1;
            let (moved, end) = self.pull_further(entry, pulled, from)?;
            at_arm_limit = end.as_ref().is_some_and(at_limit);
            if !at_arm_limit {
                pending = end.map(|end| PullEnd::Failure { end });
            }
            if !moved {
                // Nothing new to estimate from: stop with the estimates so far (a pull that
                // could not start at a new base pose: the part's limit, or the arm's there
                // too).
                let end = pending.take().unwrap_or(out_of_pulls(at_arm_limit));
                let kept = self.kept(entry, pulled, best, last, end, extra_pulls);
                return Ok((kept, o_post));
            }
        }
    }

    /// The base pose a further pull starts from after the last pull stopped at the arm's
    /// limit (`JointLimit`: it cannot go on from that pose): PlanBase for the last contact,
    /// facing it along the last tracked normal at `interaction_distance`, as the first
    /// attempt's pose was placed for the handle. `None` (pulling stops at the limit) when
    /// [`DiscoverySettings::reposition_at_arm_limit`] is off, when no free pose is found, or
    /// when the pose found is the one the arm stopped at (within 1 cm and 1°).
    fn past_arm_limit(
        &self,
        entry: &mut HandleLog,
        pulled: &Pulled,
        free: &FreeSpace,
    ) -> Option<Isometry2<f64>> {
        let s = self.s;
        if !s.reposition_at_arm_limit {
            return None;
        }
        let c = pulled.contact_post;
        let toward = self.toward_robot(&c).ok()?;
        let dir = horizontal(&pulled.normal, &toward)?;
        let b = plan_base(free, &c, &dir, s.interaction_distance, s.base_search_radius)?;
        let moved = (b.translation.vector - pulled.base.translation.vector).norm();
        let turned = b.rotation.angle_to(&pulled.base.rotation).abs();
        if moved < 0.01 && turned < 1f64.to_radians() {
            return None;
        }
        entry.notes.push(format!(
            "the arm reached a limit with the estimate in doubt: pulling on from \
             ({:.2}, {:.2}, {:.0}°), in front of the last contact ({moved:.2} m and {:.0}° from \
             where it stopped)",
            b.translation.x,
            b.translation.y,
            b.rotation.angle().to_degrees(),
            turned.to_degrees()
        ));
        Some(b)
    }

    /// The estimate the loop ends with, logged in `entry`: the most confident one (`best`,
    /// never `None` once the loop ran), with its opening re-measured to the last contact
    /// ([`reopened`]) when it came from a round before the `last` (a further pull made the
    /// estimate worse — a view the estimator could not use — and the part moved on since).
    fn kept(
        &self,
        entry: &mut HandleLog,
        pulled: &Pulled,
        best: Option<(usize, Estimate, Vec<Doubt>, f64)>,
        last: usize,
        end: PullEnd,
        extra_pulls: usize,
    ) -> Estimate {
        let Some((round, mut estimate, doubts, _)) = best else {
            return Estimate::unknown("no estimate");
        };
        if round < last {
            reopened(&mut estimate, &pulled.contact_pre, &pulled.contact_post);
            entry.notes.push(format!(
                "kept the estimate after {round} further pull(s), more confident than the                  later ones; its opening re-measured to the last contact"
            ));
            entry.estimate = Some(EstimateLog::new(self.estimator.name(), &estimate));
        }
        entry.pulling = Some(PullingLog {
            end,
            extra_pulls,
            estimate_round: round,
            doubts,
        });
        estimate
    }

    /// One further pull from base pose `from` (the last successful attempt's, or a new one
    /// past the arm's limit): LocalNavTo there, a new pre-interaction observation
    /// (DetectFailure's reference), a grasp at the last contact along the last tracked
    /// normal, and pull steps until the contact is `extra_pull` from that grasp; then
    /// retract. The attempt is logged in `entry` and its poses appended to `pulled` (a new
    /// grasp segment); a pull that moved the part makes `from` the pose later pulls return
    /// to. Returns whether the part moved, and the attempt's end unless it succeeded (`None`:
    /// pulling may go on).
    fn pull_further(
        &mut self,
        entry: &mut HandleLog,
        pulled: &mut Pulled,
        from: Isometry2<f64>,
    ) -> Result<(bool, Option<AttemptEnd>), Stop> {
        let s = self.s;
        let goal = LocalGoal {
            target: pulled.contact_post,
            world_from_base: from,
        };
        if let Err(failure) = self.robot.navigate_local(&goal) {
            let end = AttemptEnd::Navigation { failure };
            entry.attempts.push(skipped(from, end.clone()));
            return Ok((false, Some(end)));
        }
        let o_pre = match self.robot.observe(s.observation_camera) {
            Ok(o) => o,
            Err(e) => {
                let end = AttemptEnd::Sensor {
                    reason: e.to_string(),
                };
                entry.attempts.push(skipped(from, end.clone()));
                return Ok((false, Some(end)));
            }
        };
        checked_cloud(&o_pre, "pre-interaction")?;
        let input = AttemptInput {
            o_pre: &o_pre,
            hotspot: pulled.contact_post,
            normal: pulled.normal,
            world_from_base: from,
            first_grasp: None,
            target: s.extra_pull,
        };
        let seg = pulled.ee_poses.len();
        let result = attempt(&mut *self.robot, s, &input, &mut pulled.ee_poses)?;
        if pulled.ee_poses.len() > seg {
            pulled.segments.push(seg);
        }
        let moved = result.log.steps > 0;
        if let Some(c) = result.contact {
            pulled.contact_post = c;
            entry.pull_distance = (c - pulled.contact_pre).norm();
        }
        pulled.normal = result.normal;
        let end = result.log.end.clone();
        entry.attempts.push(result.log);
        if let Err(f) = self.robot.retract() {
            return fail(Stage::Exploration, format!("retract: {f}"));
        }
        if moved {
            pulled.base = from;
        }
        Ok((moved, (!end.is_success() || at_limit(&end)).then_some(end)))
    }
}

/// How far `estimate` is from confident: the largest ratio of its 95 % axis half-angle and
/// pivot radius to their limits and of its type improbability `1 − p` to the allowed
/// `1 − confident_type_probability` (at most 1: confident on that count); ∞ without an
/// uncertainty. Lower is more confident.
pub(crate) fn shortfall(estimate: &Estimate, s: &DiscoverySettings) -> f64 {
    let Some(u) = &estimate.uncertainty else {
        return f64::INFINITY;
    };
    let ratio = |x: f64, limit: f64| {
        let r = x / limit;
        if r.is_nan() { f64::INFINITY } else { r }
    };
    let type_ratio = if u.type_probability >= s.confident_type_probability {
        0.0
    } else {
        ratio(1.0 - u.type_probability, 1.0 - s.confident_type_probability)
    };
    ratio(u.axis_half_angle_95(), s.confident_axis_95)
        .max(
            u.pivot_radius_95()
                .map_or(0.0, |r| ratio(r, s.confident_pivot_95)),
        )
        .max(type_ratio)
}

/// Sets the opening of `estimate` to the motion of the contact from `pre` to `post` about
/// (along) its axis: the signed angle between the contact's offsets from the axis (right-
/// handed about it), or the displacement's component along the axis.
pub(crate) fn reopened(estimate: &mut Estimate, pre: &Point3<f64>, post: &Point3<f64>) {
    match &mut estimate.joint {
        JointEstimate::Revolute { axis, pivot, angle } => {
            let off = |c: &Point3<f64>| {
                let d = c - *pivot;
                d - axis.into_inner() * axis.dot(&d)
            };
            let (a, b) = (off(pre), off(post));
            *angle = axis.dot(&a.cross(&b)).atan2(a.dot(&b));
        }
        JointEstimate::Prismatic { axis, distance } => *distance = axis.dot(&(post - pre)),
        JointEstimate::Unknown { .. } => {}
    }
}

/// How pulling ends with no failure to report: at the arm's limit if the last pull stopped
/// there, else on the budget of further pulls.
fn out_of_pulls(at_arm_limit: bool) -> PullEnd {
    if at_arm_limit {
        PullEnd::JointLimit
    } else {
        PullEnd::Budget
    }
}

/// Whether an attempt ended at the arm's limit (`JointLimit`: the motion cannot go on from
/// that base pose; a robot that reports the part's own limit so ends there too).
fn at_limit(end: &AttemptEnd) -> bool {
    matches!(
        end,
        AttemptEnd::Pull {
            failure: HardwareFailure::JointLimit
        } | AttemptEnd::SuccessAfter {
            failure: HardwareFailure::JointLimit
        }
    )
}

/// The confidence limits of `s` that `estimate` does not meet: its axis's 95 % half-angle
/// above `confident_axis_95`, its pivot's 95 % radius above `confident_pivot_95` (revolute),
/// its type probability below `confident_type_probability`; no uncertainty at all (an
/// unknown joint, a singular fit) is one doubt. Empty: confident.
pub(crate) fn doubts(estimate: &Estimate, s: &DiscoverySettings) -> Vec<Doubt> {
    let Some(u) = &estimate.uncertainty else {
        return vec![Doubt::NoUncertainty];
    };
    let mut out = Vec::new();
    let half_angle_95 = u.axis_half_angle_95();
    // A NaN counts as a doubt.
    let above = |x: f64, limit: f64| x.is_nan() || x > limit;
    if above(half_angle_95, s.confident_axis_95) {
        out.push(Doubt::Axis {
            half_angle_95,
            limit: s.confident_axis_95,
        });
    }
    if let Some(radius_95) = u.pivot_radius_95() {
        if above(radius_95, s.confident_pivot_95) {
            out.push(Doubt::Pivot {
                radius_95,
                limit: s.confident_pivot_95,
            });
        }
    }
    if u.type_probability.is_nan() || u.type_probability < s.confident_type_probability {
        out.push(Doubt::Type {
            probability: u.type_probability,
            limit: s.confident_type_probability,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix2, Unit, Vector3};

    use super::*;
    use crate::articulation::{CHI2_2DOF_95, PlaneCovariance, Uncertainty};

    /// A revolute estimate about z through the origin whose 95 % half-angle and pivot radius
    /// are `axis_deg` degrees and `pivot` metres (isotropic: σ = value / √5.99).
    fn revolute(axis_deg: f64, pivot: f64, p: f64) -> Estimate {
        let z = Vector3::z_axis();
        let basis = [Vector3::x_axis(), Vector3::y_axis()];
        let iso = |r: f64| PlaneCovariance {
            basis,
            covariance: Matrix2::identity() * (r * r / CHI2_2DOF_95),
        };
        Estimate {
            uncertainty: Some(Uncertainty {
                type_probability: p,
                axis: iso(axis_deg.to_radians()),
                pivot: Some(iso(pivot)),
            }),
            joint: JointEstimate::Revolute {
                axis: z,
                pivot: Point3::origin(),
                angle: 0.1,
            },
            ..Estimate::unknown("")
        }
    }

    /// Against the default limits (2°, 2 cm, 0.99): each limit that is exceeded is one doubt;
    /// the shortfall is the largest ratio (2.5° / 2° = 1.25; (1 − 0.95) / 0.01 = 5).
    #[test]
    fn doubts_and_shortfall() {
        let s = DiscoverySettings::default();
        let ok = revolute(1.5, 0.015, 0.999);
        assert!(doubts(&ok, &s).is_empty());
        assert!((shortfall(&ok, &s) - 0.75).abs() < 1e-9);
        let wide = revolute(2.5, 0.015, 0.999);
        assert!(matches!(doubts(&wide, &s)[..], [Doubt::Axis { .. }]));
        assert!((shortfall(&wide, &s) - 1.25).abs() < 1e-9);
        let all = revolute(2.5, 0.025, 0.95);
        assert_eq!(doubts(&all, &s).len(), 3);
        assert!((shortfall(&all, &s) - 5.0).abs() < 1e-6);
        let unknown = Estimate::unknown("too little motion");
        assert_eq!(doubts(&unknown, &s), vec![Doubt::NoUncertainty]);
        assert_eq!(shortfall(&unknown, &s), f64::INFINITY);
    }

    /// The opening re-measured from the contacts, by hand: about z through (1, 0, 0) the
    /// contact (1.5, 0, 0.4) turned by 60° is (1.25, 0.433, 0.7) (height is ignored); along
    /// x, a contact moved by (0.2, 0.05, 0) slid 0.2.
    #[test]
    fn reopened_from_the_contacts() {
        let mut e = revolute(1.0, 0.01, 0.999);
        if let JointEstimate::Revolute { pivot, .. } = &mut e.joint {
            *pivot = Point3::new(1.0, 0.0, 0.0);
        }
        let pre = Point3::new(1.5, 0.0, 0.4);
        let post = Point3::new(1.0 + 0.5 * 0.5, 0.5 * 3f64.sqrt() / 2.0, 0.7);
        reopened(&mut e, &pre, &post);
        let JointEstimate::Revolute { angle, .. } = e.joint else {
            unreachable!()
        };
        assert!((angle - 60f64.to_radians()).abs() < 1e-12, "{angle}");
        let mut slide = Estimate {
            joint: JointEstimate::Prismatic {
                axis: Unit::new_normalize(Vector3::x()),
                distance: 0.0,
            },
            ..Estimate::unknown("")
        };
        reopened(&mut slide, &pre, &(pre + Vector3::new(0.2, 0.05, 0.0)));
        let JointEstimate::Prismatic { distance, .. } = slide.joint else {
            unreachable!()
        };
        assert!((distance - 0.2).abs() < 1e-12);
    }
}
