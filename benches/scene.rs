//! The scene model on generated scenes (tests/scene/generators.rs, fixed seed), each figure with
//! a baseline timed in the same run:
//!
//! - `scene_fk`: [`forward_kinematics`] of a 100-part tree (depth ≤ 4) against Pinocchio's
//!   `forwardKinematics` on the same tree, through its Rust API and in a C++ loop (needs the
//!   `pinocchio` feature; both must give the same part placements, checked once before timing).
//! - `scene_collisions`: [`collisions`] at pre-computed random states against a brute-force
//!   baseline with parry directly (exact distance for every collider pair of every checked body
//!   pair, no bounding-sphere filter). Throughput is in checked body pairs (part–part and
//!   part–base). Both must report the same colliding pairs.
//! - `scene_sweep`: [`check_joint_motion`] over full-range one-joint motions, default
//!   [`SweepSettings`], against the paper's check (6 evenly spaced values, overlap of the moving
//!   parts' world AABBs with every other body's). Throughput is in motions. The verdicts are
//!   tabulated before timing, among them the motions the paper's check passes but ours finds a
//!   collision on.
//!
//! The generators pack every part within a few metres of the origin, so many bodies overlap at
//! a random state (the bench prints how many pairs collide). The collision and sweep benches
//! therefore also run a *spread* copy of the scene, its root parts (and their subtrees) moved
//! onto a 1.5 m grid: closer to a kitchen, where most pairs are far apart.
//! Sweeps are drawn among motions whose moving subtree has geometry and starts clear of every
//! other body, as a planner would ask.
//!
//! `cargo bench --bench scene -- --warm-up-time 1 --measurement-time 2`
//! (`--no-default-features` drops the Pinocchio baseline.)

#[path = "../tests/scene/generators.rs"]
mod generators;

use std::collections::BTreeSet;
use std::hint::black_box;

