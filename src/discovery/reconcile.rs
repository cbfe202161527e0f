//! Reconciling an estimated model with what the robot saw happen without a collision.
//!
//! Registration boxes each part around its observed points. Depth noise and a few points of a
//! neighbouring front make a box reach a centimetre or two past the true surface, while
//! kitchen fronts are 3–6 mm apart, so neighbouring estimated boxes can overlap where the
//! real parts did not touch: at the closed state the mapping saw, or along a motion the robot
//! executed (a door's hinge edge swinging into the drawer front next to it). The task layer
//! then finds every move of those parts colliding.
//!
//! What the robot saw is evidence: a state it saw, and a single-joint motion it executed, were
//! collision-free. [`reconcile`] makes the model agree with each [`Observation`] by moving box
//! faces inward, conflict by conflict: the faces of the newest part first (when it is in the
//! conflict; the parts before it already agreed), else of the other body (a part's only, for
//! a part–base conflict), the cut (of [`CUTS`]) that resolves it removing the least volume — one
//! face, or in a state two faces of one box. The other faces keep their extent, so a box is
//! never shrunk on a side where nothing conflicts (shrinking every side took 2 cm off the
//! kitchen's dishwasher door next to the sink door's handle, and the real arm then touched
//! the real door).
//!
//! Cuts only shrink boxes, so an observation made consistent stays consistent while later
//! ones are reconciled. A conflict that no cut of at most the largest of [`CUTS`] resolves
//! is reported, not forced.

use nalgebra::{Translation3, Vector3};
use serde::{Deserialize, Serialize};

use super::error::DiscoveryError;
use crate::scene::collision::BodyName;
use crate::scene::collision::{
    Body, SweepSettings, SweepStatus, check_joint_motion, collisions, collisions_of,
};
use crate::scene::{JointId, PartId, SceneData, SceneModel, Shape, State, forward_kinematics};

/// Face cuts tried (m), smallest first.
pub const CUTS: [f64; 8] = [0.003, 0.006, 0.01, 0.015, 0.02, 0.03, 0.05, 0.08];
/// The smallest half extent (m) a cut box keeps.
const MIN_HALF_EXTENT: f64 = 0.005;
/// Conflicts resolved at most per observation (each round resolves one).
const MAX_ROUNDS: usize = 40;

/// Something the robot saw happen without a collision.
#[derive(Debug, Clone, PartialEq)]
pub enum Observation {
    /// The scene stood in this state (the mapping saw it closed; a task's start state).
    State(State),
    /// Joint `joint` moved from `from` to `to` (clamped into its limits), every other joint
    /// as in `state`.
    Motion {
        /// The other joints' values.
        state: State,
        /// The joint that moved.
        joint: JointId,
        /// Its value before (rad or m).
        from: f64,
        /// Its value after (rad or m).
        to: f64,
    },
}

/// One box face moved inward by [`reconcile`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoxCut {
    /// The part whose box was cut.
    pub part: String,
    /// Index of the box among the part's colliders.
    pub collider: usize,
    /// The face: box axis (0, 1, 2 for the box frame's x, y, z) and side (+1 or −1).
    pub axis: usize,
    /// `+1.0` for the face at `+half_extent`, `−1.0` for the opposite one.
    pub side: f64,
    /// How far the face moved in (m).
    pub depth: f64,
    /// The body the cut separates it from.
    pub other: BodyName,
    /// Index of the observation that required it.
    pub observation: usize,
}

/// A conflict no cut resolved: bodies `a` and `b` touch in observation `observation`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Conflict {
    /// Index of the observation.
    pub observation: usize,
    /// One body (a part).
    pub a: BodyName,
    /// The other body.
    pub b: BodyName,
}

/// What [`reconcile`] changed and what it could not resolve.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Reconciliation {
    /// The face cuts, in the order made.
    pub cuts: Vec<BoxCut>,
    /// The conflicts left.
    pub unresolved: Vec<Conflict>,
}

