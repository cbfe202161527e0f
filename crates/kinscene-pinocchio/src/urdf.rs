//! Models parsed from URDF by Pinocchio's own parser ([`Model::from_urdf_str`]).
//!
//! The C++ side builds the model (`pinocchio::urdf::buildModelFromXML`); this module reads it
//! back joint by joint and frame by frame into the Rust-side description every other part of
//! the crate answers lookups from, and checks it against the invariants a [`crate::ModelBuilder`]
//! model has (supported joint kinds, depth-first coordinates, valid limits and inertias).

use std::collections::HashMap;
use std::ffi::{CStr, c_char};
use std::ptr::{self, NonNull};

use nalgebra::{Matrix3, Vector3};

use crate::builder::checked_placement;
use crate::construct::{Building, backend};
use crate::ffi::{self, Api, FrameInfo, JointInfo, RawModel};
use crate::{
    Error, Frame, FrameIndex, FrameKind, Inertia, Joint, JointIndex, JointKind, JointLimits, Model,
};

impl Model {
    /// Parses a URDF document with Pinocchio's parser (urdfdom) into a **fixed-base** model:
    /// `pinocchio::urdf::buildModelFromXML` without a root joint, so the root link is rigidly
    /// attached to the universe.
    ///
    /// What Pinocchio makes of the document, as seen through this crate:
    /// - `revolute` joints are [`JointKind::Revolute`], `continuous` joints
    ///   [`JointKind::RevoluteUnbounded`] (q = `(cos θ, sin θ)`, nq = 2, nv = 1), `prismatic`
    ///   joints [`JointKind::Prismatic`], each with its axis normalised (Pinocchio's specialised
    ///   X/Y/Z joint when the axis is a coordinate axis); `planar` joints
    ///   [`JointKind::Planar`] (Pinocchio ignores the URDF axis: motion in the joint frame's XY
    ///   plane). Each joint's frame carries its name ([`FrameKind::Joint`]).
    /// - Every link is a [`FrameKind::Body`] frame named after it ([`Model::link_frame`]); a
    ///   `fixed` joint is a [`FrameKind::FixedJoint`] frame, and links below it are frames of
    ///   the nearest moving ancestor joint (or the universe).
    /// - Position limits of revolute and prismatic joints come from `<limit lower upper>`;
    ///   velocity and effort limits from `<limit velocity effort>` (`None` where Pinocchio holds
    ///   an infinite value).
    /// - Inertias of all links on a joint are summed into one body per joint
    ///   ([`Model::bodies`]: one entry per joint, the universe included, carrying non-zero
    ///   inertia).
    /// - Joint order and q/v layout are Pinocchio's (depth-first), available per joint as
    ///   [`Joint::idx_q`], [`Joint::nq`], [`Joint::idx_v`].
    ///
    /// URDF keeps link and joint names in separate namespaces, so a link and a joint may share
    /// a name here; [`Model::frame_index`] then returns the first frame of that name, while
    /// [`Model::joint_index`] and [`Model::link_frame`] look up by kind.
    ///
    /// # Errors
    /// [`Error::Backend`] with Pinocchio's exception message when the document is rejected:
    /// malformed XML, a document that is no valid URDF (unknown joint type, missing link,
    /// several roots...); urdfdom's own diagnostic, which it would otherwise print to stderr,
    /// is appended to the message. [`Error::UnsupportedJoint`] for a `floating` joint (or any
    /// other type without a [`JointKind`]), [`Error::InvalidAxis`] for a zero axis,
    /// [`Error::NonFinite`] for a non-finite origin, the errors of [`JointLimits::validate`]
    /// (e.g. [`Error::InvertedLimits`]) and of [`Inertia::validate`], and [`Error::Load`] when
    /// the shim cannot be loaded.
    ///
    /// # Example
    /// ```
    /// use std::f64::consts::FRAC_PI_2;
    ///
    /// use kinscene_pinocchio::{Data, Model, forward_kinematics, frame_placement, set_joint_value};
    /// use nalgebra::{Point3, Vector3};
    ///
    /// let xml = r#"<robot name="cabinet">
    ///   <link name="carcass"/>
    ///   <link name="door"/>
    ///   <joint name="hinge" type="revolute">
    ///     <parent link="carcass"/><child link="door"/>
    ///     <origin xyz="1 0 0"/><axis xyz="0 0 1"/>
    ///     <limit lower="0" upper="2" effort="0" velocity="0"/>
    ///   </joint>
    /// </robot>"#;
    /// let model = Model::from_urdf_str(xml)?;
    /// let hinge = model.joint_index("hinge").unwrap();
    /// let mut q = model.neutral();
    /// set_joint_value(&model, &mut q, hinge, FRAC_PI_2)?;
    ///
    /// let mut data = Data::new(&model)?;
    /// forward_kinematics(&model, &mut data, &q)?;
    /// let door = frame_placement(&model, &data, model.link_frame("door").unwrap())?;
    /// // Opened by 90° about +z at (1, 0, 0): the door's +x now points along +y.
    /// assert!((door * Point3::origin() - Point3::new(1.0, 0.0, 0.0)).norm() < 1e-12);
    /// assert!((door * Vector3::x() - Vector3::y()).norm() < 1e-12);
    /// # Ok::<(), kinscene_pinocchio::Error>(())
    /// ```
    pub fn from_urdf_str(xml: &str) -> Result<Model, Error> {
        let api = ffi::api()?;
        let mut building = Building(ptr::null_mut());
        // SAFETY: `xml` is live for the call and its length is passed; `building.0` is a live
        // out-pointer, owned by the guard from here on.
        ffi::call("ks_pin_model_from_urdf", |e, n| unsafe {
            (api.model_from_urdf)(xml.as_ptr().cast(), xml.len(), &mut building.0, e, n)
        })?;
        let raw = building.0;
        let mut sizes = [0usize; 4];
        let [nq, nv, njoints, nframes] = &mut sizes;
        // SAFETY: a live model and four live out-pointers.
        unsafe { (api.model_sizes)(raw, nq, nv, njoints, nframes) };
        let [nq, nv, njoints, nframes] = sizes;

        let frames = (0..nframes)
            .map(|f| read_frame(api, raw, f))
            .collect::<Result<Vec<_>, _>>()?;
        let mut joints = Vec::with_capacity(njoints.saturating_sub(1));
        let (mut next_q, mut next_v) = (0, 0);
        for j in 1..njoints {
            let joint = read_joint(api, raw, j, &frames)?;
            // The Rust side assumes Pinocchio's layout: coordinates in joint order, parents
            // before children (depth-first). Pinocchio guarantees it; a mismatch would be a bug.
            if joint.idx_q != next_q || joint.idx_v != next_v || joint.parent.0 >= j {
                return Err(backend(
                    "ks_pin_model_joint_info",
                    format!(
                        "joint {:?} breaks the expected layout (idx_q {}, idx_v {}, parent {})",
                        joint.name, joint.idx_q, joint.idx_v, joint.parent.0
                    ),
                ));
            }
            next_q += joint.nq();
            next_v += joint.nv();
            joints.push(joint);
        }
        if (next_q, next_v) != (nq, nv) {
            return Err(backend(
                "ks_pin_model_sizes",
                format!(
                    "Pinocchio reports nq = {nq}, nv = {nv}; the joints add up to {next_q}, {next_v}"
                ),
            ));
        }
        let mut bodies = Vec::new();
        for j in 0..njoints {
            if let Some(inertia) = read_inertia(api, raw, j)? {
                bodies.push((JointIndex(j), inertia));
            }
        }
        let mut names = HashMap::with_capacity(frames.len());
        for (i, frame) in frames.iter().enumerate() {
            names.entry(frame.name.clone()).or_insert(FrameIndex(i));
        }
        let raw = NonNull::new(raw).expect("ks_pin_model_from_urdf succeeded");
        building.0 = ptr::null_mut();
        Ok(Model::from_raw(
            raw,
            joints,
            frames,
            bodies,
            names,
            (nq, nv),
        ))
    }
}

