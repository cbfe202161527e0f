//! The fast exact validity check of arm configurations at a fixed base pose, and the discrete
//! check of a straight arm motion built on it ([`ArmCheck`]).
//!
//! **Answer.** [`ArmCheck::is_valid`] gives the answer of the exact parry check,
//! `self_collision(poses).is_none() && scene_collision(poses, ..).is_none()` of
//! [`RobotCollision`] (same poses, same pairs, same exemptions, same margin; with
//! [`ArmCheck::with_self_margin`], `self_collision_within(poses, margin)`): the sphere model
//! is only the broad phase. A link whose spheres clear every obstacle cannot reach the scene,
//! and a checked pair whose spheres are apart cannot touch (the spheres cover the exact shapes,
//! see the module [`super`]); every other link and pair is decided by parry.
//!
//! **Along a motion** ([`ArmCheck::check_motion`]) a pair of links whose spheres meet, and a
//! link whose spheres reach an obstacle, are decided by parry's distance once and then
//! carried: at another state of the same straight motion the pair (the link and that
//! obstacle) is apart as long as one of the distances found at the states evaluated so far,
//! less the most they can have closed in since (a bound from the joint displacements and the
//! links' lever arms, see `levers` and the `bounds` module), stays 1 µm above zero (above the
//! margin). That proves the exact geometry apart, so each state's
//! answer is still the exact one (anything within 1 µm of the threshold is re-evaluated).
//!
//! **Continuous by default** ([`ArmCheck::with_continuous`]). The same bounds give each free
//! state evaluated a span of the motion's parameter around it that is free (the distances
//! less the most the links can move); the check evaluates the motion's end, its start, then
//! the middle of whatever no span covers yet, until nothing is left. So the whole motion is
//! certified, however thin the obstacles, not only the states a discrete check visits. Near
//! the scene and between close links the bounds are exact distances (a link or pair whose
//! spheres come within [`CONTINUOUS_BAND`] is handed to parry), so the spans stay long where
//! the spheres overshoot the shapes. On MotionBenchMaker (the `mbm` bench) this costs 1.6× the
//! discrete check's median planning time, and none of the returned paths fails the finer
//! re-check that 19 of the discrete check's fail.
//!
//! **Cost per configuration.** Forward kinematics into scratch buffers (no allocation once
//! they have grown), the spheres placed, then per link one test of a ball enclosing its
//! spheres against every obstacle (most links stop here) and only where that ball reaches an
//! obstacle the link's spheres; per checked pair one test of the two links' balls before
//! their spheres. Parry runs only for the links and pairs whose spheres meet something.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};

use nalgebra::{Isometry3, Point3};

use super::check::SPHERE_SLACK;
use super::obstacles::GapScratch;
use super::{EdgeScene, RobotSpheres, SphereData, SphereObstacles, levers};
use crate::kinematics::robot::collision::PlacedScene;
use crate::kinematics::robot::{RobotCollision, RobotError, RobotModel};

mod bounds;
mod continuous;
mod span;

pub use continuous::{CONTACT_CLEARANCE, CONTINUOUS_BAND, MAX_CONTINUOUS_STATES};

use bounds::Bounds;

/// The arm's validity against one scene state at a fixed base pose: the exact answer with the
/// sphere model as broad phase (see the module's answer). Built once per scene state and base
/// pose ([`ArmCheck::new`] places the scene and packs the obstacles); `Send + Sync`.
///
/// Scratch lives in an [`ArmCheckData`] the caller owns ([`ArmCheck::is_valid_with`]), or in
/// one per thread ([`ArmCheck::is_valid`], for closures handed to a planner).
pub struct ArmCheck<'a> {
    robot: &'a RobotModel,
    collision: &'a RobotCollision,
    spheres: &'a RobotSpheres,
    scene: PlacedScene<'a>,
    obstacles: SphereObstacles,
    margin: f64,
    world_from_base: Isometry3<f64>,
    world_from_root: Isometry3<f64>,
    /// Per link, a ball (link frame) enclosing its spheres; `None` without spheres.
    balls: Vec<Option<(Point3<f64>, f64)>>,
    /// Per checked pair `(i, k)` (order of [`RobotSpheres::checked_pairs`]), the joints that
    /// move link `k` relative to link `i` with their lever arms (see [`levers`]).
    levers: Vec<Vec<(usize, f64)>>,
    /// Per link `l`, the joints that move it in the world with their lever arms (the levers
    /// of the pair `(0, l)`: the base does not move).
    link_levers: Vec<Vec<(usize, f64)>>,
    /// Whether a motion check skips the states certified free by a checked state's span.
    spans: bool,
    /// Whether a motion check certifies the whole motion ([`ArmCheck::with_continuous`]).
    continuous: bool,
    /// How far (m) the obstacles' reach and the pairs' clearance are grown in the broad
    /// phase: [`CONTINUOUS_BAND`] for a continuous check, else 0. The sphere gaps to the
    /// obstacles are that much less than the spheres' clearance, and a pair whose spheres come
    /// within it has its exact distance computed.
    band: f64,
    /// The clearance (m, `>= 0`) every checked link pair keeps ([`ArmCheck::with_self_margin`]).
    self_margin: f64,
    /// This check's identity, unique in the process and renewed by every setting: a scratch
    /// remembers an answer only together with the identity of the check that gave it
    /// ([`ArmCheckData`]).
    id: u64,
}

