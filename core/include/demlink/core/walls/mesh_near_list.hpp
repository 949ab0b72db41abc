#pragma once
/// Candidate triangles of one mesh (or deformable surface) per nearby particle: for every particle whose
/// sphere inflated by the skin reaches a triangle at build time, the list of such
/// triangles, each with a tangential history. Built together with the particle
/// neighbour list (same skin, same cell grid) and rebuilt when particles or the
/// mesh have moved more than skin/2; histories are carried across rebuilds and
/// slot changes like the particle pairs'.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/particles/cell_grid.hpp"
#include "demlink/core/base/math_types.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

struct MeshNearList {
  std::vector<std::uint32_t> slots;      ///< particles with at least one candidate
  std::vector<std::uint32_t> offsets{0}; ///< candidates of slots[k]: [offsets[k], offsets[k+1])
  std::vector<std::uint32_t> triangles;  ///< candidate triangle indices, ascending per row
  std::vector<Vec3> history;             ///< tangential spring per candidate

  /// Rebuilds from the current mesh pose, using `grid` (built over the current
  /// particle positions) to find particles near each triangle.
  void build(const ParticleArrays& particles, const MeshBody& mesh, const CellGrid& grid, double skin,
             std::span<const std::uint32_t> newSlotOfOld) {
    build(particles, mesh.worldVertices(), mesh.triangles(), {}, grid, skin, newSlotOfOld);
  }
  /// The same for any triangle surface (a mesh, a deformable body's surface): world
  /// vertices, triangles over them and, unless empty, per triangle 1 = takes part,
  /// 0 = left out (a deformable surface's inactive triangles).
  void build(const ParticleArrays& particles, std::span<const Vec3> vertices,
             std::span<const std::array<std::uint32_t, 3>> triangles, std::span<const char> active,
             const CellGrid& grid, double skin, std::span<const std::uint32_t> newSlotOfOld);

  /// Checkpoint payload (after its mesh in section MESH): slots, offsets, candidate
  /// triangles, histories.
  void save(StateWriter& out) const;
  /// Replaces the list with what save() wrote. Slots must be below `slotCount`
  /// (rows of the last neighbour build), triangles below `triangleCount`, offsets
  /// consistent; throws InputError via in.fail() otherwise (the list is unchanged).
  void restore(StateReader& in, std::size_t slotCount, std::size_t triangleCount);
};

}  // namespace demlink::core
