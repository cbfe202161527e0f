//! Exported scene URDFs load in Pinocchio and agree with the scene FK.
//!
//! Each scene is written with `scene::urdf::write_string`, parsed by Pinocchio's own URDF parser
//! (urdfdom, through the `kinscene-pinocchio` shim: `Model::from_urdf_str`, fixed base), and
//! checked two ways:
//! - structure: one Pinocchio joint per scene joint, with the same name, kind (`continuous` →
//!   Pinocchio's unbounded revolute, q = (cos θ, sin θ)), axis, parent and limits;
//! - placements: at several states, every part's link frame equals `world_from_part` of the
//!   scene FK, and every handle link's origin and +x axis equal `world_from_handle`'s grasp point
//!   and outward normal (the scene URDF handle convention).
//!
//! Pinocchio is the independent side here: it shares no code with the scene FK or the exporter,
//! only the URDF document.
//!
//! Tolerance [`TOL`] = 1e-9 (metres for positions; unitless for rotation-matrix entries and
//! unit normals). Both sides compose the same chain: at most `MAX_DEPTH` = 4 origins
//! (translations ≤ 0.6 m per axis, so ≤ 4·0.6·√3 ≈ 4.2 m from the world origin) and joint
//! motions, plus a handle offset ≤ 0.5 m per axis; double rounding alone differs by ~1e-15. The
//! document adds the export's own rounding: lengths, limits and axes round-trip exactly, but each
//! `rpy` is written on a 1e-12 rad grid, which the exporter bounds at about 1e-11 rad of rotation
//! per origin (see `scene::urdf`'s round-trip notes). Four such origins on a chain turn by at
//! most 4e-11 rad, moving a point ≤ 5 m away by ≤ 2e-10 m: 1e-9 keeps a 5× margin over that
//! worst case, while a lossy export (six printed digits: ~1e-6), a wrong rpy convention, axis,
//! sign or composition order shows up at 1e-3 or more.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use kinscene::kinematics::pinocchio::{
    self as pin, Data as PinData, JointIndex, JointKind as PinKind, Model as PinModel,
};
use kinscene::scene::urdf::{self, ExportOptions, HANDLE_SUFFIX, ImportOptions};
use kinscene::scene::{
    JointKind, Parent, SceneData, SceneModel, State, forward_kinematics, world_from_handle,
};
use nalgebra::{Isometry3, Vector3};
use proptest::prelude::*;

use super::fixtures::kitchenette;
use super::generators::{scene_builder, state};

const TOL: f64 = 1e-9;

/// A fresh directory for meshes the exporter writes (convex meshes without a source file),
/// removed when dropped. Pinocchio's kinematic model does not read meshes; the exporter needs
/// the directory to write them.
struct MeshDir(PathBuf);

impl MeshDir {
    fn new() -> MeshDir {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "kinscene-urdf-pinocchio-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        MeshDir(dir)
    }

    fn options(&self) -> ExportOptions {
        ExportOptions {
            mesh_dir: Some(self.0.clone()),
            ..ExportOptions::default()
        }
    }
}

impl Drop for MeshDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The URDF link of a handle: its name, with [`HANDLE_SUFFIX`] appended if it lacks it.
fn handle_link(name: &str) -> String {
    if name.ends_with(HANDLE_SUFFIX) {
        name.to_owned()
    } else {
        format!("{name}{HANDLE_SUFFIX}")
    }
}

/// Largest entry-wise difference of the translations and rotation matrices.
fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> f64 {
    let dt = (a.translation.vector - b.translation.vector).amax();
    let dr = (a.rotation.to_rotation_matrix().matrix() - b.rotation.to_rotation_matrix().matrix())
        .amax();
    dt.max(dr)
}

/// Exports `model` and parses the document with Pinocchio.
fn to_pinocchio(model: &SceneModel) -> Result<PinModel, String> {
    let mesh_dir = MeshDir::new();
    let xml = urdf::write_string(model, &mesh_dir.options()).map_err(|e| format!("export: {e}"))?;
    PinModel::from_urdf_str(&xml).map_err(|e| format!("Pinocchio: {e}\n{xml}"))
}

