//! IK targets and the task error (residual and its Jacobian) each step minimises.

use nalgebra::{DMatrix, DVector, Isometry3, Point3, Unit, Vector3};

use super::IkError;

/// Largest accepted `|‖axis‖ − 1|` of a target axis and `|‖quaternion‖ − 1|` of a target
/// rotation: what `Unit::new_normalize` produces is within ~1e-16, so anything beyond 1e-9 was
/// built unchecked from a non-unit value.
const UNIT_TOLERANCE: f64 = 1e-9;

/// What the tool frame must reach, in the model's root frame (for a robot, the base frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkTarget {
    /// The full pose `root_from_tool` (6 constraints).
    Pose(Isometry3<f64>),
    /// Tool origin at `position` with the tool +z axis pointing along `axis` (same direction,
    /// not opposite); the rotation about the axis is free (5 constraints). For grasps whose
    /// roll about the approach direction does not matter.
    PositionAxis {
        /// Tool origin (m, root frame).
        position: Point3<f64>,
        /// Direction of tool +z (root frame).
        axis: Unit<Vector3<f64>>,
    },
    /// Tool origin at `position` with the tool +z axis within `half_angle` of `axis` (a cone
    /// about it); the rotation about tool +z is free (up to 5 constraints: the angle beyond
    /// the cone is the rotation error). For grasps that tolerate a tilted approach.
    PositionCone {
        /// Tool origin (m, root frame).
        position: Point3<f64>,
        /// The cone's axis (root frame).
        axis: Unit<Vector3<f64>>,
        /// The cone's half-angle (rad), in `[0, π/2]`; 0 is [`IkTarget::PositionAxis`].
        half_angle: f64,
    },
}

impl IkTarget {
    /// Number of task rows: 6 for a pose, 5 for a position + axis or cone.
    pub fn rows(&self) -> usize {
        match self {
            IkTarget::Pose(_) => 6,
            IkTarget::PositionAxis { .. } | IkTarget::PositionCone { .. } => 5,
        }
    }

    /// Position and rotation error (m, rad) of the tool pose `root_from_tool` with respect to
    /// this target, as the convergence test measures them (see
    /// [`crate::kinematics::ik::IkSettings::rotation_tolerance`]).
    pub fn errors(&self, root_from_tool: &Isometry3<f64>) -> (f64, f64) {
        let p = root_from_tool.translation.vector;
        match self {
            IkTarget::Pose(target) => (
                (target.translation.vector - p).norm(),
                (target.rotation * root_from_tool.rotation.inverse()).angle(),
            ),
            IkTarget::PositionAxis { position, axis } => {
                let z = root_from_tool.rotation * Vector3::z();
                ((position.coords - p).norm(), angle_between(&z, axis))
            }
            IkTarget::PositionCone {
                position,
                axis,
                half_angle,
            } => {
                let z = root_from_tool.rotation * Vector3::z();
                let beyond = (angle_between(&z, axis) - half_angle).max(0.0);
                ((position.coords - p).norm(), beyond)
            }
        }
    }

    /// `Err` unless the target is finite and its rotation or axis is unit length.
    pub(crate) fn validate(&self) -> Result<(), IkError> {
        match self {
            IkTarget::Pose(pose) => {
                if !pose.translation.vector.iter().all(|c| c.is_finite()) {
                    return Err(IkError::NonFinite {
                        what: "target position",
                    });
                }
                let quaternion = pose.rotation.as_ref().coords;
                if !quaternion.iter().all(|c| c.is_finite()) {
                    return Err(IkError::NonFinite {
                        what: "target rotation",
                    });
                }
                let norm = quaternion.norm();
                if (norm - 1.0).abs() > UNIT_TOLERANCE {
                    return Err(IkError::NonUnitRotation { norm });
                }
            }
            IkTarget::PositionCone {
                position,
                axis,
                half_angle,
            } => {
                if !(0.0..=std::f64::consts::FRAC_PI_2).contains(half_angle) {
                    return Err(IkError::InvalidCone {
                        half_angle: *half_angle,
                    });
                }
                return IkTarget::PositionAxis {
                    position: *position,
                    axis: *axis,
                }
                .validate();
            }
            IkTarget::PositionAxis { position, axis } => {
                if !position.coords.iter().all(|c| c.is_finite()) {
                    return Err(IkError::NonFinite {
                        what: "target position",
                    });
                }
                if !axis.iter().all(|c| c.is_finite()) {
                    return Err(IkError::NonFinite {
                        what: "target axis",
                    });
                }
                let norm = axis.norm();
                if (norm - 1.0).abs() > UNIT_TOLERANCE {
                    return Err(IkError::NonUnitAxis { norm });
                }
            }
        }
        Ok(())
    }
}

/// The residual `e` (m, rad) and task Jacobian `J` (rows × n) of one step: the step QP
/// minimises `½‖J dq − e‖² + ...`.
#[derive(Debug)]
pub(crate) struct Task {
    pub residual: DVector<f64>,
    pub jacobian: DMatrix<f64>,
    pub position_error: f64,
    pub rotation_error: f64,
}

