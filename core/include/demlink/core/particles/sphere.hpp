#pragma once
/// A sphere's volume and mass: the one formula every particle, source, time-step
/// check and export uses, so a mass computed anywhere equals the particle's own bit
/// for bit.
#include <numbers>

namespace demlink::core {

/// 4/3 pi r^3 [m^3] for `radius` [m].
[[nodiscard]] constexpr double sphereVolume(double radius) {
  return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

/// 4/3 pi r^3 rho [kg] for `radius` [m] and `density` [kg/m^3] (the solver paper's
/// table 3 prints 3/4, a typo).
[[nodiscard]] constexpr double sphereMass(double radius, double density) { return sphereVolume(radius) * density; }

}  // namespace demlink::core