/// Checks `pin` (a Pinocchio model of `model`'s URDF) against the scene: structure, then the
/// placements of every part and handle at each of `states`.
fn check_against_pinocchio(
    model: &SceneModel,
    pin: &PinModel,
    states: &[State],
) -> Result<(), String> {
    if pin.joints().len() != model.joints().len() {
        return Err(format!(
            "Pinocchio has {} joints, the scene {}",
            pin.joints().len(),
            model.joints().len()
        ));
    }
    // Pinocchio joint of each scene joint (by JointId index).
    let pin_joint: Vec<JointIndex> = model
        .joints()
        .iter()
        .map(|j| {
            pin.joint_index(&j.name)
                .ok_or_else(|| format!("no Pinocchio joint {:?}", j.name))
        })
        .collect::<Result<_, _>>()?;

    for part in model.parts() {
        let k = part.joint().index();
        let joint = &model.joints()[k];
        let pj = pin.joint(pin_joint[k]).map_err(|e| e.to_string())?;
        let axis = match (joint.kind, joint.continuous, pj.kind) {
            (JointKind::Revolute, false, PinKind::Revolute { axis })
            | (JointKind::Revolute, true, PinKind::RevoluteUnbounded { axis })
            | (JointKind::Prismatic, false, PinKind::Prismatic { axis }) => axis,
            (kind, continuous, got) => {
                return Err(format!(
                    "joint {:?}: scene {kind:?} (continuous: {continuous}) became {got:?}",
                    joint.name
                ));
            }
        };
        if (axis - joint.axis).amax() > TOL {
            return Err(format!(
                "joint {:?}: axis {} vs {}",
                joint.name, axis, joint.axis
            ));
        }
        let parent = match part.parent() {
            Parent::Base => JointIndex::UNIVERSE,
            Parent::Part(p) => pin_joint[model.part(p).unwrap().joint().index()],
        };
        if pj.parent != parent {
            return Err(format!(
                "joint {:?}: Pinocchio parent {:?}, expected {parent:?}",
                joint.name, pj.parent
            ));
        }
        if !joint.continuous {
            let (lo, hi) = pj
                .limits
                .position
                .ok_or_else(|| format!("joint {:?}: no position limits", joint.name))?;
            if (lo - joint.limits.lower).abs() > TOL || (hi - joint.limits.upper).abs() > TOL {
                return Err(format!(
                    "joint {:?}: limits [{lo}, {hi}] vs {:?}",
                    joint.name, joint.limits
                ));
            }
        }
        let link = pin
            .link_frame(part.name())
            .ok_or_else(|| format!("no link frame {:?}", part.name()))?;
        if pin.frame(link).unwrap().parent_joint != pin_joint[k] {
            return Err(format!("link {:?} is not on its joint", part.name()));
        }
    }

    let mut scene_data = SceneData::new(model);
    let mut pin_data = PinData::new(pin).map_err(|e| e.to_string())?;
    for state in states {
        forward_kinematics(model, &mut scene_data, state).map_err(|e| e.to_string())?;
        let mut q = pin.neutral();
        for (k, value) in state.as_slice().iter().enumerate() {
            pin::set_joint_value(pin, &mut q, pin_joint[k], *value).map_err(|e| e.to_string())?;
        }
        pin::forward_kinematics(pin, &mut pin_data, &q).map_err(|e| e.to_string())?;
        for part in model.parts() {
            let expected = scene_data.world_from_part(part.id()).unwrap();
            let frame = pin.link_frame(part.name()).unwrap();
            let got = pin::frame_placement(pin, &pin_data, frame).map_err(|e| e.to_string())?;
            let err = pose_error(&got, expected);
            if err > TOL {
                return Err(format!(
                    "part {:?} at {:?}: Pinocchio {got} vs scene {expected} (error {err:e})",
                    part.name(),
                    state.as_slice()
                ));
            }
        }
        for (id, handle) in model.handles() {
            let expected = world_from_handle(model, &scene_data, id).map_err(|e| e.to_string())?;
            let name = handle_link(&handle.name);
            let frame = pin
                .link_frame(&name)
                .ok_or_else(|| format!("no handle link {name:?}"))?;
            let got = pin::frame_placement(pin, &pin_data, frame).map_err(|e| e.to_string())?;
            let dp = (got.translation.vector - expected.position.coords).amax();
            let dn = (got.rotation * Vector3::x() - expected.normal.into_inner()).amax();
            if dp.max(dn) > TOL {
                return Err(format!(
                    "handle {name:?} at {:?}: position error {dp:e}, normal error {dn:e}",
                    state.as_slice()
                ));
            }
        }
    }
    Ok(())
}

