/// Mass properties of a closed triangle mesh by signed tetrahedra (solid_mass_properties.hpp).
#include "demlink/core/geometry/solid_mass_properties.hpp"

#include <algorithm>
#include <cmath>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

SolidMassProperties solidMassProperties(const StlMesh& mesh, const std::string& field) {
  if (mesh.vertices.empty() || mesh.triangles.empty()) {
    throw InputError(field, "0 triangles", "the mesh has no triangles, so it encloses no volume");
  }
  Vec3 lo = mesh.vertices.front();
  Vec3 hi = lo;
  for (const Vec3& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Vec3 reference = 0.5 * (lo + hi);
  double volume = 0.0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (const auto& tri : mesh.triangles) {
    const Vec3 a = mesh.vertices[tri[0]] - reference;
    const Vec3 b = mesh.vertices[tri[1]] - reference;
    const Vec3 c = mesh.vertices[tri[2]] - reference;
    const double v = a.dot(b.cross(c)) / 6.0;
    const Vec3 s = a + b + c;
    volume += v;
    first += (v / 4.0) * s;
    second += (v / 20.0) * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  const double diagonal = (hi - lo).norm();
  const double smallest = 1e-9 * diagonal * diagonal * diagonal;
  if (!std::isfinite(volume) || !first.allFinite() || !second.allFinite()) {
    throw InputError(field, formatValue(volume) + " m^3", "the volume integrals overflow (coordinates too large)");
  }
  if (volume < -smallest) {
    throw InputError(field, formatValue(volume) + " m^3",
                     "the enclosed volume is negative: the triangles are wound clockwise seen from outside "
                     "(inward normals); reverse the vertex order of every triangle");
  }
  if (!(volume > smallest)) {
    throw InputError(field, formatValue(volume) + " m^3",
                     "the surface encloses no volume (below 1e-9 x the bounding-box diagonal cubed)");
  }
  SolidMassProperties out;
  out.volume = volume;
  const Vec3 centroid = first / volume;
  Mat3 central = second - volume * centroid * centroid.transpose();
  central = 0.5 * (central + central.transpose()).eval();
  out.centroid = centroid + reference;
  out.inertia = central.trace() * Mat3::Identity() - central;
  out.principal = principalAxes(out.inertia);
  for (const Vec3& v : mesh.vertices) out.bounding_radius = std::max(out.bounding_radius, (v - out.centroid).norm());
  return out;
}

}  // namespace demlink::core
