/// Bounds and frame settings of a SimulationBox (contract in translate_frame.hpp). Range
/// checks are core::SimulationSettings::validate's; this file only maps fields
/// and rejects fields that make no sense for the chosen mode.
#include "demlink/server/scene/translate_frame.hpp"

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
void translateFrame(const v1::SimulationBox& box, const std::string& prefix, core::SimulationSettings& settings) {
  if (box.has_bounds()) {
    const v1::SimulationBox::Bounds& bounds = box.bounds();
    const std::string b = prefix + ".bounds";
    switch (bounds.mode()) {
      case v1::SimulationBox::Bounds::MODE_UNSPECIFIED:
      case v1::SimulationBox::Bounds::FIXED:
        if (bounds.has_limit_lower()) {
          throw core::InputError(b + ".limit_lower", "(given)", "only GROWING bounds have a limit box");
        }
        if (bounds.has_limit_upper()) {
          throw core::InputError(b + ".limit_upper", "(given)", "only GROWING bounds have a limit box");
        }
        break;
      case v1::SimulationBox::Bounds::GROWING:
        if (!bounds.has_limit_lower()) throw core::InputError(b + ".limit_lower", "(missing)", "required for GROWING");
        if (!bounds.has_limit_upper()) throw core::InputError(b + ".limit_upper", "(missing)", "required for GROWING");
        if (settings.bounds) {
          settings.bounds->growing = true;
          settings.bounds->limit_lower = toVec3(bounds.limit_lower());
          settings.bounds->limit_upper = toVec3(bounds.limit_upper());
        }
        break;
      default:
        throw core::InputError(b + ".mode", std::to_string(bounds.mode()), "unknown bounds mode (FIXED, GROWING)");
    }
  }
  if (box.has_frame()) {
    const v1::SimulationBox::Frame& frame = box.frame();
    settings.frame.linear_acceleration = toVec3(frame.linear_acceleration());
    settings.frame.angular_velocity = toVec3(frame.angular_velocity());
    settings.frame.angular_acceleration = toVec3(frame.angular_acceleration());
    settings.frame.origin = toVec3(frame.origin());
  }
}

}  // namespace demlink::server
