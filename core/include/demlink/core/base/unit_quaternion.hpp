#pragma once
/// Rotations given as quaternions by a user or a client: every input quaternion is
/// checked and normalised here, with a norm that cannot overflow.
#include <string>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

/// |q| computed with scaling (Eigen's stableNorm): finite for every finite q, so
/// (1e308, 1e308, 0, 0) has the norm 1.41e308, not infinity.
[[nodiscard]] double quaternionNorm(const Quat& q);

/// q / |q|. Throws InputError naming `field + ".w"` (".x", ".y", ".z") with its value for
/// the first non-finite component, or `field` with the four values when q is zero.
[[nodiscard]] Quat requireUnitQuaternion(const std::string& field, const Quat& q);

}  // namespace demlink::core
