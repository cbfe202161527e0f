// kinscene Pinocchio shim: one small translation unit (it is the slowest shim to compile).
//
// Only the explicitly instantiated signatures of libpinocchio_default are used where possible
// (context::VectorXs / Matrix6xs arguments, Eigen::Ref for forwardKinematics), so most
// algorithms are linked from the library instead of being instantiated here.
#include "shim.h"

#include <chrono>
#include <string>

#include "urdf.hpp"

#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>

namespace pin = pinocchio;

struct ks_pin_model {
    pin::Model model;
};

struct ks_pin_data {
    explicit ks_pin_data(const pin::Model& m) : data(m), q(m.nq), jacobian(6, m.nv) {}
    pin::Data data;
    Eigen::VectorXd q;                   // reused input buffer (avoids an allocation per call)
    pin::Data::Matrix6x jacobian;        // reused output buffer
};

namespace {

using ConstVec = Eigen::Map<const Eigen::VectorXd>;

pin::SE3 se3_from_pose7(const double* p) {
    const Eigen::Quaterniond rotation(p[3], p[0], p[1], p[2]);  // (w, x, y, z)
    return pin::SE3(rotation.toRotationMatrix(), Eigen::Vector3d(p[4], p[5], p[6]));
}

void pose7_from_se3(const pin::SE3& m, double* out) {
    const Eigen::Quaterniond rotation(m.rotation());
    out[0] = rotation.x();
    out[1] = rotation.y();
    out[2] = rotation.z();
    out[3] = rotation.w();
    out[4] = m.translation().x();
    out[5] = m.translation().y();
    out[6] = m.translation().z();
}

void check_joint(const pin::Model& m, size_t joint) {
    if (joint >= static_cast<size_t>(m.njoints)) throw ks::InvalidArgument("joint index out of range");
}

void check_frame(const pin::Model& m, size_t frame) {
    if (frame >= m.frames.size()) throw ks::InvalidArgument("frame index out of range");
}

// Pinocchio's specialised joint when the unit axis is a coordinate axis, else the unaligned one.
pin::JointModel make_joint(int kind, const Eigen::Vector3d& axis) {
    const int aligned = axis == Eigen::Vector3d::UnitX()   ? 0
                        : axis == Eigen::Vector3d::UnitY() ? 1
                        : axis == Eigen::Vector3d::UnitZ() ? 2
                                                           : -1;
    switch (kind) {
    case KS_PIN_REVOLUTE:
        if (aligned == 0) return pin::JointModelRX();
        if (aligned == 1) return pin::JointModelRY();
        if (aligned == 2) return pin::JointModelRZ();
        return pin::JointModelRevoluteUnaligned(axis);
    case KS_PIN_REVOLUTE_UNBOUNDED:
        if (aligned == 0) return pin::JointModelRUBX();
        if (aligned == 1) return pin::JointModelRUBY();
        if (aligned == 2) return pin::JointModelRUBZ();
        return pin::JointModelRevoluteUnboundedUnaligned(axis);
    case KS_PIN_PRISMATIC:
        if (aligned == 0) return pin::JointModelPX();
        if (aligned == 1) return pin::JointModelPY();
        if (aligned == 2) return pin::JointModelPZ();
        return pin::JointModelPrismaticUnaligned(axis);
    case KS_PIN_PLANAR:
        return pin::JointModelPlanar();
    default:
        throw ks::InvalidArgument("unknown joint kind");
    }
}

pin::FrameType frame_type(int kind) {
    switch (kind) {
    case KS_PIN_OP_FRAME: return pin::OP_FRAME;
    case KS_PIN_FIXED_JOINT: return pin::FIXED_JOINT;
    case KS_PIN_BODY: return pin::BODY;
    default: throw ks::InvalidArgument("frames of this kind cannot be added");
    }
}

int frame_kind(pin::FrameType type) {
    switch (type) {
    case pin::OP_FRAME: return KS_PIN_OP_FRAME;
    case pin::FIXED_JOINT: return KS_PIN_FIXED_JOINT;
    case pin::BODY: return KS_PIN_BODY;
    case pin::JOINT: return KS_PIN_JOINT_FRAME;
    default: return KS_PIN_SENSOR;
    }
}

// The ks_pin_joint_kind and unit axis of a Pinocchio joint (the inverse of make_joint).
int joint_kind(const pin::JointModel& joint, Eigen::Vector3d& axis) {
    const auto& v = joint.toVariant();
    axis.setZero();
    if (boost::get<pin::JointModelRX>(&v)) return axis = Eigen::Vector3d::UnitX(), KS_PIN_REVOLUTE;
    if (boost::get<pin::JointModelRY>(&v)) return axis = Eigen::Vector3d::UnitY(), KS_PIN_REVOLUTE;
    if (boost::get<pin::JointModelRZ>(&v)) return axis = Eigen::Vector3d::UnitZ(), KS_PIN_REVOLUTE;
    if (const auto* j = boost::get<pin::JointModelRevoluteUnaligned>(&v))
        return axis = j->axis, KS_PIN_REVOLUTE;
    if (boost::get<pin::JointModelRUBX>(&v))
        return axis = Eigen::Vector3d::UnitX(), KS_PIN_REVOLUTE_UNBOUNDED;
    if (boost::get<pin::JointModelRUBY>(&v))
        return axis = Eigen::Vector3d::UnitY(), KS_PIN_REVOLUTE_UNBOUNDED;
    if (boost::get<pin::JointModelRUBZ>(&v))
        return axis = Eigen::Vector3d::UnitZ(), KS_PIN_REVOLUTE_UNBOUNDED;
    if (const auto* j = boost::get<pin::JointModelRevoluteUnboundedUnaligned>(&v))
        return axis = j->axis, KS_PIN_REVOLUTE_UNBOUNDED;
    if (boost::get<pin::JointModelPX>(&v)) return axis = Eigen::Vector3d::UnitX(), KS_PIN_PRISMATIC;
    if (boost::get<pin::JointModelPY>(&v)) return axis = Eigen::Vector3d::UnitY(), KS_PIN_PRISMATIC;
    if (boost::get<pin::JointModelPZ>(&v)) return axis = Eigen::Vector3d::UnitZ(), KS_PIN_PRISMATIC;
    if (const auto* j = boost::get<pin::JointModelPrismaticUnaligned>(&v))
        return axis = j->axis, KS_PIN_PRISMATIC;
    if (boost::get<pin::JointModelPlanar>(&v)) return KS_PIN_PLANAR;
    return KS_PIN_UNSUPPORTED;
}

}  // namespace

