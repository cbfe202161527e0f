//! Self-collision exemptions: which link pairs are never checked against each other, from an
//! SRDF or computed by sampling as setup tools do, and the SRDF that records them.

use std::sync::Arc;

use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::srdf::{DisabledPair, GroupState, Srdf, SrdfGroup};
use super::{RobotCollision, RobotConfig, RobotError, RobotModel};
use crate::InvalidSetting;

/// Why a link pair is exempt from self-collision checking.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PairReason {
    /// A link and the child link of its joint.
    Adjacent,
    /// Touching in at least [`PairSampling::always_fraction`] of the sampled configurations:
    /// the pair's geometry overlaps by construction, so checking it would forbid every motion.
    Always,
    /// Touching in none of the sampled configurations.
    Never,
    /// Touching at [`RobotModel::neutral`] (but not always).
    Default,
    /// Listed by an SRDF, with the reason it gives.
    Srdf(String),
}

impl std::fmt::Display for PairReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PairReason::Adjacent => f.write_str("Adjacent"),
            PairReason::Always => f.write_str("Always"),
            PairReason::Never => f.write_str("Never"),
            PairReason::Default => f.write_str("Default"),
            PairReason::Srdf(reason) if reason.is_empty() => f.write_str("User"),
            PairReason::Srdf(reason) => f.write_str(reason),
        }
    }
}

/// A link pair exempt from self-collision checking: indices into [`RobotModel::links`],
/// `link1 < link2`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AllowedPair {
    /// The first link.
    pub link1: usize,
    /// The second link.
    pub link2: usize,
    /// Why.
    pub reason: PairReason,
}

/// A link pair that is checked, but of which some collider pairs are exempt: each robot link
/// carries the colliders of several URDF links ([`RobotLink::merged`](super::RobotLink::merged),
/// through fixed and frozen joints), and an SRDF disables some of the URDF link pairs between
/// them but not all (on a mobile manipulator whose torso is frozen into the base, the arm's
/// first link and the torso, but not the arm's first link and the head).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExemptColliders {
    /// The first link (index into [`RobotModel::links`]).
    pub link1: usize,
    /// The second link, `link1 < link2`.
    pub link2: usize,
    /// The exempt collider pairs `(a, b)`: collider `a` of `link1` and collider `b` of
    /// `link2` (indices into their [`colliders`](super::RobotLink::colliders)), sorted.
    pub colliders: Vec<(usize, usize)>,
}

/// How [`RobotModel::with_sampled_pairs`] finds the exempt pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct PairSampling {
    /// Arm configurations drawn uniformly within the joint limits (continuous joints within
    /// ±π). Default 2000 (setup tools use 1 000 to 10 000).
    pub samples: usize,
    /// Seed of the ChaCha8 generator of the samples. Default 0.
    pub seed: u64,
    /// A pair touching in at least this fraction of the samples is [`PairReason::Always`].
    /// Default 0.95.
    pub always_fraction: f64,
    /// Exempt the pairs that never touched ([`PairReason::Never`]), as setup tools do: fewer
    /// pairs to check, at the risk of missing a collision in a configuration the samples did
    /// not come near. Default false: on the shipped Gen3, 10 pairs touch in none of 1 000
    /// samples, yet one of them touches in 2 of 1 000 fresh ones.
    pub disable_never: bool,
}

impl Default for PairSampling {
    fn default() -> Self {
        PairSampling {
            samples: 2000,
            seed: 0,
            always_fraction: 0.95,
            disable_never: false,
        }
    }
}

impl RobotModel {
    /// The self-collision exemptions, when the robot has them: from
    /// [`RobotModel::with_srdf`], [`RobotModel::with_sampled_pairs`] or
    /// [`RobotModel::with_allowed_pairs`]. `None` for a robot loaded from a URDF alone: its
    /// [`RobotCollision`] then guesses them from a single pose (adjacent links and the pairs
    /// touching at [`RobotModel::neutral`]).
    pub fn allowed_pairs(&self) -> Option<&[AllowedPair]> {
        self.allowed_pairs.as_deref()
    }