/// The next [`ArmCheck`] identity.
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

fn fresh_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

impl std::fmt::Debug for ArmCheck<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ArmCheck")
            .field("obstacles", &self.obstacles.len())
            .field("margin", &self.margin)
            .field("world_from_base", &self.world_from_base)
            .finish_non_exhaustive()
    }
}

/// Scratch of [`ArmCheck`]: link poses, placed spheres, the links and pairs left for parry,
/// one interpolated state and the bisection queue of a motion. Reused across calls, and by
/// any number of checks: the one answer it remembers (the last configuration found valid) is
/// tied to the check that computed it, so another check (another scene, base pose or
/// setting) never reads an answer that is not its own.
#[derive(Debug, Clone, Default)]
pub struct ArmCheckData {
    /// The identity of the check whose answer `state.last_valid` is.
    owner: u64,
    state: StateScratch,
    /// The interpolated configuration of a motion check.
    q: Vec<f64>,
    /// Index intervals of a motion check still to bisect.
    queue: VecDeque<(usize, usize)>,
    /// Parameter intervals of a continuous motion check still to certify.
    intervals: VecDeque<(f64, f64)>,
}

#[derive(Debug, Clone, Default)]
struct StateScratch {
    poses: Vec<Isometry3<f64>>,
    spheres: SphereData,
    /// Links whose spheres reach an obstacle.
    links: Vec<usize>,
    /// Per link of `links`, per obstacle: whether a sphere of the link reaches it.
    reached: Vec<Vec<bool>>,
    /// Checked pairs whose spheres meet (indices into the checked pairs).
    pairs: Vec<usize>,
    /// Per link, its enclosing ball (`ArmCheck::balls`) in the world at `poses`.
    world_balls: Vec<Option<(Point3<f64>, f64)>>,
    /// Per link, the least gap from its spheres to the obstacles they do not reach, where the
    /// broad phase compared them (`NaN` elsewhere; [`SphereObstacles::link_gaps`]), and the
    /// scratch of that comparison.
    link_gaps: Vec<f32>,
    gap_scratch: GapScratch,
    /// Per link, its world ball's clearance from every obstacle
    /// ([`SphereObstacles::ball_clearance`]; `+∞` without a ball), which the spans reuse.
    ball_gaps: Vec<f32>,
    /// Along the motion being checked: per checked pair, how fast (m per unit of the motion's
    /// parameter) the distance of its links can change, and the distance bounds found with
    /// the parameters they were found at.
    speed: Vec<f64>,
    bound: Bounds,
    /// The same for a link against one obstacle: per link, how fast it can approach the
    /// scene, and per link and obstacle (item `link · obstacles + obstacle`) the bounds.
    link_speed: Vec<f64>,
    scene_bound: Bounds,
    /// The last configuration found valid: asked again (a planner checks a motion's end and
    /// then the motion), it is not recomputed.
    last_valid: Vec<f64>,
}

/// The least certified distance (m) of a pair between parry's evaluations along a motion: it
/// absorbs the rounding of parry's distance and of the bound's arithmetic.
const CERTIFIED_GAP: f64 = 1e-6;

/// Distance (m) up to which a pair's distance is computed exactly along a motion; beyond it
/// the bound is this value (shape pairs farther apart are not computed, and GJK stops once it
/// proves a pair farther, see `Placed::distance_within`). It only sets how far the spans
/// reach, never an answer: on MotionBenchMaker 2 cm costs fewer instructions than 1 or 5 cm
/// (GJK stopped sooner against states re-checked more often).
const BOUND_CUTOFF: f64 = 0.02;