use criterion::{Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use kinscene::scene::collision::{
    Body, CollisionSettings, SweepSettings, SweepStatus, check_joint_motion, collisions,
};
use kinscene::scene::{
    JointId, Parent, SceneData, SceneModel, Shape, State, forward_kinematics, joint_axis,
};
use nalgebra::{Isometry3, Translation3};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::TestRunner;

/// Parts of the FK scene.
const FK_PARTS: usize = 100;
/// Parts of the collision and sweep scenes.
const QUERY_PARTS: usize = 50;
/// Random states per collision batch.
const STATES: usize = 16;
/// One-joint motions per sweep batch.
const MOTIONS: usize = 100;
/// Grid spacing (m) of the root parts in the spread scenes.
const SPREAD: f64 = 1.5;
/// Joint values the paper checks along a motion ("we sample 6 configurations").
const PAPER_SAMPLES: usize = 6;

/// A generated scene with exactly `parts` parts and at least `base_shapes` base shapes:
/// `generators::scene(parts)` caps the size and draws it uniformly, so draw until both match
/// (same seed, same scene).
fn generated_scene(runner: &mut TestRunner, parts: usize, base_shapes: usize) -> SceneModel {
    let strategy = generators::scene(parts);
    loop {
        let model = strategy.new_tree(runner).expect("strategy").current();
        if model.parts().len() == parts && model.base().shapes.len() >= base_shapes {
            return model;
        }
    }
}

/// `model` with its root parts (those on the base) moved onto a square grid of `spacing`
/// metres centred on the origin (their subtrees move with them); base shapes unchanged.
fn spread(model: &SceneModel, spacing: f64) -> SceneModel {
    let mut builder = model.to_builder();
    let roots = builder.parts.iter().filter(|p| p.parent.is_none()).count();
    let side = (roots as f64).sqrt().ceil() as usize;
    let offset = (side as f64 - 1.0) * spacing / 2.0;
    let roots = builder.parts.iter_mut().filter(|p| p.parent.is_none());
    for (k, part) in roots.enumerate() {
        let (i, j) = (k % side, k / side);
        let shift = Translation3::new(
            i as f64 * spacing - offset,
            j as f64 * spacing - offset,
            0.0,
        );
        part.joint.parent_from_joint = shift * part.joint.parent_from_joint;
    }
    builder.build().expect("moving roots keeps a scene valid")
}

fn draw<T>(runner: &mut TestRunner, strategy: impl Strategy<Value = T>) -> T {
    strategy.new_tree(runner).expect("strategy").current()
}

// ---------------------------------------------------------------------------------------------
// Forward kinematics

#[cfg(feature = "pinocchio")]
mod pinocchio_baseline {
    //! The scene tree as a Pinocchio model: joint `k + 1` is scene joint `k` (scene part ids are
    //! depth-first, which is the order `ModelBuilder` needs).

    use kinscene::kinematics::pinocchio::{
        JointIndex, JointKind as PinKind, JointLimits, Model, ModelBuilder,
    };
    use kinscene::scene::{JointKind, Parent, SceneModel};

    pub fn model(scene: &SceneModel) -> Model {
        let mut b = ModelBuilder::new();
        for (part, joint) in scene.parts().iter().zip(scene.joints()) {
            let parent = match part.parent() {
                Parent::Base => JointIndex::UNIVERSE,
                Parent::Part(p) => JointIndex(p.index() + 1),
            };
            let kind = match joint.kind {
                JointKind::Revolute => PinKind::Revolute { axis: joint.axis },
                JointKind::Prismatic => PinKind::Prismatic { axis: joint.axis },
            };
            let limits = JointLimits::position(joint.limits.lower, joint.limits.upper);
            let index = b
                .add_joint(&joint.name, parent, joint.parent_from_joint, kind, limits)
                .expect("a valid scene joint is a valid Pinocchio joint");
            assert_eq!(index.0, part.id().index() + 1, "depth-first order");
        }
        b.build().expect("the Pinocchio shim loads")
    }
}

fn fk(c: &mut Criterion) {
    let mut runner = TestRunner::deterministic();
    let model = generated_scene(&mut runner, FK_PARTS, 0);
    let state = draw(&mut runner, generators::state(&model));
    let depth = model.parts().iter().map(|p| p.depth()).max().unwrap_or(0);
    let revolute = model
        .joints()
        .iter()
        .filter(|j| j.kind == kinscene::scene::JointKind::Revolute)
        .count();
    println!(
        "scene_fk: {} parts, depth {depth}, {revolute} revolute / {} prismatic joints",
        model.parts().len(),
        model.nq() - revolute
    );
    let mut data = SceneData::new(&model);
    forward_kinematics(&model, &mut data, &state).expect("fk");

    let mut group = c.benchmark_group("scene_fk");
    group.bench_function("kinscene", |b| {
        b.iter(|| forward_kinematics(&model, &mut data, black_box(&state)).expect("fk"))
    });

    #[cfg(feature = "pinocchio")]
    {
        use kinscene::kinematics::pinocchio::{self as pin, JointIndex};
        let pin_model = pinocchio_baseline::model(&model);
        let mut pin_data = pin::Data::new(&pin_model).expect("data");
        let q = nalgebra::DVector::from_column_slice(state.as_slice());
        pin::forward_kinematics(&pin_model, &mut pin_data, &q).expect("fk");
        // Same placements (translation in m, rotation angle in rad) to 1e-9: the two time the
        // same computation.
        let mut worst = 0.0f64;
        for part in model.parts() {
            let ours = data.world_from_part(part.id()).expect("part");
            let theirs =
                pin::joint_placement(&pin_model, &pin_data, JointIndex(part.id().index() + 1))
                    .expect("placement");
            let dt = (ours.translation.vector - theirs.translation.vector).norm();
            let dr = ours.rotation.angle_to(&theirs.rotation);
            worst = worst.max(dt).max(dr);
        }
        assert!(worst <= 1e-9, "Pinocchio and kinscene FK differ by {worst}");
        println!("scene_fk: Pinocchio placements agree to {worst:.1e}");

        group.bench_function("pinocchio_rust_api", |b| {
            b.iter(|| {
                pin::forward_kinematics(&pin_model, &mut pin_data, black_box(&q)).expect("fk")
            })
        });
        // The last part's frame: updateFramePlacement of one frame on top of the FK pass (the C++
        // loop is the backend's benchmark support, `--features bench`).
        #[cfg(feature = "bench")]
        let frame = pin_model
            .joint(JointIndex(model.nq()))
            .expect("joint")
            .frame;
        #[cfg(feature = "bench")]
        group.bench_function("pinocchio_cpp_loop", |b| {
            b.iter_custom(|iterations| {
                pin::bench::cpp_forward_kinematics_loop(
                    &pin_model,
                    &mut pin_data,
                    &q,
                    frame,
                    iterations,
                )
                .expect("C++ loop")
            })
        });
    }
    group.finish();
}

// ---------------------------------------------------------------------------------------------
// Brute-force collision baseline with parry

/// A collider as a parry shape with its placement in its owner's frame.
struct BruteShape {
    shape: SharedShape,
    owner_from_parry: Isometry3<f64>,
}

fn pose(iso: &Isometry3<f64>) -> Pose {
    let q = iso.rotation.quaternion();
    let t = iso.translation.vector;
    Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

/// The parry shape the crate compiles for `shape` (its public conversion), placed in its owner.
fn brute_shape(shape: &Shape, owner_from_shape: &Isometry3<f64>) -> BruteShape {
    let (parry, shape_from_parry) =
        kinscene::scene::collision::parry_shape(shape).expect("generated hulls span a volume");
    BruteShape {
        shape: parry,
        owner_from_parry: owner_from_shape * shape_from_parry,
    }
}

/// A body pair as plain indices: `(part, Ok(part) | Err(base shape))`.
type PairKey = (usize, Result<usize, usize>);

fn key(a: Body, b: Body) -> PairKey {
    let index = |body| match body {
        Body::Part(p) => Ok(p.index()),
        Body::Base(s) => Err(s.index()),
    };
    (index(a).expect("`a` is a part"), index(b))
}

/// The parry shapes of every part (part frame) and base shape (world frame), and the body pairs
/// the crate checks with default settings: every part against every later part except its
/// parent and children, and against every base shape.
struct Brute {
    parts: Vec<Vec<BruteShape>>,
    base: Vec<(BruteShape, Pose)>,
    pairs: Vec<PairKey>,
}

impl Brute {
    fn new(model: &SceneModel) -> Self {
        let parts = model
            .parts()
            .iter()
            .map(|p| {
                p.colliders()
                    .iter()
                    .map(|c| brute_shape(&c.shape, &c.part_from_shape))
                    .collect()
            })
            .collect();
        let base = model
            .base()
            .shapes
            .iter()
            .map(|s| {
                let b = brute_shape(&s.shape, &s.world_from_shape);
                let p = pose(&b.owner_from_parry);
                (b, p)
            })
            .collect();
        let n = model.parts().len();
        let parent = |i: usize| match model.parts()[i].parent() {
            Parent::Part(p) => Some(p.index()),
            Parent::Base => None,
        };
        let mut pairs = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                if parent(j) != Some(i) && parent(i) != Some(j) {
                    pairs.push((i, Ok(j)));
                }
            }
            pairs.extend((0..model.base().shapes.len()).map(|k| (i, Err(k))));
        }
        Brute { parts, base, pairs }
    }

    /// The colliding pairs (exact distance 0) at the poses in `data`.
    fn collisions(&self, data: &SceneData) -> Vec<PairKey> {
        let placed: Vec<Vec<(&BruteShape, Pose)>> = self
            .parts
            .iter()
            .zip(data.world_from_parts())
            .map(|(shapes, world_from_part)| {
                shapes
                    .iter()
                    .map(|s| (s, pose(&(world_from_part * s.owner_from_parry))))
                    .collect()
            })
            .collect();
        let base: Vec<(&BruteShape, Pose)> = self.base.iter().map(|(s, p)| (s, *p)).collect();
        let mut out = Vec::new();
        for &(i, other) in &self.pairs {
            let theirs = match other {
                Ok(j) => &placed[j][..],
                Err(k) => std::slice::from_ref(&base[k]),
            };
            let mut d = f64::INFINITY;
            for (x, px) in &placed[i] {
                for (y, py) in theirs {
                    let e = query::distance(px, &*x.shape, py, &*y.shape)
                        .expect("convex shapes")
                        .distance;
                    d = d.min(e.max(0.0));
                }
            }
            if d <= 0.0 {
                out.push((i, other));
            }
        }
        out
    }
}

