//! The base pose near the navigation grid's boundary, decided in exact geometry: a slot a
//! little wider than the robot's disc that the 5 cm grid closes.
//!
//! Geometry (all hand-derived; robot radius r = 0.3 m, the default boundary clearance
//! m = 0.01 m, grid cells of 0.05 m on explicit bounds [-2.5, 2.5] × [-1.5, 2.5], so cell
//! edges lie on multiples of 0.05 and centres on odd multiples of 0.025):
//! - two walls (base boxes, z in [0, 1]) span y in [0, 1.2] and |x| in [w, 1], so the slot
//!   between them is 2w wide;
//! - at the slot's back a panel (a part, box |x| <= 0.25, y in [1.21, 1.26], z in [0.2, 0.9])
//!   slides up along z by up to 0.3 m; its handle is at (0, 1.205) facing -y, at height
//!   0.55 to 0.85 (inside the default grasp band).
//!
//! The handle is operable only from inside the slot: a base must lie in front of it (y <=
//! 1.205) within 0.9 m of it, so y >= 0.305 with |x| < w: inside the walls' y-range; beside
//! the walls (|x| >= 1.31) or before them (y <= -0.31) it is farther than 0.9 m.
//!
//! In exact geometry a base at (x, y) inside the slot clears the walls by `w − |x| − r`, so a
//! pose with clearance m exists iff `w >= r + m = 0.31`. On the grid a wall's face at `x = w`
//! (0.3 < w < 0.35) marks the square [0.30, 0.35] it touches, and the inflation blocks every
//! centre within r of it: |x| >= 0.30 − 0.3 = 0, every column of the slot. So the grid alone
//! (`boundary_clearance: None`, the task layer's previous behaviour: no cell is freed, each
//! base pose is a cell centre) finds the move infeasible for any such w.
//!
//! - w = 0.3225 (the slot 2.5 cm wider than 2(r + m)): the base poses with clearance >= m are
//!   |x| <= 0.0125 — no cell centre (the nearest columns are at ±0.025), but the 5 × 5
//!   witness points of the columns at ±0.025 include x = 0 (clearance 0.0225). Feasible.
//! - w = 0.3075 (3 cm narrower): the best clearance is 0.0075 < m. Infeasible.

use kinscene::scene::nav::{GridBounds, NavGridSettings};
use kinscene::scene::{
    BaseShape, Handle, Joint, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape,
};
use kinscene::task::{Outcome, Step, TaskSettings, validate};
use nalgebra::{Isometry3, Point2, Point3, Vector3};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::shape::{Cuboid, Cylinder};

use super::cases::{problem, run, solved};

const RADIUS: f64 = 0.3;
const CLEARANCE: f64 = 0.01;
/// The grid's height band (the default navigation settings).
const BAND: [f64; 2] = [0.01, 2.0];

/// The boxes of the scene at the start (the panel down): centre and half extents.
fn boxes(w: f64) -> Vec<([f64; 3], [f64; 3])> {
    let half = (1.0 - w) / 2.0;
    vec![
        ([-(w + half), 0.6, 0.5], [half, 0.6, 0.5]),
        ([w + half, 0.6, 0.5], [half, 0.6, 0.5]),
        ([0.0, 1.235, 0.55], [0.25, 0.025, 0.35]),
    ]
}

fn slot(w: f64) -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.nav_settings(NavGridSettings {
        bounds: Some(GridBounds {
            min: Point2::new(-2.5, -1.5),
            max: Point2::new(2.5, 2.5),
        }),
        ..NavGridSettings::default()
    });
    for (name, (c, h)) in ["left", "right"].iter().zip(boxes(w)) {
        b.add_base_shape(BaseShape::new(
            *name,
            Shape::cuboid(Vector3::new(h[0], h[1], h[2])),
            Isometry3::translation(c[0], c[1], c[2]),
        ));
    }
    b.add_part(
        PartSpec::on_base(
            "panel",
            Joint::prismatic(
                "lift",
                Point3::new(0.0, 1.235, 0.0),
                Vector3::z(),
                Limits::new(0.0, 0.3),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.5, 0.05, 0.7)),
            Isometry3::translation(0.0, 0.0, 0.55),
        )
        .with_handle(Handle::new(
            "panel_handle",
            Point3::new(0.0, -0.03, 0.55),
            -Vector3::y(),
        )),
    );
    b.build().expect("the slot scene is valid")
}

const GOAL: &str = "[goal]\nlift = { min = 0.25 }\n[robot]\nbase = [0.0, -1.0, 0.0]";

