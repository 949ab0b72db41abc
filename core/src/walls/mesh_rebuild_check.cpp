#include "demlink/core/walls/mesh_rebuild_check.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "demlink/core/parallel/parallel_loops.hpp"

namespace demlink::core {
namespace {

/// Largest |now - (p + Q (built - p0))|^2 over the particles, chunk-parallel; with Q the
/// identity and p = p0 the largest squared absolute displacement.
double largestBodyFrameShift2(std::span<const Vec3> built, std::span<const Vec3> now, const Mat3& q,
                              const Vec3& p, const Vec3& p0, ThreadPool* pool) {
  const std::size_t n = now.size();
  const std::uint32_t chunks = chunkCount(n);
  std::vector<double> largest(chunks, 0.0);
  parallelParts(pool, chunks, [&](std::uint32_t chunk) {
    double m = 0.0;
    for (std::size_t i = chunkBegin(n, chunks, chunk); i < chunkBegin(n, chunks, chunk + 1); ++i) {
      m = std::max(m, (now[i] - p - q * (built[i] - p0)).squaredNorm());
    }
    largest[chunk] = m;
  });
  return largest.empty() ? 0.0 : *std::max_element(largest.begin(), largest.end());
}

}  // namespace

bool meshNearListsStale(std::span<const MeshBody> meshes, std::span<const char> colliding,
                        std::span<const Vec3> built, std::span<const Vec3> now, double skin, ThreadPool* pool) {
  if (built.size() != now.size()) return true;
  const double skin2 = skin * skin;
  double absolute2 = -1.0;  // largest squared absolute displacement, computed once when needed
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (colliding[m] == 0) continue;
    const MeshBody& mesh = meshes[m];
    if (absolute2 < 0.0) absolute2 = largestBodyFrameShift2(built, now, Mat3::Identity(), Vec3::Zero(), Vec3::Zero(), pool);
    const double moved = mesh.maxDisplacementSinceMark();
    if (moved == 0.0) {
      if (absolute2 > skin2) return true;
      continue;
    }
    if (std::sqrt(absolute2) + moved <= skin) continue;  // |u| <= |x - x_build| + mesh displacement
    const Mat3 q = (mesh.orientation() * mesh.markOrientation().conjugate()).normalized().toRotationMatrix();
    if (largestBodyFrameShift2(built, now, q, mesh.position(), mesh.markPosition(), pool) > skin2) return true;
  }
  return false;
}

}  // namespace demlink::core
