/// Bounds on input motion (contract in input_bounds.hpp).
#include "demlink/core/base/input_bounds.hpp"

#include <cmath>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

void requireFiniteVector(const std::string& field, const Vec3& v) {
  for (int k = 0; k < 3; ++k) requireFinite(field + "[" + std::to_string(k) + "]", v[k]);
}

void requireBoundedVector(const std::string& field, const Vec3& v, double bound, const std::string& unit) {
  for (int k = 0; k < 3; ++k) {
    const std::string name = field + "[" + std::to_string(k) + "]";
    requireFinite(name, v[k]);
    if (!(std::abs(v[k]) <= bound)) {
      throw InputError(name, formatValue(v[k]), "magnitude must be at most " + formatValue(bound) + " " + unit);
    }
  }
}

}  // namespace demlink::core
