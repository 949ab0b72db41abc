/// Bucket shell triangles and its STL file. Why core's writer: the server reads the bytes
/// with core's STL reader, so writing them with the same library removes one way for the
/// two to disagree.
#include "bucket_mesh.hpp"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::examples::excavator {

BucketMesh makeBucketMesh() {
  BucketMesh mesh;
  const double half = 0.5 * kBucketWidth;
  // Vertex 2k: profile corner k at y = -half; 2k + 1: at y = +half.
  for (const auto& p : kBucketProfile) {
    mesh.vertices.emplace_back(p[0], -half, p[1]);
    mesh.vertices.emplace_back(p[0], half, p[1]);
  }
  auto lo = [](std::uint32_t k) { return 2 * k; };
  auto hi = [](std::uint32_t k) { return 2 * k + 1; };
  const auto corners = static_cast<std::uint32_t>(kBucketProfile.size());
  // Back and bottom plates: one strip per profile edge.
  for (std::uint32_t k = 0; k + 1 < corners; ++k) {
    mesh.triangles.push_back({lo(k), lo(k + 1), hi(k + 1)});
    mesh.triangles.push_back({lo(k), hi(k + 1), hi(k)});
  }
  // Side plates: the (convex) profile polygon as a fan from the pivot corner.
  for (std::uint32_t k = 1; k + 1 < corners; ++k) {
    mesh.triangles.push_back({lo(0), lo(k + 1), lo(k)});
    mesh.triangles.push_back({hi(0), hi(k), hi(k + 1)});
  }
  return mesh;
}

std::string writeBucketStl(const BucketMesh& mesh, const std::string& path) {
  core::writeStlBinary(path, mesh.vertices, mesh.triangles);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error("cannot read back " + path);
  std::string bytes(static_cast<std::size_t>(in.tellg()), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()))) throw std::runtime_error("cannot read back " + path);
  return bytes;
}

double bucketCapacity() {
  double twiceArea = 0.0;  // shoelace over the closed profile (the mouth closes it)
  for (std::size_t k = 0; k < kBucketProfile.size(); ++k) {
    const auto& a = kBucketProfile[k];
    const auto& b = kBucketProfile[(k + 1) % kBucketProfile.size()];
    twiceArea += a[0] * b[1] - b[0] * a[1];
  }
  return 0.5 * std::abs(twiceArea) * kBucketWidth;
}

}  // namespace demlink::examples::excavator