fn collision(c: &mut Criterion) {
    let mut runner = TestRunner::deterministic();
    let dense = generated_scene(&mut runner, QUERY_PARTS, 2);
    let spread_scene = spread(&dense, SPREAD);
    let settings = CollisionSettings::default();
    let mut group = c.benchmark_group("scene_collisions");
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    for (label, model) in [("dense", &dense), ("spread", &spread_scene)] {
        let datas: Vec<SceneData> = (0..STATES)
            .map(|_| {
                let state = draw(&mut runner, generators::state(model));
                let mut data = SceneData::new(model);
                forward_kinematics(model, &mut data, &state).expect("fk");
                data
            })
            .collect();
        let brute = Brute::new(model);
        let mut colliding = 0;
        for data in &datas {
            let ours: BTreeSet<PairKey> = collisions(model, data, &settings)
                .expect("collisions")
                .into_iter()
                .map(|c| key(c.a, c.b))
                .collect();
            let theirs: BTreeSet<PairKey> = brute.collisions(data).into_iter().collect();
            assert_eq!(ours, theirs, "colliding pairs differ");
            colliding += ours.len();
        }
        let colliders: usize = model.parts().iter().map(|p| p.colliders().len()).sum();
        println!(
            "scene_collisions/{label}: {} parts ({} on the base, {colliders} colliders), {} base shapes, {} checked body pairs; {:.1} colliding per state on average ({STATES} states, same pairs in both)",
            model.parts().len(),
            model
                .parts()
                .iter()
                .filter(|p| p.parent() == Parent::Base)
                .count(),
            model.base().shapes.len(),
            brute.pairs.len(),
            colliding as f64 / STATES as f64,
        );

        group.throughput(Throughput::Elements((STATES * brute.pairs.len()) as u64));
        group.bench_function(format!("{label}/kinscene"), |b| {
            b.iter(|| {
                for data in &datas {
                    black_box(collisions(model, black_box(data), &settings).expect("collisions"));
                }
            })
        });
        group.bench_function(format!("{label}/parry_brute_force"), |b| {
            b.iter(|| {
                for data in &datas {
                    black_box(brute.collisions(black_box(data)));
                }
            })
        });
    }
    group.finish();
}

