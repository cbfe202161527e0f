//! Mapping-stage helpers: detection fusion and registration against the base map.

use kinscene::discovery::{
    DiscoveryError, FusionSettings, HandleDetection, MappedHandle, RegistrationSettings, Rejection,
    fuse_detections, register_handles,
};
use kinscene::scene::{SceneData, forward_kinematics, urdf, world_from_handle};
use nalgebra::{Point3, Vector3};

use super::scenes::cabinet_base;

fn det(p: [f64; 3], confidence: f64) -> HandleDetection {
    HandleDetection {
        position: Point3::from(p),
        half_extents: Vector3::new(0.01, 0.02, 0.06),
        confidence,
        stamp: 0.0,
    }
}

#[test]
fn fusion_merges_repeated_views_and_drops_a_lone_weak_detection() {
    let views = vec![
        // View 0: handle A, plus a duplicate box of A 2 cm away (suppressed within the view).
        vec![det([1.0, 0.0, 0.7], 0.8), det([1.02, 0.0, 0.7], 0.6)],
        // View 1: A again, and B.
        vec![det([1.01, 0.01, 0.7], 0.7), det([2.0, 0.0, 0.7], 0.9)],
        // View 2: a lone weak detection far from everything.
        vec![det([3.0, 0.0, 0.7], 0.3)],
    ];
    let fused = fuse_detections(&views, &FusionSettings::default()).unwrap();
    assert_eq!(fused.len(), 2, "{fused:#?}");
    // Sorted by confidence. A: 1 - (1 - 0.8)(1 - 0.7) = 0.94 > B: 0.9.
    let a = &fused[0];
    assert!((a.confidence - 0.94).abs() < 1e-12, "{}", a.confidence);
    assert_eq!(a.views, 2);
    // Confidence-weighted mean of (1.0, 0, 0.7) w 0.8 and (1.01, 0.01, 0.7) w 0.7:
    // x = (0.8 + 0.707) / 1.5 = 1.004667, y = 0.007 / 1.5 = 0.004667.
    assert!(
        (a.position - Point3::new(1.004_666_666_666_667, 0.004_666_666_666_667, 0.7)).norm()
            < 1e-12
    );
    // RMS distance: the two points are 0.01·√2 apart, split 7:8 by the weights;
    // sqrt(0.8·(7/15·d)² + 0.7·(8/15·d)²)/sqrt(1.5) with d = 0.014142.
    let d = 0.01 * 2f64.sqrt();
    let expected = ((0.8 * (7.0 / 15.0 * d).powi(2) + 0.7 * (8.0 / 15.0 * d).powi(2)) / 1.5).sqrt();
    assert!((a.spread - expected).abs() < 1e-12);
    let b = &fused[1];
    assert!((b.confidence - 0.9).abs() < 1e-12);
    assert_eq!(b.views, 1);
    // The weak detection alone is dropped; seen three times it is kept (1 - 0.7³ = 0.657).
    let three = vec![
        vec![det([3.0, 0.0, 0.7], 0.3)],
        vec![det([3.01, 0.0, 0.7], 0.3)],
        vec![det([3.0, 0.01, 0.7], 0.3)],
    ];
    let fused = fuse_detections(&three, &FusionSettings::default()).unwrap();
    assert_eq!(fused.len(), 1);
    assert!((fused[0].confidence - 0.657).abs() < 1e-12);
    // Two handles 5 cm apart in one view stay separate only with a smaller merge radius.
    let close = vec![vec![det([0.0, 0.0, 0.7], 0.9), det([0.05, 0.0, 0.7], 0.9)]];
    assert_eq!(
        fuse_detections(&close, &FusionSettings::default())
            .unwrap()
            .len(),
        1
    );
    let fine = FusionSettings {
        merge_radius: 0.03,
        ..FusionSettings::default()
    };
    assert_eq!(fuse_detections(&close, &fine).unwrap().len(), 2);
}

#[test]
fn fusion_rejects_bad_input() {
    let nan = vec![vec![det([f64::NAN, 0.0, 0.0], 0.5)]];
    assert!(matches!(
        fuse_detections(&nan, &FusionSettings::default()),
        Err(DiscoveryError::NonFinite { .. })
    ));
    let over = vec![vec![det([0.0, 0.0, 0.0], 1.5)]];
    assert!(matches!(
        fuse_detections(&over, &FusionSettings::default()),
        Err(DiscoveryError::ConfidenceOutOfRange { .. })
    ));
    let bad = FusionSettings {
        merge_radius: -1.0,
        ..FusionSettings::default()
    };
    assert!(matches!(
        fuse_detections(&[], &bad),
        Err(DiscoveryError::InvalidSetting(s)) if s.field == "merge_radius"
    ));
}

