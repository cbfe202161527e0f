//! Kitchen-like task scenes, goals and start states for the task-layer tests and benches.
//!
//! Reusable from benches through `#[path = ".../tests/task/generators.rs"] mod generators;`;
//! depends only on `kinscene`, `nalgebra` and `proptest`.
//!
//! # Layout
//! A rectangular room `[0, W] × [0, D]` (world frame, z up) closed by walls. Base cabinets
//! (carcass depth [`DEPTH`], height [`HEIGHT`]) stand in *runs* along the walls, counter-
//! clockwise: south (along y = 0), east, north, west. A run has a frame `world_from_run`:
//! local x along the wall (from 0 to the run's length), local y pointing into the room with
//! y = 0 the plane of the carcass fronts (carcasses fill y ∈ [−DEPTH, 0]), local z up.
//! Between two runs that meet at a corner, the earlier run ends in a corner block and the
//! later starts with a filler; the filler width `f` sets how close the two corner units'
//! doors come (see *corner pairs*).
//!
//! # Units
//! Each unit spans `[x0, x0 + width]` of its run, every moving part sits [`GAP`] clear of
//! every carcass panel and of its neighbours in the closed state, and every part carries one
//! handle named `<part>_handle`, [`HANDLE_OUT`] in front of its front, normal pointing into
//! the room (the tray of [`Rack::OnDoor`]: along its slide, i.e. into the room once its door
//! is open).
//! - **Door**: a solid carcass box and a door ([`FRONT`] thick, from z = [`DOOR_BOTTOM`] to
//!   `HEIGHT − GAP`) on a vertical hinge at the front face, at one edge
//!   ([`Hinge::Left`] / [`Hinge::Right`] as seen from the room), opening into the room,
//!   limits `[0, upper]` (π/2, or 2.0 rad for doors that swing past square and can hit an
//!   opened neighbour). Joint `<part>_hinge`.
//! - **Double door**: two such doors hinged at the outer edges, meeting in the middle.
//! - **Drawers**: a hollow carcass (side, back, bottom and top panels [`PANEL`] thick) with
//!   1–3 drawers stacked in it, each a front plus a body inside the carcass, on a prismatic
//!   joint `<part>_slide` pulling toward the room, limits `[0, travel]`.
//! - **Dishwasher**: a hollow carcass, a door on a horizontal hinge along its bottom front
//!   edge (z = [`DW_HINGE_Z`]) falling open toward the room (`<part>_hinge`, `[0, π/2]`; open
//!   it lies flat just above the floor), and a rack (`<part>_rack_slide`):
//!   [`Rack::OnBase`]: a basket in the tub on a base slide toward the room, `[0, 0.45]` m,
//!   above the open door — it cannot come out while the door is closed;
//!   [`Rack::OnDoor`]: a tray on the inside of the door sliding along the door, `[0, 0.35]` m —
//!   with the door closed it slides up and hits the carcass top beyond 0.23 m.
//!
//! # Corner pairs
//! Where two runs meet, the corner units may be single doors (limits `[0, π/2]`) both hinged
//! at the corner with a filler of 0.15–0.25 m: each door opens freely on its own, but with
//! both opened past about 1 rad their leaves cross (listed in [`Kitchen::corner_pairs`]).
//! Other corners get a 5 cm filler; a door there hinged toward the corner and allowed past
//! square (2 rad) hits the other run's carcass before its limit.
//!
//! # Island
//! Optionally a peninsula (a fixed 0.9 m high block named `island`) from the west wall runs
//! parallel to the south run at 1.05–1.35 m from its fronts, leaving a dead-end corridor open
//! to the east: a door opened in the corridor can cut the robot off from the units behind it.
//! There is no west run then. The robot starts in the open area north of it (or in the
//! middle of the room without island), at least 1.2 m from every front.

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_2;