KS_API void ks_pin_version(char* out, size_t len) { ks::set_error(out, len, PINOCCHIO_VERSION); }

KS_API int ks_pin_model_new(ks_pin_model** out, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] { *out = new ks_pin_model(); });
}

KS_API void ks_pin_model_free(ks_pin_model* model) { delete model; }

KS_API int ks_pin_model_add_joint(ks_pin_model* model, int kind, size_t parent,
                                  const double* parent_from_joint, const double* axis,
                                  const char* name, const double* lower, const double* upper,
                                  const double* velocity, const double* effort,
                                  size_t* out_joint, size_t* out_frame, char* err,
                                  size_t err_len) {
    return ks::guard(err, err_len, [&] {
        pin::Model& m = model->model;
        check_joint(m, parent);
        const pin::JointModel joint = make_joint(kind, Eigen::Vector3d(axis[0], axis[1], axis[2]));
        const pin::JointIndex id =
            m.addJoint(parent, joint, se3_from_pose7(parent_from_joint), std::string(name));
        const int nq = m.nqs[id], nv = m.nvs[id], iq = m.idx_qs[id], iv = m.idx_vs[id];
        m.lowerPositionLimit.segment(iq, nq) = ConstVec(lower, nq);
        m.upperPositionLimit.segment(iq, nq) = ConstVec(upper, nq);
        m.upperVelocityLimit.segment(iv, nv) = ConstVec(velocity, nv);
        m.lowerVelocityLimit.segment(iv, nv) = -ConstVec(velocity, nv);
        m.upperEffortLimit.segment(iv, nv) = ConstVec(effort, nv);
        m.lowerEffortLimit.segment(iv, nv) = -ConstVec(effort, nv);
        // The parent's JOINT frame is the previous frame of the new joint frame.
        int parent_frame = 0;
        for (size_t f = 0; f < m.frames.size(); ++f) {
            if (m.frames[f].parentJoint == parent &&
                (parent == 0 || m.frames[f].type == pin::JOINT)) {
                parent_frame = static_cast<int>(f);
                break;
            }
        }
        *out_frame = m.addJointFrame(id, parent_frame);
        *out_joint = id;
    });
}

