//! States Θ: validation against the model, clamping, and the traits shared data needs.

use std::collections::BTreeMap;

use kinscene::scene::{Error, Limits, State};
use nalgebra::Vector3;

use super::fixtures::kitchenette;
use super::validation::{build, hinge, part};

#[test]
fn states_are_validated() {
    let m = kitchenette();
    assert_eq!(
        State::from_values(&m, [("nope", 0.0)]).unwrap_err(),
        Error::UnknownJoint {
            name: "nope".into()
        }
    );
    assert!(matches!(
        State::from_values(&m, [("door_hinge", f64::NAN)]).unwrap_err(),
        Error::NonFinite { .. }
    ));
    assert_eq!(
        State::from_values(&m, [("door_hinge", 3.0)]).unwrap_err(),
        Error::JointLimit {
            joint: "door_hinge".into(),
            value: 3.0,
            min: 0.0,
            max: 2.0
        }
    );
    let map: BTreeMap<String, f64> = [("drawer_slide".to_string(), 0.25)].into();
    let s = State::from_map(&m, &map).unwrap();
    assert_eq!(s.value_by_name(&m, "drawer_slide").unwrap(), 0.25);
    assert_eq!(s.to_map(&m).unwrap()["drawer_slide"], 0.25);

    // Clamping is explicit and separate.
    let mut s =
        State::from_values_clamped(&m, [("door_hinge", 3.0), ("drawer_slide", -1.0)]).unwrap();
    assert_eq!(s.value_by_name(&m, "door_hinge").unwrap(), 2.0);
    assert_eq!(s.value_by_name(&m, "drawer_slide").unwrap(), 0.0);
    let id = m.joint_id("door_hinge").unwrap();
    assert_eq!(s.set_clamped(&m, id, f64::INFINITY).unwrap(), 2.0);
    assert!(s.set_clamped(&m, id, f64::NAN).is_err());
    // A failed checked set leaves the state unchanged.
    assert!(s.set(&m, id, -0.5).is_err());
    assert_eq!(s.value(id), Some(2.0));

    assert!(matches!(
        State::from_slice(&m, &[0.0]).unwrap_err(),
        Error::DimensionMismatch {
            expected: 4,
            got: 1,
            ..
        }
    ));
}

#[test]
fn zero_state_clamps_zero_into_the_limits() {
    let m = build(vec![
        part("a", None, hinge("j1", Vector3::z(), Limits::new(0.2, 1.0))),
        part(
            "b",
            None,
            hinge("j2", Vector3::z(), Limits::new(-1.0, -0.3)),
        ),
        part("c", None, hinge("j3", Vector3::z(), Limits::new(-1.0, 1.0))),
    ])
    .unwrap();
    assert_eq!(m.zero_state().as_slice(), &[0.2, -0.3, 0.0]);
}

#[test]
fn models_are_shareable_and_serialisable() {
    fn send_sync<T: Send + Sync>() {}
    fn serde<T: serde::Serialize + serde::de::DeserializeOwned>() {}
    send_sync::<kinscene::scene::SceneModel>();
    send_sync::<kinscene::scene::SceneData>();
    serde::<kinscene::scene::SceneModel>();
    serde::<kinscene::scene::SceneModelBuilder>();
    serde::<State>();
    serde::<kinscene::scene::nav::NavGrid>();
}
