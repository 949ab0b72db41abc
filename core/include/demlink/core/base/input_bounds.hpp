#pragma once
/// Bounds on the motion and extent a scene or a client may give. Each lies far beyond
/// any DEM use and far below overflow, so the first step of a scene that passes them is
/// finite: a value past a bound (gravity -1e308, a room spinning at 1e308 rad/s) is a
/// typo or an attack, and refusing it names the field instead of writing NaN outputs.
/// docs/server.md ("Limits and defaults") lists them.
#include <cstdint>
#include <string>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

inline constexpr double kMaxSpeed = 1.0e5;                 ///< a particle's or the step's speed scale [m/s]
inline constexpr double kMaxAcceleration = 1.0e9;          ///< gravity, the room's accelerations [m/s^2]
inline constexpr double kMaxAngularVelocity = 1.0e7;       ///< a particle's or the room's spin [rad/s]
inline constexpr double kMaxAngularAcceleration = 1.0e12;  ///< the room's angular acceleration [rad/s^2]
inline constexpr double kMaxCoordinate = 1.0e9;            ///< a particle's position [m]
inline constexpr double kMaxSourceParticleRate = 1.0e9;    ///< a particle source's count rate [1/s]
inline constexpr double kMaxSourceMassRate = 1.0e9;        ///< a particle source's mass rate [kg/s]
/// Particles one source tries to place in one step [-]: what is owed beyond it is counted
/// as shortfall at once, so a step's work stays bounded whatever the rate and time step.
inline constexpr std::uint64_t kMaxSourcePlacementsPerStep = 100000;

/// Throws InputError naming `field + "[k]"` for the first component that is not finite.
void requireFiniteVector(const std::string& field, const Vec3& v);
/// Throws InputError naming `field + "[k]"` for the first component that is not finite
/// or whose magnitude exceeds `bound` (`unit` follows the bound in the reason).
void requireBoundedVector(const std::string& field, const Vec3& v, double bound, const std::string& unit);

}  // namespace demlink::core