    /// The checked link pairs of which some collider pairs are exempt (from
    /// [`RobotModel::with_srdf`]: the colliders of URDF links whose pair the SRDF disables);
    /// [`RobotCollision`] skips those collider pairs. Empty without an SRDF.
    pub fn exempt_colliders(&self) -> &[ExemptColliders] {
        &self.exempt_colliders
    }

    /// This robot with these self-collision exemptions (every other pair of links with shapes
    /// is checked).
    ///
    /// # Errors
    /// [`RobotError::InvalidSetting`] for a link index out of range or a pair of a link with
    /// itself.
    pub fn with_allowed_pairs(mut self, pairs: Vec<AllowedPair>) -> Result<RobotModel, RobotError> {
        let n = self.links.len();
        let mut pairs = pairs;
        for p in &mut pairs {
            if p.link1 >= n || p.link2 >= n {
                return Err(InvalidSetting::new(
                    "allowed pair link index",
                    p.link1.max(p.link2) as f64,
                    format!("below {n}, the number of links"),
                )
                .into());
            }
            if p.link1 == p.link2 {
                return Err(InvalidSetting::new(
                    "allowed pair link index",
                    p.link1 as f64,
                    "different from the pair's other link",
                )
                .into());
            }
            if p.link1 > p.link2 {
                std::mem::swap(&mut p.link1, &mut p.link2);
            }
        }
        pairs.sort_by_key(|p| (p.link1, p.link2));
        pairs.dedup_by_key(|p| (p.link1, p.link2));
        self.allowed_pairs = Some(Arc::from(pairs));
        Ok(self)
    }

    /// This robot with what an SRDF says about it:
    /// - its `disable_collisions` pairs as the self-collision exemptions, never more than the
    ///   SRDF exempts: two robot links are exempt when every pair of the URDF links they carry
    ///   ([`RobotLink::merged`](super::RobotLink::merged), the links merged into them through
    ///   fixed and frozen joints) is disabled; when only some are, the pairs of their colliders
    ///   are exempt and the rest of the link pair is checked
    ///   ([`RobotModel::exempt_colliders`]); pairs naming a link with no collision elements
    ///   or not in the URDF are skipped (see [`RobotModel::srdf_unknown_links`]);
    /// - its stowed group state ([`RobotModel::srdf_stow`]) as [`RobotModel::neutral`]: the arm
    ///   joints it names take its values, the others keep theirs.
    ///
    /// # Errors
    /// [`RobotError::Srdf`] for a stow state value count that does not match its joint (arm
    /// joints have one coordinate); [`RobotModel::with_neutral`]'s errors for values outside
    /// the limits.
    pub fn with_srdf(self, srdf: &Srdf) -> Result<RobotModel, RobotError> {
        let disabled = |a: &str, b: &str| {
            srdf.disabled
                .iter()
                .find(|d| (d.link1 == a && d.link2 == b) || (d.link1 == b && d.link2 == a))
        };
        let mut pairs = Vec::new();
        let mut partial = Vec::new();
        for i in 0..self.links.len() {
            for j in i + 1..self.links.len() {
                let (x, y) = (&self.links[i].merged, &self.links[j].merged);
                if x.is_empty() || y.is_empty() {
                    continue;
                }
                let mut reason = None;
                let all = x.iter().all(|a| {
                    y.iter().all(|b| {
                        disabled(a, b)
                            .inspect(|d| {
                                reason.get_or_insert_with(|| d.reason.clone());
                            })
                            .is_some()
                    })
                });
                if all {
                    pairs.push(AllowedPair {
                        link1: i,
                        link2: j,
                        reason: PairReason::Srdf(reason.unwrap_or_default()),
                    });
                    continue;
                }
                // Some URDF link pairs disabled: their colliders' pairs.
                let (li, lj) = (&self.links[i], &self.links[j]);
                let mut colliders = Vec::new();
                for a in 0..li.colliders.len() {
                    for b in 0..lj.colliders.len() {
                        if let (Some(x), Some(y)) = (li.source(a), lj.source(b))
                            && disabled(x, y).is_some()
                        {
                            colliders.push((a, b));
                        }
                    }
                }
                if !colliders.is_empty() {
                    partial.push(ExemptColliders {
                        link1: i,
                        link2: j,
                        colliders,
                    });
                }
            }
        }
        let mut neutral = self.neutral.clone();
        if let Some(state) = self.srdf_stow(srdf) {
            for (joint, values) in &state.joints {
                let Some(k) = self.joints.iter().position(|j| &j.name == joint) else {
                    continue;
                };
                if values.len() != 1 {
                    return Err(RobotError::Srdf {
                        element: format!("<group_state name=\"{}\"> joint {joint:?}", state.name),
                        message: format!("{} values for a one-coordinate joint", values.len()),
                    });
                }
                neutral[k] = values[0];
            }
        }
        let mut robot = self.with_allowed_pairs(pairs)?.with_neutral(&neutral)?;
        robot.exempt_colliders = Arc::from(partial);
        Ok(robot)
    }