thread_local! {
    /// Per-thread scratch of [`ArmCheck::is_valid`] and [`ArmCheck::check_motion`].
    static SCRATCH: RefCell<ArmCheckData> = RefCell::new(ArmCheckData::default());
}

impl<'a> ArmCheck<'a> {
    /// The check for `robot` with base pose `base` (`[x, y, yaw]`), `spheres` built from
    /// `robot` and `collision`, against `scene` (its exemption and margin as
    /// [`RobotCollision::scene_collision`] takes them).
    ///
    /// # Errors
    /// [`RobotError::DimensionMismatch`] when `spheres` or `collision` have another number of
    /// links than `robot`, [`RobotError::NonFiniteValue`] for a non-finite base pose.
    pub fn new(
        robot: &'a RobotModel,
        collision: &'a RobotCollision,
        spheres: &'a RobotSpheres,
        scene: EdgeScene<'a>,
        base: [f64; 3],
    ) -> Result<Self, RobotError> {
        let links = super::edge::check_inputs(robot, spheres, base)?;
        let world_from_base = RobotModel::world_from_base(base);
        let balls = spheres
            .links()
            .iter()
            .map(|l| {
                if l.is_empty() {
                    return None;
                }
                let sum = l
                    .iter()
                    .fold(nalgebra::Vector3::zeros(), |s, b| s + b.center.coords);
                let center = Point3::from(sum / l.len() as f64);
                let radius = l
                    .iter()
                    .map(|b| (b.center - center).norm() + b.radius)
                    .fold(0.0, f64::max);
                Some((center, radius))
            })
            .collect();
        let placed = PlacedScene::new(scene.model, scene.data, scene.exempt);
        // Grown by the continuous check's band (the default, `with_continuous`).
        let obstacles = SphereObstacles::new(scene.model, scene.data, scene.exempt, scene.margin)
            .inflated(CONTINUOUS_BAND as f32);
        // Both take the scene's shapes in the same order: obstacle k is placed shape k.
        debug_assert_eq!(placed.len(), obstacles.len());
        Ok(ArmCheck {
            robot,
            collision,
            spheres,
            scene: placed,
            obstacles,
            margin: scene.margin,
            world_from_base,
            world_from_root: world_from_base * robot.base_from_arm_root(),
            balls,
            levers: spheres
                .checked_pairs()
                .iter()
                .map(|&(i, k)| levers(robot, spheres.links(), i, k))
                .collect(),
            link_levers: (0..links)
                .map(|l| levers(robot, spheres.links(), 0, l))
                .collect(),
            spans: true,
            continuous: true,
            band: CONTINUOUS_BAND,
            self_margin: 0.0,
            id: fresh_id(),
        })
    }

    /// With a clearance between the robot's own links: a configuration is valid only when
    /// every checked link pair keeps more than `margin` (m) apart, as
    /// [`RobotCollision::self_collision_within`] checks it (the scene's margin is the
    /// [`EdgeScene`]'s). A negative or NaN margin counts as 0, the default: touching is the
    /// only self-collision. Paths planned with no self-clearance may graze the robot between
    /// checked states, and a real arm tracks its path with some error.
    pub fn with_self_margin(mut self, margin: f64) -> Self {
        self.self_margin = if margin > 0.0 { margin } else { 0.0 };
        self.id = fresh_id();
        self
    }

    /// With `false`, [`ArmCheck::check_motion`] evaluates every state it visits instead of
    /// skipping the states certified free around each free state it evaluated (the default,
    /// `true`; see `span` in the module's source). The answers are the same; the setting
    /// exists to measure what the spans save.
    pub fn with_spans(mut self, spans: bool) -> Self {
        self.spans = spans;
        self.id = fresh_id();
        self
    }