/// Copies a name the shim returned (valid while the model lives).
fn name(ptr: *const c_char, what: &'static str, index: usize) -> Result<String, Error> {
    if ptr.is_null() {
        return Err(backend(what, format!("no name for index {index}")));
    }
    // SAFETY: a NUL-terminated string owned by the live model.
    Ok(unsafe { CStr::from_ptr(ptr) }
        .to_string_lossy()
        .into_owned())
}

fn read_frame(api: &Api, raw: *mut RawModel, index: usize) -> Result<Frame, Error> {
    let mut info = FrameInfo {
        kind: 0,
        parent_joint: 0,
        parent_frame: 0,
        joint_from_frame: [0.0; 7],
    };
    // SAFETY: a live model, an in-range index (below nframes) and a live out-struct.
    ffi::call("ks_pin_model_frame_info", |e, n| unsafe {
        (api.model_frame_info)(raw, index, &mut info, e, n)
    })?;
    // SAFETY: a live model.
    let name = name(
        unsafe { (api.model_frame_name)(raw, index) },
        "ks_pin_model_frame_name",
        index,
    )?;
    let kind = match info.kind {
        ffi::OP_FRAME => FrameKind::Operational,
        ffi::FIXED_JOINT => FrameKind::FixedJoint,
        ffi::BODY => FrameKind::Body,
        ffi::JOINT_FRAME => FrameKind::Joint,
        other => {
            return Err(backend(
                "ks_pin_model_frame_info",
                format!("frame {name:?} has a frame type ({other}) this crate does not model"),
            ));
        }
    };
    Ok(Frame {
        name,
        parent_joint: JointIndex(info.parent_joint),
        joint_from_frame: checked_placement(
            &ffi::isometry(&info.joint_from_frame),
            "joint_from_frame",
        )?,
        kind,
    })
}

