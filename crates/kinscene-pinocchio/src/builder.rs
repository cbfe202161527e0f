//! Building a [`Model`] programmatically: joints, bodies and frames, validated in Rust.

use std::collections::HashMap;

use nalgebra::{Isometry3, UnitQuaternion};

use crate::{
    Error, Frame, FrameIndex, FrameKind, Inertia, Joint, JointIndex, JointKind, JointLimits, Model,
};

/// Name of joint 0 and frame 0, as in Pinocchio.
pub const UNIVERSE_NAME: &str = "universe";

/// Collects joints, bodies and frames; [`ModelBuilder::build`] turns them into a [`Model`].
///
/// Every `add_*` method validates its input and returns the new index, so a builder never holds
/// an invalid model. Nothing touches C++ before [`ModelBuilder::build`].
///
/// # Example
/// ```
/// use kinscene_pinocchio::{JointIndex, JointKind, JointLimits, ModelBuilder};
/// use nalgebra::{Isometry3, Vector3};
///
/// let mut b = ModelBuilder::new();
/// let shoulder = b.add_joint(
///     "shoulder",
///     JointIndex::UNIVERSE,
///     Isometry3::translation(0.0, 0.0, 0.3),
///     JointKind::Revolute { axis: Vector3::z() },
///     JointLimits::position(-2.8, 2.8),
/// )?;
/// let tool = b.add_frame("tool", shoulder, Isometry3::translation(0.5, 0.0, 0.0))?;
/// let model = b.build()?;
/// assert_eq!((model.nq(), model.nv()), (1, 1));
/// assert_eq!(model.frame_index("tool"), Some(tool));
/// # Ok::<(), kinscene_pinocchio::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct ModelBuilder {
    joints: Vec<Joint>,
    frames: Vec<Frame>,
    bodies: Vec<(JointIndex, Inertia)>,
    names: HashMap<String, FrameIndex>,
    nq: usize,
    nv: usize,
}

impl Default for ModelBuilder {
    fn default() -> Self {
        ModelBuilder::new()
    }
}

impl ModelBuilder {
    /// An empty model: the universe joint 0 and the universe frame 0.
    pub fn new() -> ModelBuilder {
        let universe = Frame {
            name: UNIVERSE_NAME.to_owned(),
            parent_joint: JointIndex::UNIVERSE,
            joint_from_frame: Isometry3::identity(),
            kind: FrameKind::FixedJoint,
        };
        ModelBuilder {
            joints: Vec::new(),
            frames: vec![universe],
            bodies: Vec::new(),
            names: HashMap::from([(UNIVERSE_NAME.to_owned(), FrameIndex::UNIVERSE)]),
            nq: 0,
            nv: 0,
        }
    }

    /// Adds a joint `name` of `kind` under `parent`, placed at `parent_from_joint` (the joint
    /// frame in the parent joint's frame at the neutral configuration). Also adds the joint's
    /// frame, with the same name.
    ///
    /// Joints must be added depth-first: `parent` is the universe or a joint on the chain from
    /// the universe to the last added joint.
    ///
    /// # Errors
    /// [`Error::InvalidName`], [`Error::DuplicateName`], [`Error::JointOutOfRange`] (unknown
    /// parent), [`Error::NotDepthFirst`], [`Error::NonFinite`] (placement),
    /// [`Error::InvalidAxis`], and the errors of [`JointLimits::validate`].
    pub fn add_joint(
        &mut self,
        name: &str,
        parent: JointIndex,
        parent_from_joint: Isometry3<f64>,
        kind: JointKind,
        limits: JointLimits,
    ) -> Result<JointIndex, Error> {
        self.check_new_name("joint", name)?;
        self.check_joint(parent)?;
        if !self.on_last_chain(parent) {
            return Err(Error::NotDepthFirst {
                joint: name.to_owned(),
                parent: parent.0,
            });
        }
        let parent_from_joint = checked_placement(&parent_from_joint, "parent_from_joint")?;
        let kind = kind.normalised(name)?;
        limits.validate(name, &kind)?;

        let index = JointIndex(self.joints.len() + 1);
        let frame = self.push_frame(name, index, Isometry3::identity(), FrameKind::Joint);
        self.joints.push(Joint {
            name: name.to_owned(),
            kind,
            parent,
            parent_from_joint,
            limits,
            idx_q: self.nq,
            idx_v: self.nv,
            frame,
        });
        self.nq += kind.nq();
        self.nv += kind.nv();
        Ok(index)
    }

    /// Appends a rigid body to `joint` (Pinocchio's `appendBodyToJoint`; several bodies on one
    /// joint add up).
    ///
    /// # Errors
    /// [`Error::JointOutOfRange`], and the errors of [`Inertia::validate`].
    pub fn add_body(&mut self, joint: JointIndex, inertia: Inertia) -> Result<(), Error> {
        self.check_joint(joint)?;
        inertia.validate(joint.0)?;
        self.bodies.push((joint, inertia));
        Ok(())
    }

