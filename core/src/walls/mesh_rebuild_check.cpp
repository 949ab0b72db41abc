#include "demlink/core/walls/mesh_rebuild_check.hpp"

#include <algorithm>
#include <vector>

#include "demlink/core/parallel/parallel_loops.hpp"

namespace demlink::core {
namespace {

/// A mesh away from its mark: x_build maps to p + Q (x_build - p0) if carried along.
struct Carried {
  Mat3 q;
  Vec3 p;
  Vec3 p0;
  double bound;  ///< largest distance of a vertex from p [m]
  /// (skin - the mesh's displacement bound)^2, or -1: a particle that moved less than
  /// skin - bound moved less than the skin in the mesh's frame (|u| <= |d| + bound).
  double free2;
};

}  // namespace

bool meshNearListsStale(std::span<const MeshBody> meshes, std::span<const char> colliding,
                        std::span<const Vec3> built, std::span<const Vec3> now, std::span<const double> radius,
                        double skin, ThreadPool* pool) {
  if (built.size() != now.size()) return true;
  bool anyAtMark = false;
  std::vector<Carried> moving;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (colliding[m] == 0) continue;
    const MeshBody& mesh = meshes[m];
    const double moved = mesh.maxDisplacementSinceMark();
    if (moved == 0.0) {
      anyAtMark = true;
      continue;
    }
    const Mat3 q = (mesh.orientation() * mesh.markOrientation().conjugate()).normalized().toRotationMatrix();
    const double free2 = moved < skin ? (skin - moved) * (skin - moved) : -1.0;
    moving.push_back({q, mesh.position(), mesh.markPosition(), mesh.boundingRadius(), free2});
  }
  if (!anyAtMark && moving.empty()) return false;
  // One pass: per chunk, whether some particle is more than the skin from where a mesh
  // at its mark (absolute displacement) or a moving mesh (carried position) would have it.
  const double skin2 = skin * skin;
  const std::size_t n = now.size();
  const std::uint32_t chunks = chunkCount(n);
  std::vector<char> stale(chunks, 0);
  parallelParts(pool, chunks, [&](std::uint32_t chunk) {
    for (std::size_t i = chunkBegin(n, chunks, chunk); i < chunkBegin(n, chunks, chunk + 1); ++i) {
      const double d2 = (now[i] - built[i]).squaredNorm();
      if (anyAtMark && d2 > skin2) {
        stale[chunk] = 1;
        return;
      }
      for (const Carried& c : moving) {
        if (d2 <= c.free2) continue;
        // Out of the mesh's reach now: it touches none of its triangles, so none is missed.
        const double reach = c.bound + radius[i];
        if ((now[i] - c.p).squaredNorm() > reach * reach) continue;
        if ((now[i] - c.p - c.q * (built[i] - c.p0)).squaredNorm() > skin2) {
          stale[chunk] = 1;
          return;
        }
      }
    }
  });
  return std::find(stale.begin(), stale.end(), 1) != stale.end();
}

}  // namespace demlink::core