use kinscene::scene::collision::{CollisionSettings, collisions, distances};
use kinscene::scene::nav::{NavGridSettings, occupancy};
use kinscene::scene::{
    BaseShape, Handle, Joint, JointKind, Limits, PartSpec, SceneData, SceneModel,
    SceneModelBuilder, Shape, State, forward_kinematics,
};
use kinscene::task::{DEFAULT_ROBOT_RADIUS, GoalSpec, RobotSpec, TargetSpec, TargetTable};
use nalgebra::{Isometry3, Point2, Point3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;

/// Carcass depth (m).
pub const DEPTH: f64 = 0.6;
/// Carcass height (m).
pub const HEIGHT: f64 = 0.85;
/// Clearance (m) between a closed part and any carcass panel or neighbouring part.
pub const GAP: f64 = 0.004;
/// Carcass panel thickness (m).
pub const PANEL: f64 = 0.018;
/// Thickness of door and drawer fronts (m).
pub const FRONT: f64 = 0.02;
/// Distance of a handle in front of its front (m).
pub const HANDLE_OUT: f64 = 0.03;
/// Height of a door's bottom edge (plinth) (m).
pub const DOOR_BOTTOM: f64 = 0.1;
/// Height of door handles (m).
pub const HANDLE_Z: f64 = 0.7;
/// Height of a dishwasher door's hinge line (m).
pub const DW_HINGE_Z: f64 = 0.05;
/// Wall thickness and height (m).
pub const WALL: [f64; 2] = [0.1, 2.4];
/// Smallest free distance between opposite runs' fronts (m).
pub const MIN_FREE: f64 = 2.4;
/// Depth of the peninsula (m).
pub const ISLAND_DEPTH: f64 = 0.9;

/// A small deterministic generator (SplitMix64): the kitchen is a pure function of its
/// [`KitchenParams`], so proptest shrinks the parameters, not the geometry.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
}

/// Where a vertical door is hinged, as seen from the room (facing the wall).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hinge {
    /// At the unit's edge with the larger run coordinate x (the left edge seen from the room).
    Left,
    /// At the unit's edge with the smaller run coordinate x.
    Right,
}

/// How a dishwasher's rack is mounted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rack {
    /// A basket in the tub on a slide fixed to the base.
    OnBase,
    /// A tray riding on the inside of the door (a child of the door).
    OnDoor,
}

/// What a unit contains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UnitKind {
    /// One door.
    Door {
        /// Hinge side.
        hinge: Hinge,
        /// Upper limit (rad).
        upper: f64,
    },
    /// Two doors hinged at the outer edges.
    DoubleDoor {
        /// Upper limit of both (rad).
        upper: f64,
    },
    /// Stacked drawers.
    Drawers {
        /// 1–3.
        count: usize,
        /// Pull-out limit (m).
        travel: f64,
    },
    /// Dishwasher door and rack.
    Dishwasher {
        /// Rack mount.
        rack: Rack,
    },
    /// A fixed panel (no parts).
    Blank,
}

impl UnitKind {
    /// Number of parts the unit adds.
    pub fn parts(&self) -> usize {
        match *self {
            UnitKind::Door { .. } => 1,
            UnitKind::DoubleDoor { .. } | UnitKind::Dishwasher { .. } => 2,
            UnitKind::Drawers { count, .. } => count,
            UnitKind::Blank => 0,
        }
    }
}

/// A unit of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// Contents.
    pub kind: UnitKind,
    /// Width along the run (m).
    pub width: f64,
}

fn iso(frame: &Isometry3<f64>, x: f64, y: f64, z: f64) -> Isometry3<f64> {
    frame * Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::identity())
}

/// The box spanning `min..max` in some frame: its shape and pose in that frame.
pub fn aabb(min: [f64; 3], max: [f64; 3]) -> (Shape, Isometry3<f64>) {
    (
        Shape::box_size(Vector3::new(
            max[0] - min[0],
            max[1] - min[1],
            max[2] - min[2],
        )),
        Isometry3::translation(
            0.5 * (min[0] + max[0]),
            0.5 * (min[1] + max[1]),
            0.5 * (min[2] + max[2]),
        ),
    )
}

/// Adds a fixed box spanning `min..max` in `frame` to the base map.
pub fn add_box(
    b: &mut SceneModelBuilder,
    name: impl Into<String>,
    frame: &Isometry3<f64>,
    min: [f64; 3],
    max: [f64; 3],
) {
    let (shape, pose) = aabb(min, max);
    b.add_base_shape(BaseShape::new(name, shape, frame * pose));
}

