#pragma once
/// When may a rigid mesh's near list (mesh_near_list.hpp) have missed a contact?
///
/// A (particle, triangle) pair left out of the list was more than r + skin apart at the
/// build. A rigid motion of the mesh keeps every distance in its own frame, so only the
/// particle's displacement seen from the body frame can close that gap:
///   u = (x - p) - Q (x_build - p_mark),   Q = R R_mark^T,
/// with (p, R) the mesh pose now and (p_mark, R_mark) at the build (MeshBody's mark). The
/// list stays complete while |u| <= skin for every particle. A particle riding in a bucket
/// has u ~ 0, so a moving tool no longer forces a rebuild every skin/2 of its travel, and
/// a still mesh lets particles use the whole skin instead of half of it.
///
/// A particle farther from a moving mesh's reference point than the mesh's bounding radius
/// plus its own radius touches none of its triangles now, so it cannot be missing from the
/// list: only the particles within that reach are transformed.
///
/// Cost: one pass over the particles per step (it stops at the first stale chunk). The
/// answer does not depend on the thread count.
#include <span>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/parallel/thread_pool.hpp"
#include "demlink/core/walls/mesh_body.hpp"

namespace demlink::core {

/// True when some mesh of `meshes` whose `colliding` entry is non-zero may miss a contact
/// at positions `now` of particles of `radius`; `built` holds the positions at the last
/// build (one per particle; a count that differs is stale), `skin` the lists' skin [m].
[[nodiscard]] bool meshNearListsStale(std::span<const MeshBody> meshes, std::span<const char> colliding,
                                      std::span<const Vec3> built, std::span<const Vec3> now,
                                      std::span<const double> radius, double skin, ThreadPool* pool);

}  // namespace demlink::core
