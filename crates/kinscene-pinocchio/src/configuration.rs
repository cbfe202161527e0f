//! The configuration space: validating q, `integrate`, `difference`, `normalize`.
//!
//! q lives on a manifold: the `(cos θ, sin θ)` pair of an unbounded revolute joint and of a
//! planar joint must be a unit vector, and v (nv entries) is a tangent vector, so nq ≠ nv for
//! such models. **Every function of this crate rejects a q whose pairs are off unit length by
//! more than [`UNIT_NORM_TOLERANCE`]** ([`Error::NotNormalized`]) rather than normalising it
//! silently; call [`normalize`] first when q comes from arithmetic that does not preserve the
//! norm (plain interpolation, an optimiser's step).

use nalgebra::DVector;

use crate::{Error, JointIndex, JointKind, Model, ffi};

/// Largest accepted `| ‖(cos, sin)‖ − 1 |` in q. Pinocchio uses the pair as is, so a pair off by
/// ε scales the joint's rotation matrix by 1 + ε; 1e-9 keeps that error below what double
/// precision kinematics of a metre-scale robot resolves in practice, while accepting the
/// output of [`integrate`] (renormalised to first order, error ~1e-16) and of `cos`/`sin`.
pub const UNIT_NORM_TOLERANCE: f64 = 1e-9;

/// Checks that `q` is a valid configuration of `model`.
///
/// # Errors
/// [`Error::DimensionMismatch`] (length ≠ nq), [`Error::NonFinite`], [`Error::NotNormalized`].
pub fn check_configuration(model: &Model, q: &DVector<f64>) -> Result<(), Error> {
    check_q(model, q, "q")
}

/// Rescales every `(cos, sin)` pair of `q` to unit length, in place.
///
/// # Errors
/// [`Error::DimensionMismatch`], [`Error::NonFinite`], and [`Error::NotNormalized`] for a pair
/// too close to zero (norm below 1e-12) to have a direction.
pub fn normalize(model: &Model, q: &mut DVector<f64>) -> Result<(), Error> {
    check_finite(model.nq(), q, "q")?;
    for joint in model.joints() {
        if let Some(offset) = joint.kind.unit_pair_offset() {
            let i = joint.idx_q + offset;
            let norm = q[i].hypot(q[i + 1]);
            if norm < 1e-12 {
                return Err(Error::NotNormalized {
                    joint: joint.name.clone(),
                    norm,
                });
            }
            q[i] /= norm;
            q[i + 1] /= norm;
        }
    }
    Ok(())
}

/// Writes the value of the one-degree-of-freedom joint `joint` into `q`: the angle (radians)
/// of a revolute joint, the displacement (metres) of a prismatic one, and for an unbounded
/// revolute (URDF `continuous`) joint the pair `(cos θ, sin θ)` of the angle θ given. The
/// other entries of `q` are left as they are. No limit is enforced (as everywhere in this
/// crate).
///
/// This is how joint values keyed by name map onto q for a model whose layout came from
/// elsewhere (e.g. [`Model::from_urdf_str`]): `model.joint_index(name)`, then this.
///
/// # Errors
/// [`Error::DimensionMismatch`] (length of `q` ≠ nq), [`Error::JointOutOfRange`] (the
/// universe or past the last joint), [`Error::NotScalarJoint`] for a planar joint,
/// [`Error::NonFinite`] for a NaN or infinite value.
pub fn set_joint_value(
    model: &Model,
    q: &mut DVector<f64>,
    joint: JointIndex,
    value: f64,
) -> Result<(), Error> {
    if q.len() != model.nq() {
        return Err(Error::DimensionMismatch {
            what: "q",
            expected: model.nq(),
            got: q.len(),
        });
    }
    let j = model.joint(joint)?;
    if !value.is_finite() {
        return Err(Error::NonFinite {
            what: "joint value",
        });
    }
    match j.kind {
        JointKind::Revolute { .. } | JointKind::Prismatic { .. } => q[j.idx_q] = value,
        JointKind::RevoluteUnbounded { .. } => {
            let (sin, cos) = value.sin_cos();
            q[j.idx_q] = cos;
            q[j.idx_q + 1] = sin;
        }
        JointKind::Planar => {
            return Err(Error::NotScalarJoint {
                joint: j.name.clone(),
            });
        }
    }
    Ok(())
}

/// The configuration reached from `q` by following the tangent vector `v` for unit time
/// (Pinocchio's `integrate`, q ⊕ v). For a planar joint this is the SE(2) exponential with v
/// expressed in the moving frame; for revolute and prismatic coordinates it is `q + v`.
///
/// # Errors
/// [`Error::DimensionMismatch`], [`Error::NonFinite`], [`Error::NotNormalized`] (q),
/// [`Error::Backend`].
pub fn integrate(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> Result<DVector<f64>, Error> {
    check_q(model, q, "q")?;
    check_finite(model.nv(), v, "v")?;
    let api = ffi::api()?;
    let mut out = DVector::zeros(model.nq());
    // SAFETY: q has nq entries, v nv, out nq (checked above).
    ffi::call("ks_pin_integrate", |e, n| unsafe {
        (api.integrate)(model.raw(), q.as_ptr(), v.as_ptr(), out.as_mut_ptr(), e, n)
    })?;
    Ok(out)
}

/// The tangent vector v with `integrate(q0, v) = q1` (Pinocchio's `difference`, q1 ⊖ q0). For
/// `(cos, sin)` pairs the angle part lies in (−π, π].
///
/// # Errors
/// [`Error::DimensionMismatch`], [`Error::NonFinite`], [`Error::NotNormalized`],
/// [`Error::Backend`].
pub fn difference(
    model: &Model,
    q0: &DVector<f64>,
    q1: &DVector<f64>,
) -> Result<DVector<f64>, Error> {
    check_q(model, q0, "q0")?;
    check_q(model, q1, "q1")?;
    let api = ffi::api()?;
    let mut out = DVector::zeros(model.nv());
    // SAFETY: q0 and q1 have nq entries, out nv.
    ffi::call("ks_pin_difference", |e, n| unsafe {
        (api.difference)(
            model.raw(),
            q0.as_ptr(),
            q1.as_ptr(),
            out.as_mut_ptr(),
            e,
            n,
        )
    })?;
    Ok(out)
}

/// Size, finiteness and unit pairs of a configuration named `what`.
pub(crate) fn check_q(model: &Model, q: &DVector<f64>, what: &'static str) -> Result<(), Error> {
    check_finite(model.nq(), q, what)?;
    for joint in model.joints() {
        if let Some(offset) = joint.kind.unit_pair_offset() {
            let i = joint.idx_q + offset;
            let norm = q[i].hypot(q[i + 1]);
            if (norm - 1.0).abs() > UNIT_NORM_TOLERANCE {
                return Err(Error::NotNormalized {
                    joint: joint.name.clone(),
                    norm,
                });
            }
        }
    }
    Ok(())
}

/// Length `expected` and all entries finite.
pub(crate) fn check_finite(
    expected: usize,
    x: &DVector<f64>,
    what: &'static str,
) -> Result<(), Error> {
    if x.len() != expected {
        return Err(Error::DimensionMismatch {
            what,
            expected,
            got: x.len(),
        });
    }
    if !x.iter().all(|c| c.is_finite()) {
        return Err(Error::NonFinite { what });
    }
    Ok(())
}
