//! Small hand-built scenes whose poses are easy to derive by hand.

use std::f64::consts::FRAC_PI_2;

use kinscene::scene::{
    Handle, Joint, JointKind, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape,
};
use nalgebra::{Isometry3, Point3, Vector3};

/// A part `door` on the base, hinged by `hinge` at the world origin about +z with limits
/// [0, upper] rad, with one cuboid collider (`half_extents`, centred at `centre` in the door frame).
pub fn hinged_door(upper: f64, half_extents: Vector3<f64>, centre: Vector3<f64>) -> PartSpec {
    PartSpec::on_base(
        "door",
        Joint::revolute(
            "hinge",
            Point3::origin(),
            Vector3::z(),
            Limits::new(0.0, upper),
        ),
    )
    .with_collider(
        Shape::cuboid(half_extents),
        Isometry3::translation(centre.x, centre.y, centre.z),
    )
}

/// A kitchenette:
/// - `door` on hinge `door_hinge`: pivot (1, 2, 0.5), axis +z, limits [0, 2] rad; a 0.45 m
///   wide slab along +x of the part frame; handle `door_handle` at (0.45, -0.02, 0.3), normal -y.
/// - `drawer` on `drawer_slide`: origin (0.5, 0, 0.4), axis -y, limits [0, 0.4] m; handle
///   `drawer_handle` at (0, -0.21, 0.05), normal -y.
/// - `dw_door` on `dw_hinge`: origin (2, 0, 0.1), axis -x, limits [0, π/2]; handle
///   `dw_door_handle` at (0, 0.02, 0.65), normal +y.
/// - `dw_rack` on `dw_rack_slide`, riding on `dw_door`: origin (0, -0.1, 0.4) in the door
///   frame, axis +z (door frame), limits [0, 0.3] m; handle `dw_rack_handle` at (0, 0, 0.2),
///   normal +z.
pub fn kitchenette() -> SceneModel {
    let mut b = SceneModelBuilder::new();
    // Added child first: parents may be referred to before they are added.
    b.add_part(
        PartSpec::on_part(
            "dw_rack",
            "dw_door",
            Joint::new(
                "dw_rack_slide",
                JointKind::Prismatic,
                Isometry3::translation(0.0, -0.1, 0.4),
                Vector3::z(),
                Limits::new(0.0, 0.3),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.25, 0.05, 0.2)),
            Isometry3::translation(0.0, -0.06, 0.0),
        )
        .with_handle(Handle::new(
            "dw_rack_handle",
            Point3::new(0.0, 0.0, 0.2),
            Vector3::z(),
        )),
    );
    b.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "door_hinge",
                Point3::new(1.0, 2.0, 0.5),
                Vector3::z(),
                Limits::new(0.0, 2.0),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.225, 0.01, 0.3)),
            Isometry3::translation(0.225, 0.0, 0.3),
        )
        .with_handle(Handle::new(
            "door_handle",
            Point3::new(0.45, -0.02, 0.3),
            -Vector3::y(),
        )),
    );
    b.add_part(
        PartSpec::on_base(
            "drawer",
            Joint::prismatic(
                "drawer_slide",
                Point3::new(0.5, 0.0, 0.4),
                -Vector3::y(),
                Limits::new(0.0, 0.4),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.2, 0.2, 0.05)),
            Isometry3::translation(0.0, 0.0, 0.0),
        )
        .with_handle(Handle::new(
            "drawer_handle",
            Point3::new(0.0, -0.21, 0.05),
            -Vector3::y(),
        )),
    );
    b.add_part(
        PartSpec::on_base(
            "dw_door",
            Joint::revolute(
                "dw_hinge",
                Point3::new(2.0, 0.0, 0.1),
                -Vector3::x(),
                Limits::new(0.0, FRAC_PI_2),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.3, 0.01, 0.35)),
            Isometry3::translation(0.0, 0.0, 0.35),
        )
        .with_handle(Handle::new(
            "dw_door_handle",
            Point3::new(0.0, 0.02, 0.65),
            Vector3::y(),
        )),
    );
    b.build().expect("the kitchenette is valid")
}