    /// The SRDF's group state this robot takes as its stow: [`Srdf::stow_state_for`] this
    /// robot's arm joints.
    pub fn srdf_stow<'s>(&self, srdf: &'s Srdf) -> Option<&'s GroupState> {
        let joints: Vec<&str> = self.joints.iter().map(|j| j.name.as_str()).collect();
        srdf.stow_state_for(&joints)
    }

    /// The link names an SRDF's `disable_collisions` pairs use that carry no collision
    /// elements in this model (sorted, without repeats): links without geometry, links of a
    /// subtree the model leaves out, or a mismatch between the SRDF and the URDF.
    pub fn srdf_unknown_links(&self, srdf: &Srdf) -> Vec<String> {
        let mut unknown: Vec<String> = srdf
            .disabled
            .iter()
            .flat_map(|d| [&d.link1, &d.link2])
            .filter(|name| !self.links.iter().any(|l| l.merged.contains(name)))
            .cloned()
            .collect();
        unknown.sort();
        unknown.dedup();
        unknown
    }

    /// This robot with exemptions computed as setup tools compute them: adjacent links; pairs
    /// touching at [`RobotModel::neutral`]; pairs touching in at least
    /// [`PairSampling::always_fraction`] of random arm configurations; and, only with
    /// [`PairSampling::disable_never`], pairs touching in none of them. Save them with
    /// [`RobotModel::to_srdf`].
    ///
    /// # Errors
    /// [`RobotError::InvalidSetting`] for no samples or a fraction outside (0, 1];
    /// [`RobotCollision::new`]'s errors.
    pub fn with_sampled_pairs(self, sampling: &PairSampling) -> Result<RobotModel, RobotError> {
        let pairs = self.sampled_pairs(sampling, true)?;
        self.with_allowed_pairs(pairs)
    }

    /// The exemptions of [`RobotModel::with_sampled_pairs`]; the pairs touching at the neutral
    /// configuration only if `at_neutral`.
    pub(super) fn sampled_pairs(
        &self,
        sampling: &PairSampling,
        at_neutral: bool,
    ) -> Result<Vec<AllowedPair>, RobotError> {
        if sampling.samples == 0 {
            return Err(InvalidSetting::new("pair sampling samples", 0.0, "at least 1").into());
        }
        if !(sampling.always_fraction > 0.0 && sampling.always_fraction <= 1.0) {
            return Err(InvalidSetting::new(
                "pair sampling always_fraction",
                sampling.always_fraction,
                "in (0, 1]",
            )
            .into());
        }
        // Every pair with shapes checked: the counts below see all of them.
        let all_checked = self.clone().with_allowed_pairs(Vec::new())?;
        let collision = RobotCollision::new(&all_checked)?;
        let n = self.links.len();
        let mut counts = vec![0usize; n * n];
        let mut rng = ChaCha8Rng::seed_from_u64(sampling.seed);
        let mut arm = DVector::zeros(self.dof());
        for _ in 0..sampling.samples {
            for (q, joint) in arm.iter_mut().zip(&self.joints) {
                let (lo, hi) = if joint.lower.is_finite() && joint.upper.is_finite() {
                    (joint.lower, joint.upper)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                };
                *q = if hi > lo {
                    rng.random_range(lo..=hi)
                } else {
                    lo
                };
            }
            let poses = self.link_poses(&RobotConfig {
                base: [0.0; 3],
                arm: arm.clone(),
            })?;
            for (i, j) in collision.touching_pairs(&poses) {
                counts[i * n + j] += 1;
            }
        }
        let neutral = self.link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: self.neutral.clone(),
        })?;
        let touching_at_neutral = if at_neutral {
            collision.touching_pairs(&neutral)
        } else {
            Vec::new()
        };
        let has_shapes: Vec<bool> = self.links.iter().map(|l| !l.colliders.is_empty()).collect();
        let mut pairs = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                if !has_shapes[i] || !has_shapes[j] {
                    continue;
                }
                let fraction = counts[i * n + j] as f64 / sampling.samples as f64;
                let reason = if j == i + 1 {
                    PairReason::Adjacent
                } else if touching_at_neutral.contains(&(i, j)) {
                    PairReason::Default
                } else if fraction >= sampling.always_fraction {
                    PairReason::Always
                } else if fraction == 0.0 && sampling.disable_never {
                    PairReason::Never
                } else {
                    continue;
                };
                pairs.push(AllowedPair {
                    link1: i,
                    link2: j,
                    reason,
                });
            }
        }
        Ok(pairs)
    }

    /// The robot's semantic description as an SRDF: a group `arm` (the chain from the base
    /// link to the last arm link), the group state `stow` ([`RobotModel::neutral`]) and the
    /// exemptions of [`RobotModel::allowed_pairs`], as every pair of the URDF links the two
    /// robot links carry ([`RobotLink::merged`](super::RobotLink::merged); none when the
    /// robot has no exemptions).
    pub fn to_srdf(&self) -> Srdf {
        let name = |i: usize| self.links[i].name.clone();
        Srdf {
            robot: self.name.clone(),
            groups: vec![SrdfGroup {
                name: "arm".into(),
                chain: Some((name(0), name(self.joints.len()))),
                ..SrdfGroup::default()
            }],
            group_states: vec![GroupState {
                name: "stow".into(),
                group: "arm".into(),
                joints: self
                    .joints
                    .iter()
                    .zip(self.neutral.iter())
                    .map(|(j, &q)| (j.name.clone(), vec![q]))
                    .collect(),
            }],
            // Every pair of the URDF links the two robot links carry, then the URDF link
            // pairs of the partly exempt link pairs.
            disabled: self
                .allowed_pairs()
                .unwrap_or_default()
                .iter()
                .flat_map(|p| {
                    let (x, y) = (&self.links[p.link1].merged, &self.links[p.link2].merged);
                    x.iter().flat_map(move |a| {
                        y.iter().map(move |b| DisabledPair {
                            link1: a.clone(),
                            link2: b.clone(),
                            reason: p.reason.to_string(),
                        })
                    })
                })
                .chain(
                    self.exempt_colliders
                        .iter()
                        .flat_map(|e| self.source_pairs(e)),
                )
                .collect(),
        }
    }

    /// The URDF link pairs the collider pairs of `e` come from, each once (in order of first
    /// appearance), as SRDF lines.
    fn source_pairs(&self, e: &ExemptColliders) -> Vec<DisabledPair> {
        let (li, lj) = (&self.links[e.link1], &self.links[e.link2]);
        let mut out: Vec<DisabledPair> = Vec::new();
        for &(a, b) in &e.colliders {
            let (Some(x), Some(y)) = (li.source(a), lj.source(b)) else {
                continue;
            };
            if !out.iter().any(|d| d.link1 == x && d.link2 == y) {
                out.push(DisabledPair {
                    link1: x.to_owned(),
                    link2: y.to_owned(),
                    reason: PairReason::Srdf(String::new()).to_string(),
                });
            }
        }
        out
    }
}
