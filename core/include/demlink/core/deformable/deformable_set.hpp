#pragma once
/// The deformable bodies of a world (mass-spring, FEM) with, per body, the candidate
/// triangles of its surface per nearby particle. The neighbour stage builds the near
/// lists, the deformable stages move the bodies, the force stage reads both.
#include <memory>
#include <vector>

#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/walls/mesh_near_list.hpp"

namespace demlink::core {

struct DeformableSet {
  std::vector<std::unique_ptr<DeformableBody>> bodies;
  std::vector<MeshNearList> near;  ///< per body
};

}  // namespace demlink::core