    /// Adds an operational frame (`OP_FRAME`) `name` rigidly attached to `parent_joint` at
    /// `joint_from_frame`.
    ///
    /// # Errors
    /// [`Error::InvalidName`], [`Error::DuplicateName`], [`Error::JointOutOfRange`],
    /// [`Error::NonFinite`].
    pub fn add_frame(
        &mut self,
        name: &str,
        parent_joint: JointIndex,
        joint_from_frame: Isometry3<f64>,
    ) -> Result<FrameIndex, Error> {
        self.add_fixed(name, parent_joint, joint_from_frame, FrameKind::Operational)
    }

    /// Like [`ModelBuilder::add_frame`], but the frame is marked as a fixed joint
    /// (`FIXED_JOINT`), e.g. for a URDF `fixed` joint merged into its parent link.
    ///
    /// # Errors
    /// As [`ModelBuilder::add_frame`].
    pub fn add_fixed_joint_frame(
        &mut self,
        name: &str,
        parent_joint: JointIndex,
        joint_from_frame: Isometry3<f64>,
    ) -> Result<FrameIndex, Error> {
        self.add_fixed(name, parent_joint, joint_from_frame, FrameKind::FixedJoint)
    }

    /// Number of joints so far, the universe included.
    pub fn njoints(&self) -> usize {
        self.joints.len() + 1
    }

    /// Builds the Pinocchio model. The builder is left unchanged (build several models from it,
    /// or keep adding).
    ///
    /// # Errors
    /// [`Error::Load`] when the shim cannot be loaded, [`Error::Backend`] when Pinocchio
    /// throws.
    pub fn build(&self) -> Result<Model, Error> {
        Model::from_parts(
            self.joints.clone(),
            self.frames.clone(),
            self.bodies.clone(),
            self.names.clone(),
            (self.nq, self.nv),
        )
    }

    pub(crate) fn from_model_parts(
        joints: Vec<Joint>,
        frames: Vec<Frame>,
        bodies: Vec<(JointIndex, Inertia)>,
        names: HashMap<String, FrameIndex>,
        (nq, nv): (usize, usize),
    ) -> ModelBuilder {
        ModelBuilder {
            joints,
            frames,
            bodies,
            names,
            nq,
            nv,
        }
    }

    fn add_fixed(
        &mut self,
        name: &str,
        parent_joint: JointIndex,
        joint_from_frame: Isometry3<f64>,
        kind: FrameKind,
    ) -> Result<FrameIndex, Error> {
        self.check_new_name("frame", name)?;
        self.check_joint(parent_joint)?;
        let placement = checked_placement(&joint_from_frame, "joint_from_frame")?;
        Ok(self.push_frame(name, parent_joint, placement, kind))
    }

    fn push_frame(
        &mut self,
        name: &str,
        joint: JointIndex,
        placement: Isometry3<f64>,
        kind: FrameKind,
    ) -> FrameIndex {
        let index = FrameIndex(self.frames.len());
        self.frames.push(Frame {
            name: name.to_owned(),
            parent_joint: joint,
            joint_from_frame: placement,
            kind,
        });
        self.names.insert(name.to_owned(), index);
        index
    }

    fn check_new_name(&self, what: &'static str, name: &str) -> Result<(), Error> {
        if name.is_empty() || name.contains('\0') {
            return Err(Error::InvalidName {
                what,
                name: name.to_owned(),
            });
        }
        if self.names.contains_key(name) {
            return Err(Error::DuplicateName {
                what,
                name: name.to_owned(),
            });
        }
        Ok(())
    }

    fn check_joint(&self, joint: JointIndex) -> Result<(), Error> {
        if joint.0 > self.joints.len() {
            return Err(Error::JointOutOfRange {
                index: joint.0,
                count: self.njoints(),
            });
        }
        Ok(())
    }

    /// Whether `joint` is the universe or an ancestor-or-self of the last added joint.
    fn on_last_chain(&self, joint: JointIndex) -> bool {
        let mut at = JointIndex(self.joints.len());
        loop {
            if at == joint {
                return true;
            }
            if at == JointIndex::UNIVERSE {
                return false;
            }
            at = self.joints[at.0 - 1].parent;
        }
    }
}

/// `iso` with a renormalised rotation, or `Err` when any entry is not finite.
pub(crate) fn checked_placement(
    iso: &Isometry3<f64>,
    what: &'static str,
) -> Result<Isometry3<f64>, Error> {
    let q = iso.rotation.quaternion();
    let finite = q
        .coords
        .iter()
        .chain(iso.translation.vector.iter())
        .all(|c| c.is_finite());
    if !finite || q.norm() < 0.5 {
        return Err(Error::NonFinite { what });
    }
    let rotation = UnitQuaternion::from_quaternion(*q);
    Ok(Isometry3::from_parts(iso.translation, rotation))
}