KS_API int ks_pin_model_append_body(ks_pin_model* model, size_t joint, double mass,
                                    const double* com, const double* inertia, char* err,
                                    size_t err_len) {
    return ks::guard(err, err_len, [&] {
        check_joint(model->model, joint);
        const Eigen::Map<const Eigen::Matrix3d> rotational(inertia);
        const pin::Inertia body(mass, Eigen::Vector3d(com[0], com[1], com[2]), rotational);
        model->model.appendBodyToJoint(joint, body, pin::SE3::Identity());
    });
}

KS_API int ks_pin_model_add_frame(ks_pin_model* model, const char* name, size_t parent_joint,
                                  size_t parent_frame, const double* joint_from_frame, int kind,
                                  size_t* out_frame, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        pin::Model& m = model->model;
        check_joint(m, parent_joint);
        check_frame(m, parent_frame);
        const pin::FrameType type = frame_type(kind);
        const pin::Frame frame(std::string(name), parent_joint, parent_frame,
                               se3_from_pose7(joint_from_frame), type);
        *out_frame = m.addFrame(frame, false);
    });
}

KS_API int ks_pin_model_from_urdf(const char* xml, size_t xml_len, ks_pin_model** out,
                                  char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        auto* model = new ks_pin_model();
        try {
            model->model = ks::model_from_urdf(std::string(xml, xml_len));
        } catch (...) {
            delete model;
            throw;
        }
        *out = model;
    });
}

KS_API int ks_pin_model_joint_info(const ks_pin_model* model, size_t joint,
                                   ks_pin_joint_info* out, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const pin::Model& m = model->model;
        check_joint(m, joint);
        if (joint == 0) throw ks::InvalidArgument("the universe joint has no joint model");
        const pin::JointModel& j = m.joints[joint];
        Eigen::Vector3d axis;
        out->kind = joint_kind(j, axis);
        for (int k = 0; k < 3; ++k) out->axis[k] = axis[k];
        out->parent = m.parents[joint];
        pose7_from_se3(m.jointPlacements[joint], out->parent_from_joint);
        out->idx_q = static_cast<size_t>(m.idx_qs[joint]);
        out->idx_v = static_cast<size_t>(m.idx_vs[joint]);
        out->nq = static_cast<size_t>(m.nqs[joint]);
        out->nv = static_cast<size_t>(m.nvs[joint]);
        out->lower = m.lowerPositionLimit[m.idx_qs[joint]];
        out->upper = m.upperPositionLimit[m.idx_qs[joint]];
        out->velocity = m.upperVelocityLimit[m.idx_vs[joint]];
        out->effort = m.upperEffortLimit[m.idx_vs[joint]];
        ks::set_error(out->type_name, sizeof out->type_name, j.shortname().c_str());
    });
}

KS_API int ks_pin_model_frame_info(const ks_pin_model* model, size_t frame,
                                   ks_pin_frame_info* out, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const pin::Model& m = model->model;
        check_frame(m, frame);
        const pin::Frame& f = m.frames[frame];
        out->kind = frame_kind(f.type);
        out->parent_joint = f.parentJoint;
        out->parent_frame = f.parentFrame;
        pose7_from_se3(f.placement, out->joint_from_frame);
    });
}

KS_API int ks_pin_model_inertia(const ks_pin_model* model, size_t joint, double* mass,
                                double* com, double* inertia, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const pin::Model& m = model->model;
        check_joint(m, joint);
        const pin::Inertia& y = m.inertias[joint];
        *mass = y.mass();
        for (int k = 0; k < 3; ++k) com[k] = y.lever()[k];
        Eigen::Map<Eigen::Matrix3d> rotational(inertia);
        rotational = y.inertia().matrix();
    });
}

KS_API const char* ks_pin_model_joint_name(const ks_pin_model* model, size_t joint) {
    const pin::Model& m = model->model;
    return joint < m.names.size() ? m.names[joint].c_str() : nullptr;
}

KS_API const char* ks_pin_model_frame_name(const ks_pin_model* model, size_t frame) {
    const pin::Model& m = model->model;
    return frame < m.frames.size() ? m.frames[frame].name.c_str() : nullptr;
}

KS_API void ks_pin_model_sizes(const ks_pin_model* model, size_t* nq, size_t* nv,
                               size_t* njoints, size_t* nframes) {
    *nq = static_cast<size_t>(model->model.nq);
    *nv = static_cast<size_t>(model->model.nv);
    *njoints = static_cast<size_t>(model->model.njoints);
    *nframes = model->model.frames.size();
}