/// `model` with its boxes cut back until every observation is collision-free in it (see the
/// module documentation): a [`Observation::State`] has no colliding pair under
/// `sweep.collision`; a [`Observation::Motion`] is certified [`SweepStatus::Free`] by
/// [`check_joint_motion`] with `sweep` (an inconclusive sweep counts as a conflict with the
/// nearest pair, so a box left within the sweep's resolution of its neighbour is cut back
/// too). Observations are reconciled in order. Non-box colliders are never cut.
///
/// `newest` is the part to cut first: the one just registered, when the others already agreed
/// with what the robot saw (their boxes then stay as they were whenever cutting the newest
/// one resolves the conflict; otherwise the other body's least-volume cut is taken).
///
/// # Errors
/// [`DiscoveryError::Scene`] if the settings are invalid, an observation's state does not fit
/// `model`, or a cut model cannot be built (it is the input's tree with smaller boxes, so only
/// an invalid input fails).
pub fn reconcile(
    model: &SceneModel,
    observations: &[Observation],
    sweep: &SweepSettings,
    newest: Option<PartId>,
) -> Result<(SceneModel, Reconciliation), DiscoveryError> {
    sweep.validate()?;
    let mut model = model.clone();
    let mut out = Reconciliation::default();
    for (index, observation) in observations.iter().enumerate() {
        let observation = clamped(&model, observation);
        let mut stuck: Vec<(Body, Body)> = Vec::new();
        for _ in 0..MAX_ROUNDS {
            let Some((a, b)) = offender(&model, &observation, sweep, &stuck)? else {
                break;
            };
            // The newest part's faces first; if none of its cuts resolves the conflict, the
            // other body's (never the newest's candidates twice).
            let parts: Vec<PartId> = [a, b]
                .into_iter()
                .filter_map(|body| match body {
                    Body::Part(p) => Some(p),
                    Body::Base(_) => None,
                })
                .collect();
            let (first, rest): (Vec<PartId>, Vec<PartId>) =
                parts.into_iter().partition(|p| Some(*p) == newest);
            let cut = match best_cut(&model, &observation, sweep, a, b, &first)? {
                Some(c) => Some(c),
                None => best_cut(&model, &observation, sweep, a, b, &rest)?,
            };
            match cut {
                Some((cuts, cut_model)) => {
                    for cut in cuts {
                        let other = if Body::Part(cut.part) == a { b } else { a };
                        out.cuts.push(BoxCut {
                            part: model
                                .part(cut.part)
                                .map_or_else(String::new, |p| p.name().to_string()),
                            collider: cut.collider,
                            axis: cut.axis,
                            side: cut.side,
                            depth: cut.depth,
                            other: BodyName::of(&model, other),
                            observation: index,
                        });
                    }
                    model = cut_model;
                }
                None => stuck.push((a, b)),
            }
        }
        out.unresolved
            .extend(stuck.into_iter().map(|(a, b)| Conflict {
                observation: index,
                a: BodyName::of(&model, a),
                b: BodyName::of(&model, b),
            }));
    }
    Ok((model, out))
}

/// The observation with a motion's ends clamped into the joint's limits.
fn clamped(model: &SceneModel, observation: &Observation) -> Observation {
    match observation {
        Observation::Motion {
            state,
            joint,
            from,
            to,
        } => {
            let clamp = |v: f64| {
                model
                    .joint(*joint)
                    .map_or(v, |j| v.clamp(j.limits.lower, j.limits.upper))
            };
            Observation::Motion {
                state: state.clone(),
                joint: *joint,
                from: clamp(*from),
                to: clamp(*to),
            }
        }
        other => other.clone(),
    }
}

/// The body pairs in conflict in `observation`, nearest (or first along the motion) first.
fn conflicts(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
) -> Result<Vec<(Body, Body)>, DiscoveryError> {
    let mut data = SceneData::new(model);
    let contacts = match observation {
        Observation::State(state) => {
            forward_kinematics(model, &mut data, state)?;
            collisions(model, &data, &sweep.collision)?
        }
        Observation::Motion {
            state,
            joint,
            from,
            to,
        } => {
            let outcome = check_joint_motion(model, &mut data, state, *joint, *from, *to, sweep)?;
            match outcome.status {
                SweepStatus::Free => Vec::new(),
                SweepStatus::Collision { contacts, .. } => contacts,
                SweepStatus::Inconclusive { nearest, .. } => nearest,
            }
        }
    };
    Ok(contacts.into_iter().map(|c| (c.a, c.b)).collect())
}

