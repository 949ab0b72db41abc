#include "demlink/core/materials/material.hpp"

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

void Material::validate(const std::string& fieldPrefix) const {
  requirePositive(fieldPrefix + ".density", density);
  requirePositive(fieldPrefix + ".youngs_modulus", youngs_modulus);
  requireOpenRange(fieldPrefix + ".poisson_ratio", poisson_ratio, -1.0, 0.5);
  requireHalfOpenRange(fieldPrefix + ".restitution", restitution, 0.0, 1.0);
  requireNonNegative(fieldPrefix + ".sliding_friction", sliding_friction);
  requireNonNegative(fieldPrefix + ".rolling_friction", rolling_friction);
  requireNonNegative(fieldPrefix + ".cohesion_energy_density", cohesion_energy_density);
}

}  // namespace demlink::core