fn read_joint(
    api: &Api,
    raw: *mut RawModel,
    index: usize,
    frames: &[Frame],
) -> Result<Joint, Error> {
    let mut info = JointInfo {
        kind: 0,
        axis: [0.0; 3],
        parent: 0,
        parent_from_joint: [0.0; 7],
        idx_q: 0,
        idx_v: 0,
        nq: 0,
        nv: 0,
        lower: 0.0,
        upper: 0.0,
        velocity: 0.0,
        effort: 0.0,
        type_name: [0; 64],
    };
    // SAFETY: a live model, an index in 1..njoints and a live out-struct.
    ffi::call("ks_pin_model_joint_info", |e, n| unsafe {
        (api.model_joint_info)(raw, index, &mut info, e, n)
    })?;
    // SAFETY: a live model.
    let name = name(
        unsafe { (api.model_joint_name)(raw, index) },
        "ks_pin_model_joint_name",
        index,
    )?;
    let axis = Vector3::from(info.axis);
    let kind = match info.kind {
        ffi::REVOLUTE => JointKind::Revolute { axis },
        ffi::REVOLUTE_UNBOUNDED => JointKind::RevoluteUnbounded { axis },
        ffi::PRISMATIC => JointKind::Prismatic { axis },
        ffi::PLANAR => JointKind::Planar,
        _ => {
            // SAFETY: the shim NUL-terminates `type_name` within its 64 bytes.
            let kind = unsafe { CStr::from_ptr(info.type_name.as_ptr()) }
                .to_string_lossy()
                .into_owned();
            return Err(Error::UnsupportedJoint { joint: name, kind });
        }
    }
    .normalised(&name)?;
    if (info.nq, info.nv) != (kind.nq(), kind.nv()) {
        return Err(backend(
            "ks_pin_model_joint_info",
            format!(
                "joint {name:?}: nq = {}, nv = {} do not match its kind",
                info.nq, info.nv
            ),
        ));
    }
    let unlimited = |lo: f64, hi: f64| lo <= -f64::MAX && hi >= f64::MAX;
    let finite = |x: f64| (x < f64::MAX).then_some(x);
    let limits = JointLimits {
        position: (kind.nq() == 1 && !unlimited(info.lower, info.upper))
            .then_some((info.lower, info.upper)),
        velocity: finite(info.velocity),
        effort: finite(info.effort),
    };
    limits.validate(&name, &kind)?;
    let joint = JointIndex(index);
    let frame = frames
        .iter()
        .position(|f| f.kind == FrameKind::Joint && f.parent_joint == joint)
        .map(FrameIndex)
        .ok_or_else(|| {
            backend(
                "ks_pin_model_frame_info",
                format!("joint {name:?} has no JOINT frame"),
            )
        })?;
    Ok(Joint {
        parent_from_joint: checked_placement(
            &ffi::isometry(&info.parent_from_joint),
            "parent_from_joint",
        )?,
        name,
        kind,
        parent: JointIndex(info.parent),
        limits,
        idx_q: info.idx_q,
        idx_v: info.idx_v,
        frame,
    })
}

/// The inertia carried by joint `index`, `None` when it is zero (no link with an inertial).
fn read_inertia(api: &Api, raw: *mut RawModel, index: usize) -> Result<Option<Inertia>, Error> {
    let mut mass = 0.0;
    let mut com = Vector3::zeros();
    let mut rotational = Matrix3::zeros();
    // SAFETY: a live model, an index below njoints, and out-buffers of 1, 3 and 9 doubles.
    ffi::call("ks_pin_model_inertia", |e, n| unsafe {
        (api.model_inertia)(
            raw,
            index,
            &mut mass,
            com.as_mut_ptr(),
            rotational.as_mut_ptr(),
            e,
            n,
        )
    })?;
    if mass == 0.0 && com.iter().all(|&c| c == 0.0) && rotational.iter().all(|&c| c == 0.0) {
        return Ok(None);
    }
    let inertia = Inertia {
        mass,
        com,
        rotational,
    };
    inertia.validate(index)?;
    Ok(Some(inertia))
}