// ---------------------------------------------------------------------------------------------
// Sweeps

/// A full-range motion of one joint, the others at `state`.
struct Motion {
    state: State,
    joint: JointId,
    a: f64,
    b: f64,
}

/// The paper's feasibility check of one motion: at 6 evenly spaced values from `a` to `b`, does
/// the world AABB of any moving part overlap that of another body (same pairs as ours)?
/// Returns true for "free".
struct Paper<'a> {
    model: &'a SceneModel,
    brute: &'a Brute,
}

impl Paper<'_> {
    fn aabb(shapes: &[BruteShape], world_from_owner: &Isometry3<f64>) -> Option<Aabb> {
        shapes
            .iter()
            .map(|s| {
                s.shape
                    .compute_aabb(&pose(&(world_from_owner * s.owner_from_parry)))
            })
            .reduce(|x, y| x.merged(&y))
    }

    fn is_free(&self, data: &mut SceneData, m: &Motion) -> bool {
        forward_kinematics(self.model, data, &m.state).expect("fk");
        let axis = joint_axis(self.model, data, m.joint).expect("joint");
        let theta0 = m.state.as_slice()[m.joint.index()];
        let root = &self.model.parts()[m.joint.part().index()];
        let moving = root.subtree();
        let (first, end) = (root.id().index(), root.id().index() + moving.len());
        let parent = match root.parent() {
            Parent::Part(p) => Some(p.index()),
            Parent::Base => None,
        };
        // Other bodies at the state: every part outside the subtree except the root's parent,
        // and every base shape.
        let fixed: Vec<Aabb> = (0..self.model.parts().len())
            .filter(|&j| (j < first || j >= end) && Some(j) != parent)
            .filter_map(|j| Self::aabb(&self.brute.parts[j], &data.world_from_parts()[j]))
            .chain(self.brute.base.iter().map(|(s, p)| s.shape.compute_aabb(p)))
            .collect();
        for k in 0..PAPER_SAMPLES {
            let theta = m.a + (m.b - m.a) * k as f64 / (PAPER_SAMPLES - 1) as f64;
            let motion = axis.displacement(theta - theta0);
            for i in first..end {
                let Some(part) =
                    Self::aabb(&self.brute.parts[i], &(motion * data.world_from_parts()[i]))
                else {
                    continue;
                };
                if fixed.iter().any(|f| f.intersects(&part)) {
                    return false;
                }
            }
        }
        true
    }
}

