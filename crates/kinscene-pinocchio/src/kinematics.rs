//! Forward kinematics, placements and frame Jacobians.

use nalgebra::{DMatrix, DVector, Isometry3};

use crate::configuration::check_q;
use crate::{Data, Error, FrameIndex, JointIndex, Model, ReferenceFrame, ffi};

/// Computes every joint placement (`world_from_joint`) for configuration `q` (Pinocchio's
/// `forwardKinematics`). Afterwards [`joint_placement`] and [`frame_placement`] read the result;
/// frame placements are derived on demand from their joint's placement, so adding frames does
/// not slow this call down.
///
/// # Errors
/// [`Error::DataModelMismatch`], [`Error::DimensionMismatch`], [`Error::NonFinite`],
/// [`Error::NotNormalized`], [`Error::Backend`].
pub fn forward_kinematics(model: &Model, data: &mut Data, q: &DVector<f64>) -> Result<(), Error> {
    data.check(model)?;
    check_q(model, q, "q")?;
    let api = ffi::api()?;
    data.set_placements_valid(false);
    // SAFETY: model and data match (checked); q has nq entries.
    ffi::call("ks_pin_forward_kinematics", |e, n| unsafe {
        (api.forward_kinematics)(model.raw(), data.raw_mut(), q.as_ptr(), e, n)
    })?;
    data.set_placements_valid(true);
    Ok(())
}

/// `world_from_joint` as of the last [`forward_kinematics`] on `data` (the universe joint gives
/// the identity).
///
/// # Errors
/// [`Error::DataModelMismatch`], [`Error::KinematicsNotComputed`], [`Error::JointOutOfRange`].
pub fn joint_placement(
    model: &Model,
    data: &Data,
    joint: JointIndex,
) -> Result<Isometry3<f64>, Error> {
    data.check(model)?;
    ready(data)?;
    if joint.0 >= model.njoints() {
        return Err(Error::JointOutOfRange {
            index: joint.0,
            count: model.njoints(),
        });
    }
    let api = ffi::api()?;
    let mut pose = [0.0; 7];
    // SAFETY: valid joint index; `pose` holds 7 doubles.
    ffi::call("ks_pin_joint_placement", |e, n| unsafe {
        (api.joint_placement)(model.raw(), data.raw(), joint.0, pose.as_mut_ptr(), e, n)
    })?;
    Ok(ffi::isometry(&pose))
}

/// `world_from_frame` as of the last [`forward_kinematics`] on `data`:
/// `world_from_joint(parent) * joint_from_frame`.
///
/// # Errors
/// [`Error::DataModelMismatch`], [`Error::KinematicsNotComputed`], [`Error::FrameOutOfRange`].
pub fn frame_placement(
    model: &Model,
    data: &Data,
    frame: FrameIndex,
) -> Result<Isometry3<f64>, Error> {
    data.check(model)?;
    ready(data)?;
    model.frame(frame)?;
    let api = ffi::api()?;
    let mut pose = [0.0; 7];
    // SAFETY: valid frame index; `pose` holds 7 doubles.
    ffi::call("ks_pin_frame_placement", |e, n| unsafe {
        (api.frame_placement)(model.raw(), data.raw(), frame.0, pose.as_mut_ptr(), e, n)
    })?;
    Ok(ffi::isometry(&pose))
}

/// The Jacobian of `frame` at configuration `q` (6 × nv), expressed in `reference`
/// (Pinocchio's `computeFrameJacobian`).
///
/// Rows 0–2 are the linear velocity (m/s), rows 3–5 the angular velocity (rad/s), per unit of
/// each velocity coordinate (column); see [`ReferenceFrame`] for which point and axes. Columns
/// of joints that do not move the frame are zero.
///
/// This recomputes the placements of the joints supporting the frame only, so it leaves `data`
/// needing a new [`forward_kinematics`] before placements are read again.
///
/// # Errors
/// [`Error::DataModelMismatch`], [`Error::DimensionMismatch`], [`Error::NonFinite`],
/// [`Error::NotNormalized`], [`Error::FrameOutOfRange`], [`Error::Backend`].
pub fn frame_jacobian(
    model: &Model,
    data: &mut Data,
    q: &DVector<f64>,
    frame: FrameIndex,
    reference: ReferenceFrame,
) -> Result<DMatrix<f64>, Error> {
    data.check(model)?;
    check_q(model, q, "q")?;
    model.frame(frame)?;
    let mut jacobian = DMatrix::zeros(6, model.nv());
    jacobian_into(model, data, q, frame, reference, &mut jacobian)?;
    Ok(jacobian)
}

/// `computeFrameJacobian` into `jacobian` (6 × nv, checked by the callers with `data`, `q`
/// and `frame`); marks the placements stale.
fn jacobian_into(
    model: &Model,
    data: &mut Data,
    q: &DVector<f64>,
    frame: FrameIndex,
    reference: ReferenceFrame,
    jacobian: &mut DMatrix<f64>,
) -> Result<(), Error> {
    let api = ffi::api()?;
    data.set_placements_valid(false);
    // SAFETY: valid frame index; q has nq entries; `jacobian` is 6 × nv, column-major like the
    // shim's output.
    ffi::call("ks_pin_frame_jacobian", |e, n| unsafe {
        (api.frame_jacobian)(
            model.raw(),
            data.raw_mut(),
            q.as_ptr(),
            frame.0,
            reference.raw(),
            jacobian.as_mut_ptr(),
            e,
            n,
        )
    })
}

/// The placement `world_from_frame` and the `LOCAL_WORLD_ALIGNED` Jacobian (6 × nv, written
/// into `jacobian`) of `frame` at configuration `q`, in one pass over the frame's support: what
/// [`forward_kinematics`], [`frame_placement`] and [`frame_jacobian`] give together, without
/// the full forward pass and without allocating (the inner loop of iterative IK).
///
/// Pinocchio's `computeFrameJacobian` in the world-aligned references updates the placements
/// of the joints supporting the frame, so the frame's placement is read from them. Like
/// [`frame_jacobian`], this leaves `data` needing a new [`forward_kinematics`] before
/// placements are read again.
///
/// # Errors
/// As [`frame_jacobian`]; [`Error::DimensionMismatch`] also when `jacobian` is not 6 × nv.
pub fn frame_placement_and_jacobian(
    model: &Model,
    data: &mut Data,
    q: &DVector<f64>,
    frame: FrameIndex,
    jacobian: &mut DMatrix<f64>,
) -> Result<Isometry3<f64>, Error> {
    data.check(model)?;
    check_q(model, q, "q")?;
    model.frame(frame)?;
    if jacobian.shape() != (6, model.nv()) {
        return Err(Error::DimensionMismatch {
            what: "jacobian (6 × nv entries)",
            expected: 6 * model.nv(),
            got: jacobian.len(),
        });
    }
    jacobian_into(
        model,
        data,
        q,
        frame,
        ReferenceFrame::LocalWorldAligned,
        jacobian,
    )?;
    let api = ffi::api()?;
    let mut pose = [0.0; 7];
    // SAFETY: valid frame index; `pose` holds 7 doubles. The placements of the frame's support
    // (all the shim reads) were just computed by `computeFrameJacobian`.
    ffi::call("ks_pin_frame_placement", |e, n| unsafe {
        (api.frame_placement)(model.raw(), data.raw(), frame.0, pose.as_mut_ptr(), e, n)
    })?;
    Ok(ffi::isometry(&pose))
}

fn ready(data: &Data) -> Result<(), Error> {
    if data.placements_valid() {
        Ok(())
    } else {
        Err(Error::KinematicsNotComputed)
    }
}
