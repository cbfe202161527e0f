//! Ground-truth scenes for the discovery tests: a cabinet carcass with one door or one drawer.

use kinscene::scene::{
    BaseShape, Handle, Joint, JointKind, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape,
};
use nalgebra::{Isometry3, Point3, Vector3};

/// A box from its world extents.
pub fn slab(name: &str, lo: [f64; 3], hi: [f64; 3]) -> BaseShape {
    let c = (Vector3::from(lo) + Vector3::from(hi)) / 2.0;
    let h = (Vector3::from(hi) - Vector3::from(lo)) / 2.0;
    BaseShape::new(
        name,
        Shape::cuboid(h),
        Isometry3::translation(c.x, c.y, c.z),
    )
}

/// The static base: a floor (top at z = 0, below the navigation band) and a solid carcass
/// x in [0, 0.6], y in [0, 0.5], z in [0, 0.8] whose front face is the plane y = 0, facing -y.
pub fn cabinet_base() -> SceneModelBuilder {
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(slab("floor", [-2.0, -3.0, -0.05], [3.0, 2.0, 0.0]));
    b.add_base_shape(slab("carcass", [0.0, 0.0, 0.0], [0.6, 0.5, 0.8]));
    b
}

/// Pivot of the door's hinge (world): the left front edge, as seen by a robot facing +y.
pub const DOOR_PIVOT: [f64; 3] = [0.005, -0.02, 0.05];
/// The door's true axis (world): -z, so that a positive value swings the free (+x) edge
/// towards the robot (-y): rotating +x about -z by a small positive angle gives -y.
pub const DOOR_AXIS: [f64; 3] = [0.0, 0.0, -1.0];

/// The cabinet with a left-hinged door: a 0.59 × 0.02 × 0.70 slab in front of the carcass
/// (world x in [0.005, 0.595], y in [-0.02, 0], z in [0.05, 0.75]); handle 5.5 cm from the
/// free edge, 3 cm proud of the door face, at world (0.54, -0.05, 0.45); limits [0, 1.9].
pub fn door_cabinet() -> SceneModel {
    let mut b = cabinet_base();
    let p = Point3::from(DOOR_PIVOT);
    b.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "door_hinge",
                p,
                Vector3::from(DOOR_AXIS),
                Limits::new(0.0, 1.9),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.295, 0.01, 0.35)),
            Isometry3::translation(0.295, 0.01, 0.35),
        )
        .with_handle(Handle::new(
            "door_handle",
            Point3::new(0.535, -0.03, 0.4),
            -Vector3::y(),
        )),
    );
    b.build().expect("door cabinet builds")
}

/// The cabinet with a small (0.25 m wide) left-hinged door, hinged like [`door_cabinet`]'s
/// (pivot [`DOOR_PIVOT`], axis [`DOOR_AXIS`]): a 0.25 × 0.02 × 0.70 slab (world x in
/// [0.005, 0.255], y in [-0.02, 0], z in [0.05, 0.75]); handle 5.5 cm from the free edge,
/// 3 cm proud, at world (0.2, -0.05, 0.45), 0.195 m from the hinge line horizontally (radius
/// of its arc: √(0.195² + 0.03²) = 0.197 m); limits [0, 1.9].
pub fn small_door_cabinet() -> SceneModel {
    let mut b = cabinet_base();
    b.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "door_hinge",
                Point3::from(DOOR_PIVOT),
                Vector3::from(DOOR_AXIS),
                Limits::new(0.0, 1.9),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.125, 0.01, 0.35)),
            Isometry3::translation(0.125, 0.01, 0.35),
        )
        .with_handle(Handle::new(
            "door_handle",
            Point3::new(0.195, -0.03, 0.4),
            -Vector3::y(),
        )),
    );
    b.build().expect("small door cabinet builds")
}

/// The drawer's true axis (world): -y, out of the carcass towards the robot.
pub const DRAWER_AXIS: [f64; 3] = [0.0, -1.0, 0.0];

