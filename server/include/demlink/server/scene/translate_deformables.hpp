#pragma once
/// Scene compiler, deformable bodies: mass_spring_body and fem_body declarations
/// (proto/demlink/v1/deformables.proto) -> core::MassSpringSpec / core::FemSpec ->
/// core::MassSpringBody / core::FemBody added to the world.
///
/// Why the specs are built here and validated again by core: the scene's field names
/// (fixed.regions[k].lo, mesh.msh_file) are not the engine's (fixed_regions, msh_path),
/// so every value the scene spells differently is checked here under its scene path;
/// what only the built body can know (a node index beyond the lattice, a file's content)
/// comes from core with the body's path in front.
#include <filesystem>
#include <string>

#include "demlink/core/deformable/fem_body.hpp"
#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/core/world.hpp"
#include "demlink/server/scene/translate_mesh_body.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// The engine spec of one mass_spring_body named `name`: files resolved against
/// `files` (and required to exist), the material resolved, defaults filled in.
/// Throws core::InputError naming `fieldPrefix + ".<field>"`, e.g. ".box.node_spacing",
/// ".total_mass", ".explicit_nodes.springs[3].b", ".fixed.regions[0].hi".
[[nodiscard]] core::MassSpringSpec translateMassSpringBody(const v1::MassSpringBody& body, const std::string& name,
                                                           const MaterialResolver& resolveMaterial,
                                                           const FileScope& files,
                                                           const std::string& fieldPrefix);

/// The engine spec of one fem_body (as translateMassSpringBody; e.g. ".mesh.msh_file",
/// ".mesh.poisson_ratio", ".matrices.stiffness_matrix_file", ".rayleigh_alpha").
[[nodiscard]] core::FemSpec translateFemBody(const v1::FemBody& body, const std::string& name,
                                             const MaterialResolver& resolveMaterial,
                                             const FileScope& files,
                                             const std::string& fieldPrefix);

/// Builds every mass_spring_body and fem_body of the scene, in declaration order, and adds
/// it to the world (after the mesh bodies: attached_to names one of world.meshes(), whose
/// pose then drives the body's driven nodes every step through a core::DeformableAttachment).
void addDeformableBodies(const v1::Scene& scene, const MaterialResolver& resolveMaterial,
                         const FileScope& files, core::World& world);

/// The nodes a client's DeformableBodyOutput and the run's node CSV report for `declared`
/// (DeformableOutputNodes): the given indices (checked against `nodeCount`, InputError naming
/// `field + ".nodes[k]"`), or every stride-th of the `surfaceCount` surface nodes so that at
/// most max_count (0: 10000) are listed.
[[nodiscard]] std::vector<std::uint32_t> outputNodesOf(const v1::DeformableOutputNodes& declared,
                                                       std::size_t nodeCount, std::size_t surfaceCount,
                                                       const std::string& field);

}  // namespace demlink::server