/// The first conflicting pair of `observation` not in `stuck`.
fn offender(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
    stuck: &[(Body, Body)],
) -> Result<Option<(Body, Body)>, DiscoveryError> {
    Ok(conflicts(model, observation, sweep)?
        .into_iter()
        .find(|p| !stuck.contains(p)))
}

/// Whether the pair `(a, b)` still conflicts in `observation`.
fn still_conflicting(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
    a: Body,
    b: Body,
) -> Result<bool, DiscoveryError> {
    if let (Observation::State(state), Body::Part(p)) = (observation, a) {
        // The pair is one of `a`'s: checking `a`'s pairs is enough.
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, state)?;
        let contacts = collisions_of(model, &data, &sweep.collision, p)?;
        return Ok(contacts
            .iter()
            .any(|c| (c.a, c.b) == (a, b) || (c.a, c.b) == (b, a)));
    }
    Ok(conflicts(model, observation, sweep)?
        .iter()
        .any(|&p| p == (a, b) || p == (b, a)))
}

/// One face cut: part, collider index, box axis, side (+1 or −1), depth (m).
#[derive(Debug, Clone, Copy)]
struct Cut {
    part: PartId,
    collider: usize,
    axis: usize,
    side: f64,
    depth: f64,
}

/// `model` with `cuts` applied: each box face moved inward by its depth, the opposite face
/// kept. `None` if a collider is not a box or too thin for its cuts.
fn apply(model: &SceneModel, cuts: &[Cut]) -> Result<Option<SceneModel>, DiscoveryError> {
    let mut builder = model.to_builder();
    for cut in cuts {
        let Some(c) = builder
            .parts
            .get_mut(cut.part.index())
            .and_then(|p| p.colliders.get_mut(cut.collider))
        else {
            return Ok(None);
        };
        let Shape::Cuboid { half_extents } = &mut c.shape else {
            return Ok(None);
        };
        let half = half_extents[cut.axis] - cut.depth / 2.0;
        if half < MIN_HALF_EXTENT {
            return Ok(None);
        }
        half_extents[cut.axis] = half;
        let mut shift = Vector3::zeros();
        shift[cut.axis] = -cut.side * cut.depth / 2.0;
        c.part_from_shape *= Translation3::from(shift);
    }
    Ok(Some(builder.build()?))
}

