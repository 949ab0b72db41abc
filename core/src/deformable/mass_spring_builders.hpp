#pragma once
/// The three sources of a mass-spring body's nodes, springs and surface triangles
/// (MassSpringSpec): a box or plate lattice, an STL surface, explicit lists.
/// Internal to core/src/deformable.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/core/deformable/mass_spring_body.hpp"

namespace demlink::core {

/// Most nodes a mass-spring body may have (memory and step cost stay bounded; a
/// lattice is counted before anything is allocated).
inline constexpr std::size_t kMaxMassSpringNodes = 1'000'000;

struct MassSpringTopology {
  std::vector<Vec3> nodes;
  std::vector<SpringSpec> springs;  ///< rest lengths resolved (> 0)
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// Builds and validates the source the spec names (exactly one of box, stl_path,
/// nodes); errors are InputError naming "<fieldPrefix>.<field>" and the value.
[[nodiscard]] MassSpringTopology buildMassSpringTopology(const MassSpringSpec& spec, const std::string& fieldPrefix);

}  // namespace demlink::core
