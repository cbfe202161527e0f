//! The shim's C ABI (`cpp/shim.h`), declared by hand, and the lazily loaded function table.
//!
//! Nothing here is public: the safe layer (`builder`, `model`, `kinematics`, `configuration`)
//! validates every input before it reaches these pointers.

use std::ffi::{c_char, c_int};
use std::sync::OnceLock;

use kinscene_shim::{LoadError, Shim};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use crate::Error;

/// Opaque `ks_pin_model`.
#[repr(C)]
pub(crate) struct RawModel {
    _private: [u8; 0],
}

/// Opaque `ks_pin_data`.
#[repr(C)]
pub(crate) struct RawData {
    _private: [u8; 0],
}

/// `ks_pin_joint_kind`.
pub(crate) const REVOLUTE: c_int = 0;
pub(crate) const REVOLUTE_UNBOUNDED: c_int = 1;
pub(crate) const PRISMATIC: c_int = 2;
pub(crate) const PLANAR: c_int = 3;

// KS_PIN_UNSUPPORTED (-1) is read back for other joint types: any value not matched above.

/// `ks_pin_frame_kind`.
pub(crate) const OP_FRAME: c_int = 0;
pub(crate) const FIXED_JOINT: c_int = 1;
pub(crate) const BODY: c_int = 2;
pub(crate) const JOINT_FRAME: c_int = 3;

/// `ks_pin_joint_info`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub(crate) struct JointInfo {
    pub kind: c_int,
    pub axis: [f64; 3],
    pub parent: usize,
    pub parent_from_joint: [f64; 7],
    pub idx_q: usize,
    pub idx_v: usize,
    pub nq: usize,
    pub nv: usize,
    pub lower: f64,
    pub upper: f64,
    pub velocity: f64,
    pub effort: f64,
    pub type_name: [c_char; 64],
}

/// `ks_pin_frame_info`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameInfo {
    pub kind: c_int,
    pub parent_joint: usize,
    pub parent_frame: usize,
    pub joint_from_frame: [f64; 7],
}

/// `ks_pin_reference_frame`.
pub(crate) const LOCAL: c_int = 0;
pub(crate) const WORLD: c_int = 1;
pub(crate) const LOCAL_WORLD_ALIGNED: c_int = 2;

/// Typed pointers to every shim function; valid while `_shim` is loaded (the whole process).
pub(crate) struct Api {
    _shim: Shim,
    pub version: unsafe extern "C" fn(*mut c_char, usize),
    pub model_new: unsafe extern "C" fn(*mut *mut RawModel, *mut c_char, usize) -> c_int,
    pub model_free: unsafe extern "C" fn(*mut RawModel),
    #[allow(clippy::type_complexity)]
    pub model_add_joint: unsafe extern "C" fn(
        *mut RawModel,
        c_int,
        usize,
        *const f64,
        *const f64,
        *const c_char,
        *const f64,
        *const f64,
        *const f64,
        *const f64,
        *mut usize,
        *mut usize,
        *mut c_char,
        usize,
    ) -> c_int,
    pub model_append_body: unsafe extern "C" fn(
        *mut RawModel,
        usize,
        f64,
        *const f64,
        *const f64,
        *mut c_char,
        usize,
    ) -> c_int,
    #[allow(clippy::type_complexity)]
    pub model_add_frame: unsafe extern "C" fn(
        *mut RawModel,
        *const c_char,
        usize,
        usize,
        *const f64,
        c_int,
        *mut usize,
        *mut c_char,
        usize,
    ) -> c_int,
    pub model_from_urdf:
        unsafe extern "C" fn(*const c_char, usize, *mut *mut RawModel, *mut c_char, usize) -> c_int,
    pub model_joint_info:
        unsafe extern "C" fn(*const RawModel, usize, *mut JointInfo, *mut c_char, usize) -> c_int,
    pub model_frame_info:
        unsafe extern "C" fn(*const RawModel, usize, *mut FrameInfo, *mut c_char, usize) -> c_int,
    #[allow(clippy::type_complexity)]
    pub model_inertia: unsafe extern "C" fn(
        *const RawModel,
        usize,
        *mut f64,
        *mut f64,
        *mut f64,
        *mut c_char,
        usize,
    ) -> c_int,
    pub model_joint_name: unsafe extern "C" fn(*const RawModel, usize) -> *const c_char,
    pub model_frame_name: unsafe extern "C" fn(*const RawModel, usize) -> *const c_char,
    pub model_sizes:
        unsafe extern "C" fn(*const RawModel, *mut usize, *mut usize, *mut usize, *mut usize),
    pub data_new:
        unsafe extern "C" fn(*const RawModel, *mut *mut RawData, *mut c_char, usize) -> c_int,
    pub data_free: unsafe extern "C" fn(*mut RawData),
    pub forward_kinematics: unsafe extern "C" fn(
        *const RawModel,
        *mut RawData,
        *const f64,
        *mut c_char,
        usize,
    ) -> c_int,
    pub joint_placement: unsafe extern "C" fn(
        *const RawModel,
        *const RawData,
        usize,
        *mut f64,
        *mut c_char,
        usize,
    ) -> c_int,
    pub frame_placement: unsafe extern "C" fn(
        *const RawModel,
        *const RawData,
        usize,
        *mut f64,
        *mut c_char,
        usize,
    ) -> c_int,
    #[allow(clippy::type_complexity)]
    pub frame_jacobian: unsafe extern "C" fn(
        *const RawModel,
        *mut RawData,
        *const f64,
        usize,
        c_int,
        *mut f64,
        *mut c_char,
        usize,
    ) -> c_int,
    pub integrate: unsafe extern "C" fn(
        *const RawModel,
        *const f64,
        *const f64,
        *mut f64,
        *mut c_char,
        usize,
    ) -> c_int,
    pub difference: unsafe extern "C" fn(
        *const RawModel,
        *const f64,
        *const f64,
        *mut f64,
        *mut c_char,
        usize,
    ) -> c_int,
    pub neutral: unsafe extern "C" fn(*const RawModel, *mut f64, *mut c_char, usize) -> c_int,
    #[cfg(feature = "bench")]
    #[allow(clippy::type_complexity)]
    pub bench_forward_kinematics: unsafe extern "C" fn(
        *const RawModel,
        *mut RawData,
        *const f64,
        usize,
        u64,
        *mut u64,
        *mut f64,
        *mut c_char,
        usize,
    ) -> c_int,
}

