// Internal to the shim: URDF parsing lives in its own translation unit (urdf.cpp), so the
// urdfdom and parser headers stay out of shim.cpp.
#pragma once

#include <string>

#include <pinocchio/multibody/fwd.hpp>

namespace ks {

// pinocchio::urdf::buildModelFromXML into a fresh fixed-base model (no root joint). Throws on
// failure, with urdfdom's console_bridge diagnostics appended to the exception's message.
pinocchio::Model model_from_urdf(const std::string& xml);

}  // namespace ks
