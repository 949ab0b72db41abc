/// Input checks (contract in cosim_inputs.hpp).
#include "demlink/server/cosim/cosim_inputs.hpp"

#include <cmath>
#include <string>

#include "demlink/core/input_error.hpp"
#include "demlink/core/unit_quaternion.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

/// The first non-finite double/float in `message` (recursively), as (path, value).
std::optional<std::pair<std::string, double>> firstNonFinite(const Message& message, const std::string& path) {
  const google::protobuf::Reflection* reflection = message.GetReflection();
  std::vector<const FieldDescriptor*> fields;
  reflection->ListFields(message, &fields);
  for (const FieldDescriptor* field : fields) {
    const std::string name = path + "." + std::string(field->name());
    if (field->is_repeated()) {
      const int n = reflection->FieldSize(message, field);
      for (int k = 0; k < n; ++k) {
        const std::string item = name + "[" + std::to_string(k) + "]";
        double value = 0.0;
        if (field->cpp_type() == FieldDescriptor::CPPTYPE_DOUBLE) {
          value = reflection->GetRepeatedDouble(message, field, k);
        } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT) {
          value = static_cast<double>(reflection->GetRepeatedFloat(message, field, k));
        } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
          if (auto bad = firstNonFinite(reflection->GetRepeatedMessage(message, field, k), item)) return bad;
          continue;
        } else {
          continue;
        }
        if (!std::isfinite(value)) return std::make_pair(item, value);
      }
      continue;
    }
    if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      if (auto bad = firstNonFinite(reflection->GetMessage(message, field), name)) return bad;
    } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_DOUBLE) {
      const double value = reflection->GetDouble(message, field);
      if (!std::isfinite(value)) return std::make_pair(name, value);
    } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT) {
      const auto value = static_cast<double>(reflection->GetFloat(message, field));
      if (!std::isfinite(value)) return std::make_pair(name, value);
    }
  }
  return std::nullopt;
}

v1::Error invalid(const CosimComponent& component, const std::string& field, const std::string& value,
                  const std::string& reason) {
  return makeError(v1::Error::INVALID_INPUT,
                   "component \"" + component.name + "\": " + field + " = " + value + ": " + reason, component.name,
                   field, true);
}

/// Error{INVALID_INPUT} unless `q` is a unit quaternion within 1e-6.
std::optional<v1::Error> notUnit(const CosimComponent& component, const v1::Quaternion& q, const std::string& field) {
  const double norm = core::quaternionNorm(toQuat(q));  // scaled: no overflow for huge components
  if (std::abs(norm - 1.0) <= 1.0e-6) return std::nullopt;
  return invalid(component, field, "norm " + core::formatValue(norm), "must be a unit quaternion (within 1e-6)");
}

}  // namespace

std::optional<v1::Error> checkInput(const CosimComponent& component, const v1::DataPackage& package) {
  const bool isBody = component.kind_case == v1::ComponentDeclaration::kRigidBody;
  const bool isBox = component.kind_case == v1::ComponentDeclaration::kSimulationBox;
  const bool isDeformable = component.kind_case == v1::ComponentDeclaration::kMassSpringBody ||
                            component.kind_case == v1::ComponentDeclaration::kFemBody;
  switch (package.input_case()) {
    case v1::DataPackage::kRigidBodyInput: {
      if (!isBody) return invalid(component, "rigid_body_input", "(given)", "a " + component.kind + " takes no rigid_body_input");
      if (auto bad = firstNonFinite(package.rigid_body_input(), "rigid_body_input")) {
        return invalid(component, bad->first, core::formatValue(bad->second), "must be finite");
      }
      const v1::RigidBodyInput& input = package.rigid_body_input();
      if (!input.has_position()) return invalid(component, "rigid_body_input.position", "(missing)", "required");
      if (!input.has_orientation()) return invalid(component, "rigid_body_input.orientation", "(missing)", "required");
      if (auto bad = notUnit(component, input.orientation(), "rigid_body_input.orientation")) return bad;
      return std::nullopt;
    }
    case v1::DataPackage::kDeformableBodyInput: {
      if (!isDeformable) {
        return invalid(component, "deformable_body_input", "(given)",
                       "a " + component.kind + " takes no deformable_body_input");
      }
      if (component.deformable_attached) {
        return invalid(component, "deformable_body_input", "(given)",
                       "the body is attached_to a rigid body, whose pose drives it");
      }
      if (auto bad = firstNonFinite(package.deformable_body_input(), "deformable_body_input")) {
        return invalid(component, bad->first, core::formatValue(bad->second), "must be finite");
      }
      const v1::DeformableBodyInput& input = package.deformable_body_input();
      if (!input.has_position()) return invalid(component, "deformable_body_input.position", "(missing)", "required");
      if (!input.has_orientation()) {
        return invalid(component, "deformable_body_input.orientation", "(missing)", "required");
      }
      if (auto bad = notUnit(component, input.orientation(), "deformable_body_input.orientation")) return bad;
      return std::nullopt;
    }
    case v1::DataPackage::kSimulationBoxInput: {
      if (!isBox) {
        return invalid(component, "simulation_box_input", "(given)", "a " + component.kind + " takes no simulation_box_input");
      }
      if (auto bad = firstNonFinite(package.simulation_box_input(), "simulation_box_input")) {
        return invalid(component, bad->first, core::formatValue(bad->second), "must be finite");
      }
      if (package.simulation_box_input().has_frame()) {
        try {
          frameOf(package.simulation_box_input().frame()).validate("simulation_box_input.frame");
        } catch (const core::InputError& error) {
          return invalid(component, error.field(), error.value(), error.reason());
        }
      }
      return std::nullopt;
    }
    case v1::DataPackage::INPUT_NOT_SET:
      if (isBody) return invalid(component, "rigid_body_input", "(missing)", "a rigid_body package needs its pose");
      return std::nullopt;
  }
  return invalid(component, "input", std::to_string(static_cast<int>(package.input_case())), "unknown input");
}

core::RigidPose poseOf(const v1::RigidBodyInput& input) {
  // Not normalised here: core::targetPose normalises once, so a client and an in-process
  // driver that pass the same quaternion get bit-identical motion.
  return {toVec3(input.position()), toQuat(input.orientation())};
}

core::RigidTwist twistOf(const v1::RigidBodyInput& input) {
  return {toVec3(input.linear_velocity()), toVec3(input.angular_velocity())};
}

core::RigidPose poseOf(const v1::DeformableBodyInput& input) {
  return {toVec3(input.position()), toQuat(input.orientation()).normalized()};
}

core::RigidTwist twistOf(const v1::DeformableBodyInput& input) {
  return {toVec3(input.linear_velocity()), toVec3(input.angular_velocity())};
}

core::FrameMotion frameOf(const v1::SimulationBox::Frame& frame) {
  core::FrameMotion out;
  out.linear_acceleration = toVec3(frame.linear_acceleration());
  out.angular_velocity = toVec3(frame.angular_velocity());
  out.angular_acceleration = toVec3(frame.angular_acceleration());
  out.origin = toVec3(frame.origin());
  return out;
}

}  // namespace demlink::server
