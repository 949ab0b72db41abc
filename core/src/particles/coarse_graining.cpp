#include "demlink/core/particles/coarse_graining.hpp"

#include <algorithm>
#include <cmath>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

void CoarseGraining::validate(const std::string& field) const {
  if (!(std::isfinite(factor) && factor >= 1.0)) {
    throw InputError(field, formatValue(factor), "a coarse-graining factor is finite and >= 1");
  }
}

std::size_t CoarseGraining::count(std::size_t grains) const {
  const double parcels = std::round(static_cast<double>(grains) / (factor * factor * factor));
  return std::max<std::size_t>(1, static_cast<std::size_t>(parcels));
}

}  // namespace demlink::core
