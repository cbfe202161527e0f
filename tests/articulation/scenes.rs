//! The synthetic scenes: cabinets with a door, a drawer or a sliding panel, built from boxes
//! in the map frame, with their cameras and grasp.

use super::*;

/// Panel thickness, m.
const T: f64 = 0.018;

fn boxed(
    world_from_frame: &Isometry3<f64>,
    center: [f64; 3],
    half: [f64; 3],
    label: usize,
) -> SyntheticBox {
    SyntheticBox {
        world_from_box: world_from_frame * Isometry3::translation(center[0], center[1], center[2]),
        half_extents: Vector3::from(half),
        label,
    }
}

/// A cabinet body open at the front, in its frame: x right, y into the cabinet, z up, front
/// opening at y = 0 spanning x ∈ [0, w], z ∈ [0, h]; depth d.
fn cabinet_body(f: &Isometry3<f64>, w: f64, d: f64, h: f64) -> Vec<SyntheticBox> {
    vec![
        boxed(
            f,
            [T / 2.0, d / 2.0, h / 2.0],
            [T / 2.0, d / 2.0, h / 2.0],
            0,
        ),
        boxed(
            f,
            [w - T / 2.0, d / 2.0, h / 2.0],
            [T / 2.0, d / 2.0, h / 2.0],
            0,
        ),
        boxed(
            f,
            [w / 2.0, d / 2.0, T / 2.0],
            [w / 2.0 - T, d / 2.0, T / 2.0],
            0,
        ),
        boxed(
            f,
            [w / 2.0, d / 2.0, h - T / 2.0],
            [w / 2.0 - T, d / 2.0, T / 2.0],
            0,
        ),
        boxed(
            f,
            [w / 2.0, d - T / 2.0, h / 2.0],
            [w / 2.0 - T, T / 2.0, h / 2.0 - T],
            0,
        ),
    ]
}

/// A closed door panel covering the opening plus a vertical bar handle at `handle_x`, height
/// `handle_z`; returns the boxes and the grasp point (front of the handle).
fn door(
    f: &Isometry3<f64>,
    w: f64,
    h: f64,
    handle_x: f64,
    handle_z: f64,
    label: usize,
) -> (Vec<SyntheticBox>, Point3<f64>) {
    let boxes = vec![
        boxed(
            f,
            [w / 2.0, -T / 2.0, h / 2.0],
            [w / 2.0 - 0.002, T / 2.0, h / 2.0 - 0.002],
            label,
        ),
        boxed(
            f,
            [handle_x, -T - 0.025, handle_z],
            [0.008, 0.008, 0.06],
            label,
        ),
        boxed(
            f,
            [handle_x, -T - 0.0125, handle_z + 0.05],
            [0.006, 0.0125, 0.006],
            label,
        ),
        boxed(
            f,
            [handle_x, -T - 0.0125, handle_z - 0.05],
            [0.006, 0.0125, 0.006],
            label,
        ),
    ];
    (boxes, f * Point3::new(handle_x, -T - 0.033, handle_z))
}

/// A drawer (front, sides, bottom, back) filling `[x0, x1] × [z0, z1]` of the opening, depth `d`.
fn drawer(
    f: &Isometry3<f64>,
    x0: f64,
    x1: f64,
    z0: f64,
    z1: f64,
    d: f64,
) -> (Vec<SyntheticBox>, Point3<f64>) {
    let (cx, cz, hw, hh) = (
        (x0 + x1) / 2.0,
        (z0 + z1) / 2.0,
        (x1 - x0) / 2.0,
        (z1 - z0) / 2.0,
    );
    let inner = hw - 0.01;
    let boxes = vec![
        boxed(
            f,
            [cx, -T / 2.0, cz],
            [hw - 0.002, T / 2.0, hh - 0.002],
            PART,
        ),
        boxed(
            f,
            [cx - inner + 0.006, d / 2.0, cz - 0.01],
            [0.006, d / 2.0 - 0.01, hh - 0.03],
            PART,
        ),
        boxed(
            f,
            [cx + inner - 0.006, d / 2.0, cz - 0.01],
            [0.006, d / 2.0 - 0.01, hh - 0.03],
            PART,
        ),
        boxed(
            f,
            [cx, d / 2.0, z0 + 0.03],
            [inner, d / 2.0 - 0.01, 0.006],
            PART,
        ),
        boxed(
            f,
            [cx, d - 0.02, cz - 0.01],
            [inner, 0.006, hh - 0.03],
            PART,
        ),
        boxed(f, [cx, -T - 0.025, cz], [0.08, 0.008, 0.008], PART),
        boxed(
            f,
            [cx - 0.07, -T - 0.0125, cz],
            [0.006, 0.0125, 0.006],
            PART,
        ),
        boxed(
            f,
            [cx + 0.07, -T - 0.0125, cz],
            [0.006, 0.0125, 0.006],
            PART,
        ),
    ];
    (boxes, f * Point3::new(cx, -T - 0.033, cz))
}

