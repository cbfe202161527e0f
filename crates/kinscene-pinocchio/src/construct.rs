//! Replaying a validated [`crate::ModelBuilder`] into a C++ `pinocchio::Model`.

use std::ffi::CString;
use std::ptr::{self, NonNull};

use nalgebra::Vector3;

use crate::ffi::{self, RawModel};
use crate::{Error, Frame, FrameKind, Inertia, Joint, JointIndex, JointKind};

/// Owns a C++ model until it is handed to a `Model` (frees it when building fails half-way).
pub(crate) struct Building(pub(crate) *mut RawModel);

impl Drop for Building {
    fn drop(&mut self) {
        if let (false, Ok(api)) = (self.0.is_null(), ffi::api()) {
            // SAFETY: a model from `model_new` that no `Model` owns yet.
            unsafe { (api.model_free)(self.0) };
        }
    }
}

/// Creates the C++ model for validated builder contents and checks that Pinocchio numbered
/// joints and frames as the builder did.
pub(crate) fn build_raw(
    joints: &[Joint],
    frames: &[Frame],
    bodies: &[(JointIndex, Inertia)],
    (nq, nv): (usize, usize),
) -> Result<NonNull<RawModel>, Error> {
    let api = ffi::api()?;
    let mut building = Building(ptr::null_mut());
    // SAFETY (all calls below): pointers are to live locals of the sizes shim.h documents;
    // joint and frame indices were validated by the builder.
    ffi::call("ks_pin_model_new", |e, n| unsafe {
        (api.model_new)(&mut building.0, e, n)
    })?;
    let raw = building.0;
    // Pinocchio numbers frames in insertion order: replay the builder's order exactly.
    let mut frame_at = 1;
    for (i, joint) in joints.iter().enumerate() {
        // Frames added to earlier joints before this joint come first, in builder order.
        while frame_at < joint.frame.0 {
            add_frame(api, raw, frames, frame_at)?;
            frame_at += 1;
        }
        let name = CString::new(joint.name.as_str()).expect("builder rejects NUL bytes");
        let (kind, axis) = raw_kind(&joint.kind);
        let (nq, nv) = (joint.kind.nq(), joint.kind.nv());
        let (lower, upper) = joint
            .limits
            .position
            .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
        let lower = vec![lower; nq];
        let upper = vec![upper; nq];
        let velocity = vec![joint.limits.velocity.unwrap_or(f64::INFINITY); nv];
        let effort = vec![joint.limits.effort.unwrap_or(f64::INFINITY); nv];
        let pose = ffi::pose7(&joint.parent_from_joint);
        let (mut out_joint, mut out_frame) = (0usize, 0usize);
        ffi::call("ks_pin_model_add_joint", |e, n| unsafe {
            (api.model_add_joint)(
                raw,
                kind,
                joint.parent.0,
                pose.as_ptr(),
                axis.as_ptr(),
                name.as_ptr(),
                lower.as_ptr(),
                upper.as_ptr(),
                velocity.as_ptr(),
                effort.as_ptr(),
                &mut out_joint,
                &mut out_frame,
                e,
                n,
            )
        })?;
        expect_index("joint", i + 1, out_joint)?;
        expect_index("joint frame", joint.frame.0, out_frame)?;
        frame_at = joint.frame.0 + 1;
    }
    while frame_at < frames.len() {
        add_frame(api, raw, frames, frame_at)?;
        frame_at += 1;
    }
    for (joint, body) in bodies {
        let rotational = body.rotational;
        ffi::call("ks_pin_model_append_body", |e, n| unsafe {
            (api.model_append_body)(
                raw,
                joint.0,
                body.mass,
                body.com.as_ptr(),
                rotational.as_ptr(),
                e,
                n,
            )
        })?;
    }
    let mut sizes = [0usize; 4];
    let [s0, s1, s2, s3] = &mut sizes;
    // SAFETY: four live out-pointers.
    unsafe { (api.model_sizes)(raw, s0, s1, s2, s3) };
    if sizes != [nq, nv, joints.len() + 1, frames.len()] {
        return Err(backend(
            "model sizes",
            format!(
                "Pinocchio reports {sizes:?}, expected {:?}",
                [nq, nv, joints.len() + 1, frames.len()]
            ),
        ));
    }
    let raw = NonNull::new(building.0).expect("model_new succeeded");
    building.0 = ptr::null_mut();
    Ok(raw)
}

fn add_frame(
    api: &ffi::Api,
    raw: *mut RawModel,
    frames: &[Frame],
    index: usize,
) -> Result<(), Error> {
    let frame = &frames[index];
    let name = CString::new(frame.name.as_str()).expect("builder rejects NUL bytes");
    let kind = match frame.kind {
        FrameKind::FixedJoint => ffi::FIXED_JOINT,
        FrameKind::Body => ffi::BODY,
        FrameKind::Operational | FrameKind::Joint => ffi::OP_FRAME,
    };
    // The parent joint's own frame: the universe frame, or the JOINT frame of that joint.
    let parent_frame = frames
        .iter()
        .position(|f| {
            f.parent_joint == frame.parent_joint
                && (frame.parent_joint.0 == 0 || f.kind == FrameKind::Joint)
        })
        .unwrap_or(0);
    let pose = ffi::pose7(&frame.joint_from_frame);
    let mut out = 0usize;
    // SAFETY: live CString, pose7 array and out-pointer; indices validated by the builder.
    ffi::call("ks_pin_model_add_frame", |e, n| unsafe {
        (api.model_add_frame)(
            raw,
            name.as_ptr(),
            frame.parent_joint.0,
            parent_frame,
            pose.as_ptr(),
            kind,
            &mut out,
            e,
            n,
        )
    })?;
    expect_index("frame", index, out)
}

fn raw_kind(kind: &JointKind) -> (std::ffi::c_int, Vector3<f64>) {
    match *kind {
        JointKind::Revolute { axis } => (ffi::REVOLUTE, axis),
        JointKind::RevoluteUnbounded { axis } => (ffi::REVOLUTE_UNBOUNDED, axis),
        JointKind::Prismatic { axis } => (ffi::PRISMATIC, axis),
        JointKind::Planar => (ffi::PLANAR, Vector3::z()),
    }
}

fn expect_index(what: &str, expected: usize, got: usize) -> Result<(), Error> {
    if expected == got {
        Ok(())
    } else {
        Err(backend(
            "index",
            format!("Pinocchio gave {what} index {got}, expected {expected}"),
        ))
    }
}

pub(crate) fn backend(function: &'static str, message: String) -> Error {
    Error::Backend(kinscene_shim::CallError::Exception { function, message })
}