/// Generated scenes (up to `max_parts` parts, depth ≤ 4) made exportable-interesting: each
/// revolute joint is `continuous` with probability ½, and every other handle already carries
/// the [`HANDLE_SUFFIX`] (the exporter appends it to the others); with three random states.
fn scene_with_states(max_parts: usize) -> impl Strategy<Value = (SceneModel, Vec<State>)> {
    (scene_builder(max_parts), any::<u64>())
        .prop_map(|(mut b, bits)| {
            for (i, part) in b.parts.iter_mut().enumerate() {
                if part.joint.kind == JointKind::Revolute && (bits >> (i % 64)) & 1 == 1 {
                    part.joint.continuous = true;
                }
                for (k, handle) in part.handles.iter_mut().enumerate() {
                    if (i + k) % 2 == 0 {
                        handle.name.push_str(HANDLE_SUFFIX);
                    }
                }
            }
            b.build().expect("generated scenes are valid")
        })
        .prop_flat_map(|model| {
            let states = prop::collection::vec(state(&model), 3);
            (Just(model), states)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Any generated scene (up to 50 parts) exports to a URDF that Pinocchio loads, with the
    /// scene's structure and the scene FK's part and handle placements.
    #[test]
    fn exported_scenes_load_in_pinocchio_and_match_scene_fk(
        (model, states) in scene_with_states(50)
    ) {
        let pin = to_pinocchio(&model).map_err(TestCaseError::fail)?;
        check_against_pinocchio(&model, &pin, &states).map_err(TestCaseError::fail)?;
    }
}

/// The states of `model` at every joint's lower limit, upper limit and midpoint (all joints
/// together), and one state per joint with only that joint at its upper limit.
fn limit_states(model: &SceneModel) -> Vec<State> {
    let joints = model.joints();
    let at = |f: &dyn Fn(usize) -> f64| {
        State::from_slice(model, &(0..joints.len()).map(f).collect::<Vec<_>>()).unwrap()
    };
    let mut states = vec![
        at(&|k| joints[k].limits.lower),
        at(&|k| joints[k].limits.upper),
        at(&|k| 0.5 * (joints[k].limits.lower + joints[k].limits.upper)),
    ];
    for j in 0..joints.len() {
        states.push(at(&|k| {
            if k == j {
                joints[k].limits.upper
            } else {
                joints[k].limits.lower
            }
        }));
    }
    states
}

#[test]
fn kitchenette_with_rack_on_door_exports_to_pinocchio() {
    // The dishwasher rack rides on the door (a two-level tree); Pinocchio must carry it along.
    let model = kitchenette();
    let pin = to_pinocchio(&model).unwrap();
    let rack = pin.joint_index("dw_rack_slide").unwrap();
    assert_eq!(
        pin.joint(rack).unwrap().parent,
        pin.joint_index("dw_hinge").unwrap()
    );
    check_against_pinocchio(&model, &pin, &limit_states(&model)).unwrap();
}

fn kitchen_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/kitchen.urdf")
}

#[test]
fn kitchen_urdf_in_pinocchio_matches_the_imported_scene() {
    // Pinocchio parses the authored file itself: an independent check of the importer (fixed
    // links merged into parts, handle links' origin and +x as grasp point and normal).
    let path = kitchen_path();
    let model = urdf::read_file(&path, &ImportOptions::default()).unwrap();
    let pin = PinModel::from_urdf_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    check_against_pinocchio(&model, &pin, &limit_states(&model)).unwrap();
}

#[test]
fn exported_kitchen_loads_in_pinocchio_and_matches_the_scene() {
    let model = urdf::read_file(kitchen_path(), &ImportOptions::default()).unwrap();
    let pin = to_pinocchio(&model).unwrap();
    check_against_pinocchio(&model, &pin, &limit_states(&model)).unwrap();
}