/// Floor and a wall behind the cabinet (cabinet frame), plus a closed neighbour cabinet to the
/// right.
fn surroundings(f: &Isometry3<f64>, w: f64, d: f64, h: f64) -> Vec<SyntheticBox> {
    let mut out = vec![
        boxed(f, [w / 2.0, 0.0, -0.05], [1.5, 1.8, 0.05], 0),
        boxed(f, [w / 2.0, d + 0.05, 1.0], [1.5, 0.05, 1.0], 0),
    ];
    let right = f * Isometry3::translation(w + 0.004, 0.0, 0.0);
    out.extend(cabinet_body(&right, 0.5, d, h));
    out.extend(door(&right, 0.5, h, 0.08, h * 0.6, 0).0);
    out
}

/// Cameras in front of the cabinet (cabinet frame offsets), looking at its centre; the post
/// observation is taken from a small step back and aside (as the paper does).
fn cameras(f: &Isometry3<f64>, w: f64, h: f64, side: f64) -> (DepthCamera, DepthCamera) {
    let target = f * Point3::new(w / 2.0, 0.1, h / 2.0);
    let cam = |offset: Vector3<f64>| DepthCamera {
        origin: f * Point3::new(w / 2.0 + offset.x, offset.y, h / 2.0 + offset.z),
        target,
        up: Vector3::z(),
        horizontal_fov: 60f64.to_radians(),
        width: 200,
        height: 150,
        max_range: 4.0,
    };
    (
        cam(Vector3::new(side, -1.1, 0.45)),
        cam(Vector3::new(side * 1.6, -1.3, 0.55)),
    )
}

/// The gripper approaching the handle along the cabinet's +y, fingers vertical.
fn grasp_pose(f: &Isometry3<f64>, contact: Point3<f64>) -> Isometry3<f64> {
    let approach = f.rotation * Vector3::y();
    let rotation = UnitQuaternion::face_towards(&approach, &Vector3::z());
    Isometry3::from_parts(Translation3::from(contact.coords), rotation)
}

fn frame(x: f64, y: f64, yaw_deg: f64) -> Isometry3<f64> {
    Isometry3::new(Vector3::new(x, y, 0.0), Vector3::z() * yaw_deg.to_radians())
}

