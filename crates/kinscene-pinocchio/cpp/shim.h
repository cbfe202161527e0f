// C ABI of the kinscene Pinocchio shim.
//
// Conventions (see ks_common.h): every fallible function returns a ks_status and takes
// (char* err, size_t err_len) last; no C++ exception crosses this boundary.
//
// Layouts shared with the Rust side (crate kinscene-pinocchio, src/ffi.rs):
// - pose7: 7 doubles [qx, qy, qz, qw, tx, ty, tz], a unit quaternion then a translation in
//   metres; it maps the child frame to the parent (parent_from_child).
// - Jacobians: 6 x nv doubles, column-major; rows are linear velocity (3) then angular (3).
// - q has model nq entries, v has model nv entries.
//
// The Rust side validates every input (sizes, finiteness, unit axes, indices, limits) before
// calling; the shim still lets Pinocchio's own checks throw, which ks::guard turns into
// KS_EXCEPTION.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "ks_common.h"

typedef struct ks_pin_model ks_pin_model;
typedef struct ks_pin_data ks_pin_data;

enum ks_pin_joint_kind : int {
    KS_PIN_REVOLUTE = 0,            // nq = 1, nv = 1, about `axis`
    KS_PIN_REVOLUTE_UNBOUNDED = 1,  // nq = 2 (cos, sin), nv = 1, about `axis`
    KS_PIN_PRISMATIC = 2,           // nq = 1, nv = 1, along `axis`
    KS_PIN_PLANAR = 3,              // nq = 4 (x, y, cos, sin), nv = 3, in the joint's XY plane
    KS_PIN_UNSUPPORTED = -1,        // read-back only: a Pinocchio joint type without an equivalent
};

enum ks_pin_frame_kind : int {
    KS_PIN_OP_FRAME = 0,
    KS_PIN_FIXED_JOINT = 1,
    KS_PIN_BODY = 2,         // the frame of a URDF link
    KS_PIN_JOINT_FRAME = 3,  // read-back only: a joint's own frame (made by add_joint)
    KS_PIN_SENSOR = 4,       // read-back only
};

// One joint of a model, as Pinocchio holds it (ks_pin_model_joint_info).
typedef struct ks_pin_joint_info {
    int kind;                    // ks_pin_joint_kind; KS_PIN_UNSUPPORTED for other types
    double axis[3];              // unit axis in the joint frame (zero for planar/unsupported)
    size_t parent;               // parent joint index
    double parent_from_joint[7]; // pose7 of the joint frame in the parent joint's frame
    size_t idx_q, idx_v, nq, nv;
    double lower, upper;         // position limits of the joint's first q coordinate
    double velocity, effort;     // upper velocity and effort limits of its first v coordinate
    char type_name[64];          // Pinocchio's shortname() ("JointModelRX"), NUL-terminated
} ks_pin_joint_info;

// One frame of a model (ks_pin_model_frame_info).
typedef struct ks_pin_frame_info {
    int kind;                    // ks_pin_frame_kind
    size_t parent_joint;
    size_t parent_frame;         // Pinocchio's previous frame in the kinematic tree
    double joint_from_frame[7];  // pose7 of the frame in its parent joint's frame
} ks_pin_frame_info;

enum ks_pin_reference_frame : int {
    KS_PIN_LOCAL = 0,
    KS_PIN_WORLD = 1,
    KS_PIN_LOCAL_WORLD_ALIGNED = 2,
};

// Writes Pinocchio's version string ("4.1.0") into out (NUL-terminated, truncated to len).
KS_API void ks_pin_version(char* out, size_t len);

// An empty model (only the universe joint 0 and the universe frame 0).
KS_API int ks_pin_model_new(ks_pin_model** out, char* err, size_t err_len);
KS_API void ks_pin_model_free(ks_pin_model* model);

// Adds a joint under `parent` and its JOINT frame (same name) under the parent's joint frame.
// `axis` (3 doubles, unit) is ignored for KS_PIN_PLANAR. `lower`/`upper` have the joint's nq
// entries, `velocity`/`effort` its nv entries (+inf for "no limit"; lower bounds of velocity and
// effort are their negatives). Writes the new joint index and frame index.
KS_API int ks_pin_model_add_joint(ks_pin_model* model, int kind, size_t parent,
                                  const double* parent_from_joint, const double* axis,
                                  const char* name, const double* lower, const double* upper,
                                  const double* velocity, const double* effort,
                                  size_t* out_joint, size_t* out_frame, char* err,
                                  size_t err_len);

// Appends a rigid body to `joint`: mass (kg), centre of mass in the joint frame (3, metres),
// rotational inertia about the centre of mass in joint axes (9, column-major, kg m^2).
KS_API int ks_pin_model_append_body(ks_pin_model* model, size_t joint, double mass,
                                    const double* com, const double* inertia, char* err,
                                    size_t err_len);