/// The cuts of least volume that resolve the conflict of `(a, b)` in `observation`, with the
/// cut model, among the faces of `parts` (the conflict's parts, or some of them). One face; in a
/// [`Observation::State`] also two faces of the same box (a box tilted into a corner of a
/// carcass overlaps it on two sides), which a sweep is too costly to try.
fn best_cut(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
    a: Body,
    b: Body,
    parts: &[PartId],
) -> Result<Option<(Vec<Cut>, SceneModel)>, DiscoveryError> {
    // Every candidate with the volume it removes (face area times depth), tried cheapest
    // first: the first that resolves the conflict is the least-volume one.
    let mut candidates: Vec<(f64, Vec<Cut>)> = Vec::new();
    for &p in parts {
        let Some(part) = model.part(p) else { continue };
        for (i, collider) in part.colliders().iter().enumerate() {
            let Shape::Cuboid { half_extents: h } = &collider.shape else {
                continue;
            };
            let mut faces = Vec::new();
            for axis in 0..3 {
                let area = 4.0 * h[(axis + 1) % 3] * h[(axis + 2) % 3];
                for side in [1.0, -1.0] {
                    for depth in CUTS {
                        let cut = Cut {
                            part: p,
                            collider: i,
                            axis,
                            side,
                            depth,
                        };
                        faces.push((area * depth, cut));
                    }
                }
            }
            candidates.extend(faces.iter().map(|(v, c)| (*v, vec![*c])));
            if matches!(observation, Observation::State(_)) {
                for (x, (v1, c1)) in faces.iter().enumerate() {
                    for (v2, c2) in &faces[x + 1..] {
                        if (c1.axis, c1.side) != (c2.axis, c2.side) {
                            candidates.push((v1 + v2, vec![*c1, *c2]));
                        }
                    }
                }
            }
        }
    }
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0));
    for (_, cuts) in candidates {
        let Some(cut_model) = apply(model, &cuts)? else {
            continue;
        };
        if !still_conflicting(&cut_model, observation, sweep, a, b)? {
            return Ok(Some((cuts, cut_model)));
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Vector3};

    use super::*;
    use crate::scene::{Joint, JointKind, Limits, PartSpec, SceneModelBuilder};

    /// Adds a part on the base with one box (half extents `half`, centre `centre` in the part
    /// frame) on a joint at the origin: revolute limits [0, 1.5], prismatic [0, 0.4].
    fn add_box_part(
        b: &mut SceneModelBuilder,
        name: &str,
        kind: JointKind,
        axis: Vector3<f64>,
        half: Vector3<f64>,
        centre: Vector3<f64>,
    ) {
        let (suffix, upper) = match kind {
            JointKind::Revolute => ("hinge", 1.5),
            JointKind::Prismatic => ("slide", 0.4),
        };
        let joint = Joint::new(
            format!("{name}_{suffix}"),
            kind,
            Isometry3::identity(),
            axis,
            Limits::new(0.0, upper),
        );
        b.add_part(PartSpec::on_base(name, joint).with_collider(
            Shape::cuboid(half),
            Isometry3::translation(centre.x, centre.y, centre.z),
        ));
    }

    /// The world x range of part `k`'s first box, and its y, z half extents.
    fn range(m: &SceneModel, k: usize) -> ([f64; 2], [f64; 2]) {
        let c = &m.parts()[k].colliders()[0];
        let Shape::Cuboid { half_extents: h } = &c.shape else {
            panic!("a box")
        };
        let x = c.part_from_shape.translation.x;
        ([x - h.x, x + h.x], [h.y, h.z])
    }

    /// Two drawer fronts side by side whose estimated boxes overlap by 1.2 cm in x at the closed
    /// state (left: x 0 .. 0.50, right: x 0.488 .. 0.79; both 2 cm thick, 0.4 m tall). The
    /// cheapest separating cut moves one inner x face by 15 mm, the smallest of CUTS above
    /// the overlap (the x face areas are 0.02 × 0.4 m², against 0.5 × 0.4 or 0.302 × 0.4 for
    /// the y faces; z faces and outer x faces do not separate the boxes, and any pair of faces
    /// that does removes more): after it no pair collides, one box lost 15 mm of x extent on
    /// its inner side only and every other extent and face is unchanged.
    #[test]
    fn overlapping_fronts_are_cut_on_one_face() {
        let mut b = SceneModelBuilder::new();
        for (name, lo, hi) in [("left", 0.0, 0.50), ("right", 0.488, 0.79)] {
            add_box_part(
                &mut b,
                name,
                JointKind::Prismatic,
                -Vector3::y(),
                Vector3::new((hi - lo) / 2.0, 0.01, 0.2),
                Vector3::new((lo + hi) / 2.0, 0.01, 0.5),
            );
        }
        let est = b.build().unwrap();
        let closed = Observation::State(est.zero_state());
        let sweep = SweepSettings::default();
        assert!(!conflicts(&est, &closed, &sweep).unwrap().is_empty());
        let (cut, log) = reconcile(&est, std::slice::from_ref(&closed), &sweep, None).unwrap();
        assert!(log.unresolved.is_empty(), "{log:?}");
        assert_eq!(log.cuts.len(), 1, "{log:?}");
        assert!(conflicts(&cut, &closed, &sweep).unwrap().is_empty());
        let before = [range(&est, 0), range(&est, 1)];
        let after = [range(&cut, 0), range(&cut, 1)];
        let changed: Vec<usize> = (0..2).filter(|&k| before[k] != after[k]).collect();
        assert_eq!(changed.len(), 1, "{before:?} → {after:?}");
        let k = changed[0];
        assert_eq!(before[k].1, after[k].1, "y and z extents kept");
        // The outer face stays; the inner one moves in by one of CUTS.
        let (outer, inner) = if k == 0 { (0, 1) } else { (1, 0) };
        assert!((before[k].0[outer] - after[k].0[outer]).abs() < 1e-12);
        let moved = (before[k].0[inner] - after[k].0[inner]).abs();
        assert!((moved - 0.015).abs() < 1e-12, "moved {moved}");
    }

    /// A door hinged at the origin about −z (it opens towards −y) whose estimated box reaches
    /// 1 cm past its hinge line: x −0.01 .. 0.5, y −0.02 .. 0, z 0 .. 0.6; a drawer front beside
    /// it at x −0.41 .. −0.012, same y and z. Closed they are 2 mm apart (no conflict). Turned
    /// by θ (R(−θ)), the box corner beyond the hinge, (−0.01, −0.02), goes to
    /// (−0.01 cos θ − 0.02 sin θ, 0.01 sin θ − 0.02 cos θ): at the observed 0.5 rad that is
    /// (−0.0184, −0.0128), inside the drawer. By hand, the cheapest cut that frees the motion
    /// moves an x face by 10 mm: the door's hinge face to x = 0 (the corner then stays at
    /// x ≥ −0.02 sin 0.5 = −0.0096 > −0.012), or the drawer's inner face to x = −0.022 (beyond
    /// the corner's −0.0184); 3 and 6 mm leave the corner inside (at −0.0157 or −0.0131 for
    /// the door, the drawer face at −0.015 or −0.018). The two faces have the same area,
    /// 0.02 × 0.6 m²; no z face separates the boxes and a y face costs at least 25 times more.
    #[test]
    fn observed_door_motion_is_made_free() {
        let mut b = SceneModelBuilder::new();
        add_box_part(
            &mut b,
            "door",
            JointKind::Revolute,
            -Vector3::z(),
            Vector3::new(0.255, 0.01, 0.3),
            Vector3::new(0.245, -0.01, 0.3),
        );
        add_box_part(
            &mut b,
            "drawer",
            JointKind::Prismatic,
            -Vector3::y(),
            Vector3::new(0.199, 0.01, 0.3),
            Vector3::new(-0.211, -0.01, 0.3),
        );
        let est = b.build().unwrap();
        let door = est.joint_id("door_hinge").unwrap();
        let observations = [
            Observation::State(est.zero_state()),
            Observation::Motion {
                state: est.zero_state(),
                joint: door,
                from: 0.0,
                to: 0.5,
            },
        ];
        let sweep = SweepSettings::default();
        assert!(
            conflicts(&est, &observations[0], &sweep)
                .unwrap()
                .is_empty()
        );
        assert!(
            !conflicts(&est, &observations[1], &sweep)
                .unwrap()
                .is_empty()
        );
        let (cut, log) = reconcile(&est, &observations, &sweep, None).unwrap();
        assert!(log.unresolved.is_empty(), "{log:?}");
        assert_eq!(log.cuts.len(), 1, "{log:?}");
        let c = &log.cuts[0];
        assert_eq!((c.axis, c.depth, c.observation), (0, 0.01, 1), "{c:?}");
        for o in &observations {
            assert!(conflicts(&cut, o, &sweep).unwrap().is_empty(), "{log:?}");
        }
        // Either the door's hinge face or the drawer's inner face moved; the door's free edge
        // (x = 0.5) and the drawer's far edge (x = −0.41) are kept.
        let (door_x, drawer_x) = (range(&cut, 0).0, range(&cut, 1).0);
        assert!((door_x[1] - 0.5).abs() < 1e-12 && (drawer_x[0] + 0.41).abs() < 1e-12);
        let door_cut = (door_x[0] - 0.0).abs() < 1e-12 && (drawer_x[1] + 0.012).abs() < 1e-12;
        let drawer_cut = (door_x[0] + 0.01).abs() < 1e-12 && (drawer_x[1] + 0.022).abs() < 1e-12;
        assert!(door_cut ^ drawer_cut, "{door_x:?} {drawer_x:?}");
    }
}