/// The cabinet with a drawer: front 0.5 × 0.02 × 0.2 (world x in [0.05, 0.55], y in
/// [-0.02, 0], z in [0.5, 0.7]) on a 0.46 × 0.4 × 0.16 body inside the carcass; prismatic
/// along -y from the centre of the front's outer face (0.3, -0.02, 0.6); handle 3 cm proud at
/// world (0.3, -0.05, 0.6); limits [0, 0.4].
pub fn drawer_cabinet() -> SceneModel {
    drawer_in(cabinet_base())
}

/// The drawer of [`drawer_cabinet`] in a hollow carcass of the same outline: 2 cm side panels
/// (x in [0, 0.02] and [0.58, 0.6]), a 4 cm back (y in [0.46, 0.5]), 5 cm bottom and top
/// (z in [0, 0.05] and [0.75, 0.8]); the cavity x in [0.02, 0.58], y in [0, 0.46], z in
/// [0.05, 0.75] holds the drawer's body (x in [0.07, 0.53], y in [0, 0.4], z in [0.52, 0.68]).
pub fn hollow_drawer_cabinet() -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(slab("floor", [-2.0, -3.0, -0.05], [3.0, 2.0, 0.0]));
    b.add_base_shape(slab("left", [0.0, 0.0, 0.0], [0.02, 0.5, 0.8]));
    b.add_base_shape(slab("right", [0.58, 0.0, 0.0], [0.6, 0.5, 0.8]));
    b.add_base_shape(slab("back", [0.02, 0.46, 0.0], [0.58, 0.5, 0.8]));
    b.add_base_shape(slab("bottom", [0.02, 0.0, 0.0], [0.58, 0.46, 0.05]));
    b.add_base_shape(slab("top", [0.02, 0.0, 0.75], [0.58, 0.46, 0.8]));
    drawer_in(b)
}

/// The drawer of [`drawer_cabinet`] on the base `b`.
fn drawer_in(mut b: SceneModelBuilder) -> SceneModel {
    b.add_part(
        PartSpec::on_base(
            "drawer",
            Joint::new(
                "drawer_slide",
                JointKind::Prismatic,
                Isometry3::translation(0.3, -0.02, 0.6),
                Vector3::from(DRAWER_AXIS),
                Limits::new(0.0, 0.4),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.25, 0.01, 0.1)),
            Isometry3::translation(0.0, 0.01, 0.0),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.23, 0.2, 0.08)),
            Isometry3::translation(0.0, 0.22, 0.0),
        )
        .with_handle(Handle::new(
            "drawer_handle",
            Point3::new(0.0, -0.03, 0.0),
            -Vector3::y(),
        )),
    );
    b.build().expect("drawer cabinet builds")
}

/// The door cabinet with a tray built into the door: a child part of the door sliding out
/// along the door's outward normal (door frame -y). Door frame: x along the face towards the
/// free edge, y into the carcass, z up; the door slab is y in [0, 0.02]. Tray front plate x in
/// [0.2, 0.4], y in [-0.02, 0], z in [0.1, 0.2] (2 cm proud of the door face, like a drawer
/// front), on a body x in [0.21, 0.39], y in [0, 0.2], z in [0.11, 0.19] through the door;
/// joint origin at the plate's outer face centre (0.3, -0.02, 0.15), limits [0, 0.15]; handle
/// 3 cm proud: door frame (0.3, -0.05, 0.15), world (0.305, -0.07, 0.2) when closed.
pub fn door_with_tray() -> SceneModel {
    let mut b = door_cabinet().to_builder();
    b.add_part(
        PartSpec::on_part(
            "tray",
            "door",
            Joint::new(
                "tray_slide",
                JointKind::Prismatic,
                Isometry3::translation(0.3, -0.02, 0.15),
                -Vector3::y(),
                Limits::new(0.0, 0.15),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.1, 0.01, 0.05)),
            Isometry3::translation(0.0, 0.01, 0.0),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.09, 0.1, 0.04)),
            Isometry3::translation(0.0, 0.12, 0.0),
        )
        .with_handle(Handle::new(
            "tray_handle",
            Point3::new(0.0, -0.03, 0.0),
            -Vector3::y(),
        )),
    );
    b.build().expect("door with tray builds")
}