/// Parry's distance from the robot's footprint at `(x, y)` (a vertical cylinder of the robot
/// radius spanning the height band) to a box.
fn footprint_distance(x: f64, y: f64, (c, h): ([f64; 3], [f64; 3])) -> f64 {
    let half = (BAND[1] - BAND[0]) / 2.0;
    let s = std::f64::consts::FRAC_1_SQRT_2;
    // Parry's cylinder runs along y: a quarter turn about x stands it up.
    let upright = Rotation::from_xyzw(s, 0.0, 0.0, s);
    let robot = Pose::from_parts(Vector::new(x, y, BAND[0] + half), upright);
    let shape = Pose::from_parts(Vector::new(c[0], c[1], c[2]), Rotation::IDENTITY);
    parry3d_f64::query::distance(
        &robot,
        &Cylinder::new(half, RADIUS),
        &shape,
        &Cuboid::new(Vector::new(h[0], h[1], h[2])),
    )
    .expect("cylinder-box distance is supported")
    .distance
}

#[test]
fn a_slot_the_grid_closes_is_operable_from_an_exact_witness() {
    let w = 0.3225;
    let model = slot(w);
    let problem = problem(&model, GOAL);
    // The grid alone (the previous behaviour) closes the slot.
    let grid_only = TaskSettings {
        boundary_clearance: None,
        ..TaskSettings::default()
    };
    let r = run(&model, &problem, &grid_only);
    assert!(
        matches!(r.outcome, Outcome::Infeasible(_)),
        "the grid closes the slot: {:?}",
        r.outcome
    );
    let settings = TaskSettings::default();
    assert_eq!(settings.boundary_clearance, Some(CLEARANCE));
    let r = run(&model, &problem, &settings);
    // `solved` also runs the independent validator (its own parry queries).
    let p = solved(&model, &problem, &settings, &r);
    assert_eq!(p.steps.len(), 1, "{p:#?}");
    let [x, y, _] = p.steps[0].base.expect("the search records its base pose");
    // Hand-derived: inside the slot, |x| <= w − r − m, in front of the handle within reach.
    assert!(x.abs() <= w - RADIUS - CLEARANCE + 1e-12, "x = {x}");
    assert!((0.305..=1.205).contains(&y), "y = {y}");
    // Not a cell centre: no centre of the slot keeps the clearance.
    assert!(
        ((x + 2.5) / 0.05 - 0.5).fract().abs() > 1e-9,
        "x = {x} is a cell centre"
    );
    // Independent check: parry's distance from the footprint to every box is at least m.
    for b in boxes(w) {
        let d = footprint_distance(x, y, b);
        assert!(
            d >= CLEARANCE - 1e-9,
            "footprint at ({x}, {y}) is {d} from {b:?}"
        );
    }
}

#[test]
fn a_slot_three_centimetres_narrower_stays_closed() {
    let w = 0.3075;
    let model = slot(w);
    let problem = problem(&model, GOAL);
    // Independent check of the premise: at the slot's middle, the best place, parry's
    // distance to a wall is w − r = 0.0075 < m.
    let d = footprint_distance(0.0, 0.5, boxes(w)[0]);
    assert!((d - (w - RADIUS)).abs() < 1e-6 && d < CLEARANCE, "d = {d}");
    let r = run(&model, &problem, &TaskSettings::default());
    assert!(
        matches!(r.outcome, Outcome::Infeasible(_)),
        "no base pose clears the walls by {CLEARANCE}: {:?}",
        r.outcome
    );
}

/// The validator's exact rule on hand-built plans: the base pose (0, 0.5) (facing the handle)
/// clears the walls by w − r: 0.0225 in the wide slot (accepted, the chain of straight moves
/// down the slot's middle reaches the open floor), 0.0075 < m in the narrow one (rejected as
/// occupied), and the grid alone rejects it in both.
#[test]
fn the_validator_decides_a_recorded_pose_in_the_slot_exactly() {
    let step = Step {
        joint: "lift".into(),
        from: 0.0,
        to: 0.3,
        handle: None,
        base: Some([0.0, 0.5, std::f64::consts::FRAC_PI_2]),
        travel: 0.0,
        cost: 0.0,
    };
    let grid_only = TaskSettings {
        boundary_clearance: None,
        ..TaskSettings::default()
    };
    for (w, accepted) in [(0.3225, true), (0.3075, false)] {
        let model = slot(w);
        let problem = problem(&model, GOAL);
        let steps = [step.clone()];
        let v = validate(&model, &problem, &steps, &TaskSettings::default()).expect("fits");
        assert_eq!(v.valid, accepted, "w = {w}: {v:?}");
        if !accepted {
            let (_, why) = v.first_failure.expect("a failing step");
            assert!(why.contains("occupied before the move"), "{why}");
        }
        let v = validate(&model, &problem, &steps, &grid_only).expect("fits");
        assert!(!v.valid, "the grid alone rejects it (w = {w})");
    }
}
