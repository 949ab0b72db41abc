#pragma once
/// The rigid walls particles touch: planes and prescribed-motion meshes, each with
/// its near list, whether each mesh collides at the current force evaluation (its
/// collision window), and the force stage's scratch for them. The world owns one;
/// the neighbour stage builds the near lists, the force stage reads them.
#include <cstddef>
#include <utility>
#include <vector>

#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/walls/mesh_contact.hpp"
#include "demlink/core/walls/mesh_near_list.hpp"
#include "demlink/core/walls/plane_wall.hpp"

namespace demlink::core {

struct Walls {
  std::vector<PlaneWall> planes;
  std::vector<MeshBody> meshes;
  std::vector<MeshNearList> mesh_near;  ///< per mesh: candidate triangles per nearby particle
  /// Per mesh: collides at the current force evaluation (MeshBody collision window).
  std::vector<char> mesh_colliding;
  /// Per plane and pair-loop chunk, then the slots after the listed rows (force stage scratch).
  std::vector<PlaneLoad> plane_loads;
  std::vector<MeshContactPoint> contact_scratch;  ///< force stage scratch of the mesh contacts
  /// Force stage scratch of the mesh contacts, per mesh and pair-loop chunk, then the
  /// slots after the listed rows.
  std::vector<MeshContactChunk> contact_chunks;

  /// Adds a mesh with an empty near list, not colliding until the next update.
  void addMesh(MeshBody mesh) {
    meshes.push_back(std::move(mesh));
    mesh_near.emplace_back();
    mesh_colliding.push_back(0);
  }
  /// Updates mesh_colliding for a force evaluation at `time` [s]; true if any changed.
  bool updateMeshCollision(double time) {
    bool changed = false;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const char colliding = meshes[m].collidesAt(time) ? 1 : 0;
      changed = changed || colliding != mesh_colliding[m];
      mesh_colliding[m] = colliding;
    }
    return changed;
  }
};

}  // namespace demlink::core