fn mapped(p: [f64; 3]) -> MappedHandle {
    MappedHandle::from_detection(&det(p, 0.9))
}

#[test]
fn registration_snaps_to_the_cabinet_face_with_its_normal() {
    // The carcass spans x [0, 0.6], y [0, 0.5], z [0, 0.8]; the floor's top is z = 0.
    let base = cabinet_base().base;
    let handles = [
        mapped([0.3, -0.04, 0.6]),   // 4 cm in front of the front face (y = 0)
        mapped([0.63, 0.25, 0.5]),   // 3 cm beside the right face (x = 0.6)
        mapped([0.3, 0.25, 0.4]),    // inside the carcass
        mapped([0.3, -0.6, 0.6]),    // 60 cm in front: nothing to attach to
        mapped([0.625, -0.02, 0.5]), // off the front-right edge
    ];
    let r = register_handles(&handles, &base, &RegistrationSettings::default()).unwrap();
    assert_eq!(r.handles.len(), 3);
    let front = r.handles[0].attachment.as_ref().unwrap();
    assert_eq!(front.base_shape, "carcass");
    assert!((front.normal - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-12);
    assert!((front.distance - 0.04).abs() < 1e-12);
    assert!((front.surface_point - Point3::new(0.3, 0.0, 0.6)).norm() < 1e-12);
    let side = r.handles[1].attachment.as_ref().unwrap();
    assert!((side.normal - Vector3::x()).norm() < 1e-12);
    assert!((side.distance - 0.03).abs() < 1e-12);
    // Off the edge: the right face scores 0.025 + 0.25 · 0.02 = 0.03 (plane distance +
    // weighted lateral offset), the front face 0.02 + 0.25 · 0.025 = 0.02625: the front wins.
    let edge = r.handles[2].attachment.as_ref().unwrap();
    assert!((edge.normal + Vector3::y()).norm() < 1e-12);
    assert!((edge.distance - 0.02).abs() < 1e-12);
    assert_eq!(r.rejected.len(), 2);
    assert!(
        matches!(&r.rejected[0].1, Rejection::InsideSolid { base_shape, depth }
        if base_shape == "carcass" && (depth - 0.25).abs() < 1e-9)
    );
    assert!(
        matches!(r.rejected[1].1, Rejection::FarFromBase { distance }
        if (distance - 0.6).abs() < 1e-9)
    );
}

/// The kitchen's handles at the zero state, registered against its base map (open-fronted
/// carcasses, panels, walls, a mesh sink): each attaches to a face whose normal is the
/// handle's true outward normal (within 1°), except the dishwasher rack's, which sits inside
/// the closed tub.
#[test]
fn kitchen_handles_register_with_their_true_normals() {
    let model = urdf::read_file(
        "examples/scenes/kitchen.urdf",
        &urdf::ImportOptions::default(),
    )
    .unwrap();
    let mut data = SceneData::new(&model);
    forward_kinematics(&model, &mut data, &model.zero_state()).unwrap();
    let mut names = Vec::new();
    let mut handles = Vec::new();
    let mut normals = Vec::new();
    for (id, h) in model.handles() {
        let pose = world_from_handle(&model, &data, id).unwrap();
        names.push(h.name.clone());
        handles.push(mapped(pose.position.coords.into()));
        normals.push(pose.normal.into_inner());
    }
    let settings = RegistrationSettings::default();
    let r = register_handles(&handles, model.base(), &settings).unwrap();
    assert!(r.rejected.is_empty(), "{:#?}", r.rejected);
    assert_eq!(r.handles.len(), 11);
    for h in &r.handles {
        let k = handles
            .iter()
            .position(|g| g.position == h.position)
            .unwrap();
        let a = h.attachment.as_ref().unwrap();
        let angle = a.normal.angle(&normals[k]).to_degrees();
        if names[k] == "dishwasher_rack_handle" {
            // Inside the closed tub (a mapping detector would not see it); registration is
            // geometric only and attaches it to the nearest tub wall.
            continue;
        }
        assert!(
            angle < 1.0,
            "{}: normal {:?} vs true {:?} ({angle}°) on {}",
            names[k],
            a.normal,
            normals[k],
            a.base_shape
        );
    }
}