/// A part with one box collider spanning `min..max` in its frame.
fn with_box(p: PartSpec, min: [f64; 3], max: [f64; 3]) -> PartSpec {
    let (shape, pose) = aabb(min, max);
    p.with_collider(shape, pose)
}

/// Solid carcass of `[x0, x1]`.
fn solid_carcass(b: &mut SceneModelBuilder, run: &Isometry3<f64>, prefix: &str, x0: f64, x1: f64) {
    add_box(
        b,
        format!("{prefix}_carcass"),
        run,
        [x0, -DEPTH, 0.0],
        [x1, 0.0, HEIGHT],
    );
}

/// Hollow carcass of `[x0, x1]`, open at the front: sides, back, bottom, top.
fn hollow_carcass(b: &mut SceneModelBuilder, run: &Isometry3<f64>, prefix: &str, x0: f64, x1: f64) {
    let (d, h, p) = (DEPTH, HEIGHT, PANEL);
    add_box(
        b,
        format!("{prefix}_side_a"),
        run,
        [x0, -d, 0.0],
        [x0 + p, 0.0, h],
    );
    add_box(
        b,
        format!("{prefix}_side_b"),
        run,
        [x1 - p, -d, 0.0],
        [x1, 0.0, h],
    );
    add_box(
        b,
        format!("{prefix}_back"),
        run,
        [x0 + p, -d, 0.0],
        [x1 - p, -d + p, h],
    );
    add_box(
        b,
        format!("{prefix}_bottom"),
        run,
        [x0 + p, -d + p, 0.0],
        [x1 - p, 0.0, p],
    );
    add_box(
        b,
        format!("{prefix}_top"),
        run,
        [x0 + p, -d + p, h - p],
        [x1 - p, 0.0, h],
    );
}

/// A vertical door `name` covering `[lo, hi]` of the run (its closed extent), hinged at the
/// front face, with joint `<name>_hinge` and handle `<name>_handle` 5 cm from the free edge.
pub fn door(
    run: &Isometry3<f64>,
    name: &str,
    lo: f64,
    hi: f64,
    hinge: Hinge,
    upper: f64,
) -> PartSpec {
    let w = hi - lo;
    // Right hinge (at lo): the leaf along +x of the joint frame, rotating about +z takes +x
    // to +y (into the room). Left hinge (at hi): the leaf along −x, rotating about −z.
    let (pivot, axis, sign) = match hinge {
        Hinge::Right => (lo, Vector3::z(), 1.0),
        Hinge::Left => (hi, -Vector3::z(), -1.0),
    };
    let joint = Joint::new(
        format!("{name}_hinge"),
        JointKind::Revolute,
        iso(run, pivot, GAP + FRONT, 0.0),
        axis,
        Limits::new(0.0, upper),
    );
    let (x0, x1) = if sign > 0.0 { (0.0, w) } else { (-w, 0.0) };
    with_box(
        PartSpec::on_base(name, joint),
        [x0, -FRONT, DOOR_BOTTOM],
        [x1, 0.0, HEIGHT - GAP],
    )
    .with_handle(Handle::new(
        format!("{name}_handle"),
        Point3::new(sign * (w - 0.05), HANDLE_OUT, HANDLE_Z),
        Vector3::y(),
    ))
}

