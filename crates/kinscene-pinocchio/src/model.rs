//! The immutable [`Model`]: lookups answered in Rust, the C++ model behind a pointer.

use std::collections::HashMap;
use std::ptr::NonNull;
use std::sync::atomic::{AtomicU64, Ordering};

use nalgebra::DVector;

use crate::ffi::{self, RawModel};
use crate::{Error, Frame, FrameIndex, FrameKind, Inertia, Joint, JointIndex, ModelBuilder};

static NEXT_MODEL_ID: AtomicU64 = AtomicU64::new(1);

/// A kinematic tree held by Pinocchio, built with [`ModelBuilder`]. Immutable once built.
///
/// `Model` is `Send + Sync`: share it (`&Model`, `Arc<Model>`) between threads, each with its
/// own [`crate::Data`]. Lookups (sizes, names, limits) are answered in Rust without calling C++.
#[derive(Debug)]
pub struct Model {
    raw: NonNull<RawModel>,
    id: u64,
    nq: usize,
    nv: usize,
    joints: Vec<Joint>,
    frames: Vec<Frame>,
    bodies: Vec<(JointIndex, Inertia)>,
    names: HashMap<String, FrameIndex>,
}

// SAFETY: the C++ model is mutated only inside `construct::build_raw`, before the `Model` exists. Every
// later use passes it as `const pinocchio::Model&` to Pinocchio functions that read it (they keep
// all mutable state in `Data`), so concurrent shared access is sound, and it may be freed from
// any thread.
unsafe impl Send for Model {}
// SAFETY: as above: after construction the model is only read.
unsafe impl Sync for Model {}

impl Drop for Model {
    fn drop(&mut self) {
        if let Ok(api) = ffi::api() {
            // SAFETY: `raw` came from `model_new` and is freed exactly once, here.
            unsafe { (api.model_free)(self.raw.as_ptr()) };
        }
    }
}

impl Model {
    pub(crate) fn from_parts(
        joints: Vec<Joint>,
        frames: Vec<Frame>,
        bodies: Vec<(JointIndex, Inertia)>,
        names: HashMap<String, FrameIndex>,
        (nq, nv): (usize, usize),
    ) -> Result<Model, Error> {
        let raw = crate::construct::build_raw(&joints, &frames, &bodies, (nq, nv))?;
        Ok(Model::from_raw(
            raw,
            joints,
            frames,
            bodies,
            names,
            (nq, nv),
        ))
    }

    /// Wraps a C++ model whose contents `joints`, `frames`, `bodies` and `names` describe
    /// exactly (checked by the caller).
    pub(crate) fn from_raw(
        raw: NonNull<RawModel>,
        joints: Vec<Joint>,
        frames: Vec<Frame>,
        bodies: Vec<(JointIndex, Inertia)>,
        names: HashMap<String, FrameIndex>,
        (nq, nv): (usize, usize),
    ) -> Model {
        Model {
            raw,
            id: NEXT_MODEL_ID.fetch_add(1, Ordering::Relaxed),
            nq,
            nv,
            joints,
            frames,
            bodies,
            names,
        }
    }

    /// Identifies this model among all models of the process (for [`crate::Data`] checks).
    pub(crate) fn id(&self) -> u64 {
        self.id
    }

    pub(crate) fn raw(&self) -> *const RawModel {
        self.raw.as_ptr()
    }

    /// Number of configuration coordinates (length of q).
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// Number of velocity coordinates (length of v, columns of a Jacobian).
    pub fn nv(&self) -> usize {
        self.nv
    }

    /// Number of joints, the universe included (Pinocchio's `njoints`).
    pub fn njoints(&self) -> usize {
        self.joints.len() + 1
    }

    /// Joints 1..njoints in index order (`joints()[i]` is `JointIndex(i + 1)`).
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// A joint (not the universe, which has no kind or placement).
    ///
    /// # Errors
    /// [`Error::JointOutOfRange`] for the universe or an index past the last joint.
    pub fn joint(&self, joint: JointIndex) -> Result<&Joint, Error> {
        joint
            .0
            .checked_sub(1)
            .and_then(|i| self.joints.get(i))
            .ok_or(Error::JointOutOfRange {
                index: joint.0,
                count: self.njoints(),
            })
    }

    /// The joint called `name` (`Some(JointIndex::UNIVERSE)` for `"universe"`).
    pub fn joint_index(&self, name: &str) -> Option<JointIndex> {
        if name == crate::builder::UNIVERSE_NAME {
            return Some(JointIndex::UNIVERSE);
        }
        let frame = self.frames.get(self.names.get(name)?.0)?;
        if frame.kind == FrameKind::Joint {
            return Some(frame.parent_joint);
        }
        // A URDF link may share its name with a joint (URDF keeps them in separate
        // namespaces); `names` then holds whichever frame came first.
        self.joints
            .iter()
            .position(|j| j.name == name)
            .map(|i| JointIndex(i + 1))
    }

