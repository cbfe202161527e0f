//! Rigid-body inertia attached to a joint.

use nalgebra::{Matrix3, Vector3};

use crate::Error;

/// Mass properties of a rigid body, expressed in the frame of the joint that carries it.
///
/// Kinematics does not need inertias; they are optional and stored in Pinocchio's model for
/// later dynamics or centre-of-mass queries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia {
    /// Mass, kg (non-negative).
    pub mass: f64,
    /// Centre of mass in the joint frame, metres.
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, in joint-frame axes, kg m². Symmetric
    /// positive semi-definite.
    pub rotational: Matrix3<f64>,
}

impl Inertia {
    /// A point mass at `com`.
    pub fn point_mass(mass: f64, com: Vector3<f64>) -> Inertia {
        Inertia {
            mass,
            com,
            rotational: Matrix3::zeros(),
        }
    }

    /// Checks the inertia of a body carried by joint index `joint` (used in messages).
    ///
    /// Symmetry is checked to 1e-9 relative to the largest entry; positive semi-definiteness
    /// allows eigenvalues down to -1e-12 times the largest entry (rounding in a symmetric
    /// eigen-decomposition is a few ulps of the largest entry).
    ///
    /// # Errors
    /// [`Error::NonFinite`], [`Error::NegativeMass`], [`Error::InvalidInertia`].
    pub fn validate(&self, joint: usize) -> Result<(), Error> {
        if !self.mass.is_finite() {
            return Err(Error::NonFinite { what: "mass" });
        }
        if self.mass < 0.0 {
            return Err(Error::NegativeMass {
                joint,
                mass: self.mass,
            });
        }
        if !self.com.iter().all(|c| c.is_finite()) {
            return Err(Error::NonFinite { what: "com" });
        }
        if !self.rotational.iter().all(|c| c.is_finite()) {
            return Err(Error::NonFinite {
                what: "rotational inertia",
            });
        }
        let scale = self.rotational.amax().max(f64::MIN_POSITIVE);
        if (self.rotational - self.rotational.transpose()).amax() > 1e-9 * scale {
            return Err(Error::InvalidInertia {
                joint,
                reason: "is not symmetric",
            });
        }
        let eigen = self.rotational.symmetric_eigenvalues();
        if eigen.min() < -1e-12 * scale {
            return Err(Error::InvalidInertia {
                joint,
                reason: "is not positive semi-definite",
            });
        }
        Ok(())
    }
}
