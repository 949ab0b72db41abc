/// Barycentric coupling of a deformable surface (deformable_surface.hpp): the
/// wall velocity at a contact point and the node forces of a contact force.
#include "demlink/core/deformable/deformable_surface.hpp"

#include <algorithm>
#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {
namespace {

/// Barycentric weights of `point` in triangle (a, b, c). The point is the closest point of
/// the triangle to a sphere centre, so it lies on the triangle; the weights are clamped to
/// [0, 1] and renormalised against rounding. A zero-area triangle spreads equally.
Vec3 barycentricWeights(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& point) {
  const Vec3 e0 = b - a;
  const Vec3 e1 = c - a;
  const Vec3 d = point - a;
  const double d00 = e0.dot(e0);
  const double d01 = e0.dot(e1);
  const double d11 = e1.dot(e1);
  const double d20 = d.dot(e0);
  const double d21 = d.dot(e1);
  const double denominator = d00 * d11 - d01 * d01;
  if (!(denominator > 0.0)) return Vec3::Constant(1.0 / 3.0);
  const double wb = std::clamp((d11 * d20 - d01 * d21) / denominator, 0.0, 1.0);
  const double wc = std::clamp((d00 * d21 - d01 * d20) / denominator, 0.0, 1.0);
  const double wa = std::max(0.0, 1.0 - wb - wc);
  const double sum = wa + wb + wc;
  return Vec3(wa, wb, wc) / sum;
}

}  // namespace

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
    const auto& tri = triangles_[t];
    for (const std::uint32_t node : tri) {
      if (node >= nodeCount) {
        throw InputError(fieldPrefix + ".triangles[" + std::to_string(t) + "]", std::to_string(node),
                         "node index out of range (the body has " + std::to_string(nodeCount) + " nodes)");
      }
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      throw InputError(fieldPrefix + ".triangles[" + std::to_string(t) + "]",
                       std::to_string(tri[0]) + ", " + std::to_string(tri[1]) + ", " + std::to_string(tri[2]),
                       "a triangle needs three distinct nodes");
    }
  }
}

void DeformableSurface::setActive(std::size_t triangle, bool active) { active_.at(triangle) = active ? 1 : 0; }

Vec3 DeformableSurface::velocityAt(std::uint32_t triangle, const Vec3& point) const {
  const auto& tri = triangles_[triangle];
  const Vec3 w = barycentricWeights(positions_[tri[0]], positions_[tri[1]], positions_[tri[2]], point);
  return w[0] * velocities_[tri[0]] + w[1] * velocities_[tri[1]] + w[2] * velocities_[tri[2]];
}

void DeformableSurface::addContactForce(std::uint32_t triangle, const Vec3& point, const Vec3& forceOnSurface) {
  const auto& tri = triangles_[triangle];
  const Vec3 w = barycentricWeights(positions_[tri[0]], positions_[tri[1]], positions_[tri[2]], point);
  for (int k = 0; k < 3; ++k) node_forces_[tri[k]] += w[k] * forceOnSurface;
}

void DeformableSurface::clearForces() { std::fill(node_forces_.begin(), node_forces_.end(), Vec3::Zero()); }

void DeformableSurface::markNeighbourBuild() { mark_positions_ = positions_; }

double DeformableSurface::maxDisplacementSinceMark() const {
  double largest2 = 0.0;
  for (std::size_t n = 0; n < positions_.size(); ++n) {
    largest2 = std::max(largest2, (positions_[n] - mark_positions_[n]).squaredNorm());
  }
  return std::sqrt(largest2);
}

void DeformableSurface::save(StateWriter& out) const {
  out.writeVector(mark_positions_);
  out.writeVector(active_);
}

void DeformableSurface::restore(StateReader& in) {
  std::vector<Vec3> marks = in.readVector<Vec3>();
  std::vector<char> active = in.readVector<char>();
  requireSameLength(in, marks, positions_, "surface node count differs from the scene's");
  requireSameLength(in, active, triangles_, "surface triangle count differs from the scene's");
  mark_positions_ = std::move(marks);
  active_ = std::move(active);
}

}  // namespace demlink::core