// Adds a frame fixed to `parent_joint` (whose JOINT frame is `parent_frame`). `kind` is
// KS_PIN_OP_FRAME, KS_PIN_FIXED_JOINT or KS_PIN_BODY.
KS_API int ks_pin_model_add_frame(ks_pin_model* model, const char* name, size_t parent_joint,
                                  size_t parent_frame, const double* joint_from_frame, int kind,
                                  size_t* out_frame, char* err, size_t err_len);

// Parses a URDF document (`xml_len` bytes, not necessarily NUL-terminated) into a new
// fixed-base model: pinocchio::urdf::buildModelFromXML without a root joint. Joints become
// Pinocchio joints (revolute/continuous/prismatic with the specialised X/Y/Z type when the axis
// is a coordinate axis), links BODY frames, fixed joints FIXED_JOINT frames; inertias are
// appended to their joints. A malformed document or one Pinocchio rejects gives KS_EXCEPTION,
// with urdfdom's own diagnostics (normally printed to stderr) appended to the message.
KS_API int ks_pin_model_from_urdf(const char* xml, size_t xml_len, ks_pin_model** out,
                                  char* err, size_t err_len);

// Read-back, for models Pinocchio built (URDF): joint `joint` (1..njoints-1), frame `frame`,
// and the total inertia carried by `joint` (0..njoints-1; mass in kg, centre of mass in the
// joint frame, rotational inertia about it in joint axes, 9 doubles column-major).
KS_API int ks_pin_model_joint_info(const ks_pin_model* model, size_t joint,
                                   ks_pin_joint_info* out, char* err, size_t err_len);
KS_API int ks_pin_model_frame_info(const ks_pin_model* model, size_t frame,
                                   ks_pin_frame_info* out, char* err, size_t err_len);
KS_API int ks_pin_model_inertia(const ks_pin_model* model, size_t joint, double* mass,
                                double* com, double* inertia, char* err, size_t err_len);
// The name of joint `joint` / frame `frame` (NULL when out of range). The pointer stays valid
// while the model lives (models are never modified after construction).
KS_API const char* ks_pin_model_joint_name(const ks_pin_model* model, size_t joint);
KS_API const char* ks_pin_model_frame_name(const ks_pin_model* model, size_t frame);

// Sizes, for consistency checks: nq, nv, number of joints (with the universe), of frames.
KS_API void ks_pin_model_sizes(const ks_pin_model* model, size_t* nq, size_t* nv,
                               size_t* njoints, size_t* nframes);

// Scratch data sized for `model`.
KS_API int ks_pin_data_new(const ks_pin_model* model, ks_pin_data** out, char* err,
                           size_t err_len);
KS_API void ks_pin_data_free(ks_pin_data* data);

// pinocchio::forwardKinematics (joint placements oMi only).
KS_API int ks_pin_forward_kinematics(const ks_pin_model* model, ks_pin_data* data,
                                     const double* q, char* err, size_t err_len);

// world_from_joint (data.oMi) as pose7; valid after ks_pin_forward_kinematics.
KS_API int ks_pin_joint_placement(const ks_pin_model* model, const ks_pin_data* data,
                                  size_t joint, double* out_pose7, char* err, size_t err_len);

// world_from_frame = oMi[parent] * frame placement, computed on demand (data.oMf untouched).
KS_API int ks_pin_frame_placement(const ks_pin_model* model, const ks_pin_data* data,
                                  size_t frame, double* out_pose7, char* err, size_t err_len);

// pinocchio::computeFrameJacobian into out (6 x nv, column-major). Updates the joint placements
// on the frame's support only.
KS_API int ks_pin_frame_jacobian(const ks_pin_model* model, ks_pin_data* data, const double* q,
                                 size_t frame, int reference, double* out, char* err,
                                 size_t err_len);

// pinocchio::integrate / difference / neutral.
KS_API int ks_pin_integrate(const ks_pin_model* model, const double* q, const double* v,
                            double* out_q, char* err, size_t err_len);
KS_API int ks_pin_difference(const ks_pin_model* model, const double* q0, const double* q1,
                             double* out_v, char* err, size_t err_len);
KS_API int ks_pin_neutral(const ks_pin_model* model, double* out_q, char* err, size_t err_len);

// Benchmark only: runs forwardKinematics + updateFramePlacement(frame) `iterations` times in a
// C++ loop and writes the elapsed wall time (steady clock, ns) and a checksum of the frame
// translations (so the loop cannot be optimised away).
KS_API int ks_pin_bench_forward_kinematics(const ks_pin_model* model, ks_pin_data* data,
                                           const double* q, size_t frame, uint64_t iterations,
                                           uint64_t* out_elapsed_ns, double* out_checksum,
                                           char* err, size_t err_len);
