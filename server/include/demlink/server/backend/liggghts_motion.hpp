#pragma once
/// A moving mesh as LIGGGHTS-PUBLIC commands (fix move/mesh), kept free of LIGGGHTS and MPI
/// like liggghts_script.hpp.
///
/// Our engine moves a mesh at a constant twist (velocity u of its reference point P,
/// angular velocity w) exactly: P moves by u t and the mesh turns by w t about the world
/// axis through the moving P (MeshBody::advance). LIGGGHTS superposes move/mesh fixes in
/// their order of creation, each in the frame the earlier ones carry along ("the origin
/// of the rotation axis would be in local reference frame", LIGGGHTS documentation of
/// fix move/mesh). A `linear` fix at u followed by a `rotate` fix about P therefore turns
/// the mesh about the axis through the moving P: the same motion, and the same wall
/// velocity u + w x (x - P(t)) seen by the particles.
#include <cstddef>
#include <string>
#include <vector>

#include "demlink/core/math_types.hpp"

namespace demlink::server {

/// One LIGGGHTS fix: its id (for unfix) and the command that creates it.
struct LiggghtsFix {
  std::string id;
  std::string command;
};

/// The fixes that move mesh `mesh` (its fix mesh/surface/stress liggghtsMeshFix(mesh)) at
/// the constant twist `linear` [m/s] of the reference point `reference` [m] and `angular`
/// [rad/s] (world frame), in creation order; none for a mesh at rest. LIGGGHTS requires
/// superposed move/mesh fixes to be removed in the reverse order.
[[nodiscard]] std::vector<LiggghtsFix> liggghtsMeshMotion(std::size_t mesh, const core::Vec3& reference,
                                                          const core::Vec3& linear, const core::Vec3& angular);

}  // namespace demlink::server