static API: OnceLock<Result<Api, LoadError>> = OnceLock::new();

/// The loaded shim (loaded on first use, once per process).
pub(crate) fn api() -> Result<&'static Api, Error> {
    API.get_or_init(load)
        .as_ref()
        .map_err(|e| Error::Load(e.clone()))
}

fn load() -> Result<Api, LoadError> {
    let shim = Shim::open(
        "Pinocchio",
        "KINSCENE_PINOCCHIO_SHIM",
        option_env!("KINSCENE_PINOCCHIO_SHIM_BUILT"),
    )?;
    // SAFETY: each type below is the exact signature declared in cpp/shim.h.
    unsafe {
        Ok(Api {
            version: shim.function("ks_pin_version")?,
            model_new: shim.function("ks_pin_model_new")?,
            model_free: shim.function("ks_pin_model_free")?,
            model_add_joint: shim.function("ks_pin_model_add_joint")?,
            model_append_body: shim.function("ks_pin_model_append_body")?,
            model_add_frame: shim.function("ks_pin_model_add_frame")?,
            model_from_urdf: shim.function("ks_pin_model_from_urdf")?,
            model_joint_info: shim.function("ks_pin_model_joint_info")?,
            model_frame_info: shim.function("ks_pin_model_frame_info")?,
            model_inertia: shim.function("ks_pin_model_inertia")?,
            model_joint_name: shim.function("ks_pin_model_joint_name")?,
            model_frame_name: shim.function("ks_pin_model_frame_name")?,
            model_sizes: shim.function("ks_pin_model_sizes")?,
            data_new: shim.function("ks_pin_data_new")?,
            data_free: shim.function("ks_pin_data_free")?,
            forward_kinematics: shim.function("ks_pin_forward_kinematics")?,
            joint_placement: shim.function("ks_pin_joint_placement")?,
            frame_placement: shim.function("ks_pin_frame_placement")?,
            frame_jacobian: shim.function("ks_pin_frame_jacobian")?,
            integrate: shim.function("ks_pin_integrate")?,
            difference: shim.function("ks_pin_difference")?,
            neutral: shim.function("ks_pin_neutral")?,
            #[cfg(feature = "bench")]
            bench_forward_kinematics: shim.function("ks_pin_bench_forward_kinematics")?,
            _shim: shim,
        })
    }
}

/// Calls a fallible shim function (a thin wrapper over [`kinscene_shim::call`]).
pub(crate) fn call(
    function: &'static str,
    f: impl FnOnce(*mut c_char, usize) -> c_int,
) -> Result<(), Error> {
    kinscene_shim::call(function, f).map_err(Error::Backend)
}

/// `parent_from_child` as the shim's pose7: `[qx, qy, qz, qw, tx, ty, tz]`.
pub(crate) fn pose7(iso: &Isometry3<f64>) -> [f64; 7] {
    let q = iso.rotation.quaternion();
    let t = iso.translation.vector;
    [q.i, q.j, q.k, q.w, t.x, t.y, t.z]
}

/// The inverse of [`pose7`]. The shim's quaternion comes from a rotation matrix (unit up to
/// rounding); it is renormalised here.
pub(crate) fn isometry(p: &[f64; 7]) -> Isometry3<f64> {
    let rotation = UnitQuaternion::from_quaternion(Quaternion::new(p[3], p[0], p[1], p[2]));
    Isometry3::from_parts(Translation3::new(p[4], p[5], p[6]), rotation)
}