pub(super) fn scenarios() -> Vec<Scenario> {
    let mut out = Vec::new();
    let (w, d, h) = (0.5, 0.55, 0.75);

    // Left-hinged door: hinge line at the front-left edge; opening turns it about −z.
    {
        let f = frame(-0.25, 0.0, 0.0);
        let (part, contact) = door(&f, w, h, w - 0.06, 0.6 * h, PART);
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * -Vector3::z());
        let truth = Truth::Revolute {
            axis,
            pivot: f * Point3::new(0.0, -T, 0.0),
            angle: 40f64.to_radians(),
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, 0.15);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "door left hinge",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Right-hinged door in a cabinet turned 30°: hinge at the front-right edge, about +z.
    {
        let f = frame(0.3, 0.2, 30.0);
        let (part, contact) = door(&f, w, h, 0.06, 0.6 * h, PART);
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * Vector3::z());
        let truth = Truth::Revolute {
            axis,
            pivot: f * Point3::new(w, -T, 0.3),
            angle: 35f64.to_radians(),
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, -0.15);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "door right hinge, yaw 30°",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Dishwasher-like door: hinge along the bottom front edge, about +x; handle near the top.
    {
        let f = frame(0.0, -0.4, -20.0);
        let (hw, hh) = (0.6, 0.8);
        let (part, contact) = door(&f, hw, hh, hw / 2.0, hh - 0.08, PART);
        // The dishwasher's handle is horizontal: a bar along x instead of the vertical one.
        let part = part
            .into_iter()
            .enumerate()
            .map(|(k, mut b)| {
                if k == 1 {
                    b.half_extents = Vector3::new(0.1, 0.008, 0.008);
                }
                b
            })
            .collect();
        let mut statics = cabinet_body(&f, hw, d, hh);
        statics.extend(surroundings(&f, hw, d, hh));
        let axis = Unit::new_normalize(f.rotation * Vector3::x());
        let truth = Truth::Revolute {
            axis,
            pivot: f * Point3::new(0.2, -T, 0.0),
            angle: 45f64.to_radians(),
        };
        let (camera_pre, camera_post) = cameras(&f, hw, hh, 0.1);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "dishwasher door",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Drawer pulled straight out of a cabinet turned 35°.
    for (name, yaw, distance) in [("drawer", 0.0, 0.18), ("drawer yaw 35°", 35.0, 0.12)] {
        let f = frame(0.1, 0.0, yaw);
        let (part, contact) = drawer(&f, T, w - T, h - 0.2, h - T, d);
        let mut statics = cabinet_body(&f, w, d, h);
        // A fixed lower front (panel and handle) below the drawer.
        statics.extend(door(&f, w, h - 0.22, w - 0.06, 0.35, 0).0);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * -Vector3::y());
        let truth = Truth::Prismatic { axis, distance };
        let (camera_pre, camera_post) = cameras(&f, w, h, 0.0);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name,
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Sliding panel moving sideways (along the cabinet's −x) in front of an open cabinet.
    {
        let f = frame(0.2, 0.1, 10.0);
        let (part, contact) = door(&f, w, h, w - 0.08, 0.5 * h, PART);
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * -Vector3::x());
        let truth = Truth::Prismatic {
            axis,
            distance: 0.2,
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, -0.1);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "sliding panel",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Nested: a drawer in a box mounted on a door that stands open at 50° (the door is static
    // in this interaction); the drawer slides along the opened door's outward normal.
    {
        let f = frame(-0.2, 0.0, 0.0);
        let door_motion = Screw {
            axis: -Vector3::z_axis(),
            point: f * Point3::new(0.0, -T, 0.0),
            angle: 50f64.to_radians(),
            translation: 0.0,
        }
        .to_isometry();
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let (door_boxes, _) = door(&f, w, h, w - 0.06, 0.6 * h, 0);
        statics.extend(door_boxes.into_iter().take(1).map(|mut b| {
            b.world_from_box = door_motion * b.world_from_box;
            b
        }));
        // The drawer's frame: on the door's outer face, its opening facing out of the door.
        let g = door_motion * f * Isometry3::translation(0.1, -T - 0.25, 0.3);
        let housing = [
            boxed(&g, [0.15, 0.125, -0.006], [0.15, 0.125, 0.006], 0),
            boxed(&g, [0.15, 0.125, 0.2], [0.15, 0.125, 0.006], 0),
        ];
        statics.extend(housing);
        let (part, contact) = drawer(&g, 0.01, 0.29, 0.0, 0.19, 0.24);
        let axis = Unit::new_normalize(g.rotation * -Vector3::y());
        let truth = Truth::Prismatic {
            axis,
            distance: 0.1,
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, -0.2);
        let world_from_grasp = grasp_pose(&g, contact);
        out.push(Scenario {
            name: "drawer on opened door",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    out
}