fn sweep(c: &mut Criterion) {
    let mut runner = TestRunner::deterministic();
    let dense = generated_scene(&mut runner, QUERY_PARTS, 2);
    let spread_scene = spread(&dense, SPREAD);
    let settings = SweepSettings::default();
    let mut group = c.benchmark_group("scene_sweep");
    group.sample_size(10).sampling_mode(SamplingMode::Flat);
    for (label, model) in [("dense", &dense), ("spread", &spread_scene)] {
        // Random (state, joint) pairs whose moving subtree has geometry and is clear of every
        // other body at the start value `a`, as a planner would ask (a motion that starts in
        // collision is rejected at its first sample, one without geometry is trivially free:
        // neither measures a sweep).
        let mut data = SceneData::new(model);
        let mut motions = Vec::new();
        let mut drawn = 0;
        while motions.len() < MOTIONS && drawn < 1000 * MOTIONS {
            drawn += 1;
            let state = draw(&mut runner, generators::state(model));
            let k = draw(&mut runner, 0..model.nq());
            let root = &model.parts()[k];
            if root
                .subtree()
                .all(|p| model.parts()[p.index()].colliders().is_empty())
            {
                continue;
            }
            let joint = root.joint();
            let limits = model.joints()[k].limits;
            let m = Motion {
                state,
                joint,
                a: limits.lower,
                b: limits.upper,
            };
            let start =
                check_joint_motion(model, &mut data, &m.state, m.joint, m.a, m.a, &settings)
                    .expect("sweep");
            if start.is_free() {
                motions.push(m);
            }
        }
        let brute = Brute::new(model);
        let paper = Paper {
            model,
            brute: &brute,
        };
        // Verdicts: [ours free, collision, inconclusive] × [paper free, paper blocked].
        let mut table = [[0usize; 2]; 3];
        let mut samples = 0;
        for m in &motions {
            let ours = check_joint_motion(model, &mut data, &m.state, m.joint, m.a, m.b, &settings)
                .expect("sweep");
            samples += ours.samples;
            let row = match ours.status {
                SweepStatus::Free => 0,
                SweepStatus::Collision { .. } => 1,
                SweepStatus::Inconclusive { .. } => 2,
            };
            table[row][usize::from(!paper.is_free(&mut data, m))] += 1;
        }
        println!(
            "scene_sweep/{label}: {} full-range motions clear at their start ({drawn} drawn), \
             {:.1} samples per sweep on average; \
             [paper free, paper blocked]: ours free {:?}, collision {:?}, inconclusive {:?}; \
             paper free but ours finds a collision: {}",
            motions.len(),
            samples as f64 / motions.len() as f64,
            table[0],
            table[1],
            table[2],
            table[1][0],
        );

        group.throughput(Throughput::Elements(motions.len() as u64));
        group.bench_function(format!("{label}/kinscene"), |b| {
            b.iter(|| {
                for m in &motions {
                    black_box(
                        check_joint_motion(
                            model, &mut data, &m.state, m.joint, m.a, m.b, &settings,
                        )
                        .expect("sweep"),
                    );
                }
            })
        });
        group.bench_function(format!("{label}/paper_6_aabbs"), |b| {
            b.iter(|| {
                for m in &motions {
                    black_box(paper.is_free(&mut data, m));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(scene, fk, collision, sweep);
criterion_main!(scene);
