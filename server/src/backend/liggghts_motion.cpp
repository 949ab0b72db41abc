/// Moving meshes as LIGGGHTS commands (contract in liggghts_motion.hpp).
#include "demlink/server/backend/liggghts_motion.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "demlink/server/backend/liggghts_script.hpp"

namespace demlink::server {
namespace {

/// The twist's components in the order the fixes read them: velocity x, y, z, then the
/// rates about x, y, z.
constexpr std::array<const char*, 6> kComponents = {"vx", "vy", "vz", "wx", "wy", "wz"};

/// The variable fix move/mesh reads for component `c` of mesh `mesh`.
std::string fixVariable(std::size_t mesh, const char* c) { return fmt::format("{}_{}", liggghtsMeshFix(mesh), c); }

/// The value variable it names.
std::string valueVariable(std::size_t mesh, const char* c) { return fixVariable(mesh, c) + "_now"; }

}  // namespace

core::Vec3 liggghtsStepAngles(const core::Vec3& angular, double dt) {
  const double angle = angular.norm() * dt;
  if (angle == 0.0) return core::Vec3::Zero();
  const core::Mat3 q = Eigen::AngleAxisd(angle, angular.normalized()).toRotationMatrix();
  // q = Rz(c) Ry(b) Rx(a): q(2,0) = -sin b, q(2,1) / q(2,2) = tan a, q(1,0) / q(0,0) = tan c.
  return {std::atan2(q(2, 1), q(2, 2)), std::asin(std::clamp(-q(2, 0), -1.0, 1.0)), std::atan2(q(1, 0), q(0, 0))};
}

std::vector<std::string> liggghtsMeshMotionSetup(std::size_t mesh) {
  std::vector<std::string> commands;
  for (const char* c : kComponents) {
    commands.push_back(fmt::format("variable {} equal v_{}", fixVariable(mesh, c), valueVariable(mesh, c)));
  }
  for (const char* c : kComponents) commands.push_back(fmt::format("variable {} equal 0", valueVariable(mesh, c)));
  return commands;
}

std::vector<LiggghtsFix> liggghtsMeshMotionFixes(std::size_t mesh, const core::Vec3& reference) {
  const std::string target = liggghtsMeshFix(mesh);
  std::vector<LiggghtsFix> fixes;
  const std::string slide = target + "_slide";
  fixes.push_back({slide, fmt::format("fix {} all move/mesh mesh {} linear/variable v_{} v_{} v_{}", slide, target,
                                      fixVariable(mesh, "vx"), fixVariable(mesh, "vy"), fixVariable(mesh, "vz"))});
  constexpr std::array<const char*, 3> kAxes = {"1 0 0", "0 1 0", "0 0 1"};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const char* c = kComponents[3 + axis];
    const std::string id = fmt::format("{}_turn_{}", target, c);
    fixes.push_back({id, fmt::format("fix {} all move/mesh mesh {} rotate/variable origin {:.17g} {:.17g} {:.17g} "
                                     "axis {} omega v_{}",
                                     id, target, reference.x(), reference.y(), reference.z(), kAxes[axis],
                                     fixVariable(mesh, c))});
  }
  return fixes;
}

std::vector<std::string> liggghtsMeshTwist(std::size_t mesh, const core::Vec3& linear, const core::Vec3& angular,
                                           double dt) {
  const core::Vec3 rates = liggghtsStepAngles(angular, dt) / dt;
  const std::array<double, 6> values = {linear.x(), linear.y(), linear.z(), rates.x(), rates.y(), rates.z()};
  std::vector<std::string> commands;
  for (std::size_t k = 0; k < values.size(); ++k) {
    commands.push_back(fmt::format("variable {} equal {:.17g}", valueVariable(mesh, kComponents[k]), values[k]));
  }
  return commands;
}

}  // namespace demlink::server