KS_API int ks_pin_data_new(const ks_pin_model* model, ks_pin_data** out, char* err,
                           size_t err_len) {
    return ks::guard(err, err_len, [&] { *out = new ks_pin_data(model->model); });
}

KS_API void ks_pin_data_free(ks_pin_data* data) { delete data; }

KS_API int ks_pin_forward_kinematics(const ks_pin_model* model, ks_pin_data* data,
                                     const double* q, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const Eigen::Ref<const Eigen::VectorXd> qref = ConstVec(q, model->model.nq);
        pin::forwardKinematics(model->model, data->data, qref);
    });
}

KS_API int ks_pin_joint_placement(const ks_pin_model* model, const ks_pin_data* data,
                                  size_t joint, double* out_pose7, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        check_joint(model->model, joint);
        pose7_from_se3(data->data.oMi[joint], out_pose7);
    });
}

KS_API int ks_pin_frame_placement(const ks_pin_model* model, const ks_pin_data* data,
                                  size_t frame, double* out_pose7, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        check_frame(model->model, frame);
        const pin::Frame& f = model->model.frames[frame];
        pose7_from_se3(data->data.oMi[f.parentJoint].act(f.placement), out_pose7);
    });
}

KS_API int ks_pin_frame_jacobian(const ks_pin_model* model, ks_pin_data* data, const double* q,
                                 size_t frame, int reference, double* out, char* err,
                                 size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const pin::Model& m = model->model;
        check_frame(m, frame);
        pin::ReferenceFrame rf;
        switch (reference) {
        case KS_PIN_LOCAL: rf = pin::LOCAL; break;
        case KS_PIN_WORLD: rf = pin::WORLD; break;
        case KS_PIN_LOCAL_WORLD_ALIGNED: rf = pin::LOCAL_WORLD_ALIGNED; break;
        default: throw ks::InvalidArgument("unknown reference frame");
        }
        data->q = ConstVec(q, m.nq);
        data->jacobian.setZero();  // computeFrameJacobian writes only the support's columns
        pin::computeFrameJacobian(m, data->data, data->q, frame, rf, data->jacobian);
        Eigen::Map<pin::Data::Matrix6x>(out, 6, m.nv) = data->jacobian;
    });
}

KS_API int ks_pin_integrate(const ks_pin_model* model, const double* q, const double* v,
                            double* out_q, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const pin::Model& m = model->model;
        const Eigen::VectorXd qin = ConstVec(q, m.nq), vin = ConstVec(v, m.nv);
        Eigen::VectorXd result(m.nq);
        pin::integrate(m, qin, vin, result);
        Eigen::Map<Eigen::VectorXd>(out_q, m.nq) = result;
    });
}

KS_API int ks_pin_difference(const ks_pin_model* model, const double* q0, const double* q1,
                             double* out_v, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const pin::Model& m = model->model;
        const Eigen::VectorXd a = ConstVec(q0, m.nq), b = ConstVec(q1, m.nq);
        Eigen::VectorXd result(m.nv);
        pin::difference(m, a, b, result);
        Eigen::Map<Eigen::VectorXd>(out_v, m.nv) = result;
    });
}

KS_API int ks_pin_neutral(const ks_pin_model* model, double* out_q, char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        Eigen::VectorXd result(model->model.nq);
        pin::neutral(model->model, result);
        Eigen::Map<Eigen::VectorXd>(out_q, model->model.nq) = result;
    });
}

KS_API int ks_pin_bench_forward_kinematics(const ks_pin_model* model, ks_pin_data* data,
                                           const double* q, size_t frame, uint64_t iterations,
                                           uint64_t* out_elapsed_ns, double* out_checksum,
                                           char* err, size_t err_len) {
    return ks::guard(err, err_len, [&] {
        const pin::Model& m = model->model;
        check_frame(m, frame);
        const Eigen::Ref<const Eigen::VectorXd> qref = ConstVec(q, m.nq);
        double checksum = 0.0;
        const auto start = std::chrono::steady_clock::now();
        for (uint64_t i = 0; i < iterations; ++i) {
            pin::forwardKinematics(m, data->data, qref);
            checksum += pin::updateFramePlacement(m, data->data, frame).translation().x();
        }
        const auto stop = std::chrono::steady_clock::now();
        *out_elapsed_ns = static_cast<uint64_t>(
            std::chrono::duration_cast<std::chrono::nanoseconds>(stop - start).count());
        *out_checksum = checksum;
    });
}