/// Adds `unit` at `[x0, x0 + width]` of the run with frame `run`; part names start with
/// `prefix`. Returns the names of the parts added.
pub fn add_unit(
    b: &mut SceneModelBuilder,
    run: &Isometry3<f64>,
    x0: f64,
    prefix: &str,
    unit: &Unit,
) -> Vec<String> {
    let x1 = x0 + unit.width;
    let mut parts = Vec::new();
    match unit.kind {
        UnitKind::Blank => solid_carcass(b, run, prefix, x0, x1),
        UnitKind::Door { hinge, upper } => {
            solid_carcass(b, run, prefix, x0, x1);
            let name = format!("{prefix}_door");
            b.add_part(door(run, &name, x0 + GAP, x1 - GAP, hinge, upper));
            parts.push(name);
        }
        UnitKind::DoubleDoor { upper } => {
            solid_carcass(b, run, prefix, x0, x1);
            let xm = 0.5 * (x0 + x1);
            let (a, c) = (format!("{prefix}_door_a"), format!("{prefix}_door_b"));
            b.add_part(door(run, &a, x0 + GAP, xm - GAP, Hinge::Right, upper));
            b.add_part(door(run, &c, xm + GAP, x1 - GAP, Hinge::Left, upper));
            parts.extend([a, c]);
        }
        UnitKind::Drawers { count, travel } => {
            hollow_carcass(b, run, prefix, x0, x1);
            let (lo, hi) = (PANEL, HEIGHT - PANEL);
            let slot = (hi - lo) / count as f64;
            let xc = 0.5 * (x0 + x1);
            for k in 0..count {
                let (z0, z1) = (lo + k as f64 * slot + GAP, lo + (k + 1) as f64 * slot - GAP);
                let zc = 0.5 * (z0 + z1);
                let name = format!("{prefix}_drawer{k}");
                let joint = Joint::new(
                    format!("{name}_slide"),
                    JointKind::Prismatic,
                    iso(run, xc, 0.0, zc),
                    Vector3::y(),
                    Limits::new(0.0, travel),
                );
                let half = 0.5 * unit.width;
                let p = with_box(
                    PartSpec::on_base(&name, joint),
                    [-half + GAP, GAP, z0 - zc],
                    [half - GAP, GAP + FRONT, z1 - zc],
                );
                // The body: inside the carcass between the panels, up to the front.
                let p = with_box(
                    p,
                    [-half + PANEL + GAP, -DEPTH + PANEL + GAP, z0 - zc],
                    [half - PANEL - GAP, GAP, z1 - zc - 0.03],
                )
                .with_handle(Handle::new(
                    format!("{name}_handle"),
                    Point3::new(0.0, GAP + FRONT + HANDLE_OUT, 0.0),
                    Vector3::y(),
                ));
                b.add_part(p);
                parts.push(name);
            }
        }
        UnitKind::Dishwasher { rack } => {
            hollow_carcass(b, run, prefix, x0, x1);
            let name = format!("{prefix}_dw");
            let w = unit.width - 2.0 * GAP;
            let hd = HEIGHT - GAP - DW_HINGE_Z;
            // Joint frame on the bottom front edge; rotating about −x tips the top toward +y.
            let joint = Joint::new(
                format!("{name}_hinge"),
                JointKind::Revolute,
                iso(run, x0 + GAP, GAP + FRONT, DW_HINGE_Z),
                -Vector3::x(),
                Limits::new(0.0, FRAC_PI_2),
            );
            b.add_part(
                with_box(
                    PartSpec::on_base(&name, joint),
                    [0.0, -FRONT, 0.0],
                    [w, 0.0, hd],
                )
                .with_handle(Handle::new(
                    format!("{name}_handle"),
                    Point3::new(0.5 * w, HANDLE_OUT, hd - 0.05),
                    Vector3::y(),
                )),
            );
            parts.push(name.clone());
            let rack_name = format!("{prefix}_rack");
            let half = 0.5 * unit.width - PANEL - 2.0 * GAP;
            let spec = match rack {
                Rack::OnBase => {
                    // Basket bottom 3 cm above the open door's upper face.
                    let z0 = DW_HINGE_Z + FRONT + 0.03;
                    let joint = Joint::new(
                        format!("{rack_name}_slide"),
                        JointKind::Prismatic,
                        iso(run, 0.5 * (x0 + x1), -GAP, z0),
                        Vector3::y(),
                        Limits::new(0.0, 0.45),
                    );
                    with_box(
                        PartSpec::on_base(&rack_name, joint),
                        [-half, -(DEPTH - PANEL - 2.0 * GAP), 0.0],
                        [half, 0.0, 0.2],
                    )
                    .with_handle(Handle::new(
                        format!("{rack_name}_handle"),
                        Point3::new(0.0, 0.0, 0.2),
                        Vector3::y(),
                    ))
                }
                Rack::OnDoor => {
                    // A tray 8 cm deep behind the door, 0.25–0.55 m up the door, sliding along it.
                    let joint = Joint::new(
                        format!("{rack_name}_slide"),
                        JointKind::Prismatic,
                        Isometry3::translation(0.5 * w, -FRONT - GAP, 0.25),
                        Vector3::z(),
                        Limits::new(0.0, 0.35),
                    );
                    with_box(
                        PartSpec::on_part(&rack_name, &name, joint),
                        [-half, -0.08, 0.0],
                        [half, 0.0, 0.3],
                    )
                    .with_handle(Handle::new(
                        format!("{rack_name}_handle"),
                        Point3::new(0.0, -0.04, 0.3),
                        Vector3::z(),
                    ))
                }
            };
            b.add_part(spec);
            parts.push(rack_name);
        }
    }
    parts
}