    /// With `true`, [`ArmCheck::check_motion`] certifies the whole straight motion instead of
    /// the states a discrete check visits: no obstacle, however thin, is passed between two
    /// evaluated states. The states evaluated are chosen by their certified spans (see `span`
    /// in the module's source): each free state evaluated proves an interval around it free
    /// (its distance bounds over the most the links can move), and the states evaluated next
    /// are the middles of what is left, `a` included, until nothing is; the resolution is
    /// not used. A motion is rejected where a state is not free, where a free state's span is
    /// below [`CONTACT_CLEARANCE`] over the fastest link's speed (some link or pair within
    /// that clearance of touching), or after [`MAX_CONTINUOUS_STATES`] states. A link whose
    /// spheres come within [`CONTINUOUS_BAND`] of an obstacle, and a checked pair whose
    /// spheres come that near each other, have their exact distance computed (the spheres'
    /// clearance alone would make the spans short where the spheres overshoot the exact
    /// shapes). The default is `true`; `false` gives the discrete check, which visits the
    /// states documented at [`ArmCheck::check_motion`].
    pub fn with_continuous(mut self, continuous: bool) -> Self {
        if continuous != self.continuous {
            let band = if continuous { CONTINUOUS_BAND } else { 0.0 };
            self.obstacles = self.obstacles.inflated((band - self.band) as f32);
            self.band = band;
            self.continuous = continuous;
            self.id = fresh_id();
        }
        self
    }

