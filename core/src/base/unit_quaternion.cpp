/// Input quaternions (contract in unit_quaternion.hpp).
#include "demlink/core/base/unit_quaternion.hpp"

#include <array>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

double quaternionNorm(const Quat& q) { return q.coeffs().stableNorm(); }

Quat requireUnitQuaternion(const std::string& field, const Quat& q) {
  const std::array<std::pair<const char*, double>, 4> parts = {
      {{".w", q.w()}, {".x", q.x()}, {".y", q.y()}, {".z", q.z()}}};
  for (const auto& [name, value] : parts) requireFinite(field + name, value);
  const double norm = quaternionNorm(q);
  if (!(norm > 0.0)) {
    throw InputError(field, "(" + formatValue(q.w()) + ", " + formatValue(q.x()) + ", " + formatValue(q.y()) + ", " +
                                formatValue(q.z()) + ")",
                     "must be a non-zero quaternion (w, x, y, z)");
  }
  return Quat(q.coeffs() / norm);
}

}  // namespace demlink::core