/// Parameters of [`kitchen`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KitchenParams {
    /// Number of parts (joints).
    pub parts: usize,
    /// Seed of the layout.
    pub seed: u64,
    /// Whether to add the peninsula.
    pub island: bool,
    /// Whether corners may hold conflicting door pairs.
    pub corner_pairs: bool,
}

/// A generated kitchen.
#[derive(Debug, Clone)]
pub struct Kitchen {
    /// The scene.
    pub model: SceneModel,
    /// A robot start pose (x, y, yaw), free in the all-closed state.
    pub robot: [f64; 3],
    /// Room size W × D (m).
    pub size: [f64; 2],
    /// Joint names of vertical-axis doors.
    pub doors: Vec<String>,
    /// Joint names of corner door pairs whose leaves cross when both are opened past 1 rad.
    pub corner_pairs: Vec<(String, String)>,
    /// Whether the peninsula is present.
    pub island: bool,
    /// The parameters.
    pub params: KitchenParams,
}

fn random_unit(rng: &mut Rng, max_parts: usize) -> Unit {
    loop {
        let upper = if rng.chance(0.25) { 2.0 } else { FRAC_PI_2 };
        let hinge = if rng.chance(0.5) {
            Hinge::Left
        } else {
            Hinge::Right
        };
        let u = match rng.below(20) {
            0..=5 => Unit {
                kind: UnitKind::Door { hinge, upper },
                width: rng.range(0.4, 0.6),
            },
            6..=8 => Unit {
                kind: UnitKind::DoubleDoor { upper },
                width: rng.range(0.8, 1.0),
            },
            9..=15 => Unit {
                kind: UnitKind::Drawers {
                    count: 1 + rng.below(3),
                    travel: rng.range(0.3, 0.45),
                },
                width: rng.range(0.4, 0.8),
            },
            _ => Unit {
                kind: UnitKind::Dishwasher {
                    rack: if rng.chance(0.6) {
                        Rack::OnBase
                    } else {
                        Rack::OnDoor
                    },
                },
                width: 0.6,
            },
        };
        if u.kind.parts() <= max_parts {
            return u;
        }
    }
}