    /// Whether arm configuration `q` is free (see the module's answer), with per-thread
    /// scratch. `false` for a configuration of the wrong length or with non-finite values.
    pub fn is_valid(&self, q: &[f64]) -> bool {
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut data) => self.is_valid_with(q, &mut data),
            // Re-entered from inside a check (not done here): fresh scratch.
            Err(_) => self.is_valid_with(q, &mut ArmCheckData::default()),
        })
    }

    /// [`ArmCheck::is_valid`] with caller-owned scratch.
    pub fn is_valid_with(&self, q: &[f64], data: &mut ArmCheckData) -> bool {
        self.adopt(data);
        self.state_valid(q, None, &mut data.state)
    }

    /// Makes `data` this check's: what it remembers of another check is forgotten.
    fn adopt(&self, data: &mut ArmCheckData) {
        if data.owner != self.id {
            data.owner = self.id;
            data.state.last_valid.clear();
        }
    }

    /// Whether the straight motion from `a` to `b` is free, with per-thread scratch: by
    /// default certified over the whole motion ([`ArmCheck::with_continuous`]); with the
    /// continuous check off, at the states a discrete check visits: `b` and the states
    /// `a + (j / n)·(b − a)`, `0 < j < n`, `n = ⌈‖b − a‖ / resolution⌉` (consecutive states at most `resolution`
    /// apart in the Euclidean norm of the joint values), visited in bisection order (the
    /// middle first, as OMPL's discrete motion validator) so that a blocked motion is
    /// rejected early. States within the certified span of a state found free are not
    /// evaluated: its sphere clearances and distance bounds, over the most the links can move,
    /// prove them free (see `span` in the module's source; [`ArmCheck::with_spans`]), so the
    /// answer is still that of checking every state. `a` itself is taken as valid, as a
    /// planner's motion check takes it.
    /// `false` for configurations of different or wrong lengths, non-finite values, or a
    /// `resolution` that is not positive and finite. Like any discrete check it can miss an
    /// obstacle thinner than the motion of the robot between two states, unless the check is
    /// continuous ([`ArmCheck::with_continuous`]: the whole motion certified).
    pub fn check_motion(&self, a: &[f64], b: &[f64], resolution: f64) -> bool {
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut data) => self.check_motion_with(a, b, resolution, &mut data),
            Err(_) => self.check_motion_with(a, b, resolution, &mut ArmCheckData::default()),
        })
    }

    /// [`ArmCheck::check_motion`] with caller-owned scratch.
    pub fn check_motion_with(
        &self,
        a: &[f64],
        b: &[f64],
        resolution: f64,
        data: &mut ArmCheckData,
    ) -> bool {
        if a.len() != self.robot.dof()
            || b.len() != a.len()
            || !(resolution.is_finite() && resolution > 0.0)
            || !a.iter().all(|v| v.is_finite())
        {
            return false;
        }
        self.adopt(data);
        let s = &mut data.state;
        s.speed.clear();
        s.speed.extend(self.levers.iter().map(|levers| {
            levers
                .iter()
                .map(|&(j, lever)| (b[j] - a[j]).abs() * lever)
                .sum::<f64>()
        }));
        s.bound.reset(self.levers.len());
        s.link_speed.clear();
        s.link_speed.extend(self.link_levers.iter().map(|levers| {
            levers
                .iter()
                .map(|&(j, lever)| (b[j] - a[j]).abs() * lever)
                .sum::<f64>()
        }));
        s.scene_bound
            .reset(self.link_levers.len() * self.obstacles.len());
        if self.continuous {
            return self.certify_motion(a, b, data);
        }
        if !self.state_valid(b, Some(1.0), &mut data.state) {
            return false;
        }
        let length = a
            .iter()
            .zip(b)
            .map(|(x, y)| (y - x) * (y - x))
            .sum::<f64>()
            .sqrt();
        // `as` saturates for absurdly fine resolutions.
        let n = ((length / resolution).ceil() as usize).max(1);
        data.queue.clear();
        // States within the certified span of a free state need no check (see `span`).
        let mut hi = n - 1;
        if n > 1 && self.spans {
            hi -= self.span_steps(1.0, n, n - 1, &data.state);
        }
        if hi >= 1 {
            data.queue.push_back((1, hi));
        }
        while let Some((lo, hi)) = data.queue.pop_front() {
            let mid = lo + (hi - lo) / 2;
            let t = mid as f64 / n as f64;
            data.q.clear();
            data.q.extend(a.iter().zip(b).map(|(x, y)| x + (y - x) * t));
            if !self.state_valid(&data.q, Some(t), &mut data.state) {
                return false;
            }
            // An interval of one state has no neighbour a span could skip.
            let k = if self.spans && hi > lo {
                self.span_steps(t, n, (mid - lo).max(hi - mid), &data.state)
            } else {
                0
            };
            if lo.saturating_add(k) < mid {
                data.queue.push_back((lo, mid - 1 - k));
            }
            if mid.saturating_add(k) < hi {
                data.queue.push_back((mid + 1 + k, hi));
            }
        }
        true
    }

    /// The state check: forward kinematics, the sphere broad phase, parry where it is needed.
    /// Along a motion (`at`: the state's parameter in it, with `s.speed` and `s.bound` set up
    /// for the motion), a pair whose last distance bound, less the most its links can have
    /// closed in since, is still positive is free without parry (see [`ArmCheck::pair_free`]).
    fn state_valid(&self, q: &[f64], at: Option<f64>, s: &mut StateScratch) -> bool {
        if q.len() != self.robot.dof() || !q.iter().all(|v| v.is_finite()) {
            return false;
        }
        if s.last_valid.as_slice() == q {
            return true;
        }
        self.forward(q, &mut s.poses);
        self.spheres.place(&s.poses, &mut s.spheres);
        self.broad_phase(s);
        let scene_free = (0..s.links.len()).all(|m| self.link_free(m, at, s));
        let free = scene_free && (0..s.pairs.len()).all(|k| self.pair_free(s.pairs[k], q, at, s));
        // `last_valid` also names the configuration the scratch's poses and spheres are of
        // (`span` reads them): cleared when another configuration overwrote them.
        s.last_valid.clear();
        if free {
            s.last_valid.extend_from_slice(q);
        }
        free
    }

    /// Whether checked pair `p` (spheres meeting) is apart at the poses in `s` (of arm
    /// configuration `q`). A pair whose distance table ([`RobotSpheres::pair_distance_bound`])
    /// certifies it apart by more than [`CERTIFIED_GAP`] is apart, and along a motion that
    /// bound becomes one of its bounds. Otherwise, outside a motion: parry's touch test. Along
    /// a motion, at parameter `t`: each of the pair's bounds `(t0, d0)` (a lower bound on the
    /// links' distance at `t0`) certifies it apart when `d0 − speed·|t − t0| > CERTIFIED_GAP`,
    /// since no point of link `k` moves relative to link `i` faster than `speed` (m per unit
    /// of the parameter, [`levers`]; the `bounds` module); otherwise parry's distance (exact
    /// below [`BOUND_CUTOFF`]) decides and becomes a bound.
    fn pair_free(&self, p: usize, q: &[f64], at: Option<f64>, s: &mut StateScratch) -> bool {
        let (i, k) = self.spheres.checked_pairs()[p];
        let margin = self.self_margin;
        let Some(t) = at else {
            if self.spheres.pair_distance_bound(p, q) > margin + CERTIFIED_GAP {
                return true;
            }
            return if margin > 0.0 {
                self.collision
                    .pair_distance_below(&s.poses, i, k, margin + BOUND_CUTOFF)
                    > margin
            } else {
                !self.collision.pair_touches(&s.poses, i, k)
            };
        };
        // A continuous check wants bounds that keep long spans: one carried down into the band
        // is computed again.
        if s.bound.at(p, t, s.speed[p]) > Some(margin + CERTIFIED_GAP + self.band) {
            return true;
        }
        // A table bound within the band would give a continuous check short spans where the
        // exact distance gives long ones: the exact distance decides there.
        let table = self.spheres.pair_distance_bound(p, q);
        if table > margin + CERTIFIED_GAP + self.band {
            s.bound.push(p, t, table);
            return true;
        }
        let d = self
            .collision
            .pair_distance_below(&s.poses, i, k, margin + BOUND_CUTOFF);
        s.bound.push(p, t, d);
        d > margin
    }

    /// Whether link `s.links[m]` (spheres reaching the obstacles flagged in `s.reached[m]`)
    /// keeps the margin from those obstacles at the poses in `s`: parry outside a motion;
    /// along one, per obstacle, the certificate of [`ArmCheck::pair_free`] with the link's
    /// speed in the world (the obstacles do not move) and the margin added.
    fn link_free(&self, m: usize, at: Option<f64>, s: &mut StateScratch) -> bool {
        let l = s.links[m];
        let Some(t) = at else {
            let among = &s.reached[m];
            return !self
                .collision
                .link_meets_scene(&s.poses, l, &self.scene, among, self.margin);
        };
        let margin = self.margin.max(0.0);
        for o in 0..s.reached[m].len() {
            if !s.reached[m][o] {
                continue;
            }
            let slot = l * self.obstacles.len() + o;
            if s.scene_bound.at(slot, t, s.link_speed[l]) > Some(margin + CERTIFIED_GAP + self.band)
            {
                continue;
            }
            let d = self.collision.link_shape_distance_below(
                &s.poses,
                l,
                &self.scene,
                o,
                margin + BOUND_CUTOFF,
            );
            s.scene_bound.push(slot, t, d);
            if d <= margin {
                return false;
            }
        }
        true
    }

    /// `world_from_link` for every link, as [`RobotModel::link_poses`] computes it (the same
    /// products in the same order, so the same values), into `poses`.
    fn forward(&self, q: &[f64], poses: &mut Vec<Isometry3<f64>>) {
        poses.clear();
        poses.push(self.world_from_base);
        let mut pose = self.world_from_root;
        for (joint, &v) in self.robot.arm_joints().iter().zip(q) {
            pose *= joint.parent_from_child(v);
            poses.push(pose);
        }
    }

    /// The links whose spheres reach an obstacle and the checked pairs whose spheres meet,
    /// each first tested with the links' enclosing balls.
    fn broad_phase(&self, s: &mut StateScratch) {
        s.links.clear();
        s.pairs.clear();
        s.world_balls.clear();
        s.world_balls.extend(
            self.balls
                .iter()
                .zip(&s.poses)
                .map(|(ball, pose)| ball.map(|(c, r)| (pose * c, r))),
        );
        let ball = |l: usize| s.world_balls.get(l).copied().flatten();
        s.link_gaps.clear();
        s.link_gaps.resize(s.world_balls.len(), f32::NAN);
        s.ball_gaps.clear();
        for l in 0..s.world_balls.len() {
            let Some((c, r)) = ball(l) else {
                s.ball_gaps.push(f32::INFINITY);
                continue;
            };
            let center = [c.x as f32, c.y as f32, c.z as f32];
            let gap = self.obstacles.ball_clearance(center, r as f32);
            s.ball_gaps.push(gap);
            // The ball grown by SPHERE_SLACK reaches no obstacle: nor do its spheres.
            if gap > SPHERE_SLACK {
                continue;
            }
            let k = s.links.len();
            if s.reached.len() <= k {
                s.reached.push(Vec::new());
            }
            s.reached[k].clear();
            let (reached, gap) =
                self.obstacles
                    .link_gaps(&s.spheres, l, &mut s.reached[k], &mut s.gap_scratch);
            s.link_gaps[l] = gap;
            if reached {
                s.links.push(l);
            }
        }
        for (p, &(i, j)) in self.spheres.checked_pairs().iter().enumerate() {
            let (Some((ci, ri)), Some((cj, rj))) = (ball(i), ball(j)) else {
                continue;
            };
            // Within the band too: the pair's exact distance is then computed (see `band`).
            let within = self.self_margin + self.band;
            if (ci - cj).norm() <= ri + rj + f64::from(SPHERE_SLACK) + within
                && self.spheres.pair_within(&s.spheres, i, j, within as f32)
            {
                s.pairs.push(p);
            }
        }
    }
}
