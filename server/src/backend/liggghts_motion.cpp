/// Moving meshes as LIGGGHTS commands (contract in liggghts_motion.hpp).
#include "demlink/server/backend/liggghts_motion.hpp"

#include <spdlog/fmt/fmt.h>

#include <numbers>

#include "demlink/server/backend/liggghts_script.hpp"

namespace demlink::server {

std::vector<LiggghtsFix> liggghtsMeshMotion(std::size_t mesh, const core::Vec3& reference, const core::Vec3& linear,
                                            const core::Vec3& angular) {
  std::vector<LiggghtsFix> fixes;
  const std::string target = liggghtsMeshFix(mesh);
  if (linear.norm() > 0.0) {
    const std::string id = target + "_slide";
    fixes.push_back({id, fmt::format("fix {} all move/mesh mesh {} linear {:.17g} {:.17g} {:.17g}", id, target,
                                     linear.x(), linear.y(), linear.z())});
  }
  if (const double rate = angular.norm(); rate > 0.0) {
    // After the linear fix, the origin is carried along with the mesh: it stays on P.
    const core::Vec3 axis = angular / rate;
    const std::string id = target + "_turn";
    fixes.push_back({id, fmt::format("fix {} all move/mesh mesh {} rotate origin {:.17g} {:.17g} {:.17g} axis {:.17g} "
                                     "{:.17g} {:.17g} period {:.17g}",
                                     id, target, reference.x(), reference.y(), reference.z(), axis.x(), axis.y(),
                                     axis.z(), 2.0 * std::numbers::pi / rate)});
  }
  return fixes;
}

}  // namespace demlink::server