    /// A joint's name (`"universe"` for joint 0), `None` when out of range.
    pub fn joint_name(&self, joint: JointIndex) -> Option<&str> {
        if joint == JointIndex::UNIVERSE {
            return Some(crate::builder::UNIVERSE_NAME);
        }
        self.joint(joint).ok().map(|j| j.name.as_str())
    }

    /// All frames in index order, the universe frame first.
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// A frame.
    ///
    /// # Errors
    /// [`Error::FrameOutOfRange`].
    pub fn frame(&self, frame: FrameIndex) -> Result<&Frame, Error> {
        self.frames.get(frame.0).ok_or(Error::FrameOutOfRange {
            index: frame.0,
            count: self.frames.len(),
        })
    }

    /// The frame called `name` (joint frames carry their joint's name). In a model read from
    /// URDF, where a link and a joint may share a name, this is the first such frame in index
    /// order (as Pinocchio's `getFrameId` without a type); use [`Model::link_frame`] for links.
    pub fn frame_index(&self, name: &str) -> Option<FrameIndex> {
        self.names.get(name).copied()
    }

    /// The frame of URDF link `link` (a [`FrameKind::Body`] frame; models built by
    /// [`Model::from_urdf_str`]). Its placement is the link frame: the child frame of the
    /// link's joint, composed with any `fixed` joints in between.
    pub fn link_frame(&self, link: &str) -> Option<FrameIndex> {
        self.frames
            .iter()
            .position(|f| f.kind == FrameKind::Body && f.name == link)
            .map(FrameIndex)
    }

    /// Bodies appended with [`ModelBuilder::add_body`], in order.
    pub fn bodies(&self) -> &[(JointIndex, Inertia)] {
        &self.bodies
    }

    /// The neutral configuration: zero for angles and displacements, `(cos, sin) = (1, 0)` for
    /// unit pairs (Pinocchio's `neutral`, computed in Rust).
    pub fn neutral(&self) -> DVector<f64> {
        let mut q = DVector::zeros(self.nq);
        for joint in &self.joints {
            if let Some(offset) = joint.kind.unit_pair_offset() {
                q[joint.idx_q + offset] = 1.0;
            }
        }
        q
    }

    /// Lower and upper position bounds (length nq): the joints' position limits, `±∞` for
    /// unlimited coordinates, and `[-1, 1]` for the entries of `(cos, sin)` pairs.
    pub fn position_bounds(&self) -> (DVector<f64>, DVector<f64>) {
        let mut lower = DVector::from_element(self.nq, f64::NEG_INFINITY);
        let mut upper = DVector::from_element(self.nq, f64::INFINITY);
        for joint in &self.joints {
            if let Some((lo, hi)) = joint.limits.position {
                lower[joint.idx_q] = lo;
                upper[joint.idx_q] = hi;
            }
            if let Some(offset) = joint.kind.unit_pair_offset() {
                for k in 0..2 {
                    lower[joint.idx_q + offset + k] = -1.0;
                    upper[joint.idx_q + offset + k] = 1.0;
                }
            }
        }
        (lower, upper)
    }

    /// Velocity limits (length nv; `+∞` where unlimited), rad/s or m/s.
    pub fn velocity_limits(&self) -> DVector<f64> {
        self.per_dof(|j| j.limits.velocity)
    }

    /// Effort limits (length nv; `+∞` where unlimited), N m or N.
    pub fn effort_limits(&self) -> DVector<f64> {
        self.per_dof(|j| j.limits.effort)
    }

    /// Pinocchio's neutral configuration, computed by Pinocchio (for cross-checks; prefer
    /// [`Model::neutral`]).
    ///
    /// # Errors
    /// [`Error::Backend`] if Pinocchio throws.
    pub fn pinocchio_neutral(&self) -> Result<DVector<f64>, Error> {
        let api = ffi::api()?;
        let mut q = DVector::zeros(self.nq);
        // SAFETY: `q` has nq entries.
        ffi::call("ks_pin_neutral", |e, n| unsafe {
            (api.neutral)(self.raw(), q.as_mut_ptr(), e, n)
        })?;
        Ok(q)
    }

    /// A builder holding this model's joints, bodies and frames, to extend it into a new model.
    pub fn to_builder(&self) -> ModelBuilder {
        ModelBuilder::from_model_parts(
            self.joints.clone(),
            self.frames.clone(),
            self.bodies.clone(),
            self.names.clone(),
            (self.nq, self.nv),
        )
    }

    fn per_dof(&self, limit: impl Fn(&Joint) -> Option<f64>) -> DVector<f64> {
        let mut out = DVector::from_element(self.nv, f64::INFINITY);
        for joint in &self.joints {
            if let Some(value) = limit(joint) {
                out.rows_mut(joint.idx_v, joint.kind.nv()).fill(value);
            }
        }
        out
    }
}
