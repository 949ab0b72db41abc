/// Input checks (contract in cosim_inputs.hpp).
#include "demlink/server/cosim/cosim_inputs.hpp"

#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <string>

#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/core/base/input_bounds.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/world.hpp"
#include "demlink/core/base/unit_quaternion.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using Kind = v1::ComponentDeclaration;

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
                   "component \"" + component.name + "\": " + core::InputError(field, value, reason).what(),
                   component.name, field, true);
}

/// Error{INVALID_INPUT} unless `q` is a unit quaternion within 1e-6.
std::optional<v1::Error> notUnit(const CosimComponent& component, const v1::Quaternion& q, const std::string& field) {
  const double norm = core::quaternionNorm(toQuat(q));  // scaled: no overflow for huge components
  if (std::abs(norm - 1.0) <= 1.0e-6) return std::nullopt;
  return invalid(component, field, "norm " + core::formatValue(norm), "must be a unit quaternion (within 1e-6)");
}

core::RegionChange regionChangeOf(const v1::RegionInput& input) {
  core::RegionChange change;
  if (input.has_centre()) change.centre = toVec3(input.centre());
  if (input.has_orientation()) change.orientation = toQuat(input.orientation());
  if (input.has_size()) change.size = toVec3(input.size());
  if (input.has_radius()) change.radius = input.radius();
  return change;
}

/// The engine's shape and placement of a region sensor or sink.
template <class Region>
std::optional<v1::Error> checkRegion(const CosimComponent& component, const Region* engine,
                                     const v1::RegionInput& input, const std::string& field) {
  if (engine == nullptr) return invalid(component, field, "(given)", "the component has no engine region");
  if (input.has_orientation()) {
    if (auto bad = notUnit(component, input.orientation(), field + ".orientation")) return bad;
  }
  core::VolumeShape shape = engine->shape();
  core::RegionPlacement placement = engine->placement();
  try {
    core::applyRegionChange(regionChangeOf(input), 0.0, shape, placement, field);
  } catch (const core::InputError& error) {
    return invalid(component, error.field(), error.value(), error.reason());
  }
  return std::nullopt;
}

/// Error{INVALID_INPUT} for an input of another kind than the component's, or with a
/// non-finite value.
std::optional<v1::Error> kindAndFinite(const CosimComponent& component, Kind::KindCase kind, const Message& input,
                                       const std::string& field) {
  if (component.kind_case != kind) {
    return invalid(component, field, "(given)", "a " + component.kind + " takes no " + field);
  }
  if (auto bad = firstNonFinite(input, field)) {
    return invalid(component, bad->first, core::formatValue(bad->second), "must be finite");
  }
  return std::nullopt;
}

/// The bounds a declaration's pose and twist obey (core/input_bounds.hpp), on a body's
/// run-time pose and twist.
template <class BodyInput>
std::optional<v1::Error> boundedMotion(const CosimComponent& component, const BodyInput& input,
                                       const std::string& field) {
  try {
    core::requireBoundedVector(field + ".position", toVec3(input.position()), core::kMaxCoordinate, "m");
    core::requireBoundedVector(field + ".linear_velocity", toVec3(input.linear_velocity()), core::kMaxSpeed, "m/s");
    core::requireBoundedVector(field + ".angular_velocity", toVec3(input.angular_velocity()),
                               core::kMaxAngularVelocity, "rad/s");
  } catch (const core::InputError& error) {
    return invalid(component, error.field(), error.value(), error.reason());
  }
  return std::nullopt;
}

}  // namespace