impl Task {
    /// A task of `target.rows()` rows over `n` velocity coordinates (zero until updated).
    pub fn new(target: &IkTarget, n: usize) -> Task {
        Task {
            residual: DVector::zeros(target.rows()),
            jacobian: DMatrix::zeros(target.rows(), n),
            position_error: 0.0,
            rotation_error: 0.0,
        }
    }

    /// The task at tool pose `root_from_tool`, whose frame Jacobian (6 × nv, Pinocchio's
    /// `LOCAL_WORLD_ALIGNED`: tool-origin velocity and angular velocity, both in root axes)
    /// is `jacobian`, over its columns `columns` (the task's n coordinates, in order).
    ///
    /// - Pose: `e = [p* − p; log(R* Rᵀ)]`, the rotation error as a rotation vector in root
    ///   axes, so that a rotation by `ω = e_rot` takes R to R* (first order, matching the
    ///   angular rows).
    /// - Position + axis: `e = [p* − p; θ; 0]` with rows `[J_v; u₁ᵀ J_ω; u₂ᵀ J_ω]`, where z is
    ///   the current tool +z, θ the angle from z to the target axis a, `u₁ = (z × a)/‖z × a‖`
    ///   (any unit vector ⊥ z when z ∥ a) and `u₂ = z × u₁`. Rotating by `θ u₁` takes z onto
    ///   a; the two rows constrain the angular velocity orthogonal to z only, so the roll
    ///   about the tool axis is free. This is the 5-D error "position and the components of
    ///   z × a orthogonal to z".
    ///
    /// # Panics
    /// If the task was made for a target with another row count or for another n.
    pub fn update(
        &mut self,
        target: &IkTarget,
        root_from_tool: &Isometry3<f64>,
        jacobian: &DMatrix<f64>,
        columns: &[usize],
    ) {
        assert_eq!(
            self.residual.len(),
            target.rows(),
            "task made for another target"
        );
        assert_eq!(
            self.jacobian.ncols(),
            columns.len(),
            "task made for another n"
        );
        let p = root_from_tool.translation.vector;
        for (k, &c) in columns.iter().enumerate() {
            for r in 0..3 {
                self.jacobian[(r, k)] = jacobian[(r, c)];
            }
        }
        match target {
            IkTarget::Pose(pose) => {
                let dp = pose.translation.vector - p;
                let rotation = (pose.rotation * root_from_tool.rotation.inverse()).scaled_axis();
                self.residual.rows_mut(0, 3).copy_from(&dp);
                self.residual.rows_mut(3, 3).copy_from(&rotation);
                for (k, &c) in columns.iter().enumerate() {
                    for r in 3..6 {
                        self.jacobian[(r, k)] = jacobian[(r, c)];
                    }
                }
                self.position_error = dp.norm();
                self.rotation_error = rotation.norm();
            }
            IkTarget::PositionAxis { position, axis } => {
                let dp = position.coords - p;
                let z = root_from_tool.rotation * Vector3::z();
                let theta = angle_between(&z, axis);
                let u1 = Unit::try_new(z.cross(axis), 1e-12)
                    .unwrap_or_else(|| perpendicular(&z))
                    .into_inner();
                let u2 = z.cross(&u1);
                self.residual.rows_mut(0, 3).copy_from(&dp);
                self.residual[3] = theta;
                self.residual[4] = 0.0;
                for (k, &c) in columns.iter().enumerate() {
                    let angular =
                        Vector3::new(jacobian[(3, c)], jacobian[(4, c)], jacobian[(5, c)]);
                    self.jacobian[(3, k)] = u1.dot(&angular);
                    self.jacobian[(4, k)] = u2.dot(&angular);
                }
                self.position_error = dp.norm();
                self.rotation_error = theta;
            }
            IkTarget::PositionCone {
                position,
                axis,
                half_angle,
            } => {
                let dp = position.coords - p;
                let z = root_from_tool.rotation * Vector3::z();
                let beyond = angle_between(&z, axis) - half_angle;
                self.residual.rows_mut(0, 3).copy_from(&dp);
                self.residual[3] = beyond.max(0.0);
                self.residual[4] = 0.0;
                // Inside the cone the axis is free; outside, only the tilt towards the axis
                // is constrained (the row of `u₁`, as for a position + axis).
                let u1 = Unit::try_new(z.cross(axis), 1e-12)
                    .unwrap_or_else(|| perpendicular(&z))
                    .into_inner();
                for (k, &c) in columns.iter().enumerate() {
                    let angular =
                        Vector3::new(jacobian[(3, c)], jacobian[(4, c)], jacobian[(5, c)]);
                    self.jacobian[(3, k)] = if beyond > 0.0 { u1.dot(&angular) } else { 0.0 };
                    self.jacobian[(4, k)] = 0.0;
                }
                self.position_error = dp.norm();
                self.rotation_error = beyond.max(0.0);
            }
        }
    }
}

/// Angle between two unit vectors (rad), accurate near 0 and π.
fn angle_between(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

/// Some unit vector orthogonal to the unit vector `z`.
fn perpendicular(z: &Vector3<f64>) -> Unit<Vector3<f64>> {
    let helper = if z.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    Unit::new_normalize(z.cross(&helper))
}