/// The frame of run `side` (0 south, 1 east, 2 north, 3 west) in a `w × d` room.
pub fn run_frame(side: usize, w: f64, d: f64) -> Isometry3<f64> {
    let (x, y, yaw) = match side {
        0 => (0.0, DEPTH, 0.0),
        1 => (w - DEPTH, 0.0, FRAC_PI_2),
        2 => (w, d - DEPTH, std::f64::consts::PI),
        _ => (DEPTH, d, -FRAC_PI_2),
    };
    Isometry3::from_parts(
        Translation3::new(x, y, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
    )
}

/// Adds the four walls of a `w × d` room.
pub fn add_walls(b: &mut SceneModelBuilder, w: f64, d: f64) {
    let [t, h] = WALL;
    let id = Isometry3::identity();
    add_box(b, "wall_south", &id, [-t, -t, 0.0], [w + t, 0.0, h]);
    add_box(b, "wall_north", &id, [-t, d, 0.0], [w + t, d + t, h]);
    add_box(b, "wall_west", &id, [-t, 0.0, 0.0], [0.0, d, h]);
    add_box(b, "wall_east", &id, [w, 0.0, 0.0], [w + t, d, h]);
}

/// Navigation settings of generated scenes: default resolution and height band, 0.3 m
/// padding (the walls bound the room anyway).
pub fn nav_settings() -> NavGridSettings {
    NavGridSettings {
        padding: 0.3,
        ..NavGridSettings::default()
    }
}

/// The kitchen of `params` (deterministic).
pub fn kitchen(params: &KitchenParams) -> Kitchen {
    let mut rng = Rng::new(params.seed);
    // 1. Units with exactly `params.parts` parts.
    let mut units = Vec::new();
    let mut left = params.parts;
    while left > 0 {
        let u = random_unit(&mut rng, left);
        left -= u.kind.parts();
        units.push(u);
    }
    // 2. Runs: south, east, north (, west without island), each filled up to about a quarter
    //    (third) of the total width.
    let sides = if params.island { 3 } else { 4 };
    let total: f64 = units.iter().map(|u| u.width).sum();
    let target = (total / sides as f64).max(1.2);
    let mut runs: Vec<Vec<Unit>> = vec![Vec::new(); 4];
    let mut s = 0;
    for u in units {
        let len: f64 = runs[s].iter().map(|u| u.width).sum();
        if s + 1 < sides && !runs[s].is_empty() && len + u.width > target + 0.3 {
            s += 1;
        }
        runs[s].push(u);
    }
    // 3. Corners: corner k joins the end of run k and the start of run k + 1.
    let mut filler = [0.05; 4];
    let mut corner_pair = [false; 4];
    for k in 0..4 {
        let next = (k + 1) % 4;
        // Both runs need two units, so that no unit belongs to two corners.
        if runs[k].len() < 2 || runs[next].len() < 2 {
            continue;
        }
        if !params.corner_pairs || !rng.chance(0.7) {
            continue;
        }
        // Bring a single door of each run to the corner (a swap keeps the part count; the
        // other end of each run stays put, it may belong to another corner).
        let is_door = |u: &Unit| matches!(u.kind, UnitKind::Door { .. });
        let n = runs[k].len();
        if let Some(i) = (1..n).rev().find(|&i| is_door(&runs[k][i])) {
            runs[k].swap(i, n - 1);
        }
        let m = runs[next].len();
        if let Some(i) = (0..m - 1).find(|&i| is_door(&runs[next][i])) {
            runs[next].swap(i, 0);
        }
        let (a, c) = (runs[k][n - 1].kind, runs[next][0].kind);
        if let (UnitKind::Door { .. }, UnitKind::Door { .. }) = (a, c) {
            filler[k] = rng.range(0.15, 0.25);
            corner_pair[k] = true;
            // Past square, a corner door would hit the other run's carcass.
            runs[k][n - 1].kind = UnitKind::Door {
                hinge: Hinge::Left,
                upper: FRAC_PI_2,
            };
            runs[next][0].kind = UnitKind::Door {
                hinge: Hinge::Right,
                upper: FRAC_PI_2,
            };
        }
    }
    let has = |k: usize| !runs[k % 4].is_empty();
    // Start and end blocks of each run: the corner block (DEPTH deep) belongs to the earlier
    // run's end, the filler to both.
    let ends: Vec<(f64, f64)> = (0..4)
        .map(|k| {
            let start = if has(k + 3) {
                DEPTH + filler[(k + 3) % 4]
            } else {
                0.0
            };
            let end = if has(k + 1) { DEPTH + filler[k] } else { 0.0 };
            (start, end)
        })
        .collect();
    let content = |k: usize| -> f64 {
        if runs[k].is_empty() {
            0.0
        } else {
            ends[k].0 + ends[k].1 + runs[k].iter().map(|u| u.width).sum::<f64>()
        }
    };
    // 4. Room size and peninsula.
    let passage = rng.range(1.05, 1.35);
    let open_end = rng.range(1.3, 1.6);
    let north = if has(2) { DEPTH } else { 0.0 };
    let w = content(0).max(content(2)).max(2.0 * DEPTH + MIN_FREE);
    let mut d = content(1).max(content(3)).max(2.0 * DEPTH + MIN_FREE);
    if params.island {
        d = d.max(DEPTH + passage + ISLAND_DEPTH + MIN_FREE + north);
    }
    let mut b = SceneModelBuilder::new();
    b.nav_settings(nav_settings());
    add_walls(&mut b, w, d);
    let mut doors = Vec::new();
    let mut first_last: Vec<(Option<String>, Option<String>)> = vec![(None, None); 4];
    for (k, run) in runs.iter().enumerate() {
        if run.is_empty() {
            continue;
        }
        let frame = run_frame(k, w, d);
        let length = if k % 2 == 0 { w } else { d };
        let (start, end) = ends[k];
        if start > 0.0 {
            add_box(
                &mut b,
                format!("run{k}_start"),
                &frame,
                [0.0, -DEPTH, 0.0],
                [start, 0.0, HEIGHT],
            );
        }
        if end > 0.0 {
            add_box(
                &mut b,
                format!("run{k}_end"),
                &frame,
                [length - end, -DEPTH, 0.0],
                [length, 0.0, HEIGHT],
            );
        }
        // Pad a short run with a blank panel in its middle (the corner units stay at the ends;
        // a single unit keeps its place at the run's start).
        let pad = length - content(k);
        let pad_at = if run.len() >= 2 { run.len() / 2 } else { 1 };
        let mut x = start;
        for (i, u) in run.iter().enumerate() {
            if i == pad_at && pad > 1e-9 {
                let blank = Unit {
                    kind: UnitKind::Blank,
                    width: pad,
                };
                add_unit(&mut b, &frame, x, &format!("r{k}pad"), &blank);
                x += pad;
            }
            let prefix = format!("r{k}u{i}");
            let parts = add_unit(&mut b, &frame, x, &prefix, u);
            if let UnitKind::Door { .. } | UnitKind::DoubleDoor { .. } = u.kind {
                doors.extend(parts.iter().map(|p| format!("{p}_hinge")));
            }
            if i == 0 {
                first_last[k].0 = parts.first().map(|p| format!("{p}_hinge"));
            }
            if i + 1 == run.len() {
                first_last[k].1 = parts.last().map(|p| format!("{p}_hinge"));
            }
            x += u.width;
        }
    }
    let corner_pairs = (0..4)
        .filter(|&k| corner_pair[k])
        .filter_map(|k| Some((first_last[k].1.clone()?, first_last[(k + 1) % 4].0.clone()?)))
        .collect();
    let east = if has(1) { DEPTH } else { 0.0 };
    let robot = if params.island {
        let y0 = DEPTH + passage;
        add_box(
            &mut b,
            "island",
            &Isometry3::identity(),
            [0.0, y0, 0.0],
            [w - east - open_end, y0 + ISLAND_DEPTH, 0.9],
        );
        [0.5 * w, 0.5 * (y0 + ISLAND_DEPTH + d - north), 0.0]
    } else {
        [0.5 * w, 0.5 * d, 0.0]
    };
    let model = b
        .build()
        .expect("generated kitchens are valid scene models");
    Kitchen {
        model,
        robot,
        size: [w, d],
        doors,
        corner_pairs,
        island: params.island,
        params: *params,
    }
}

/// Kitchens with exactly `parts` parts, any seed, with or without island and corner pairs.
pub fn kitchen_strategy(parts: usize) -> impl Strategy<Value = Kitchen> {
    kitchen_strategy_in(parts..=parts)
}

/// Kitchens with a number of parts in `parts`.
pub fn kitchen_strategy_in(
    parts: std::ops::RangeInclusive<usize>,
) -> impl Strategy<Value = Kitchen> {
    (parts, any::<u64>(), any::<bool>(), any::<bool>()).prop_map(
        |(parts, seed, island, corner_pairs)| {
            kitchen(&KitchenParams {
                parts,
                seed,
                island,
                corner_pairs,
            })
        },
    )
}

/// The "open" target of a joint: at least 3/4 of its upper limit.
pub fn open_target(joint: &Joint) -> TargetSpec {
    TargetSpec::Table(TargetTable {
        min: Some(0.75 * joint.limits.upper),
        ..TargetTable::default()
    })
}

/// The "closed" target: exactly 0 (default tolerance).
pub fn closed_target() -> TargetSpec {
    TargetSpec::Value(0.0)
}

/// Goals naming `n_goal_joints` distinct joints of `model` (all of them if it has fewer),
/// each open ([`open_target`], probability 3/4) or closed ([`closed_target`]).
pub fn goal(
    model: &SceneModel,
    n_goal_joints: usize,
) -> impl Strategy<Value = BTreeMap<String, TargetSpec>> + use<> {
    let joints: Vec<Joint> = model.joints().to_vec();
    let n = n_goal_joints.min(joints.len());
    (
        proptest::sample::subsequence(joints, n),
        proptest::collection::vec(prop::bool::weighted(0.75), n),
    )
        .prop_map(|(chosen, open)| {
            chosen
                .iter()
                .zip(open)
                .map(|(j, o)| {
                    let t = if o { open_target(j) } else { closed_target() };
                    (j.name.clone(), t)
                })
                .collect()
        })
}

/// Whether `state` is collision-free and leaves the robot's start cell free (inflated by the
/// default robot radius).
pub fn start_ok(kitchen: &Kitchen, state: &State) -> bool {
    let model = &kitchen.model;
    let mut data = SceneData::new(model);
    if forward_kinematics(model, &mut data, state).is_err() {
        return false;
    }
    let free = collisions(model, &data, &CollisionSettings::default()).is_ok_and(|c| c.is_empty());
    let grid = occupancy(model, &data).and_then(|g| g.inflate(DEFAULT_ROBOT_RADIUS));
    free && grid.is_ok_and(|g| {
        g.cell_of(Point2::new(kitchen.robot[0], kitchen.robot[1]))
            .is_some_and(|(i, j)| !g.is_occupied(i, j))
    })
}

/// Opens the `wanted` joints (name, value) one after another, skipping any that would make
/// the state collide or cover the robot's start; returns the start values kept.
pub fn open_safely(kitchen: &Kitchen, wanted: &[(String, f64)]) -> BTreeMap<String, f64> {
    let model = &kitchen.model;
    let mut state = model.zero_state();
    let mut kept = BTreeMap::new();
    for (name, value) in wanted {
        let mut next = state.clone();
        if next.set_by_name(model, name, *value).is_ok() && start_ok(kitchen, &next) {
            state = next;
            kept.insert(name.clone(), *value);
        }
    }
    kept
}

/// Start values: each vertical door open with probability 0.3, to its upper limit or part way
/// (uniform in 0.3–1 of it), as long as the start stays collision-free and the robot's start
/// cell free (doors violating that stay closed). Other joints start at 0.
pub fn start_state(kitchen: &Kitchen) -> impl Strategy<Value = BTreeMap<String, f64>> + use<> {
    let k = kitchen.clone();
    let n = k.doors.len();
    proptest::collection::vec((prop::bool::weighted(0.3), 0.3..=1.3f64), n).prop_map(
        move |choice| {
            let wanted: Vec<(String, f64)> = k
                .doors
                .iter()
                .zip(choice)
                .filter(|(_, (open, _))| *open)
                .map(|(name, (_, frac))| {
                    let upper = k.model.joints()[k.model.joint_id(name).unwrap().index()]
                        .limits
                        .upper;
                    (name.clone(), frac.min(1.0) * upper)
                })
                .collect();
            open_safely(&k, &wanted)
        },
    )
}

/// The goal document for a kitchen: targets, start values, the kitchen's robot start.
pub fn goal_spec(
    kitchen: &Kitchen,
    goal: BTreeMap<String, TargetSpec>,
    start: BTreeMap<String, f64>,
) -> GoalSpec {
    GoalSpec {
        goal,
        start,
        robot: RobotSpec {
            base: Some(kitchen.robot),
            radius: DEFAULT_ROBOT_RADIUS,
        },
    }
}

/// Kitchen, goal of `n_goal_joints` joints and start values, as a goal document.
pub fn instance(
    parts: std::ops::RangeInclusive<usize>,
    n_goal_joints: std::ops::RangeInclusive<usize>,
) -> impl Strategy<Value = (Kitchen, GoalSpec)> {
    (kitchen_strategy_in(parts), n_goal_joints).prop_flat_map(|(k, n)| {
        let model = k.model.clone();
        (Just(k.clone()), goal(&model, n), start_state(&k)).prop_map(|(k, g, s)| {
            let spec = goal_spec(&k, g, s);
            (k, spec)
        })
    })
}

/// The smallest clearance (m) between checked bodies at `state`, if below `limit`.
pub fn min_clearance(model: &SceneModel, state: &State, limit: f64) -> Option<f64> {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state).ok()?;
    distances(model, &data, &CollisionSettings::default(), limit)
        .ok()?
        .iter()
        .map(|c| c.distance)
        .min_by(f64::total_cmp)
}