std::optional<v1::Error> checkInput(const CosimComponent& component, const v1::DataPackage& package,
                                    double timeStep) {
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
      return boundedMotion(component, input, "rigid_body_input");
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
      return boundedMotion(component, input, "deformable_body_input");
    }
    case v1::DataPackage::kSimulationBoxInput: {
      if (!isBox) {
        return invalid(component, "simulation_box_input", "(given)", "a " + component.kind + " takes no simulation_box_input");
      }
      if (auto bad = firstNonFinite(package.simulation_box_input(), "simulation_box_input")) {
        return invalid(component, bad->first, core::formatValue(bad->second), "must be finite");
      }
      const v1::SimulationBoxInput& input = package.simulation_box_input();
      try {
        if (input.has_gravity()) {
          // The declaration's rule (core::SimulationSettings::validate): bounded, and g dt a sane speed.
          const core::Vec3 gravity = toVec3(input.gravity());
          core::requireBoundedVector("simulation_box_input.gravity", gravity, core::kMaxAcceleration, "m/s^2");
          if (!(gravity.norm() * timeStep <= core::kMaxSpeed)) {
            return invalid(component, "simulation_box_input.gravity",
                           fmt::format("({}, {}, {})", core::formatValue(gravity.x()),
                                       core::formatValue(gravity.y()), core::formatValue(gravity.z())),
                           "|gravity| x time_step = " + core::formatValue(gravity.norm() * timeStep) +
                               " m/s exceeds " + core::formatValue(core::kMaxSpeed) + " m/s per step");
          }
        }
        if (input.has_frame()) frameOf(input.frame()).validate("simulation_box_input.frame");
      } catch (const core::InputError& error) {
        return invalid(component, error.field(), error.value(), error.reason());
      }
      return std::nullopt;
    }
    case v1::DataPackage::kRegionSensorInput: {
      const std::string field = "region_sensor_input";
      if (auto bad = kindAndFinite(component, Kind::kRegionSensor, package.region_sensor_input(), field)) return bad;
      return checkRegion(component, dynamic_cast<const core::RegionSensor*>(component.engine),
                         package.region_sensor_input(), field);
    }
    case v1::DataPackage::kParticleSinkInput: {
      const std::string field = "particle_sink_input";
      if (auto bad = kindAndFinite(component, Kind::kParticleSink, package.particle_sink_input(), field)) return bad;
      if (!package.particle_sink_input().has_region()) return std::nullopt;
      return checkRegion(component, dynamic_cast<const core::ParticleSink*>(component.engine),
                         package.particle_sink_input().region(), field + ".region");
    }
    case v1::DataPackage::kParticleSourceInput: {
      const std::string field = "particle_source_input";
      const v1::ParticleSourceInput& input = package.particle_source_input();
      if (auto bad = kindAndFinite(component, Kind::kParticleSource, input, field)) return bad;
      const auto* source = dynamic_cast<const core::ParticleSource*>(component.engine);
      if (source == nullptr) return invalid(component, field, "(given)", "the component has no engine source");
      const bool perParticle = source->spec().rate_particles_per_s.has_value();
      if (input.has_rate_particles_per_s() && !perParticle) {
        return invalid(component, field + ".rate_particles_per_s", core::formatValue(input.rate_particles_per_s()),
                       "the source was declared with a mass rate; give rate_kg_per_s");
      }
      if (input.has_rate_kg_per_s() && perParticle) {
        return invalid(component, field + ".rate_kg_per_s", core::formatValue(input.rate_kg_per_s()),
                       "the source was declared with a count rate; give rate_particles_per_s");
      }
      try {
        if (input.has_rate_particles_per_s()) {
          core::requireSourceRate(field + ".rate_particles_per_s", input.rate_particles_per_s(), true);
        }
        if (input.has_rate_kg_per_s()) core::requireSourceRate(field + ".rate_kg_per_s", input.rate_kg_per_s(), false);
      } catch (const core::InputError& error) {
        return invalid(component, error.field(), error.value(), error.reason());
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

void applyComponentInput(const CosimComponent& component, const v1::DataPackage& package, core::World& world) {
  switch (package.input_case()) {
    case v1::DataPackage::kRegionSensorInput:
      dynamic_cast<core::RegionSensor&>(*component.engine)
          .changeRegion(world, regionChangeOf(package.region_sensor_input()), "region_sensor_input");
      break;
    case v1::DataPackage::kParticleSinkInput: {
      auto& sink = dynamic_cast<core::ParticleSink&>(*component.engine);
      const v1::ParticleSinkInput& input = package.particle_sink_input();
      if (input.has_region()) sink.changeRegion(world, regionChangeOf(input.region()), "particle_sink_input.region");
      if (input.has_enabled()) sink.setEnabled(input.enabled());
      break;
    }
    case v1::DataPackage::kParticleSourceInput: {
      auto& source = dynamic_cast<core::ParticleSource&>(*component.engine);
      const v1::ParticleSourceInput& input = package.particle_source_input();
      if (input.has_rate_particles_per_s()) {
        source.setRate(world, input.rate_particles_per_s(), "particle_source_input.rate_particles_per_s");
      }
      if (input.has_rate_kg_per_s()) source.setRate(world, input.rate_kg_per_s(), "particle_source_input.rate_kg_per_s");
      if (input.has_enabled()) source.setEnabled(world, input.enabled());
      break;
    }
    default: break;
  }
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
