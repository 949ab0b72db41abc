#pragma once
/// The triangle surface through which particles touch a deformable body.
///
/// Why: mass-spring and FEM bodies move their nodes every step, so their surface
/// cannot be a MeshBody (rigid, posed). Particles must still touch it with the same
/// contact laws and the same de-duplication as meshes (walls/mesh_contact.hpp).
/// A DeformableSurface is that surface: world vertex positions and velocities owned
/// by the body, triangles over them, and the node forces the contacts leave.
///
/// Math (the solver paper's D_d2dof and its transpose): a contact at point q of
/// triangle (a, b, c) with barycentric weights (w_a, w_b, w_c) of q
///   - sees the wall velocity  v(q) = w_a v_a + w_b v_b + w_c v_c,
///   - puts the force F on the nodes as w_a F, w_b F, w_c F (sums to F, and the
///     moment about any point equals that of F at q to first order in the size of
///     the triangle).
/// A triangle that lost its support (a torn spring of a mass-spring body) is
/// inactive: it takes no part in contact detection.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

class DeformableSurface {
 public:
  DeformableSurface() = default;
  /// `triangles` index the body's surface nodes 0..nodeCount-1 (counter-clockwise =
  /// outward). Throws InputError ("<fieldPrefix>.triangles") for an index out of range.
  DeformableSurface(std::size_t nodeCount, std::vector<std::array<std::uint32_t, 3>> triangles,
                    std::uint32_t materialIndex, const std::string& fieldPrefix);

  /// World positions [m] and velocities [m/s] of the surface nodes; the body writes them
  /// after it moved its nodes (sizes fixed at construction).
  [[nodiscard]] std::vector<Vec3>& positions() { return positions_; }
  [[nodiscard]] std::vector<Vec3>& velocities() { return velocities_; }
  [[nodiscard]] const std::vector<Vec3>& positions() const { return positions_; }
  [[nodiscard]] const std::vector<Vec3>& velocities() const { return velocities_; }
  [[nodiscard]] const std::vector<std::array<std::uint32_t, 3>>& triangles() const { return triangles_; }
  /// The positions under the name MeshBody gives its vertices, so the contact loop and the
  /// near list (contact_stage.hpp, mesh_near_list.hpp) serve both kinds of surface.
  [[nodiscard]] const std::vector<Vec3>& worldVertices() const { return positions_; }
  /// Per triangle: 1 = takes part in contacts, 0 = lost its support.
  [[nodiscard]] const std::vector<char>& active() const { return active_; }
  void setActive(std::size_t triangle, bool active);
  [[nodiscard]] std::uint32_t materialIndex() const { return material_index_; }

  /// Velocity of the surface at `point` on `triangle` (barycentric interpolation).
  [[nodiscard]] Vec3 velocityAt(std::uint32_t triangle, const Vec3& point) const;
  /// Adds `forceOnSurface` [N] at `point` of `triangle` to its three nodes by barycentric weights.
  void addContactForce(std::uint32_t triangle, const Vec3& point, const Vec3& forceOnSurface);
  /// Contact forces on the surface nodes since the last clearForces() [N].
  [[nodiscard]] const std::vector<Vec3>& nodeForces() const { return node_forces_; }
  void clearForces();

  /// Remembers the current positions as the reference of maxDisplacementSinceMark().
  void markNeighbourBuild();
  /// Largest displacement of a surface node since the last mark [m].
  [[nodiscard]] double maxDisplacementSinceMark() const;

  /// Checkpoint payload of what the surface keeps between steps besides the nodes the
  /// body saves: the neighbour-build mark and the active flags (the world writes it).
  void save(StateWriter& out) const;
  /// Reads what save() wrote; sizes are checked against this surface (InputError via
  /// the reader), and nothing changes unless the whole payload is valid.
  void restore(StateReader& in);

 private:
  std::vector<Vec3> positions_;
  std::vector<Vec3> velocities_;
  std::vector<Vec3> node_forces_;
  std::vector<Vec3> mark_positions_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<char> active_;
  std::uint32_t material_index_ = 0;
};

}  // namespace demlink::core
