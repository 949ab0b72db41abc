/// TEMP: minimal DeformableSurface so the FEM body builds and tests before the mass-spring
/// branch's implementation is merged (that one replaces this file).
#include "demlink/core/deformable/deformable_surface.hpp"

#include <algorithm>
#include <cmath>

#include "demlink/core/input_error.hpp"

namespace demlink::core {

DeformableSurface::DeformableSurface(std::size_t nodeCount, std::vector<std::array<std::uint32_t, 3>> triangles,
                                     std::uint32_t materialIndex, const std::string& fieldPrefix)
    : positions_(nodeCount, Vec3::Zero()),
      velocities_(nodeCount, Vec3::Zero()),
      node_forces_(nodeCount, Vec3::Zero()),
      mark_positions_(nodeCount, Vec3::Zero()),
      triangles_(std::move(triangles)),
      active_(triangles_.size(), 1),
      material_index_(materialIndex) {
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    for (const std::uint32_t v : triangles_[t]) {
      if (v >= nodeCount) {
        throw InputError(fieldPrefix + ".triangles[" + std::to_string(t) + "]", std::to_string(v),
                         "node index out of range (" + std::to_string(nodeCount) + " surface nodes)");
      }
    }
  }
}

void DeformableSurface::setActive(std::size_t triangle, bool active) { active_.at(triangle) = active ? 1 : 0; }

namespace {
Vec3 barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  const Vec3 e0 = b - a;
  const Vec3 e1 = c - a;
  const Vec3 d = p - a;
  const double d00 = e0.dot(e0);
  const double d01 = e0.dot(e1);
  const double d11 = e1.dot(e1);
  const double d20 = d.dot(e0);
  const double d21 = d.dot(e1);
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 0.0)) return Vec3(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
  const double v = (d11 * d20 - d01 * d21) / den;
  const double w = (d00 * d21 - d01 * d20) / den;
  return Vec3(1.0 - v - w, v, w);
}
}  // namespace

Vec3 DeformableSurface::velocityAt(std::uint32_t triangle, const Vec3& point) const {
  const auto& t = triangles_[triangle];
  const Vec3 w = barycentric(positions_[t[0]], positions_[t[1]], positions_[t[2]], point);
  return w[0] * velocities_[t[0]] + w[1] * velocities_[t[1]] + w[2] * velocities_[t[2]];
}

void DeformableSurface::addContactForce(std::uint32_t triangle, const Vec3& point, const Vec3& forceOnSurface) {
  const auto& t = triangles_[triangle];
  const Vec3 w = barycentric(positions_[t[0]], positions_[t[1]], positions_[t[2]], point);
  for (int k = 0; k < 3; ++k) node_forces_[t[k]] += w[k] * forceOnSurface;
}

void DeformableSurface::clearForces() { std::fill(node_forces_.begin(), node_forces_.end(), Vec3::Zero()); }

void DeformableSurface::markNeighbourBuild() { mark_positions_ = positions_; }

double DeformableSurface::maxDisplacementSinceMark() const {
  double m = 0.0;
  for (std::size_t i = 0; i < positions_.size(); ++i) m = std::max(m, (positions_[i] - mark_positions_[i]).norm());
  return m;
}

}  // namespace demlink::core
